// coturn, the TURN relay the loss harness (e2e/netem) routes WebRTC peers through so every packet
// stays on 127.0.0.1 and passes the harness's impairing UDP proxy. Found at $TURNSERVER_PATH or on
// $PATH as `turnserver`; `npm test` installs Debian's `coturn` when we are root with apt-get. Node
// built-ins only, so it runs before any dependency is installed. Without coturn the harness and
// the transport benchmark skip, saying why.
//
//   node scripts/coturn.mjs            where it is, or why not
//   node scripts/coturn.mjs --install  the same, installing it when missing (root + apt-get)
import { delimiter, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { canInstallPackages, installPackages, isExecutable } from './setup.mjs';

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

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  if (process.argv.includes('--install') && !findCoturn().ok && canInstallPackages()) {
    installPackages([{ name: 'coturn', why: 'the loss harness' }]);
  }
  const found = findCoturn();
  console.log(found.ok ? `coturn: ${found.path}` : `coturn MISSING: ${found.reason}`);
}
