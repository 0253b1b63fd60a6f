// Set-up shared by the two commands (`npm start`, `npm test`). Uses only Node built-ins, so it
// runs on a fresh clone before any dependency is installed.
import { spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import {
  existsSync,
  readFileSync,
  readdirSync,
  writeFileSync,
  accessSync,
  constants,
} from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..');

/** Run a command in the repo root, streaming its output. Returns the exit code. */
export function run(cmd, args, options = {}) {
  console.log(`\n› ${[cmd, ...args].join(' ')}`);
  const r = spawnSync(cmd, args, { cwd: root, stdio: 'inherit', ...options });
  if (r.error) {
    console.error(`could not run ${cmd}: ${r.error.message}`);
    return 127;
  }
  return r.status ?? 1;
}

function fail(message) {
  console.error(`\n✗ ${message}`);
  process.exit(1);
}

/** Time since `t0` (a performance.now() reading), for progress lines: `14 ms`, `3.4 s`, `21 s`. */
export function seconds(t0) {
  const ms = performance.now() - t0;
  if (ms < 1000) return `${Math.round(ms)} ms`;
  return ms < 10_000 ? `${(ms / 1000).toFixed(1)} s` : `${Math.round(ms / 1000)} s`;
}

/**
 * What `npm start` needs installed: the server's and the lab's dependencies (ws, uplot, Vite and
 * its esbuild), not the test and benchmark tools. `npm ci` with these workspace filters installs
 * 23 packages instead of ~300.
 */
const SERVE_WORKSPACES = ['packages/server', 'packages/cli', 'apps/lab'];

/**
 * Whether node_modules holds every package of package-lock.json at its locked version, by npm's
 * own record of what it installed (node_modules/.package-lock.json): a full `npm ci` or
 * `npm install` someone ran by hand. Optional packages (other platforms' binaries) and the
 * workspace links are not required.
 */
function fullInstallMatches(lock) {
  const hidden = join(root, 'node_modules', '.package-lock.json');
  if (!existsSync(hidden)) return false;
  let installed;
  try {
    installed = JSON.parse(readFileSync(hidden, 'utf8')).packages ?? {};
  } catch {
    return false;
  }
  for (const [key, entry] of Object.entries(lock.packages ?? {})) {
    if (!key.startsWith('node_modules/') && !key.includes('/node_modules/')) continue;
    if (entry.optional || entry.link) continue;
    if (installed[key]?.version !== entry.version) return false;
  }
  return true;
}

/**
 * Installs the exact dependencies of package-lock.json with `npm ci`, unless node_modules already
 * has them. `scope` is `'all'` (`npm test`: every workspace and tool) or `'serve'` (`npm start`:
 * only what building and serving the lab needs; a full install satisfies it too). What was
 * installed, for which lock file, is kept in node_modules/.fixedstep-install. `before(command)`
 * is called with the npm command line just before it runs. Returns true when it ran `npm ci`,
 * false when node_modules was already right.
 */
export function ensureDependencies(scope = 'all', before = () => undefined) {
  const lockText = readFileSync(join(root, 'package-lock.json'));
  const want = createHash('sha256').update(lockText).digest('hex');
  const stampFile = join(root, 'node_modules', '.fixedstep-install');
  let have;
  try {
    have = JSON.parse(readFileSync(stampFile, 'utf8'));
  } catch {
    have = undefined;
  }
  if (have?.lock === want && (have.scope === 'all' || scope === 'serve')) return false;
  if (fullInstallMatches(JSON.parse(lockText.toString('utf8')))) {
    writeFileSync(stampFile, JSON.stringify({ lock: want, scope: 'all' }));
    return false;
  }
  const filters = scope === 'serve' ? SERVE_WORKSPACES.flatMap((w) => ['--workspace', w]) : [];
  const args = ['ci', '--no-audit', '--no-fund', ...filters];
  before(`npm ${args.join(' ')}`);
  if (run('npm', args) !== 0) fail('npm ci failed: see the output above.');
  writeFileSync(stampFile, JSON.stringify({ lock: want, scope }));
  return true;
}

export function isExecutable(path) {
  try {
    accessSync(path, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

/** Whether Debian packages can be installed here: we are root on a machine with apt-get. */
export function canInstallPackages() {
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  return isRoot && isExecutable('/usr/bin/apt-get');
}

/**
 * Installs Debian packages in one `apt-get update` and one `apt-get install` (each update costs
 * tens of seconds: everything the tests need goes in one go). `wanted` lists `{ name, why }`.
 * Returns true when apt-get succeeded; never exits (a caller decides what a missing tool means).
 */
export function installPackages(wanted) {
  const names = [...new Set(wanted.map((w) => w.name))];
  if (names.length === 0) return true;
  console.log('\nInstalling Debian packages the tests need:');
  for (const w of wanted) console.log(`  ${w.name.padEnd(18)} ${w.why}`);
  const env = { ...process.env, DEBIAN_FRONTEND: 'noninteractive' };
  if (run('apt-get', ['update', '-qq'], { env }) !== 0) {
    console.warn('apt-get update failed; trying the install anyway.');
  }
  const ok = run('apt-get', ['install', '-y', '-qq', '--no-install-recommends', ...names], { env });
  if (ok !== 0) console.warn(`apt-get install ${names.join(' ')} failed.`);
  return ok === 0;
}

/** Chromium for the browser tests: $CHROMIUM_PATH, else /usr/bin/chromium; undefined if neither. */
export function findChromium() {
  const fromEnv = process.env.CHROMIUM_PATH;
  if (fromEnv) {
    if (!isExecutable(fromEnv)) fail(`CHROMIUM_PATH=${fromEnv} is not an executable file.`);
    return fromEnv;
  }
  return isExecutable('/usr/bin/chromium') ? '/usr/bin/chromium' : undefined;
}

/** Chromium's path (see {@link findChromium}), or stop with a message naming what to install. */
export function ensureChromium() {
  const found = findChromium();
  if (found) return found;
  fail(
    'The browser tests need Chromium, and none was found.\n' +
      '  On Debian/Ubuntu: sudo apt-get install chromium (or run npm test as root: it installs it)\n' +
      '  Or point at any Chromium/Chrome binary: CHROMIUM_PATH=/path/to/chromium npm test',
  );
}

/** The bin folder of Debian's PostgreSQL (initdb, pg_ctl, postgres), or undefined. */
function postgresBin() {
  const base = '/usr/lib/postgresql';
  if (!existsSync(base)) return undefined;
  const versions = readdirSync(base)
    .filter((v) => /^\d+$/.test(v))
    .sort((a, b) => Number(b) - Number(a));
  for (const v of versions) {
    const bin = join(base, v, 'bin');
    if (isExecutable(join(bin, 'initdb')) && isExecutable(join(bin, 'pg_ctl'))) return bin;
  }
  return undefined;
}

/**
 * PostgreSQL for the tests of server processes sharing one database: the bin folder of Debian's
 * `postgresql` (the tests start their own cluster in a scratch folder, as the `postgres` user, on a
 * free port — nothing is started here). Returns `{ bin }`, or `{ reason }` saying why there is none
 * (those tests are then skipped with it).
 */
export function findPostgres() {
  const bin = postgresBin();
  return bin
    ? { bin }
    : {
        reason:
          "PostgreSQL is not installed (install Debian's postgresql, or run npm test as root: it installs it)",
      };
}
