// `npm test`: every test. Installs what the tests need — dependencies (`npm ci`), and the Debian
// packages that are missing, in one apt-get run when we are root: chromium for the browser tests,
// firefox-esr, webkit2gtk-driver, xvfb and xauth for the determinism suite, postgresql for the store
// tests, haproxy for the balancer tests, coturn for the loss harness. Then: format, lint, typecheck,
// unit tests, build, the e2e tests (browser, packed packages, API reference), the tests that start
// servers or play again on busy cores, and a smoke run of the benchmarks. Runs every stage even
// when one fails, then prints a summary naming each failed test.
import { existsSync, mkdirSync, readFileSync, rmSync } from 'node:fs';
import { availableParallelism } from 'node:os';
import { join, relative } from 'node:path';
import { BUSY_BROWSER_TESTS, BUSY_UNIT_TESTS } from './busy-tests.mjs';
import { findCoturn } from './coturn.mjs';
import { missingEnginePackages } from './engines.mjs';
import { findHaproxy } from './haproxy.mjs';
import {
  canInstallPackages,
  ensureChromium,
  ensureDependencies,
  findChromium,
  findPostgres,
  installPackages,
  root,
  run,
  seconds,
} from './setup.mjs';

ensureDependencies();
const wanted = [
  ...(findChromium() ? [] : [{ name: 'chromium', why: 'the browser tests' }]),
  ...missingEnginePackages(),
  ...('bin' in findPostgres() ? [] : [{ name: 'postgresql', why: 'the store tests' }]),
  ...(findHaproxy() ? [] : [{ name: 'haproxy', why: 'the load-balancer tests' }]),
  ...(findCoturn().ok ? [] : [{ name: 'coturn', why: 'the loss harness (WebRTC through TURN)' }]),
];
if (wanted.length > 0) {
  if (canInstallPackages()) installPackages(wanted);
  else {
    console.log(
      `\nNote: not root (or no apt-get): tests that need ${wanted.map((w) => w.name).join(', ')} ` +
        'are skipped, saying why (Chromium is required).',
    );
  }
}
const chromium = ensureChromium();
const postgres = findPostgres();
const results = join(root, 'artifacts', 'test-results');
rmSync(results, { recursive: true, force: true }); // no report of an earlier run counts
mkdirSync(results, { recursive: true });

const stages = [
  ['format', 'npx', ['prettier', '--check', '.']],
  ['lint', 'npx', ['eslint', '--max-warnings', '0', '.']],
  ['typecheck', 'npx', ['tsc', '-p', 'tsconfig.json', '--noEmit']],
  [
    'unit tests',
    'npx',
    [
      'vitest',
      'run',
      '--reporter=default',
      '--reporter=json',
      `--outputFile.json=${join(results, 'unit.json')}`,
      // Vitest's default is one worker fewer than the cores — one on a 2-core machine, where the
      // stage took 254 s; two took 148 s. The tests that start servers and browsers run in the
      // busy-core stage, not here.
      '--maxWorkers',
      String(Math.max(2, availableParallelism() - 1)),
      ...BUSY_UNIT_TESTS.flatMap((f) => ['--exclude', f]),
    ],
  ],
  ['build', 'npm', ['run', 'build']],
  [
    'browser, package and API reference tests',
    'npx',
    [
      'vitest',
      'run',
      '--config',
      'e2e/vitest.config.ts',
      '--reporter=default',
      '--reporter=json',
      `--outputFile.json=${join(results, 'e2e.json')}`,
      ...BUSY_BROWSER_TESTS.flatMap((f) => ['--exclude', f]),
    ],
  ],
  ['server and browser tests, busy cores', 'node', ['scripts/busy-check.mjs']],
  ['benchmarks (smoke)', 'npm', ['run', 'bench', '--', '--quick']],
];

const env = {
  ...process.env,
  CHROMIUM_PATH: chromium,
  FIXEDSTEP_TEST_RESULTS: results,
  ...(postgres.bin ? { FIXEDSTEP_PG_BIN: postgres.bin } : { FIXEDSTEP_PG_SKIP: postgres.reason }),
};
const failed = [];
for (const [i, [name, cmd, args]] of stages.entries()) {
  const n = `${i + 1}/${stages.length}`;
  if (
    name !== 'benchmarks (smoke)' &&
    i > stages.findIndex(([s]) => s === 'build') &&
    failed.includes('build')
  ) {
    console.log(`\n✗ ${n} ${name}: not run (the build failed)`);
    failed.push(name);
    continue;
  }
  const t0 = performance.now();
  console.log(`\n▸ ${n} ${name}`);
  const ok = run(cmd, args, { env }) === 0;
  console.log(`${ok ? '✓' : '✗'} ${n} ${name}: ${ok ? 'passed' : 'FAILED'} in ${seconds(t0)}`);
  if (!ok) failed.push(name);
}

let passed = 0;
let failedTests = 0;
let skipped = 0;
for (const f of ['unit.json', 'e2e.json', 'busy-unit.json', 'busy-e2e.json']) {
  const p = join(results, f);
  if (!existsSync(p)) continue;
  const r = JSON.parse(readFileSync(p, 'utf8'));
  passed += r.numPassedTests ?? 0;
  failedTests += r.numFailedTests ?? 0;
  skipped += (r.numPendingTests ?? 0) + (r.numTodoTests ?? 0);
  // CI keeps only the end of the output: name each failed test here, where it is read.
  for (const file of r.testResults ?? []) {
    const name = relative(root, file.name);
    const failedHere = (file.assertionResults ?? []).filter((a) => a.status === 'failed');
    if (failedHere.length === 0 && file.status === 'failed') {
      console.log(`✗ ${name}: ${(file.message ?? 'the file failed to run').split('\n')[0]}`);
    }
    for (const a of failedHere) {
      console.log(`✗ ${name} > ${a.fullName}: ${(a.failureMessages?.[0] ?? '').split('\n')[0]}`);
    }
  }
}
console.log(
  `\nstages: ${stages.length - failed.length} of ${stages.length} passed${failed.length ? ` (failed: ${failed.join(', ')})` : ''}`,
);
console.log(
  `${passed} passed, ${failedTests + (failed.length && failedTests === 0 ? failed.length : 0)} failed, ${skipped} skipped`,
);
process.exit(failed.length === 0 ? 0 : 1);
