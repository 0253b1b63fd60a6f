/**
 * The measuring instruments. Everything here runs candidates side by side in one process, so
 * results are ratios under the same machine noise, never absolute thresholds.
 */
import { getHeapStatistics } from 'node:v8';
import { opsForSample, roundOrder } from './stats.js';

/** A thing to measure. */
export interface Candidate {
  /** Its label in tables. */
  readonly name: string;
  /**
   * Runs `ops` operations back to back and returns a number derived from their results, which
   * the harness keeps (the sink) so the JIT cannot discard the work. Called many times; state may
   * carry over from call to call.
   */
  run(ops: number): number;
}

/** How long to measure. */
export interface MeasurePlan {
  /** Warm-up time per candidate before the timed rounds (lets the JIT optimise), in ms. */
  readonly warmupMs: number;
  /** Length of one timed sample, in ms. */
  readonly sampleMs: number;
  /** Timed rounds; each runs one sample of every candidate, then a gc. */
  readonly rounds: number;
  /** Chunks measured per candidate by the allocation check. */
  readonly allocChunks: number;
  /** Ops per allocation chunk. */
  readonly allocOpsPerChunk: number;
}

export const FULL_PLAN: MeasurePlan = {
  warmupMs: 300,
  sampleMs: 15,
  rounds: 30,
  allocChunks: 100,
  allocOpsPerChunk: 10_000,
};

export const QUICK_PLAN: MeasurePlan = {
  warmupMs: 30,
  sampleMs: 2,
  rounds: 6,
  allocChunks: 10,
  allocOpsPerChunk: 10_000,
};

let sink = 0;

/** The sum of every candidate result so far: written to the JSON so it is observably used. */
export function sinkValue(): number {
  return sink;
}

/** Times one call of `candidate.run(ops)`, in ns. */
function timeOnce(candidate: Candidate, ops: number): number {
  const t0 = process.hrtime.bigint();
  const result = candidate.run(ops);
  const t1 = process.hrtime.bigint();
  sink += result;
  return Number(t1 - t0);
}

function fullGc(): void {
  globalThis.gc?.();
}

export interface InterleavedRun {
  /** Ops per timed sample, per candidate (calibrated in the warm-up). */
  readonly ops: number[];
  /** `samples[c][r]`: ns per op of candidate `c` in round `r`. */
  readonly samples: number[][];
}

/**
 * Warms every candidate up and calibrates its sample size, then runs `plan.rounds` rounds; each
 * round times one sample of every candidate (forwards, then backwards on the next round) and ends
 * with a gc, so garbage from one candidate is not collected on another's time.
 */
export function runInterleaved(
  candidates: readonly Candidate[],
  plan: MeasurePlan,
): InterleavedRun {
  const n = candidates.length;
  const warmupNs = plan.warmupMs * 1e6;
  const sampleNs = plan.sampleMs * 1e6;

  // Warm-up, interleaved too: double the ops per call until a call lasts a sample, and keep going
  // until each candidate has run for warmupMs. The last call's cost sets the sample size.
  const ops = new Array<number>(n).fill(16);
  const spent = new Array<number>(n).fill(0);
  const nsPerOp = new Array<number>(n).fill(0);
  for (let pass = 0; spent.some((t) => t < warmupNs); pass++) {
    for (const c of roundOrder(n, pass)) {
      if (spent[c]! >= warmupNs) continue;
      const t = timeOnce(candidates[c]!, ops[c]!);
      spent[c]! += t;
      nsPerOp[c] = t / ops[c]!;
      ops[c] = t < sampleNs ? Math.min(ops[c]! * 2, opsForSample(sampleNs, nsPerOp[c])) : ops[c]!;
    }
  }
  const sampleOps = nsPerOp.map((x) => opsForSample(sampleNs, x));

  const samples = candidates.map(() => new Array<number>(plan.rounds).fill(0));
  fullGc();
  for (let r = 0; r < plan.rounds; r++) {
    for (const c of roundOrder(n, r)) {
      samples[c]![r] = timeOnce(candidates[c]!, sampleOps[c]!) / sampleOps[c]!;
    }
    fullGc();
  }
  return { ops: sampleOps, samples };
}

export interface AllocationRun {
  /** `chunks[c][k]`: heap growth over chunk `k` of candidate `c`, in bytes. */
  readonly chunks: number[][];
  /** Heap growth over empty chunks: the readings' own overhead, in bytes. */
  readonly empty: number[];
}

/**
 * Heap growth of `chunks` chunks of `ops` ops per candidate, interleaved, each starting right after
 * a minor gc (so the young generation has room and no collection happens inside the chunk).
 * `undefined` without `--expose-gc`.
 */
export function runAllocation(
  candidates: readonly Candidate[],
  chunks: number,
  ops: number,
): AllocationRun | undefined {
  const gc = globalThis.gc;
  if (gc === undefined) return undefined;
  const used = () => getHeapStatistics().used_heap_size;

  for (let k = 0; k < 3; k++) for (const c of candidates) sink += c.run(ops);

  const out = candidates.map(() => new Array<number>(chunks).fill(0));
  const empty = new Array<number>(chunks).fill(0);
  for (let k = 0; k < chunks; k++) {
    gc({ type: 'minor' });
    const e0 = used();
    empty[k] = used() - e0;
    for (const c of roundOrder(candidates.length, k)) {
      gc({ type: 'minor' });
      const before = used();
      const result = candidates[c]!.run(ops);
      const after = used();
      sink += result;
      out[c]![k] = after - before;
    }
  }
  return { chunks: out, empty };
}
