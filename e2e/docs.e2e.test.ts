/**
 * The API reference (`npm run docs`, TypeDoc over every published package: `fixedstep`,
 * `@fixedstep/games`, `@fixedstep/rapier`, `@fixedstep/server` and `@fixedstep/cli`): it builds
 * with 0 warnings (warnings are errors, and an undocumented export is a warning), has a page for
 * every export, and `fixedstep serve` serves it at /docs/, where the lab's footer links.
 */
import { execFile } from 'node:child_process';
import { mkdtemp, readdir, readFile, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { startServer } from '@fixedstep/server';
import { dist, launchChromium } from './harness.js';

const repo = fileURLToPath(new URL('..', import.meta.url));
const typedocJs = path.join(repo, 'node_modules/typedoc/bin/typedoc');

interface Ran {
  code: number;
  output: string;
}

/** TypeDoc with the repository's typedoc.json and `args`; its exit code and everything it printed. */
function typedoc(args: readonly string[]): Promise<Ran> {
  return new Promise((resolve) => {
    execFile(
      process.execPath,
      [typedocJs, ...args],
      { cwd: repo, env: { ...process.env, NO_COLOR: '1', FORCE_COLOR: '0' } },
      (error, stdout, stderr) => {
        const code = error === null ? 0 : typeof error.code === 'number' ? error.code : 1;
        resolve({ code, output: stdout + stderr });
      },
    );
  });
}

/** Every .html file under `dir`, as paths relative to it. */
async function htmlPages(dir: string): Promise<string[]> {
  const entries = await readdir(dir, { recursive: true });
  return entries.filter((f) => f.endsWith('.html')).sort();
}

interface Reflection {
  name: string;
  kind: number;
  children?: Reflection[];
}

/** TypeDoc's ReflectionKind values of the declarations that get a page of their own. */
const PAGE_KINDS = new Set([
  2, // Module
  4, // Namespace
  8, // Enum
  32, // Variable
  64, // Function
  128, // Class
  256, // Interface
  2097152, // TypeAlias
]);

/** The declarations of `r` (modules and namespaces included, recursively) that have a page. */
function pageReflections(r: Reflection): Reflection[] {
  const out: Reflection[] = [];
  for (const c of r.children ?? []) {
    if (!PAGE_KINDS.has(c.kind)) continue;
    out.push(c);
    if (c.kind === 2 || c.kind === 4) out.push(...pageReflections(c));
  }
  return out;
}

let scratch: string;
let out: string;
let built: Ran;

beforeAll(async () => {
  scratch = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-docs-'));
  out = path.join(scratch, 'api');
  // Exactly `npm run docs`, written to a scratch folder, plus TypeDoc's model as JSON.
  built = await typedoc(['--out', out, '--json', path.join(scratch, 'api.json')]);
});

afterAll(async () => {
  await rm(scratch, { recursive: true, force: true });
});

describe('npm run docs', () => {
  it('builds the reference with 0 warnings and 0 errors', () => {
    expect(built.output).not.toMatch(/\[warning\]|\[error\]/);
    expect(built.code).toBe(0);
    expect(built.output).toContain('html generated at');
  });

  it('has a page for every export of every published package', async () => {
    const model = JSON.parse(await readFile(path.join(scratch, 'api.json'), 'utf8')) as Reflection;
    const modules = (model.children ?? []).map((m) => m.name).sort();
    expect(modules).toEqual([
      '@fixedstep/cli',
      '@fixedstep/games',
      '@fixedstep/rapier',
      '@fixedstep/server',
      'fixedstep',
    ]);
    const declarations = pageReflections(model);
    const pages = await htmlPages(out);
    console.log(
      `API reference: ${pages.length} pages (${declarations.length} modules and exports, plus index, modules and hierarchy)`,
    );
    expect(pages.length).toBe(declarations.length + 3);
    expect(pages).toContain('index.html');
    const fixedLoop = pages.find((p) => p.startsWith('classes') && p.endsWith('.FixedLoop.html'));
    expect(fixedLoop).toBeDefined();
    const html = await readFile(path.join(out, fixedLoop!), 'utf8');
    expect(html).toContain('frame');
    expect(html).toContain('alpha');
  });

  it.each([
    ['@fixedstep/server', 'functions', 'createServer'],
    ['@fixedstep/server', 'functions', 'attachRelay'],
    ['@fixedstep/server', 'functions', 'attachStateSync'],
    ['@fixedstep/server', 'functions', 'highscoreApi'],
    ['@fixedstep/rapier', 'classes', 'RapierSimulation'],
    ['@fixedstep/rapier', 'functions', 'createRapierSimulation'],
    ['@fixedstep/cli', 'functions', 'run'],
  ])('documents %s %s/%s on a page of its own', async (module, folder, name) => {
    const page = `${folder}/${module.replace(/[@/]/g, '_')}.${name}.html`; // TypeDoc's file names
    const pages = await htmlPages(out);
    expect(pages).toContain(page);
    const html = await readFile(path.join(out, page), 'utf8');
    expect(html).toContain(name);
    // Its documentation, not only its signature: a summary paragraph.
    expect(html).toMatch(/class="tsd-comment tsd-typography"><p>/);
  });

  it('fails on an export without documentation (the check that keeps the count at 0)', async () => {
    await writeFile(
      path.join(scratch, 'undocumented.ts'),
      'export function undocumented(): void {}\n',
    );
    await writeFile(
      path.join(scratch, 'tsconfig.json'),
      JSON.stringify({
        compilerOptions: { strict: true, noEmit: true },
        files: ['undocumented.ts'],
      }),
    );
    // The repository's settings, on one undocumented function.
    await writeFile(
      path.join(scratch, 'typedoc.json'),
      JSON.stringify({
        extends: [path.join(repo, 'typedoc.json')],
        entryPoints: ['undocumented.ts'],
        tsconfig: 'tsconfig.json',
        readme: 'none',
        out: 'undocumented',
      }),
    );
    const r = await typedoc(['--options', path.join(scratch, 'typedoc.json')]);
    expect(r.output).toMatch(/undocumented.*does not have any documentation/);
    expect(r.code).not.toBe(0);
  });
});

describe('the reference in the lab', () => {
  it('fixedstep serve serves it at /docs/, and the lab footer links to it', async () => {
    const server = await startServer({ port: 0, host: '127.0.0.1', root: dist, docs: out });
    const browser = await launchChromium();
    try {
      const page = await browser.newPage();
      // What went wrong on the way: errors, 4xx/5xx answers, requests that failed (a favicon
      // request cut short by the next navigation is not a failure).
      const problems: string[] = [];
      page.on('console', (m) => {
        if (m.type() === 'error') problems.push(`console: ${m.text()} (${m.location().url})`);
      });
      page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
      page.on('response', (r) => {
        if (r.status() >= 400) problems.push(`${r.status()} ${r.url()}`);
      });
      page.on('requestfailed', (r) => {
        if (r.failure()?.errorText !== 'net::ERR_ABORTED') problems.push(`failed: ${r.url()}`);
      });
      await page.goto(server.url.replace('localhost', '127.0.0.1'));
      await page.locator('footer a', { hasText: 'API reference' }).click();
      await page.waitForURL(/\/docs\/$/);
      expect(await page.title()).toContain('fixedstep');
      await page.goto(new URL('classes/fixedstep.FixedLoop.html', page.url()).href);
      expect(await page.locator('h1').first().textContent()).toContain('FixedLoop');
      // TypeDoc's own script ran: it fills the page's navigation with the modules.
      await expect.poll(() => page.locator('.tsd-navigation a').count()).toBeGreaterThan(1);
      expect(problems).toEqual([]);
    } finally {
      await browser.close();
      await server.close();
    }
  });
});
