/**
 * The release pipeline end to end, on this machine: a local registry (Verdaccio, see
 * registry-helpers.ts), every publishable workspace published to it by the release workflow's own
 * script (scripts/publish.mjs), then a user's scratch project outside the repository that
 * installs `fixedstep` and `@fixedstep/cli` from it — with no npm warning — runs the README's
 * first example and serves the lab with `npx fixedstep serve`; and `npm create fixedstep` makes
 * a game from each template — canvas, then Phaser, PixiJS and three.js (their engines proxied
 * from npm) — that installs, builds and plays in headless Chromium (create-helpers.ts: scripted
 * keys move the player as they say, the canvas shows the state, a highscore is accepted, the
 * downloaded replay passes `npm run verify`, two tabs play one room through the relay). Needs the
 * build (`npm run build`): it publishes what dist/ and packages/cli/lab hold. One registry serves
 * the whole file. The install transcripts land in artifacts/registry/ (install.txt, create.txt,
 * templates.txt with the bundle sizes), and a screenshot of each game's canvas beside them.
 */
import { existsSync } from 'node:fs';
import { mkdir, mkdtemp, readdir, readFile, rm, stat, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { gzipSync } from 'node:zlib';
import type { Browser } from 'playwright-core';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { readmeExample, repo, run, toJs, type Ran } from './pack-helpers.js';
import { launchChromium } from './harness.js';
import { startProgram, startRegistry, waitFor, type Registry } from './registry-helpers.js';
import { playOnline, playRound, serveGame, type ServedGame } from './create-helpers.js';
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

/** `npm create fixedstep@latest <name> --registry … -- --template <template>` in the scratch folder. */
function create(name: string, template: string): Promise<Ran> {
  const args = ['create', 'fixedstep@latest', name, '--registry', registry!.url];
  return run('npm', [...args, '--', '--template', template], scratch, env);
}

/**
 * `npm install` (with `flags`) in a created game: exit 0, no npm warning; what npm said.
 */
async function installGame(game: string, flags: readonly string[] = []): Promise<string> {
  const args = ['install', '--no-audit', '--no-fund', ...flags];
  const installed = await run('npm', args, game, env);
  expect({ code: installed.code, stderr: installed.stderr }).toMatchObject({ code: 0 });
  const said = (installed.stdout + installed.stderr).trim();
  // The templates allow no install script (esbuild's only checks its platform binary, which npm
  // installs as an optional dependency): npm 11 warns about scripts a project does not decide.
  expect(npmWarnings(said)).toEqual([]);
  return said;
}

/** `npm run build` in a created game: exit 0; the page's JavaScript, in bytes and gzipped. */
async function buildGame(game: string): Promise<{ js: number; gzip: number }> {
  const built = await run('npm', ['run', 'build'], game, env);
  expect({ code: built.code, output: built.stdout + built.stderr }).toMatchObject({ code: 0 });
  let js = 0;
  let gzip = 0;
  for (const file of await readdir(path.join(game, 'dist/assets'))) {
    if (!file.endsWith('.js')) continue;
    const bytes = await readFile(path.join(game, 'dist/assets', file));
    js += bytes.length;
    gzip += gzipSync(bytes).length;
  }
  return { js, gzip };
}

describe('npm create fixedstep', () => {
  let game: string;
  let served: ServedGame | undefined;

  afterAll(async () => {
    await served?.program.stop('SIGINT');
  });

  it('creates the canvas template from the registry, installs it and builds it', async () => {
    const created = await create('my-canvas-game', 'canvas');
    expect({ code: created.code, stderr: created.stderr }).toMatchObject({ code: 0 });
    game = path.join(scratch, 'my-canvas-game');
    const pkg = JSON.parse(await readFile(path.join(game, 'package.json'), 'utf8')) as {
      name: string;
      dependencies: Record<string, string>;
    };
    expect(pkg.name).toBe('my-canvas-game');
    const version = workspaces.find((w) => w.pkg.name === 'fixedstep')!.pkg.version;
    expect(pkg.dependencies.fixedstep).toBe(`^${version}`);
    const said = await installGame(game);
    console.log(`created game: npm install --no-audit --no-fund: ${said}`);
    await mkdir(path.join(repo, 'artifacts/registry'), { recursive: true });
    await writeFile(
      path.join(repo, 'artifacts/registry/create.txt'),
      `$ npm create fixedstep@latest my-canvas-game --registry ${registry!.url} -- --template canvas\n` +
        `${created.stdout.trim()}\n\n$ npm install --no-audit --no-fund\n${said}\n`,
    );
    await buildGame(game);
  }, 300_000);

  it('plays in Chromium: scripted keys, the canvas drawn, a highscore accepted, a replay the CLI verifies', async () => {
    expect(game).toBeDefined();
    served = await serveGame(game, path.join(scratch, 'game-data'), env);
    const browser = await launchChromium();
    try {
      const shot = path.join(repo, 'artifacts/registry/canvas.png');
      const round = await playRound(browser, served.url, game, shot, env);
      console.log(`canvas: npm run verify: ${round.verified}`);
    } finally {
      await browser.close();
    }
  });

  it('plays online: two tabs in one room, both stepping the round through the relay', async () => {
    expect(served).toBeDefined();
    const browser = await launchChromium();
    try {
      expect(await playOnline(browser, served!.url, 'e2e')).toBeGreaterThan(120);
    } finally {
      await browser.close();
    }
  });
});

/**
 * The engine templates: the same game as the canvas one, drawn by Phaser, PixiJS and three.js,
 * whose packages the registry proxies from npm. Made, installed and built side by side in the
 * scratch folder (npm's cache serves what the canvas game already fetched), then each played.
 */
describe('npm create fixedstep: the Phaser, PixiJS and three.js templates', () => {
  const ENGINES = ['phaser', 'pixi', 'three'] as const;
  const dirOf = (template: string) => path.join(scratch, `my-${template}-game`);

  it('creates each from the registry, installs it and builds it', async () => {
    const report: string[] = [];
    for (const template of ENGINES) {
      const created = await create(`my-${template}-game`, template);
      expect({ code: created.code, stderr: created.stderr }).toMatchObject({ code: 0 });
      expect(created.stdout).toContain(`from the ${template} template`);
    }
    const t0 = performance.now();
    // --prefer-offline: what npm's cache holds since the canvas game's install (Vite, TypeScript,
    // our packages, their metadata) is not asked for again; the engines still come through the
    // registry, which fetches them from npm.
    const said = await Promise.all(
      ENGINES.map((template) => installGame(dirOf(template), ['--prefer-offline'])),
    );
    const t1 = performance.now();
    const sizes = await Promise.all(ENGINES.map((template) => buildGame(dirOf(template))));
    const t2 = performance.now();
    ENGINES.forEach((template, k) => {
      const { js, gzip } = sizes[k]!;
      report.push(
        `${template}: npm install: ${said[k]!.split('\n').at(-1)}; ` +
          `dist/assets/*.js ${(js / 1000).toFixed(1)} kB (${(gzip / 1000).toFixed(1)} kB gzipped)`,
      );
    });
    report.push(
      `installs (together) ${((t1 - t0) / 1000).toFixed(1)} s, builds (together) ${((t2 - t1) / 1000).toFixed(1)} s`,
    );
    await writeFile(path.join(repo, 'artifacts/registry/templates.txt'), `${report.join('\n')}\n`);
    console.log(report.join('\n'));
    // The engines came through the local registry: it fetched their metadata from npm and keeps
    // it in its storage (the lockfiles say nothing: npm here omits registry addresses from them).
    const storage = path.join(scratch, 'registry/storage');
    for (const name of ['phaser', 'pixi.js', 'three']) {
      const stored = existsSync(path.join(storage, name, 'package.json'));
      expect({ name, stored }).toEqual({ name, stored: true });
    }
    // Each game is the canvas game drawn otherwise: its src/game.ts is the canvas game's.
    const canvasGame = await readFile(path.join(scratch, 'my-canvas-game/src/game.ts'), 'utf8');
    for (const template of ENGINES) {
      expect(await readFile(path.join(dirOf(template), 'src/game.ts'), 'utf8')).toBe(canvasGame);
    }
  }, 400_000);

  // Online play is src/play.ts, the same file in every template: the canvas game plays it above.
  // The three play at once (each its own page, server and data folder; each waits on state).
  let browser: Promise<Browser> | undefined;
  afterAll(async () => {
    await (await browser)?.close();
  });

  it.concurrent.each(ENGINES)(
    '%s: plays in Chromium: scripted keys, the canvas drawn, a highscore accepted, a replay the CLI verifies',
    async (template) => {
      const dir = dirOf(template);
      expect(existsSync(path.join(dir, 'dist-game/game.js'))).toBe(true);
      const serve = await serveGame(dir, path.join(scratch, `${template}-data`), env);
      try {
        browser ??= launchChromium();
        const shot = path.join(repo, `artifacts/registry/${template}.png`);
        const round = await playRound(await browser, serve.url, dir, shot, env);
        console.log(`${template}: npm run verify: ${round.verified}`);
      } finally {
        await serve.program.stop('SIGINT');
      }
    },
  );
});
