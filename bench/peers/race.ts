/**
 * Interleaved rounds over contestants that time themselves (in other processes: the C program, a
 * fresh node, one engine per process), so what is measured is the work, not the messaging. The
 * same plan as the in-process harness (lib/measure.ts): warm-up, then `plan.rounds` rounds, each
 * timing every contestant once, forwards then backwards on alternate rounds, then a gc.
 */
import type { MeasurePlan } from '../lib/measure.js';
import { roundOrder } from '../lib/stats.js';

/** Something that runs `steps` steps when asked and says how long they took, in ns. */
export interface Timed {
  time(steps: number): Promise<number>;
}

export interface RaceResult {
  /** Steps per sample, per contestant. */
  readonly steps: number[];
  /** `samples[c][r]`: ns per step of contestant `c` in round `r`. */
  readonly samples: number[][];
}

export interface RaceOptions {
  /**
   * Every contestant runs the same number of steps per sample (the first contestant's, sized to
   * `plan.sampleMs`), instead of each its own. Default false.
   */
  readonly sameSteps?: boolean;
  /** Called after the warm-up and after every round (a gc in the contestants' processes). */
  readonly gc?: () => Promise<void>;
}

/** Steps that fill a sample of `sampleMs` at `nsPerStep` (at least 1). */
export function stepsForSample(sampleMs: number, nsPerStep: number): number {
  if (!(nsPerStep > 0)) return 1;
  return Math.max(1, Math.round((sampleMs * 1e6) / nsPerStep));
}

export async function race(
  contestants: readonly Timed[],
  plan: MeasurePlan,
  options: RaceOptions = {},
): Promise<RaceResult> {
  const gc = options.gc ?? (() => Promise.resolve());
  // Warm-up, one contestant after the other: double the steps per call until a call lasts a
  // sample, for plan.warmupMs each; the last call sets the cost per step.
  const perStep = new Array<number>(contestants.length).fill(0);
  for (const [c, who] of contestants.entries()) {
    let spent = 0;
    let chunk = 1;
    while (spent < plan.warmupMs * 1e6) {
      const t = await who.time(chunk);
      spent += t;
      perStep[c] = t / chunk;
      if (t < plan.sampleMs * 1e6) chunk *= 2;
    }
  }
  const steps = perStep.map((ns) =>
    stepsForSample(plan.sampleMs, options.sameSteps === true ? perStep[0]! : ns),
  );
  const samples = contestants.map(() => new Array<number>(plan.rounds).fill(0));
  await gc();
  for (let r = 0; r < plan.rounds; r++) {
    for (const c of roundOrder(contestants.length, r)) {
      samples[c]![r] = (await contestants[c]!.time(steps[c]!)) / steps[c]!;
    }
    await gc();
  }
  return { steps, samples };
}
