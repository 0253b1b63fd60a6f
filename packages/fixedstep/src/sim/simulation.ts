/**
 * A deterministic simulation: the same start and the same inputs give the same bytes, tick for
 * tick, at any frame rate and in every JavaScript engine.
 *
 * Rules an implementation follows to keep that promise:
 * - time enters only as the tick number and the fixed step; never read a clock;
 * - randomness comes only from a seeded {@link Random} whose state is part of the saved state;
 * - math is `+ - * /`, `Math.sqrt`, `Math.floor/ceil/round/trunc/abs/min/max/sign` and the
 *   deterministic helpers of `fixedstep` (`dsin`, `dcos`, `datan2`, …) — never `Math.sin`,
 *   `cos`, `atan2`, `exp`, `pow`, `hypot` (engines differ in the last bit);
 * - iterate only over arrays in a defined order (no iteration over hash sets of objects whose
 *   order can depend on history);
 * - `save()` writes canonical bytes ({@link ByteWriter}): equal states give equal bytes.
 *
 * @typeParam I — one player's input for one tick (e.g. a {@link ButtonInput}).
 */
export interface Simulation<I = number> {
  /** Ticks stepped so far. Simulated time is `tick × step`. */
  readonly tick: number;
  /** Advance exactly one fixed step, with one input per player (index = player). */
  step(inputs: readonly I[]): void;
  /** The whole state as canonical bytes (a snapshot). */
  save(): Uint8Array;
  /**
   * Optional, with {@link saveInto}: the number of bytes {@link save} would return now. A
   * simulation with both lets `RollbackSession` keep one buffer per tick of its history and
   * write each tick's snapshot into it, instead of a new array every tick (`PhysicsWorld` has
   * both: a 2,000-body world is ~220 KB of garbage a tick less).
   */
  readonly snapshotSize?: number;
  /**
   * Optional, with {@link snapshotSize}: writes exactly {@link save}'s bytes into the start of
   * `out` (at least `snapshotSize` long) and returns how many it wrote.
   */
  saveInto?(out: Uint8Array): number;
  /** Restore exactly a state from {@link save}. Throws a RangeError on bytes it cannot read. */
  load(bytes: Uint8Array): void;
  /** A hash of the canonical state bytes (FNV-1a 64). */
  hash(): bigint;
  /**
   * Optional, with {@link skip}: true once the state is frozen — the run is over and every later
   * step, whatever its inputs, changes nothing but {@link tick} (and what is a function of the
   * tick alone, such as a clock of tick × step). Once true it stays true under `step` and
   * `skip`. `verifyReplay` then jumps from one stored hash to the next with `skip` instead of
   * stepping through a finished match tick by tick; it still computes and compares every stored
   * hash, which then differ only by the tick.
   *
   * A promise about the rules, so test it: after the end, `skip(k)` and k steps with any inputs
   * must leave equal `save()` bytes.
   */
  readonly frozen?: boolean;
  /**
   * Optional, with {@link frozen}: while frozen, advance `ticks` ticks at once, leaving exactly
   * the state `ticks` calls of `step` would. Throws a RangeError when not frozen.
   */
  skip?(ticks: number): void;
}
