/**
 * The release pipeline end to end, on this machine: a local registry (Verdaccio, see
 * registry-helpers.ts), every publishable workspace published to it by the release workflow's own
 * script (scripts/publish.mjs), then a user's scratch project outside the repository that
 * installs `fixedstep` and `@fixedstep/cli` from it — with no npm warning — runs the README's
 * first example and serves the lab with `npx fixedstep serve`; and `npm create fixedstep` makes
 * a game from the canvas template that installs, builds, plays in headless Chromium (scripted
 * keys, a highscore submitted, a replay downloaded and verified by the CLI, two tabs in one
 * room through the relay). Needs the build (`npm run build`):
 * it publishes what dist/ and packages/cli/lab hold. One registry serves the whole file. The
 * install transcripts land in artifacts/registry/ (install.txt, create.txt).
 */
import { mkdir, mkdtemp, readdir, readFile, rm, stat, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { readmeExample, repo, run, toJs, type Ran } from './pack-helpers.js';
import { launchChromium } from './harness.js';
import {
  startProgram,
  startRegistry,
  waitFor,
  type Program,
  type Registry,
} from './registry-helpers.js';
import { publishable } from '../scripts/publish.mjs';

const workspaces = publishable();

/** Lines npm printed as warnings (`npm warn …`, `npm WARN …`). */
function npmWarnings(output: string): string[] {
  return output.split('\n').filter((l) => /^npm warn/i.test(l));
}

/** Bytes of every file under `dir` (what `du` would count, without links followed). */
async function treeSize(dir: string): Promise<{ bytes: number; packages: number }> {
  let bytes = 0;
  let packages = 0;
  for (const entry of await readdir(dir, { recursive: true, withFileTypes: true })) {
    const p = path.join(entry.parentPath, entry.name);
    if (entry.isFile()) bytes += (await stat(p)).size;
    // A package: a package.json in node_modules/<name>/ or node_modules/@scope/<name>/.
    if (
      entry.name === 'package.json' &&
      /node_modules(\/@[^/]+)?$/.test(path.dirname(entry.parentPath))
    )
      packages += 1;
  }
  return { bytes, packages };
}

let scratch: string;
let registry: Registry | undefined;
let project: string;
let env: NodeJS.ProcessEnv;
let published: Ran;
let install: Ran;
const INSTALL = ['install', '--no-audit', '--no-fund', 'fixedstep', '@fixedstep/cli'];

beforeAll(async () => {
  scratch = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-registry-'));
  await mkdir(path.join(scratch, 'registry'));
  registry = await startRegistry(path.join(scratch, 'registry'));
  // Every npm below reads this configuration only: the local registry, and its token.
  env = { NPM_CONFIG_USERCONFIG: registry.npmrc, NPM_CONFIG_UPDATE_NOTIFIER: 'false' };
  published = await run(
    process.execPath,
    [path.join(repo, 'scripts/publish.mjs'), '--registry', registry.url],
    repo,
    env,
  );
  if (published.code !== 0) throw new Error(`publish failed:\n${published.stderr}`);
  project = path.join(scratch, 'my-game');
  await mkdir(project);
  await writeFile(
    path.join(project, 'package.json'),
    JSON.stringify({ name: 'my-game', private: true, type: 'module' }),
  );
  install = await run('npm', INSTALL, project, env);
}, 400_000);

afterAll(async () => {
  await registry?.stop();
  await rm(scratch, { recursive: true, force: true });
});

describe('publishing to a local registry', () => {
  it('publishes every publishable workspace, dependencies first', async () => {
    expect(workspaces.map((w) => w.pkg.name)).toEqual(
      expect.arrayContaining([
        'fixedstep',
        '@fixedstep/games',
        '@fixedstep/rapier',
        '@fixedstep/server',
        '@fixedstep/cli',
        'create-fixedstep',
      ]),
    );
    for (const { pkg } of workspaces) {
      const r = await fetch(`${registry!.url}${pkg.name.replace('/', '%2f')}`);
      const doc = (await r.json()) as { 'dist-tags'?: { latest?: string } };
      expect({ name: pkg.name, status: r.status, latest: doc['dist-tags']?.latest }).toEqual({
        name: pkg.name,
        status: 200,
        latest: pkg.version,
      });
    }
  });

  it('is idempotent: a second run skips what the registry has', async () => {
    const again = await run(
      process.execPath,
      [path.join(repo, 'scripts/publish.mjs'), '--registry', registry!.url],
      repo,
      env,
    );
    expect(again.code).toBe(0);
    for (const { pkg } of workspaces) {
      expect(again.stdout).toContain(`${pkg.name}@${pkg.version}: already published, skipped`);
    }
  });
});

describe('a user installs from the registry', () => {
  it('npm install fixedstep @fixedstep/cli: no warning on Node 20, the transcript kept', async () => {
    const warnings = npmWarnings(install.stderr + install.stdout);
    const size = await treeSize(path.join(project, 'node_modules'));
    const transcript = [
      `node ${process.version}, npm ${(await run('npm', ['--version'], project)).stdout.trim()}`,
      `registry: ${registry!.url} (Verdaccio, proxying registry.npmjs.org for third-party packages)`,
      '',
      `$ node scripts/publish.mjs --registry ${registry!.url}`,
      published.stdout.trim(),
      '',
      `$ npm ${INSTALL.join(' ')}     # in ${project}`,
      (install.stdout + install.stderr).trim(),
      `exit code ${install.code}`,
      '',
      `npm warnings: ${warnings.length}`,
      `installed tree: ${size.packages} packages, ${(size.bytes / 1e6).toFixed(1)} MB in node_modules`,
    ].join('\n');
    await mkdir(path.join(repo, 'artifacts/registry'), { recursive: true });
    await writeFile(path.join(repo, 'artifacts/registry/install.txt'), `${transcript}\n`);
    console.log(transcript);
    expect(install.code).toBe(0);
    expect(warnings).toEqual([]);
    // The installed copies are the published ones, not links into the workspace.
    const cli = JSON.parse(
      await readFile(path.join(project, 'node_modules/@fixedstep/cli/package.json'), 'utf8'),
    ) as { version: string };
    expect(cli.version).toBe(workspaces.find((w) => w.pkg.name === '@fixedstep/cli')!.pkg.version);
    // Fastify's light-my-request 6.8+ needs cookie 2, which needs Node 22 (EBADENGINE on Node 20):
    // @fixedstep/server pins 6.6 in its own dependencies, where a user's install sees it (the
    // workspace's `overrides` never reach a user).
    const lightMyRequest = JSON.parse(
      await readFile(path.join(project, 'node_modules/light-my-request/package.json'), 'utf8'),
    ) as { version: string };
    expect(lightMyRequest.version).toMatch(/^6\.6\./);
  });

  it("runs the README's first example, printing what the README says", async () => {
    const example = readmeExample(await readFile(path.join(repo, 'README.md'), 'utf8'));
    await writeFile(path.join(project, 'example.mjs'), toJs(example));
    const out = await run(process.execPath, ['example.mjs'], project);
    expect({ code: out.code, stderr: out.stderr }).toEqual({ code: 0, stderr: '' });
    expect(example).toContain(`// ${out.stdout.trim()} `);
  });

  it('npx fixedstep serve serves the lab from the package, nothing built', async () => {
    const serve = startProgram(
      'npx',
      ['fixedstep', 'serve', '--port', '0', '--data', path.join(scratch, 'data')],
      project,
      env,
    );
    try {
      const url = await waitFor(
        'fixedstep serve listening',
        () => Promise.resolve(/fixedstep lab: (http\S+)/.exec(serve.output())?.[1]),
        serve,
      );
      const page = await fetch(url);
      expect(page.status).toBe(200);
      const html = await page.text();
      expect(html).toContain('<title>fixedstep lab</title>');
      // The page's own script is served too: the lab, not only its index.
      const script = /<script[^>]+src="\.?\/?([^"]+\.js)"/.exec(html)?.[1];
      expect(script).toBeDefined();
      const js = await fetch(new URL(script!, url));
      expect(js.status).toBe(200);
      expect((await js.arrayBuffer()).byteLength).toBeGreaterThan(1000);
      expect(npmWarnings(serve.output())).toEqual([]);
    } finally {
      await serve.stop('SIGINT');
    }
  });
});

