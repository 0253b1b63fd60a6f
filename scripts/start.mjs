// `npm start`: install what serving needs, build what changed, and serve the lab (and its server)
// on one port. Extra arguments go to `fixedstep serve`, e.g. `npm start -- --port 9000`.
//
// Each stage prints what it does and how long it took, and is skipped when its inputs are
// unchanged (a content hash of them, kept in node_modules/.cache/fixedstep/), so a second start
// only launches the server. `npm start` needs JavaScript, not declarations: the packages are
// compiled file by file with esbuild (no type check; `npm test` and `npm run build` run tsc).
import { createHash } from 'node:crypto';
import { existsSync, mkdirSync, readdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, relative } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { ensureDependencies, root, seconds } from './setup.mjs';

const STAGES = 4;
const cache = join(root, 'node_modules', '.cache', 'fixedstep');
/** The packages the server runs, compiled src/ → dist/ in tsc's layout (dist/x.js for src/x.ts). */
const PACKAGES = ['packages/fixedstep', 'packages/games', 'packages/server', 'packages/cli'];

function line(text) {
  process.stdout.write(`${text}\n`);
}

/** Every file under `dir` (skipping node_modules and dist), as absolute paths. */
function filesUnder(dir) {
  const out = [];
  for (const e of readdirSync(dir, { withFileTypes: true })) {
    if (e.name === 'node_modules' || e.name === 'dist') continue;
    const p = join(dir, e.name);
    if (e.isDirectory()) out.push(...filesUnder(p));
    else if (e.isFile()) out.push(p);
  }
  return out;
}

/** A content hash of `paths` (files, or folders read whole), relative to the repository. */
function hashOf(paths, extra = '') {
  const files = [];
  for (const p of paths.map((q) => join(root, q))) {
    if (!existsSync(p)) continue;
    if (statSync(p).isDirectory()) files.push(...filesUnder(p));
    else files.push(p);
  }
  files.sort();
  const h = createHash('sha256').update(extra);
  for (const f of files) h.update(`\0${relative(root, f)}\0`).update(readFileSync(f));
  return h.digest('hex');
}

/**
 * Runs stage `n` unless its stamp says its inputs are unchanged and its outputs exist. Prints
 * what it is doing, then what it did and how long it took. `work` returns what it did
 * ("compiled 108 files").
 */
async function stage(n, name, doing, { inputs, outputs, key }, work) {
  const t0 = performance.now();
  const stampFile = join(cache, `${key}.sha256`);
  const hash = hashOf(inputs, key);
  const fresh =
    existsSync(stampFile) &&
    readFileSync(stampFile, 'utf8') === hash &&
    outputs.every((o) => existsSync(join(root, o)));
  if (fresh) {
    line(`✓ ${n}/${STAGES} ${name}: up to date (sources unchanged; checked in ${seconds(t0)})`);
    return;
  }
  line(`▸ ${n}/${STAGES} ${name}: ${doing}`);
  const done = await work();
  mkdirSync(cache, { recursive: true });
  writeFileSync(stampFile, hash);
  line(`✓ ${n}/${STAGES} ${name}: ${done} in ${seconds(t0)}`);
}

// 1. Dependencies: only what building and serving needs (a full install does too).
{
  const t0 = performance.now();
  const installed = ensureDependencies('serve', (command) => {
    line(`▸ 1/${STAGES} Dependencies: installing what the lab and the server need (${command})`);
  });
  line(
    installed
      ? `✓ 1/${STAGES} Dependencies: installed in ${seconds(t0)}`
      : `✓ 1/${STAGES} Dependencies: up to date (node_modules matches package-lock.json; checked in ${seconds(t0)})`,
  );
}

const lock = readFileSync(join(root, 'package-lock.json'));
// Vite's own esbuild: installed with the lab, whatever else is.
const viteEntry = fileURLToPath(import.meta.resolve('vite'));
const esbuild = await import(pathToFileURL(createRequire(viteEntry).resolve('esbuild')).href);

// 2. The library, the games and the CLI: TypeScript → JavaScript, one file at a time.
await stage(
  2,
  'Library, games, server, CLI',
  'compiling TypeScript to JavaScript with esbuild (no type check: npm test does that)',
  {
    key: `compile-esbuild-${esbuild.version}`,
    inputs: [
      ...PACKAGES.flatMap((p) => [`${p}/src`, `${p}/tsconfig.build.json`]),
      'tsconfig.base.json',
    ],
    outputs: PACKAGES.map((p) => `${p}/dist/index.js`).concat('packages/cli/dist/cli.js'),
  },
  async () => {
    let count = 0;
    await Promise.all(
      PACKAGES.map((p) => {
        const src = join(root, p, 'src');
        const entryPoints = filesUnder(src).filter(
          (f) => f.endsWith('.ts') && !f.endsWith('.d.ts'),
        );
        count += entryPoints.length;
        return esbuild.build({
          entryPoints,
          outbase: src,
          outdir: join(root, p, 'dist'),
          tsconfig: join(root, p, 'tsconfig.build.json'),
          format: 'esm',
          platform: 'neutral',
          target: 'es2022',
          sourcemap: true,
          logLevel: 'warning',
        });
      }),
    );
    return `compiled ${count} files`;
  },
);

// 3. The lab: Vite, from the packages' TypeScript sources (the `source` export condition).
await stage(
  3,
  'Lab',
  'building the web page with Vite',
  {
    key: `lab-${createHash('sha256').update(lock).digest('hex')}`,
    inputs: [
      'apps/lab/index.html',
      'apps/lab/src',
      'apps/lab/public',
      'apps/lab/vite.config.ts',
      'apps/lab/package.json',
      'packages/fixedstep/src',
      'packages/fixedstep/package.json',
      'packages/games/src',
      'packages/games/package.json',
      'packages/rapier/src',
      'packages/rapier/package.json',
    ],
    outputs: ['apps/lab/dist/index.html'],
  },
  async () => {
    const { build } = await import('vite');
    await build({
      root: join(root, 'apps/lab'),
      configFile: join(root, 'apps/lab/vite.config.ts'),
      logLevel: 'warn',
      build: { reportCompressedSize: false },
    });
    return 'built';
  },
);

// 4. The server, in this process.
line(`▸ 4/${STAGES} Server: starting …`);
// npm 11 does not pass on a SIGTERM sent to it (`kill <npm's pid>`, what a process manager sends):
// npm exits and this process would go on holding the port. So, run by npm, when the process that
// started this one is gone (this process is re-parented), stop as a SIGTERM asks: drain, then exit.
// Run directly (`nohup node scripts/start.mjs &`), it outlives its shell as such a process should.
if (process.env.npm_lifecycle_event === 'start') {
  const parent = process.ppid;
  setInterval(() => {
    if (process.ppid !== parent) process.kill(process.pid, 'SIGTERM');
  }, 250).unref();
}
const { run } = await import(pathToFileURL(join(root, 'packages/cli/dist/cli.js')).href);
process.exit(await run(['serve', ...process.argv.slice(2)]));
