// `npm test`'s busy-core check: the tests that start servers and browsers run again while every
// core of the machine (at least two) is kept busy by a child process spinning in a loop — a fresh
// clone's `npm test` on a loaded two-core machine. Those tests drive a simulated clock or wait on
// state, never on real-time sleeps, so they must still pass: the browser tests that play games and
// take keyboard input, and the unit tests that start servers (several processes behind HAProxy,
// idle-socket caps, state-sync rooms, the CLI's `serve`). `npm test` runs these files here only,
// not again in its quiet stages (scripts/busy-tests.mjs). With FIXEDSTEP_TEST_RESULTS set to a
// folder, each run's JSON report goes there (busy-unit.json, busy-e2e.json) for npm test's summary.
// Needs a built lab (`npm run build`) and Chromium ($CHROMIUM_PATH or /usr/bin/chromium).
//
//   node scripts/busy-check.mjs            # exit code: the first failing run's, else 0
import { spawn } from 'node:child_process';
import { availableParallelism } from 'node:os';
import { join } from 'node:path';
import { BUSY_BROWSER_TESTS, BUSY_UNIT_TESTS } from './busy-tests.mjs';
import { run } from './setup.mjs';

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
/** vitest's reporters: the default, and a JSON report named `name` when results are kept. */
function reporters(name) {
  const dir = process.env.FIXEDSTEP_TEST_RESULTS;
  return dir
    ? ['--reporter=default', '--reporter=json', `--outputFile.json=${join(dir, name)}`]
    : [];
}
const servers = run('npx', ['vitest', 'run', ...reporters('busy-unit.json'), ...BUSY_UNIT_TESTS]);
const browsers = run('npx', [
  'vitest',
  'run',
  '--config',
  'e2e/vitest.config.ts',
  ...reporters('busy-e2e.json'),
  ...BUSY_BROWSER_TESTS,
]);
stop();
process.exit(servers || browsers);
