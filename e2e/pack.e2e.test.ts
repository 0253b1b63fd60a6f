/**
 * The packages as a user gets them: `npm pack` the built workspaces, install the tarballs into a
 * scratch project outside the repository (no workspace links: the package comes from its
 * tarball), then run the READMEs' examples from Node, type-check a strict consumer under every
 * module set-up the README promises, bundle the example with Vite, and lint the tarballs with
 * publint and Are the Types Wrong. Needs the build (`npm run build`): it packs what dist/ holds.
 * The tarball's file list lands in artifacts/pack/.
 */
import { mkdir, mkdtemp, readFile, rm, stat, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { build } from 'vite';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import {
  packWorkspaces,
  readmeExample,
  repo,
  run,
  toJs,
  type Packed,
  type Ran,
} from './pack-helpers.js';

const tscJs = path.join(repo, 'node_modules/typescript/bin/tsc');
const publintJs = path.join(repo, 'node_modules/publint/src/cli.js');
const attwJs = path.join(repo, 'node_modules/@arethetypeswrong/cli/dist/index.js');
const typeRoots = [path.join(repo, 'node_modules/@types')];

let scratch: string;
let project: string;
let example: string;
const packed = new Map<string, Packed>();

beforeAll(async () => {
  scratch = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-pack-'));
  const tarballs = path.join(scratch, 'tarballs');
  project = path.join(scratch, 'consumer');
  await mkdir(tarballs);
  await mkdir(project);
  const workspaces = [
    'packages/fixedstep',
    'packages/games',
    'packages/server',
    'packages/cli',
    'packages/rapier',
  ];
  for (const [name, p] of await packWorkspaces(workspaces, tarballs)) packed.set(name, p);
  await writeFile(
    path.join(project, 'package.json'),
    JSON.stringify({ name: 'consumer', private: true, type: 'module' }),
  );
  // fixedstep has no dependencies, games only fixedstep; rapier needs Rapier's package, which
  // `npm ci` of the workspace left in npm's cache (the registry answers otherwise).
  const install = await run(
    'npm',
    ['install', '--no-audit', '--no-fund', '--prefer-offline', '--no-package-lock'].concat([
      packed.get('fixedstep')!.tarball,
      packed.get('@fixedstep/games')!.tarball,
      packed.get('@fixedstep/rapier')!.tarball,
    ]),
    project,
  );
  if (install.code !== 0) throw new Error(`npm install of the tarballs failed:\n${install.stderr}`);
  // The example as shipped in the tarball's README, as TypeScript and as JavaScript for Node.
  example = readmeExample(
    await readFile(path.join(project, 'node_modules/fixedstep/README.md'), 'utf8'),
  );
  await writeFile(path.join(project, 'example.ts'), example);
  await writeFile(path.join(project, 'example.mjs'), toJs(example));
}, 180_000);

afterAll(async () => {
  await rm(scratch, { recursive: true, force: true });
});

describe('the fixedstep tarball', () => {
  it('holds dist (JavaScript, declarations, both maps), the sources they map to, README, LICENSE', async () => {
    const p = packed.get('fixedstep')!;
    const files = p.files.map((f) => f.path).sort();
    const list = p.files
      .slice()
      .sort((a, b) => a.path.localeCompare(b.path))
      .map((f) => `${String(f.size).padStart(8)}  ${f.path}`);
    await mkdir(path.join(repo, 'artifacts/pack'), { recursive: true });
    await writeFile(
      path.join(repo, 'artifacts/pack/fixedstep-files.txt'),
      `${p.filename}: ${p.size} bytes packed, ${p.unpackedSize} unpacked, ${files.length} files\n${list.join('\n')}\n`,
    );
    console.log(
      `${p.filename}: ${p.size} B packed, ${p.unpackedSize} B unpacked, ${files.length} files`,
    );

    const unexpected = files.filter(
      (f) =>
        !/^(package\.json|README\.md|LICENSE|dist\/.+\.(js|js\.map|d\.ts|d\.ts\.map)|src\/.+\.(ts|wat))$/.test(
          f,
        ),
    );
    expect(unexpected, 'files the tarball should not hold').toEqual([]);
    for (const f of [
      'LICENSE',
      'README.md',
      'dist/index.js',
      'dist/index.d.ts',
      'dist/index.d.ts.map',
    ]) {
      expect(files).toContain(f);
    }
    // Every compiled module has its declarations, both maps and the source they point at; a
    // module whose source is gone is a stale build (rm -rf packages/fixedstep/dist, rebuild).
    const modules = files.filter((f) => f.startsWith('dist/') && f.endsWith('.js'));
    expect(modules.length).toBeGreaterThan(40);
    const missing: string[] = [];
    for (const js of modules) {
      const base = js.slice('dist/'.length, -'.js'.length);
      for (const f of [
        `dist/${base}.d.ts`,
        `dist/${base}.d.ts.map`,
        `dist/${base}.js.map`,
        `src/${base}.ts`,
      ]) {
        if (!files.includes(f)) missing.push(f);
      }
    }
    expect(missing, 'files each compiled module needs beside it').toEqual([]);

    const license = await readFile(path.join(project, 'node_modules/fixedstep/LICENSE'), 'utf8');
    expect(license).toContain('MIT License');
    expect(license).toContain('Copyright (c) 2026 fixedstep contributors');
    // The installed copy is a real directory from the tarball, not a link into the workspace.
    expect((await stat(path.join(project, 'node_modules/fixedstep'))).isSymbolicLink()).toBe(false);
    const installed = JSON.parse(
      await readFile(path.join(project, 'node_modules/fixedstep/package.json'), 'utf8'),
    ) as { license: string; repository: unknown; engines: unknown; sideEffects: unknown };
    expect(installed.license).toBe('MIT');
    expect(installed.sideEffects).toBe(false);
    expect(installed.engines).toEqual({ node: '>=20.19' });
  });

  it('runs the README example it ships from Node ESM, printing what the README says', async () => {
    // The repository's README shows the same example (tested from source by readme.test.ts).
    expect(readmeExample(await readFile(path.join(repo, 'README.md'), 'utf8'))).toBe(example);
    const out = await run(process.execPath, ['example.mjs'], project);
    expect(out.stderr).toBe('');
    expect(out.code).toBe(0);
    expect(out.stdout).toBe('60 0.013250\n');
    expect(example).toContain(`// ${out.stdout.trim()} `);
  });

  it('runs the @fixedstep/games README example: a bot match, the same twice', async () => {
    const readme = await readFile(
      path.join(project, 'node_modules/@fixedstep/games/README.md'),
      'utf8',
    );
    await writeFile(path.join(project, 'games.ts'), readmeExample(readme));
    await writeFile(path.join(project, 'games.mjs'), toJs(readmeExample(readme)));
    const out = await run(process.execPath, ['games.mjs'], project);
    expect(out.stderr).toBe('');
    expect(out.code).toBe(0);
    const lines = out.stdout.trim().split('\n');
    expect(lines.at(-1)).toBe('true');
    expect(readmeExample(readme)).toContain('// true');
  });
});

/** A strict consumer's compiler options, types aside: nothing skipped, no DOM. */
const STRICT_CHECKS = {
  strict: true,
  noUncheckedIndexedAccess: true,
  exactOptionalPropertyTypes: true,
  noImplicitOverride: true,
  target: 'ES2022',
  lib: ['ES2022'],
  skipLibCheck: false,
};

/** A strict consumer's compiler options: nothing skipped, no DOM, Node's types only. */
const STRICT = { ...STRICT_CHECKS, types: ['node'], typeRoots };

/** What a CommonJS consumer does: one loop, 100 ms of frames (6 ticks at 60 Hz), printed. */
const CJS_BODY = `
  const loop = new FixedLoop({ step: 60 });
  const clock = new ManualClock();
  loop.frame(clock.now());
  const steps: number = loop.frame(clock.advance(100));
  console.log(steps, loop.tick);
`;

/** The consumer's files besides example.ts (the README's example); cjs/ is a CommonJS package. */
const CONSUMER_FILES: Record<string, string> = {
  // Every export, so every declaration file is read and checked.
  'all.ts': `import * as fixedstep from 'fixedstep';\nexport const names: readonly string[] = Object.keys(fixedstep);\n`,
  'cjs/package.json': JSON.stringify({ type: 'commonjs' }),
  'cjs/import.cts': `import type { FixedLoop as Loop } from 'fixedstep' with { 'resolution-mode': 'import' };
async function main(): Promise<void> {
  const { FixedLoop, ManualClock } = await import('fixedstep');
  ${CJS_BODY}
  const typed: Loop = loop;
  console.log(typed.tick);
}
void main();
`,
  'cjs/require.cts': `import { FixedLoop, ManualClock } from 'fixedstep';\n${CJS_BODY}`,
  'cjs/node10.ts': `import { FixedLoop, ManualClock } from 'fixedstep';\n${CJS_BODY}`,
};

interface Setup {
  name: string;
  options: Record<string, unknown>;
  files: string[];
  /** Emitted CommonJS files to run with Node (each must print `6 6` first). */
  runs: string[];
}

/**
 * Every module set-up the README promises. Set-ups that share compiler options share one program
 * (a file's module format comes from its extension and package.json, not the program).
 */
const SETUPS: Setup[] = [
  {
    name: 'node16: ESM, and a .cts file through await import()',
    options: { module: 'node16', moduleResolution: 'node16', outDir: 'out-node16' },
    files: ['example.ts', 'cjs/import.cts'],
    runs: ['out-node16/cjs/import.cjs'],
  },
  {
    name: 'nodenext: ESM, every export, and a .cts file through require() (Node 20.19+)',
    options: { module: 'nodenext', moduleResolution: 'nodenext', outDir: 'out-nodenext' },
    files: ['example.ts', 'all.ts', 'cjs/require.cts'],
    runs: ['out-nodenext/cjs/require.cjs'],
  },
  {
    name: 'bundler',
    options: { module: 'preserve', moduleResolution: 'bundler', noEmit: true },
    files: ['example.ts', 'all.ts'],
    runs: [],
  },
  {
    name: 'node10: the top-level types field, CommonJS output run by Node 20.19+',
    options: {
      module: 'commonjs',
      moduleResolution: 'node10',
      rootDir: 'cjs',
      outDir: 'cjs/out-node10',
    },
    files: ['cjs/node10.ts'],
    runs: ['cjs/out-node10/node10.js'],
  },
];

describe('TypeScript consumers of the tarball (strict, lib ES2022 without DOM, types node, skipLibCheck false)', () => {
  /** Each set-up's tsc run, started together (they take seconds each) and awaited by its test. */
  const checks = new Map<string, Promise<Ran>>();

  beforeAll(async () => {
    for (const [name, text] of Object.entries(CONSUMER_FILES)) {
      await mkdir(path.dirname(path.join(project, name)), { recursive: true });
      await writeFile(path.join(project, name), text);
    }
    for (const setup of SETUPS) {
      const config = path.join(
        project,
        `tsconfig.${setup.options.moduleResolution as string}.json`,
      );
      await writeFile(
        config,
        JSON.stringify({ compilerOptions: { ...STRICT, ...setup.options }, files: setup.files }),
      );
      checks.set(setup.name, run(process.execPath, [tscJs, '-p', config], project));
    }
  });

  it.each(SETUPS)('$name', async (setup) => {
    const checked = await checks.get(setup.name)!;
    expect(checked.stdout + checked.stderr).toBe('');
    expect(checked.code).toBe(0);
    for (const file of setup.runs) {
      const out = await run(process.execPath, [file], project);
      expect({ code: out.code, stderr: out.stderr }).toMatchObject({ code: 0 });
      expect(out.stdout.split('\n')[0]).toBe('6 6');
    }
  });
});

/**
 * A game's own compilation: no Node types and no DOM (`lib: ["ES2022"], types: []`, how Coin
 * Dash's `build:game` compiles its simulation), and a browser game's (`lib: ["ES2022", "DOM"]`,
 * `types: []`). The declarations of fixedstep, @fixedstep/games and @fixedstep/rapier must
 * type-check under both, nothing skipped: a global of Node or the DOM named in a public signature
 * (`WebSocket`, `AbortSignal`, `Response`…) fails here with TS2304.
 */
const STANDALONE_FILES: Record<string, string> = {
  'standalone/all.ts': `import * as fixedstep from 'fixedstep';
import * as games from '@fixedstep/games';
import * as rapier from '@fixedstep/rapier';
export const names: readonly string[] = [fixedstep, games, rapier].flatMap((m) => Object.keys(m));
`,
  // The browser's own objects fit the structural types the declarations name.
  'standalone/browser.ts': `import { connectWebSocket, fetchWithRetry, quickMatch, webSocketTransport } from 'fixedstep';
export async function online(): Promise<unknown> {
  webSocketTransport(new WebSocket('wss://example.test/ws/a')).close('done');
  await connectWebSocket('wss://example.test/ws/b', { WebSocketClass: WebSocket });
  const controller = new AbortController();
  await quickMatch({
    url: 'wss://example.test/match',
    game: 'pong',
    gameVersion: 1,
    input: { id: 'pong-input' },
    minPlayers: 2,
    signal: controller.signal,
    WebSocketClass: WebSocket,
  });
  const res: Response = await fetchWithRetry(
    '/api/highscores?score=1',
    { method: 'POST', body: new Uint8Array(4), signal: controller.signal },
    { fetch: (url, init) => fetch(url, init) },
  );
  return res.json();
}
`,
};

const STANDALONE_SETUPS = [
  {
    name: 'lib ES2022, types [] (no DOM, no Node)',
    options: { lib: ['ES2022'], module: 'nodenext', moduleResolution: 'nodenext' },
    files: ['standalone/all.ts'],
  },
  {
    name: 'lib ES2022 + DOM, types [] (a browser game)',
    options: { lib: ['ES2022', 'DOM'], module: 'preserve', moduleResolution: 'bundler' },
    files: ['standalone/all.ts', 'standalone/browser.ts'],
  },
];

/**
 * Rapier's own declarations (`@dimforge/rapier2d-deterministic-compat`, not ours) name
 * `Symbol.dispose` (lib `ESNext.Disposable`) and, without the DOM, `WebAssembly`: a consumer of
 * @fixedstep/rapier adds that lib or skips library checks. Their diagnostics are set aside; every
 * other one fails the test.
 */
const UPSTREAM = 'node_modules/@dimforge/';

describe('standalone declarations: strict consumers with types [] and no ambient globals', () => {
  const checks = new Map<string, Promise<Ran>>();

  beforeAll(async () => {
    for (const [name, text] of Object.entries(STANDALONE_FILES)) {
      await mkdir(path.dirname(path.join(project, name)), { recursive: true });
      await writeFile(path.join(project, name), text);
    }
    for (const [i, setup] of STANDALONE_SETUPS.entries()) {
      const config = path.join(project, `tsconfig.standalone-${i}.json`);
      const compilerOptions = { ...STRICT_CHECKS, ...setup.options, types: [], noEmit: true };
      await writeFile(config, JSON.stringify({ compilerOptions, files: setup.files }));
      checks.set(
        setup.name,
        run(process.execPath, [tscJs, '-p', config, '--pretty', 'false'], project),
      );
    }
  });

  it.each(STANDALONE_SETUPS)('$name', async (setup) => {
    const checked = await checks.get(setup.name)!;
    // One diagnostic per unindented line (`file(line,col): error TS…`), its details indented.
    const diagnostics = (checked.stdout + checked.stderr).split(/\n(?=\S)/).filter((d) => d !== '');
    const ours = diagnostics.filter((d) => !d.startsWith(UPSTREAM));
    expect(ours).toEqual([]);
    console.log(
      `${setup.name}: ${diagnostics.length - ours.length} diagnostics in Rapier's own declarations set aside`,
    );
  });
});

describe('bundling the tarball', () => {
  it('Vite bundles the README example from dist (tree-shaken: the loop, not the library)', async () => {
    const outDir = path.join(project, 'vite-out');
    await build({
      root: project,
      configFile: false,
      logLevel: 'silent',
      publicDir: false,
      build: {
        outDir,
        emptyOutDir: true,
        target: 'es2022',
        minify: 'esbuild',
        lib: { entry: path.join(project, 'example.ts'), formats: ['es'], fileName: 'bundle' },
      },
    });
    const bundle = path.join(outDir, 'bundle.js');
    const size = (await stat(bundle)).size;
    console.log(`Vite bundle of the README example: ${size} B`);
    const out = await run(process.execPath, [bundle], project);
    expect({ code: out.code, stderr: out.stderr }).toEqual({ code: 0, stderr: '' });
    expect(out.stdout).toBe('60 0.013250\n');
    // The whole library is ~430 KB of JavaScript; sideEffects: false lets the bundler keep the
    // loop and the clock only.
    const whole = packed
      .get('fixedstep')!
      .files.filter((f) => f.path.startsWith('dist/') && f.path.endsWith('.js'))
      .reduce((sum, f) => sum + f.size, 0);
    expect(size).toBeLessThan(whole / 10);
  });
});

describe('publint and Are the Types Wrong', () => {
  it.each(['fixedstep', '@fixedstep/games', '@fixedstep/cli', '@fixedstep/rapier'])(
    '%s passes both',
    async (name) => {
      const tarball = packed.get(name)!.tarball;
      const lint = await run(process.execPath, [publintJs, 'run', tarball, '--strict'], repo);
      expect(lint.stdout + lint.stderr).toContain('All good!');
      expect(lint.code).toBe(0);
      // ESM only, by choice: a CommonJS `require` resolving to ESM is what the README documents
      // (Node 20.19+ require(esm), or `await import()`), so that one rule is not an error here.
      const attw = await run(
        process.execPath,
        [
          attwJs,
          tarball,
          '--ignore-rules',
          'cjs-resolves-to-esm',
          '--format',
          'ascii',
          '--no-color',
        ],
        repo,
      );
      expect(attw.stdout + attw.stderr).toContain('No problems found');
      expect(attw.code).toBe(0);
    },
  );
});
