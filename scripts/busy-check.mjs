// `npm test`'s busy-core check: the tests that start servers and browsers run again while every
// core of the machine (at least two) is kept busy by a child process spinning in a loop — a fresh
// clone's `npm test` on a loaded two-core machine. Those tests drive a simulated clock or wait on
// state, never on real-time sleeps, so they must still pass: the browser tests that play games and
// take keyboard input, and the unit tests that start servers (several processes behind HAProxy,
// idle-socket caps, state-sync rooms, the CLI's `serve`).
// Needs a built lab (`npm run build`) and Chromium ($CHROMIUM_PATH or /usr/bin/chromium).
//
//   node scripts/busy-check.mjs            # exit code: the first failing run's, else 0
import { spawn } from 'node:child_process';
import { availableParallelism } from 'node:os';
import { run } from './setup.mjs';

/** The browser tests that play: games by keyboard and bot, replays, recording, network play. */
const BROWSER = [
  'e2e/games.e2e.test.ts',
  'e2e/replays.e2e.test.ts',
  'e2e/debugging.e2e.test.ts',
  'e2e/network.e2e.test.ts',
];

/** The unit tests that start servers and talk to them over real sockets. */
const SERVERS = [
  'packages/server/test/net-balancer.test.ts',
  'packages/server/test/serve.test.ts',
  'packages/server/test/state-sync-server.test.ts',
  'packages/server/test/net-endpoint.test.ts',
  'packages/server/test/net-websocket.test.ts',
  'packages/cli/test/cli.test.ts',
];

const cores = Math.max(2, availableParallelism());
const spinners = Array.from({ length: cores }, () =>
  spawn(process.execPath, ['-e', 'for (;;) {}'], { stdio: 'ignore' }),
);
let stopped = false;
function stop() {
  if (stopped) return;
  stopped = true;
  for (const s of spinners) s.kill('SIGKILL');
}
process.on('exit', stop);
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    stop();
    process.exit(130);
  });
}

console.log(`busy-check: ${cores} spinning processes keep every core busy`);
const servers = run('npx', ['vitest', 'run', ...SERVERS]);
const browsers = run('npx', ['vitest', 'run', '--config', 'e2e/vitest.config.ts', ...BROWSER]);
stop();
process.exit(servers || browsers);
