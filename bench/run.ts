/**
 * The benchmark runner: `npm run bench -- [suite …] [--quick] [--json FILE] [--list]`.
 *
 * Finds the suites in `bench/suites/*.ts`, runs the chosen ones one after another, prints a table
 * per measurement and optionally writes everything as JSON. Candidates are always measured side
 * by side in one run, so read the ratios, not the absolute times.
 *
 * Each suite runs in a process of its own (this file again, with the same Node options), so what
 * one suite measures does not depend on which ran before it: the JIT's state — what is compiled,
 * inlined, deoptimized — carries over within a process and changes timings and, above all,
 * allocation figures. The child prints its sections as they come and hands its report back over
 * the IPC channel; the output and the JSON are those of one process.
 */
import { spawn } from 'node:child_process';
import { mkdirSync, readdirSync, writeFileSync } from 'node:fs';
import { cpus } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { parseArgs, selectSuites, USAGE } from './lib/args.js';
import { formatTable } from './lib/format.js';
import { FULL_PLAN, QUICK_PLAN, sinkValue } from './lib/measure.js';
import type { Section, SuiteReport } from './lib/report.js';
import { createContext, isSuite, type Suite } from './lib/suite.js';

/** Where the suites are; `FIXEDSTEP_BENCH_SUITES_DIR` points elsewhere (the runner's own tests). */
const SUITES_DIR =
  process.env.FIXEDSTEP_BENCH_SUITES_DIR ?? join(dirname(fileURLToPath(import.meta.url)), 'suites');

/** Set (to a suite's name) in a child process: run just that suite and report to the parent. */
const CHILD_ENV = 'FIXEDSTEP_BENCH_SUITE';
/**
 * Set in a child process to the file of its suite: the child imports that file alone. Importing
 * every suite would load what the others need (e.g. `ws` for the relay's): with `ws` merely
 * imported, the arena games' re-simulation ran 15–20 % slower in CPU time on Node 20 — a
 * number about the process, not the game.
 */
const CHILD_FILE_ENV = 'FIXEDSTEP_BENCH_SUITE_FILE';

/** What a child process sends back: its suite's report and its sink. */
interface ChildReport {
  readonly report: SuiteReport;
  readonly sink: number;
}

function fail(message: string, code = 2): never {
  console.error(`bench: ${message}\n\n${USAGE}`);
  process.exit(code);
}

/** The suite a `bench/suites/*.ts` file exports (checked). */
async function importSuite(file: string): Promise<Suite> {
  const mod = (await import(pathToFileURL(join(SUITES_DIR, file)).href)) as { default?: unknown };
  const suite = mod.default;
  if (!isSuite(suite)) {
    throw new Error(`bench/suites/${file}: the default export must be defineSuite({ … })`);
  }
  return suite;
}

/** Imports every `bench/suites/*.ts` (sorted by file name); the suites and their files. */
async function loadSuites(): Promise<Map<Suite, string>> {
  const files = readdirSync(SUITES_DIR)
    .filter((f) => f.endsWith('.ts') && !f.endsWith('.d.ts') && !f.startsWith('_'))
    .sort((a, b) => a.localeCompare(b));
  const suites = new Map<Suite, string>();
  for (const file of files) {
    const suite = await importSuite(file);
    if ([...suites.keys()].some((s) => s.name === suite.name)) {
      throw new Error(`bench/suites/${file}: a second suite named ${suite.name}`);
    }
    suites.set(suite, file);
  }
  return suites;
}

async function main(): Promise<void> {
  const parsed = parseArgs(process.argv.slice(2));
  if (!parsed.ok) fail(parsed.error);
  const options = parsed.options;
  if (options.help) {
    console.log(USAGE);
    return;
  }

  const files = await loadSuites();
  const suites = [...files.keys()];
  if (options.list) {
    console.log(
      formatTable(
        ['suite', 'description'],
        suites.map((s) => [s.name, s.description]),
        ['left', 'left'],
        '',
      ),
    );
    return;
  }
  const selected = selectSuites(
    suites.map((s) => s.name),
    options.suites,
  );
  if (!selected.ok) fail(selected.error);

  const plan = options.quick ? QUICK_PLAN : FULL_PLAN;
  const cpu = cpus();
  const machine = `${cpu[0]?.model.trim() ?? 'unknown CPU'} × ${cpu.length}`;
  console.log(
    `fixedstep bench — node ${process.version}, V8 ${process.versions.v8}, ${machine}` +
      (options.quick ? ' — QUICK run: rough numbers' : ''),
  );
  if (globalThis.gc === undefined) {
    console.log('warning: no --expose-gc: no gc between rounds, no allocation checks');
  }

  const started = process.hrtime.bigint();
  const reports: SuiteReport[] = [];
  let sink = 0;
  for (const name of selected.names) {
    const suite = suites.find((s) => s.name === name)!;
    console.log(`\n== ${suite.name}: ${suite.description}\n`);
    const child = await runInChild(suite, files.get(suite)!, options.quick);
    reports.push(child.report);
    sink += child.sink;
  }
  const seconds = Number(process.hrtime.bigint() - started) / 1e9;
  const failed = reports.filter((r) => !r.ok).map((r) => r.name);
  console.log(
    `${reports.length} suite(s) in ${seconds.toFixed(1)} s` +
      (failed.length > 0 ? `; FAILED: ${failed.join(', ')}` : ''),
  );

  if (options.json !== undefined) {
    const result = {
      format: 'fixedstep-bench/1',
      date: new Date().toISOString(),
      node: process.version,
      v8: process.versions.v8,
      platform: `${process.platform}-${process.arch}`,
      cpu: machine,
      quick: options.quick,
      gc: globalThis.gc !== undefined,
      plan,
      sink,
      suites: reports,
    };
    mkdirSync(dirname(options.json), { recursive: true });
    writeFileSync(options.json, `${JSON.stringify(result, null, 2)}\n`);
    console.log(`results written to ${options.json}`);
  }
  if (failed.length > 0) process.exitCode = 1;
}

