// Debian's haproxy, for the test that runs three `fixedstep serve` processes behind it
// (packages/cli/test/net-balancer.test.ts) and the check of deploy/haproxy/haproxy.cfg. Installed
// when missing and we are root on a machine with apt-get, like the browsers; never stops the
// tests: without it those tests are skipped and say why. Node built-ins only.
//
//   node scripts/haproxy.mjs   where haproxy is, or why not
import { spawnSync } from 'node:child_process';
import { accessSync, constants } from 'node:fs';
import { fileURLToPath } from 'node:url';

const CANDIDATES = ['/usr/sbin/haproxy', '/usr/local/sbin/haproxy'];

function isExecutable(path) {
  try {
    accessSync(path, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

/** The haproxy binary, or undefined. */
export function findHaproxy() {
  return CANDIDATES.find(isExecutable);
}

/** Finds haproxy, installing Debian's package when missing (root + apt-get). Never throws. */
export function ensureHaproxy() {
  const found = findHaproxy();
  if (found) return found;
  const isRoot = typeof process.getuid === 'function' && process.getuid() === 0;
  if (!isRoot || !isExecutable('/usr/bin/apt-get')) {
    console.log(
      '\nNote: the load-balancer tests will be skipped: no haproxy.\n' +
        '  On Debian/Ubuntu: sudo apt-get install haproxy',
    );
    return undefined;
  }
  console.log(
    "\nhaproxy is not installed: installing Debian's haproxy for the load-balancer tests…",
  );
  const env = { ...process.env, DEBIAN_FRONTEND: 'noninteractive' };
  const apt = (args) => spawnSync('apt-get', args, { stdio: 'inherit', env }).status;
  if (apt(['update', '-qq']) !== 0)
    console.warn('apt-get update failed; trying the install anyway.');
  if (apt(['install', '-y', '-qq', '--no-install-recommends', 'haproxy']) !== 0) {
    console.warn('apt-get install haproxy failed: the load-balancer tests will be skipped.');
  }
  return findHaproxy();
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const found = findHaproxy();
  console.log(found ? `haproxy found: ${found}` : 'haproxy MISSING (Debian: haproxy)');
}
