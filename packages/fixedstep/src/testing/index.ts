/**
 * Test helpers every scene and game uses (Box2D-style): a golden hash after N ticks, and the
 * snapshot round trip. They return plain results and messages so they work with any test runner.
 * @module
 */
import { fnv1a64, hex64 } from '../det/hash.js';
import type { Simulation } from '../sim/simulation.js';

export { hex64 };

/**
 * Steps `sim` for `ticks` ticks with inputs from `inputs(tick)` and returns the final hash in
 * 16 hex digits — compare it with the golden value, and print it on mismatch so a deliberate
 * change is easy to re-bless.
 */
export function runForHash<I>(
  sim: Simulation<I>,
  ticks: number,
  inputs: (tick: number) => readonly I[],
): string {
  for (let t = 0; t < ticks; t++) sim.step(inputs(sim.tick));
  return hex64(sim.hash());
}

/** What {@link snapshotRoundTrip} found. */
export interface RoundTripResult {
  ok: boolean;
  /** The first tick after the snapshot at which the hashes differed, or -1. */
  firstMismatch: number;
  message: string;
}

/**
 * Box2D's snapshot test: step A for `warmup` ticks, save A, load into B, then step both for
 * `ticks` ticks (120 by default) with the same inputs, and require equal hashes at every tick —
 * and equal bytes right after the load.
 */
export function snapshotRoundTrip<I>(
  make: () => Simulation<I>,
  inputs: (tick: number) => readonly I[],
  warmup = 60,
  ticks = 120,
): RoundTripResult {
  const a = make();
  for (let t = 0; t < warmup; t++) a.step(inputs(a.tick));
  const b = make();
  b.load(a.save());
  if (b.tick !== a.tick)
    return {
      ok: false,
      firstMismatch: 0,
      message: `tick after load is ${b.tick}, expected ${a.tick}`,
    };
  if (a.hash() !== b.hash())
    return { ok: false, firstMismatch: 0, message: 'hash differs right after load' };
  for (let i = 1; i <= ticks; i++) {
    const input = inputs(a.tick);
    a.step(input);
    b.step(input);
    if (a.hash() !== b.hash()) {
      return {
        ok: false,
        firstMismatch: i,
        message: `hash differs ${i} ticks after the snapshot (tick ${a.tick}): ${hex64(a.hash())} vs ${hex64(b.hash())}`,
      };
    }
  }
  return {
    ok: true,
    firstMismatch: -1,
    message: `equal hashes for ${ticks} ticks after the snapshot`,
  };
}

/** The per-tick hash trace of a run: for cross-engine and cross-rate comparisons. */
export function hashTrace<I>(
  sim: Simulation<I>,
  ticks: number,
  inputs: (tick: number) => readonly I[],
): string[] {
  const out: string[] = [];
  for (let t = 0; t < ticks; t++) {
    sim.step(inputs(sim.tick));
    out.push(hex64(sim.hash()));
  }
  return out;
}

export { fnv1a64 };
