// Debian's haproxy, for the test that runs three `fixedstep serve` processes behind it
// (packages/server/test/net-balancer.test.ts) and the check of deploy/haproxy/haproxy.cfg. `npm test`
// installs it with the other Debian packages when missing and we are root on a machine with
// apt-get; without it those tests are skipped and say why. Node built-ins only.
//
//   node scripts/haproxy.mjs   where haproxy is, or why not
import { fileURLToPath } from 'node:url';
import { isExecutable } from './setup.mjs';

const CANDIDATES = ['/usr/sbin/haproxy', '/usr/local/sbin/haproxy'];

/** The haproxy binary, or undefined. */
export function findHaproxy() {
  return CANDIDATES.find(isExecutable);
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const found = findHaproxy();
  console.log(found ? `haproxy found: ${found}` : 'haproxy MISSING (Debian: haproxy)');
}
