// Set-up shared by the two commands (`npm start`, `npm test`). Uses only Node built-ins, so it
// runs on a fresh clone before any dependency is installed.
import { spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { existsSync, readFileSync, writeFileSync, accessSync, constants } from 'node:fs';
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

/** Install the exact dependencies of package-lock.json, unless node_modules already has them. */
export function ensureDependencies() {
  const lock = join(root, 'package-lock.json');
  const stamp = join(root, 'node_modules', '.fixedstep-lock-hash');
  const want = createHash('sha256').update(readFileSync(lock)).digest('hex');
  if (existsSync(stamp) && readFileSync(stamp, 'utf8') === want) return;
  if (run('npm', ['ci', '--no-audit', '--no-fund']) !== 0)
    fail('npm ci failed: see the output above.');
  writeFileSync(stamp, want);
}

function isExecutable(path) {
  try {
    accessSync(path, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

/**
 * Find Chromium for the browser tests: $CHROMIUM_PATH, else /usr/bin/chromium, else install
 * Debian's `chromium` when we are root on a machine with apt-get. Returns its path.
 */
export function ensureChromium() {
  const fromEnv = process.env.CHROMIUM_PATH;
  if (fromEnv) {
    if (!isExecutable(fromEnv)) fail(`CHROMIUM_PATH=${fromEnv} is not an executable file.`);
    return fromEnv;
  }
  const system = '/usr/bin/chromium';
  if (isExecutable(system)) return system;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  if (isRoot && isExecutable('/usr/bin/apt-get')) {
    console.log("\nChromium is not installed: installing Debian's chromium for the browser tests…");
    const env = { ...process.env, DEBIAN_FRONTEND: 'noninteractive' };
    if (run('apt-get', ['update', '-qq'], { env }) !== 0) fail('apt-get update failed.');
    if (
      run('apt-get', ['install', '-y', '-qq', '--no-install-recommends', 'chromium'], { env }) !== 0
    ) {
      fail('apt-get install chromium failed.');
    }
    if (isExecutable(system)) return system;
  }
  fail(
    'The browser tests need Chromium, and none was found.\n' +
      '  On Debian/Ubuntu: sudo apt-get install chromium\n' +
      '  Or point at any Chromium/Chrome binary: CHROMIUM_PATH=/path/to/chromium npm test',
  );
}

/** Build the library, the CLI and the lab. */
export function build() {
  if (run('npm', ['run', 'build']) !== 0) fail('the build failed: see the output above.');
}
