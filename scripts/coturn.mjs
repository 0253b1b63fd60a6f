// coturn, the TURN relay the loss harness (e2e/netem) routes WebRTC peers through so every packet
// stays on 127.0.0.1 and passes the harness's impairing UDP proxy. Found at $TURNSERVER_PATH or on
// $PATH as `turnserver`; installed from Debian's `coturn` when we are root with apt-get. Node
// built-ins only, so it runs before any dependency is installed. Installing never stops the tests:
// without coturn the harness and the transport benchmark skip, saying why.
//
//   node scripts/coturn.mjs            where it is, or why not
//   node scripts/coturn.mjs --install  the same, installing it when missing (root + apt-get)
import { spawnSync } from 'node:child_process';
import { accessSync, constants } from 'node:fs';
import { delimiter, join } from 'node:path';
import { fileURLToPath } from 'node:url';

function isExecutable(path) {
  try {
    accessSync(path, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

/** `{ ok: true, path }` for coturn's `turnserver`, or `{ ok: false, reason }`. */
export function findCoturn(env = process.env) {
  const fromEnv = env.TURNSERVER_PATH;
  if (fromEnv) {
    return isExecutable(fromEnv)
      ? { ok: true, path: fromEnv }
      : { ok: false, reason: `TURNSERVER_PATH=${fromEnv} is not an executable file` };
  }
  for (const dir of (env.PATH ?? '/usr/local/bin:/usr/bin:/bin').split(delimiter)) {
    if (dir && isExecutable(join(dir, 'turnserver')))
      return { ok: true, path: join(dir, 'turnserver') };
  }
  if (isExecutable('/usr/bin/turnserver')) return { ok: true, path: '/usr/bin/turnserver' };
  return {
    ok: false,
    reason: 'no coturn: neither TURNSERVER_PATH nor turnserver on PATH (Debian package coturn)',
  };
}

/**
 * Finds coturn and, when missing and we are root with apt-get, installs Debian's `coturn` (without
 * starting its system service: the harness starts its own on 127.0.0.1). Never throws.
 */
export function ensureCoturn({ install = true, env = process.env } = {}) {
  let found = findCoturn(env);
  if (found.ok || !install) return found;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  if (!(isRoot && isExecutable('/usr/bin/apt-get'))) {
    console.log(
      `\nNote: the loss harness will be skipped (${found.reason}).` +
        '\n  On Debian/Ubuntu: sudo apt-get install coturn',
    );
    return found;
  }
  console.log("\ncoturn is not installed: installing Debian's coturn for the loss harness…");
  const aptEnv = { ...env, DEBIAN_FRONTEND: 'noninteractive' };
  const run = (args) => {
    console.log(`\n› apt-get ${args.join(' ')}`);
    const r = spawnSync('apt-get', args, { stdio: 'inherit', env: aptEnv });
    return r.status ?? 1;
  };
  if (run(['update', '-qq']) !== 0)
    console.warn('apt-get update failed; trying the install anyway.');
  if (run(['install', '-y', '-qq', '--no-install-recommends', 'coturn']) !== 0) {
    console.warn('apt-get install coturn failed: the loss harness will be skipped.');
  }
  found = findCoturn(env);
  return found;
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const found = process.argv.includes('--install') ? ensureCoturn() : findCoturn();
  console.log(found.ok ? `coturn: ${found.path}` : `coturn MISSING: ${found.reason}`);
}
