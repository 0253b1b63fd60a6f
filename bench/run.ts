/**
 * The benchmark runner: `npm run bench -- [suite …] [--quick] [--json FILE] [--list]`.
 *
 * Finds the suites in `bench/suites/*.ts`, runs the chosen ones one after another, prints a table
 * per measurement and optionally writes everything as JSON. Candidates are always measured side
 * by side in one run, so read the ratios, not the absolute times.
 */
import { mkdirSync, readdirSync, writeFileSync } from 'node:fs';
import { cpus } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import { parseArgs, selectSuites, USAGE } from './lib/args.js';
import { formatTable } from './lib/format.js';
import { FULL_PLAN, QUICK_PLAN, sinkValue } from './lib/measure.js';
import type { Section, SuiteReport } from './lib/report.js';
import { createContext, isSuite, type Suite } from './lib/suite.js';

const SUITES_DIR = join(dirname(fileURLToPath(import.meta.url)), 'suites');

function fail(message: string, code = 2): never {
  console.error(`bench: ${message}\n\n${USAGE}`);
  process.exit(code);
}

/** Imports every `bench/suites/*.ts` (sorted by file name) and checks it exports a suite. */
async function loadSuites(): Promise<Suite[]> {
  const files = readdirSync(SUITES_DIR)
    .filter((f) => f.endsWith('.ts') && !f.endsWith('.d.ts') && !f.startsWith('_'))
    .sort((a, b) => a.localeCompare(b));
  const suites: Suite[] = [];
  for (const file of files) {
    const mod = (await import(pathToFileURL(join(SUITES_DIR, file)).href)) as { default?: unknown };
    const suite = mod.default;
    if (!isSuite(suite)) {
      throw new Error(`bench/suites/${file}: the default export must be defineSuite({ … })`);
    }
    if (suites.some((s) => s.name === suite.name)) {
      throw new Error(`bench/suites/${file}: a second suite named ${suite.name}`);
    }
    suites.push(suite);
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

  const suites = await loadSuites();
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
  for (const name of selected.names) {
    const suite = suites.find((s) => s.name === name)!;
    console.log(`\n== ${suite.name}: ${suite.description}\n`);
    const sections: Section[] = [];
    const ctx = createContext(options.quick, plan, sections, (text) => {
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
    reports.push({
      name: suite.name,
      description: suite.description,
      ok: error === undefined,
      ...(error === undefined ? {} : { error }),
      seconds,
      sections,
    });
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
      sink: sinkValue(),
      suites: reports,
    };
    mkdirSync(dirname(options.json), { recursive: true });
    writeFileSync(options.json, `${JSON.stringify(result, null, 2)}\n`);
    console.log(`results written to ${options.json}`);
  }
  if (failed.length > 0) process.exitCode = 1;
}

await main();
