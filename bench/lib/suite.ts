/**
 * What a benchmark suite is, and the context it runs in. A suite is a module in `bench/suites/`
 * whose default export is `defineSuite({ name, description, run })`; `run.ts` finds it by itself.
 */
import { runAllocation, runInterleaved, type Candidate, type MeasurePlan } from './measure.js';
import {
  renderSection,
  type AllocationSection,
  type ComparisonSection,
  type Section,
} from './report.js';
import { bytesPerOp, summarize } from './stats.js';

export type { Candidate, MeasurePlan } from './measure.js';

export interface Suite {
  /** What to type after `npm run bench --`; by convention the file name. */
  readonly name: string;
  /** One line: what is measured against what. */
  readonly description: string;
  run(ctx: SuiteContext): void | Promise<void>;
}

export function defineSuite(suite: Suite): Suite {
  return suite;
}

export function isSuite(value: unknown): value is Suite {
  if (typeof value !== 'object' || value === null) return false;
  const s = value as Record<string, unknown>;
  return (
    typeof s.name === 'string' &&
    s.name !== '' &&
    typeof s.description === 'string' &&
    typeof s.run === 'function'
  );
}

export interface CompareOptions {
  /** What one op is, for the tables (`frame`, `step` …). Default `op`. */
  readonly unit?: string;
  /** Index of the baseline among the candidates. Default 0. */
  readonly baseline?: number;
}

/** What a suite can do. Every method prints its result and records it for `--json`. */
export interface SuiteContext {
  /** A `--quick` smoke run: suites should also shrink their own workloads. */
  readonly quick: boolean;
  readonly plan: MeasurePlan;
  /** Times the candidates side by side, interleaved; reports ns/op and ratios to the baseline. */
  compare(
    title: string,
    candidates: readonly Candidate[],
    options?: CompareOptions,
  ): ComparisonSection;
  /** Measures the heap allocated per op by each candidate. */
  allocation(
    title: string,
    candidates: readonly Candidate[],
    options?: { readonly unit?: string },
  ): AllocationSection;
  /** Prints and records a free-form table. */
  table(title: string, header: readonly string[], rows: readonly (readonly string[])[]): void;
  /** Prints and records a line of text. */
  note(text: string): void;
}

/** A context whose sections go to `sections` and, rendered, to `print`. */
export function createContext(
  quick: boolean,
  plan: MeasurePlan,
  sections: Section[],
  print: (text: string) => void,
): SuiteContext {
  const emit = <S extends Section>(section: S): S => {
    sections.push(section);
    print(renderSection(section));
    return section;
  };
  return {
    quick,
    plan,
    compare(title, candidates, options = {}) {
      const baseline = options.baseline ?? 0;
      if (candidates[baseline] === undefined) {
        throw new RangeError(`compare: no baseline candidate ${baseline}`);
      }
      const names = candidates.map((c) => c.name);
      const run = runInterleaved(candidates, plan);
      const summary = summarize(names, run.samples, baseline);
      return emit<ComparisonSection>({
        kind: 'comparison',
        title,
        unit: options.unit ?? 'op',
        baseline: names[baseline]!,
        rounds: plan.rounds,
        sampleMs: plan.sampleMs,
        candidates: summary.map((s, c) => ({
          name: s.name,
          opsPerSample: run.ops[c]!,
          ns: s.ns,
          ...(s.ratio ? { ratio: s.ratio } : {}),
          samplesNs: run.samples[c]!,
        })),
      });
    },
    allocation(title, candidates, options = {}) {
      const ops = plan.allocOpsPerChunk;
      const run = runAllocation(candidates, plan.allocChunks, ops);
      const base = {
        kind: 'allocation',
        title,
        unit: options.unit ?? 'op',
        chunks: plan.allocChunks,
        opsPerChunk: ops,
      } as const;
      if (run === undefined) {
        return emit<AllocationSection>({
          ...base,
          skipped: 'needs node --expose-gc (npm run bench passes it)',
          candidates: [],
        });
      }
      return emit<AllocationSection>({
        ...base,
        candidates: candidates.map((c, i) => ({
          name: c.name,
          bytes: bytesPerOp(run.chunks[i]!, run.empty, ops),
        })),
      });
    },
    table(title, header, rows) {
      emit({ kind: 'table', title, header, rows });
    },
    note(text) {
      emit({ kind: 'note', text });
    },
  };
}

/** A plan that measures next to nothing, allocations included: for tests of a suite's report. */
export const TINY_PLAN: MeasurePlan = {
  warmupMs: 2,
  sampleMs: 1,
  rounds: 2,
  allocChunks: 2,
  allocOpsPerChunk: 1000,
};

/**
 * A quick run of `suite` on `plan`, printing nothing (for its tests, which check the report's
 * shape, not its numbers): what it reported, and its comparisons among that.
 */
export async function quickRun(
  suite: Suite,
  plan = TINY_PLAN,
): Promise<{ sections: Section[]; comparisons: ComparisonSection[] }> {
  const sections: Section[] = [];
  await suite.run(createContext(true, plan, sections, () => undefined));
  const comparisons = sections.filter((s): s is ComparisonSection => s.kind === 'comparison');
  return { sections, comparisons };
}
