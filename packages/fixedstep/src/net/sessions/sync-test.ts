/**
 * A sync test, without a network: every tick, roll back `checkDistance` ticks and resimulate
 * them, comparing each state's bytes with the first run — a non-deterministic step or an inexact
 * save/load is caught at the exact tick on one machine.
 * @module
 */
import { fnv1a64 } from '../../det/hash.js';
import type { Simulation } from '../../sim/simulation.js';
import { diffSnapshots, type SnapshotDiff } from '../forensics.js';

/** What a {@link SyncTestSession} caught. */
export interface SyncTestMismatch {
  /**
   * - `'step'` — stepping the same state with the same inputs twice gave different states: the
   *   step reads something outside the state (a clock, `Math.random`, a global, iteration order …).
   * - `'load'` — loading an older snapshot into the simulation did not give back its bytes: a
   *   field that `load()` does not restore.
   */
  kind: 'step' | 'load';
  /**
   * The first tick whose state differs: the state after this many steps (so the step of tick
   * `tick - 1` diverged). The server's desync notice uses the same numbering.
   */
  tick: number;
  /** FNV-1a 64 of the `save()` bytes: first run, and the rerun (or the reload). */
  expected: bigint;
  actual: bigint;
  /** Which bytes differ. */
  diff: SnapshotDiff;
  /** The two states themselves (`save()` bytes): to name the field that differs. */
  expectedState: Uint8Array;
  actualState: Uint8Array;
}

/** Thrown by {@link SyncTestSession.step} on a mismatch. */
export class SyncTestError extends Error {
  constructor(readonly mismatch: SyncTestMismatch) {
    super(
      mismatch.kind === 'step'
        ? `non-deterministic step: the state of tick ${mismatch.tick} differs on a rerun (first differing byte at offset ${mismatch.diff.firstOffset})`
        : `save/load is not exact at tick ${mismatch.tick} (first differing byte at offset ${mismatch.diff.firstOffset})`,
    );
    this.name = 'SyncTestError';
  }
}

/** Options of a {@link SyncTestSession}. */
export interface SyncTestOptions {
  /**
   * Every tick, roll back this many ticks and resimulate them, comparing each state with the
   * first run (GGPO's sync test). Default 1: save, step, load, step again, compare.
   */
  checkDistance?: number;
  /** Throw a {@link SyncTestError} on the first mismatch (default), or only record it. */
  throwOnMismatch?: boolean;
}

/**
 * Rollback without a network: every tick it saves, steps, loads, steps again and compares the
 * bytes — so a non-deterministic step, or a `save()`/`load()` that forgets part of the state, is
 * caught on this machine at the exact tick, long before two players drift apart. Use it in tests
 * and in a debug mode of the game.
 */
export class SyncTestSession<I = number> {
  /** The first mismatch found, if any. */
  mismatch: SyncTestMismatch | undefined;
  /** Ticks checked. */
  checkedTicks = 0;
  readonly checkDistance: number;

  private readonly throwOnMismatch: boolean;
  private readonly saves: (Uint8Array | undefined)[];
  private readonly inputs: (readonly I[] | undefined)[];
  private readonly ticks: Float64Array;

  constructor(
    readonly sim: Simulation<I>,
    options: SyncTestOptions = {},
  ) {
    this.checkDistance = options.checkDistance ?? 1;
    if (!(
      Number.isInteger(this.checkDistance) &&
      this.checkDistance >= 1 &&
      this.checkDistance <= 64
    )) {
      throw new RangeError(
        `checkDistance must be an integer from 1 to 64, got ${this.checkDistance}`,
      );
    }
    this.throwOnMismatch = options.throwOnMismatch ?? true;
    const cap = this.checkDistance + 1;
    this.saves = new Array<Uint8Array | undefined>(cap);
    this.inputs = new Array<readonly I[] | undefined>(cap);
    this.ticks = new Float64Array(cap).fill(-1);
  }

  get tick(): number {
    return this.sim.tick;
  }

  /**
   * One checked step. Returns true when the tick checked out; on a mismatch throws (or returns
   * false with `throwOnMismatch: false`, and stops checking).
   */
  step(inputs: readonly I[]): boolean {
    const sim = this.sim;
    if (this.mismatch) {
      sim.step(inputs);
      return false;
    }
    const cap = this.saves.length;
    const t0 = sim.tick;
    this.store(t0, sim.save(), inputs);
    sim.step(inputs);
    const first = sim.save();
    this.store(t0 + 1, first, undefined);
    // Roll back `checkDistance` ticks (fewer at the start) and resimulate them.
    let from = Math.max(0, t0 + 1 - this.checkDistance);
    while (from < t0 && this.ticks[from % cap] !== from) from++;
    const start = this.saves[from % cap];
    if (start === undefined || this.ticks[from % cap] !== from) return true;
    // Loading an older state into a newer simulation must restore every byte of it.
    sim.load(start);
    const loaded = sim.save();
    if (!equalBytes(start, loaded)) return this.fail('load', from, start, loaded);
    for (let t = from; t <= t0; t++) {
      sim.step(this.inputs[t % cap]!);
      const expected = t === t0 ? first : this.saves[(t + 1) % cap]!;
      const actual = sim.save();
      if (!equalBytes(expected, actual)) return this.fail('step', t + 1, expected, actual);
    }
    this.checkedTicks++;
    return true;
  }

  private store(tick: number, bytes: Uint8Array, inputs: readonly I[] | undefined): void {
    const i = tick % this.saves.length;
    this.ticks[i] = tick;
    this.saves[i] = bytes;
    if (inputs !== undefined) this.inputs[i] = inputs.slice();
  }

  private fail(
    kind: 'step' | 'load',
    tick: number,
    expected: Uint8Array,
    actual: Uint8Array,
  ): boolean {
    this.mismatch = {
      kind,
      tick,
      expected: fnv1a64(expected),
      actual: fnv1a64(actual),
      diff: diffSnapshots(expected, actual),
      expectedState: expected,
      actualState: actual,
    };
    if (this.throwOnMismatch) throw new SyncTestError(this.mismatch);
    return false;
  }
}

function equalBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}
