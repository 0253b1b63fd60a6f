// `npm test`: every test. Installs what the tests need (dependencies; Debian's chromium, and
// firefox-esr, webkit2gtk-driver and xvfb for the determinism suite, postgresql for the
// store test, haproxy for the balancer test and coturn for the loss harness, when absent and we are root), then: format, lint, typecheck, unit tests, build, the e2e tests (browser, packed
// packages, API reference), and a smoke run of the benchmarks. Runs every stage even when one fails, then prints a summary.
import { existsSync, mkdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import {
  ensureChromium,
  ensureDependencies,
  ensurePostgres,
  root,
  run,
  seconds,
} from './setup.mjs';

ensureDependencies();
const chromium = ensureChromium();
// Firefox ESR and WebKitGTK for the cross-engine determinism suite (skipped, with the reason, when absent).
(await import('./engines.mjs')).ensureEngines();
// PostgreSQL for the two-process store test (skipped, with the reason, when absent).
const postgres = ensurePostgres();
// HAProxy for the load-balancer tests (skipped, with the reason, when absent).
(await import('./haproxy.mjs')).ensureHaproxy();
const results = join(root, 'artifacts', 'test-results');
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
    ],
  ],
  ['browser tests, busy cores', 'node', ['scripts/busy-check.mjs']],
  ['benchmarks (smoke)', 'npm', ['run', 'bench', '--', '--quick']],
];

const env = {
  ...process.env,
  CHROMIUM_PATH: chromium,
  ...(postgres.bin ? { FIXEDSTEP_PG_BIN: postgres.bin } : { FIXEDSTEP_PG_SKIP: postgres.reason }),
};
const failed = [];
for (const [i, [name, cmd, args]] of stages.entries()) {
  const n = `${i + 1}/${stages.length}`;
  if (name === 'browser, package and API reference tests' && failed.includes('build')) {
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
for (const f of ['unit.json', 'e2e.json']) {
  const p = join(results, f);
  if (!existsSync(p)) continue;
  const r = JSON.parse(readFileSync(p, 'utf8'));
  passed += r.numPassedTests ?? 0;
  failedTests += r.numFailedTests ?? 0;
  skipped += (r.numPendingTests ?? 0) + (r.numTodoTests ?? 0);
}
console.log(
  `\nstages: ${stages.length - failed.length} of ${stages.length} passed${failed.length ? ` (failed: ${failed.join(', ')})` : ''}`,
);
console.log(
  `${passed} passed, ${failedTests + (failed.length && failedTests === 0 ? failed.length : 0)} failed, ${skipped} skipped`,
);
process.exit(failed.length === 0 ? 0 : 1);