describe('npm create fixedstep', () => {
  let game: string;
  let serve: Program | undefined;
  let url: string;

  afterAll(async () => {
    await serve?.stop('SIGINT');
  });

  it('creates the canvas template from the registry, installs it and builds it', async () => {
    const created = await run(
      'npm',
      [
        'create',
        'fixedstep@latest',
        'my-canvas-game',
        '--registry',
        registry!.url,
        '--',
        '--template',
        'canvas',
      ],
      scratch,
      env,
    );
    expect({ code: created.code, stderr: created.stderr }).toMatchObject({ code: 0 });
    game = path.join(scratch, 'my-canvas-game');
    const pkg = JSON.parse(await readFile(path.join(game, 'package.json'), 'utf8')) as {
      name: string;
      dependencies: Record<string, string>;
    };
    expect(pkg.name).toBe('my-canvas-game');
    const version = workspaces.find((w) => w.pkg.name === 'fixedstep')!.pkg.version;
    expect(pkg.dependencies.fixedstep).toBe(`^${version}`);
    const installed = await run('npm', ['install', '--no-audit', '--no-fund'], game, env);
    expect({ code: installed.code, stderr: installed.stderr }).toMatchObject({ code: 0 });
    const said = (installed.stdout + installed.stderr).trim();
    console.log(`created game: npm install --no-audit --no-fund: ${said}`);
    await mkdir(path.join(repo, 'artifacts/registry'), { recursive: true });
    await writeFile(
      path.join(repo, 'artifacts/registry/create.txt'),
      `$ npm create fixedstep@latest my-canvas-game --registry ${registry!.url} -- --template canvas\n` +
        `${created.stdout.trim()}\n\n$ npm install --no-audit --no-fund\n${said}\n`,
    );
    // The template allows no install script (esbuild's only checks its platform binary, which npm
    // installs as an optional dependency): npm 11 warns about scripts a project does not decide.
    expect(npmWarnings(said)).toEqual([]);
    const built = await run('npm', ['run', 'build'], game, env);
    expect({ code: built.code, output: built.stdout + built.stderr }).toMatchObject({ code: 0 });
  }, 300_000);

  it('plays in Chromium: scripted keys, a highscore accepted, a replay the CLI verifies', async () => {
    expect(game).toBeDefined();
    serve = startProgram(
      'npx',
      [
        'fixedstep',
        'serve',
        '--root',
        'dist',
        '--games',
        './dist-game/game.js',
        '--port',
        '0',
        '--data',
        path.join(scratch, 'game-data'),
      ],
      game,
      env,
    );
    const running = serve;
    url = await waitFor(
      'the game served',
      () => Promise.resolve(/fixedstep lab: (http\S+)/.exec(running.output())?.[1]),
      running,
    );
    // The store opens while the server already listens: until then the highscore API answers
    // 503 (the page would ask again, but the browser logs the first answer as an error).
    await waitFor(
      'the store open (/readyz)',
      async () => ((await fetch(new URL('/readyz', url))).ok ? true : undefined),
      running,
    );
    const browser = await launchChromium();
    try {
      const page = await browser.newPage();
      const problems: string[] = [];
      page.on('pageerror', (e) => problems.push(e.message));
      page.on('console', (m) => {
        if (m.type() === 'error') problems.push(m.text());
      });
      await page.goto(url);
      const tick = () =>
        page.evaluate(
          () => (window as unknown as { myGame: { game: { tick: number } } }).myGame.game.tick,
        );
      await expect.poll(tick, { timeout: 20_000 }).toBeGreaterThan(0);
      await page.locator('#field').click();
      // A scripted player: right for a while, then down with a dash.
      await page.keyboard.down('ArrowRight');
      const t0 = await tick();
      await expect.poll(tick, { timeout: 20_000 }).toBeGreaterThan(t0 + 60);
      await page.keyboard.up('ArrowRight');
      await page.keyboard.down('ArrowDown');
      await page.keyboard.press('Space');
      await expect.poll(tick, { timeout: 20_000 }).toBeGreaterThan(t0 + 150);
      await page.keyboard.up('ArrowDown');
      await page.locator('#end').click();
      await expect
        .poll(() => page.locator('#hud').textContent(), { timeout: 20_000 })
        .toContain('replay verified');
      await expect
        .poll(() => page.evaluate(() => document.body.dataset.highscore), { timeout: 30_000 })
        .toBe('accepted');
      const [download] = await Promise.all([
        page.waitForEvent('download'),
        page.locator('#download').click(),
      ]);
      const file = path.join(scratch, 'my-canvas-game.fsr');
      await download.saveAs(file);
      expect((await stat(file)).size).toBeGreaterThan(50);
      expect(problems).toEqual([]);

      const verified = await run(
        'npx',
        ['fixedstep', 'replay', 'verify', file, '--games', './dist-game/game.js'],
        game,
        env,
      );
      console.log(`fixedstep replay verify: ${verified.stdout.trim()}`);
      expect({ code: verified.code, stderr: verified.stderr }).toEqual({ code: 0, stderr: '' });

      const scores = (await (await fetch(new URL('/api/highscores?game=my-game', url))).json()) as {
        entries: unknown[];
      };
      expect(scores.entries).toHaveLength(1);
    } finally {
      await browser.close();
    }
  });

  it('plays online: two tabs in one room, both stepping the round through the relay', async () => {
    expect(url).toBeDefined();
    const browser = await launchChromium();
    try {
      const pages = await Promise.all([browser.newPage(), browser.newPage()]);
      for (const page of pages) await page.goto(new URL('/?room=e2e', url).href);
      interface Online {
        myGame: { session: { simulation?: { tick: number; hash(): bigint } } };
      }
      const ticks = () =>
        Promise.all(
          pages.map((page) =>
            page.evaluate(
              () => (window as unknown as Online).myGame.session.simulation?.tick ?? -1,
            ),
          ),
        );
      await expect
        .poll(async () => Math.min(...(await ticks())), { timeout: 30_000 })
        .toBeGreaterThan(60);
      await pages[0].keyboard.down('ArrowLeft');
      await expect
        .poll(async () => Math.min(...(await ticks())), { timeout: 20_000 })
        .toBeGreaterThan(120);
      await pages[0].keyboard.up('ArrowLeft');
      for (const page of pages) {
        expect(await page.locator('#hud').textContent()).toMatch(/^room e2e · you \d+ · them \d+/);
      }
    } finally {
      await browser.close();
    }
  });
});