/** Runs one suite, printing its sections; its report. */
async function runSuite(suite: Suite, quick: boolean): Promise<SuiteReport> {
  const sections: Section[] = [];
  const ctx = createContext(quick, quick ? QUICK_PLAN : FULL_PLAN, sections, (text) => {
    console.log(`${text}\n`);
  });
  const t0 = process.hrtime.bigint();
  let error: string | undefined;
  try {
    await suite.run(ctx);
  } catch (e) {
    error = e instanceof Error ? (e.stack ?? e.message) : String(e);
    console.error(`suite ${suite.name} failed: ${error}\n`);
  }
  const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
  return {
    name: suite.name,
    description: suite.description,
    ok: error === undefined,
    ...(error === undefined ? {} : { error }),
    seconds,
    sections,
  };
}

/**
 * Runs `suite` in a fresh process: this file, the same Node options (`--expose-gc`, the loader),
 * the suite's name in the environment. Its output goes straight to ours; its report comes back
 * over IPC. A child that dies without reporting is a failed suite, with its exit code as the error.
 */
function runInChild(suite: Suite, file: string, quick: boolean): Promise<ChildReport> {
  return new Promise((resolve) => {
    const child = spawn(
      process.execPath,
      [...process.execArgv, fileURLToPath(import.meta.url), ...(quick ? ['--quick'] : [])],
      {
        env: { ...process.env, [CHILD_ENV]: suite.name, [CHILD_FILE_ENV]: file },
        stdio: ['ignore', 'inherit', 'inherit', 'ipc'],
      },
    );
    let reported: ChildReport | undefined;
    child.on('message', (message) => {
      reported = message as ChildReport;
    });
    const failed = (why: string): ChildReport => {
      console.error(`suite ${suite.name} failed: ${why}\n`);
      return {
        report: {
          name: suite.name,
          description: suite.description,
          ok: false,
          error: why,
          seconds: 0,
          sections: [],
        },
        sink: 0,
      };
    };
    child.on('error', (e) => {
      resolve(failed(`could not start its process: ${e.message}`));
    });
    child.on('exit', (code, signal) => {
      resolve(
        reported ??
          failed(`its process exited (${signal ?? `code ${String(code)}`}) without a report`),
      );
    });
  });
}

/** In a child process: run the one suite named in the environment and send the report back. */
async function child(name: string, file: string): Promise<void> {
  const parsed = parseArgs(process.argv.slice(2));
  const quick = parsed.ok && parsed.options.quick;
  const suite = await importSuite(file);
  if (suite.name !== name) throw new Error(`bench: ${file} holds ${suite.name}, not ${name}`);
  const report = await runSuite(suite, quick);
  const message: ChildReport = { report, sink: sinkValue() };
  await new Promise<void>((resolve, reject) => {
    process.send!(message, (e: Error | null) => {
      if (e) reject(e);
      else resolve();
    });
  });
  process.disconnect();
  // A suite must close what it opened. If something still holds the process (a peer library's
  // timer, a socket), name it and exit, so `npm run bench` and `npm test` never wait on it.
  setTimeout(() => {
    const held = lingering();
    console.error(
      `bench: suite ${name} still alive ${LINGER_MS / 1000} s after its report (holding: ${held || 'nothing Node names'}); ending it`,
    );
    process.exit(0);
  }, LINGER_MS).unref();
}

/** How long a suite's process may live after its report before it is ended. */
const LINGER_MS = 3000;

/** What keeps this process alive: resource kinds and counts, e.g. "TCPSocketWrap × 2". */
function lingering(): string {
  const counts = new Map<string, number>();
  for (const kind of process.getActiveResourcesInfo()) {
    counts.set(kind, (counts.get(kind) ?? 0) + 1);
  }
  // (Our own timer is unref'd: Node does not list it.)
  return [...counts].map(([kind, n]) => `${kind} × ${n}`).join(', ');
}

const childSuite = process.env[CHILD_ENV];
const childFile = process.env[CHILD_FILE_ENV];
if (childSuite !== undefined && childFile !== undefined && process.send !== undefined)
  await child(childSuite, childFile);
else await main();
