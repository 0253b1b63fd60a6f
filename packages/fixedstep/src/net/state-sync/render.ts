/**
 * The render side of state sync: what to draw of a state, snapshots kept for interpolation, the
 * render delay measured from the jitter, and the smoothing of corrections. None of it writes
 * simulation state.
 * @module
 */
import { dexp } from '../../det/math.js';

/**
 * What a state-sync client draws of a world, as numbers: `entities` entities of `fields` numbers
 * each (e.g. x and y of every player). The session reads them from every snapshot (for
 * interpolation) and from its prediction (for its own player), and blends them.
 *
 * @typeParam S — the game's simulation.
 */
export interface StateSyncRender<S> {
  /** Numbers per entity, 1–16 (e.g. 2: x and y, in the game's units). */
  readonly fields: number;
  /** Entities, a fixed count (e.g. 8 player slots). */
  readonly entities: number;
  /** Write every entity's numbers from `sim` into `out[entity × fields + field]`. Read only. */
  read(sim: S, out: Float64Array): void;
  /**
   * The entities the player in `slot` controls: drawn from the client's prediction, without lag.
   * Everything else is drawn between snapshots. Default: entity `slot`.
   */
  owned?(slot: number): readonly number[];
  /**
   * A change larger than this in any field between two snapshots, or in a correction, is a jump
   * (a respawn, a teleport): drawn at once, never blended. Default: Infinity (always blend).
   */
  readonly teleport?: number;
}

/** Snapshots' render numbers by tick, for drawing between two of them. */
export class SnapshotTimeline {
  /** Numbers per snapshot (`entities × fields`). */
  readonly size: number;
  private readonly fields: number;
  private readonly ticks: Float64Array;
  private readonly values: Float64Array[];
  private count = 0;

  constructor(fields: number, entities: number, capacity = 32) {
    this.fields = fields;
    this.size = fields * entities;
    this.ticks = new Float64Array(capacity);
    this.values = Array.from({ length: capacity }, () => new Float64Array(this.size));
  }

  /** Snapshots held. */
  get length(): number {
    return this.count;
  }

  /** The newest tick held (-Infinity when empty). */
  get newestTick(): number {
    return this.count === 0 ? -Infinity : this.ticks[this.count - 1]!;
  }

  /** The oldest tick held (Infinity when empty). */
  get oldestTick(): number {
    return this.count === 0 ? Infinity : this.ticks[0]!;
  }

  /** Keep `values` (copied) as tick `tick`'s; older than everything held and full: ignored. */
  push(tick: number, values: ArrayLike<number>): void {
    const cap = this.ticks.length;
    let i = this.count;
    while (i > 0 && this.ticks[i - 1]! > tick) i--;
    if (i > 0 && this.ticks[i - 1] === tick) return;
    if (this.count === cap) {
      if (i === 0) return;
      // Drop the oldest to make room.
      const spare = this.values[0]!;
      for (let k = 1; k < cap; k++) {
        this.ticks[k - 1] = this.ticks[k]!;
        this.values[k - 1] = this.values[k]!;
      }
      this.values[cap - 1] = spare;
      this.count--;
      i--;
    }
    const spare = this.values[this.count]!;
    for (let k = this.count; k > i; k--) {
      this.ticks[k] = this.ticks[k - 1]!;
      this.values[k] = this.values[k - 1]!;
    }
    this.ticks[i] = tick;
    this.values[i] = spare;
    for (let k = 0; k < this.size; k++) spare[k] = values[k] ?? 0;
    this.count++;
  }

  /**
   * Write the numbers at fractional tick `tick` into `out`: a straight blend of the two snapshots
   * around it (a jump larger than `teleport` shows the older until the newer's tick). Before the
   * oldest or after the newest, that snapshot's numbers are held — never extrapolated.
   * @returns `'between'`, `'after'` (held the newest: the render delay was too short), `'before'`,
   * or `'empty'`.
   */
  sample(
    tick: number,
    out: Float64Array,
    teleport = Infinity,
  ): 'between' | 'after' | 'before' | 'empty' {
    const n = this.count;
    if (n === 0) return 'empty';
    if (tick >= this.ticks[n - 1]!) {
      out.set(this.values[n - 1]!);
      return tick === this.ticks[n - 1] ? 'between' : 'after';
    }
    if (tick <= this.ticks[0]!) {
      out.set(this.values[0]!);
      return 'before';
    }
    let i = n - 1;
    while (this.ticks[i - 1]! > tick) i--;
    const t0 = this.ticks[i - 1]!;
    const t1 = this.ticks[i]!;
    const a = this.values[i - 1]!;
    const b = this.values[i]!;
    const u = (tick - t0) / (t1 - t0);
    const f = this.fields;
    for (let e = 0; e < this.size; e += f) {
      let jump = false;
      for (let k = 0; k < f; k++) if (Math.abs(b[e + k]! - a[e + k]!) > teleport) jump = true;
      for (let k = 0; k < f; k++)
        out[e + k] = jump ? a[e + k]! : a[e + k]! + (b[e + k]! - a[e + k]!) * u;
    }
    return 'between';
  }
}

/**
 * Render-side smoothing of state-sync corrections (the rollback sessions' is `CorrectionSmoother`,
 * which blends linearly over frames): when a snapshot moves the client's own prediction, the
 * drawn position keeps the difference as an offset that halves every `halfLifeMs`, so the player
 * glides to the corrected place instead of jumping. A correction larger than `snap` (a respawn) is
 * shown at once.
 */
export class PredictionSmoother {
  /** The current offsets (drawn = predicted + offset). */
  readonly offset: Float64Array;
  private readonly halfLifeMs: number;
  private readonly snap: number;

  constructor(size: number, halfLifeMs = 80, snap = Infinity) {
    if (!(halfLifeMs >= 0 && Number.isFinite(halfLifeMs))) {
      throw new RangeError(
        `PredictionSmoother: halfLifeMs must be a finite number >= 0, got ${halfLifeMs}`,
      );
    }
    this.offset = new Float64Array(size);
    this.halfLifeMs = halfLifeMs;
    this.snap = snap;
  }

  /**
   * The prediction changed from `before` to `after` (the same entities, at the same tick). Returns
   * the largest change in any number (the correction's size); keeps it as offset unless it is a
   * jump, which clears the offset.
   */
  correct(before: ArrayLike<number>, after: ArrayLike<number>): number {
    let size = 0;
    for (let k = 0; k < this.offset.length; k++) {
      const d = Math.abs(before[k]! - after[k]!);
      if (d > size) size = d;
    }
    if (!(size <= this.snap) || this.halfLifeMs === 0) {
      this.offset.fill(0);
      return size;
    }
    for (let k = 0; k < this.offset.length; k++) {
      this.offset[k] = this.offset[k]! + before[k]! - after[k]!;
    }
    return size;
  }

  /** Let `ms` of render time pass: the offset decays. */
  decay(ms: number): void {
    if (!(ms > 0)) return;
    const f = this.halfLifeMs === 0 ? 0 : dexp((-Math.LN2 * ms) / this.halfLifeMs);
    for (let k = 0; k < this.offset.length; k++) {
      const v = this.offset[k]! * f;
      this.offset[k] = Math.abs(v) < 1e-12 ? 0 : v;
    }
  }

  /** The largest offset now. */
  get magnitude(): number {
    let m = 0;
    for (let k = 0; k < this.offset.length; k++) m = Math.max(m, Math.abs(this.offset[k]!));
    return m;
  }
}

/**
 * How late snapshots arrive: per snapshot, the estimated server time of arrival minus the time its
 * tick began, over the last `window` snapshots. Its minimum is the one-way delay (plus the clock
 * estimate's error), its spread the jitter.
 */
export class LatenessWindow {
  private readonly samples: Float64Array;
  private next = 0;
  private count = 0;

  constructor(window = 64) {
    this.samples = new Float64Array(window);
  }

  add(ms: number): void {
    if (!Number.isFinite(ms)) return;
    this.samples[this.next] = ms;
    this.next = (this.next + 1) % this.samples.length;
    if (this.count < this.samples.length) this.count++;
  }

  get size(): number {
    return this.count;
  }

  /** The smallest lateness held (0 when empty). */
  get min(): number {
    if (this.count === 0) return 0;
    let m = Infinity;
    for (let i = 0; i < this.count; i++) m = Math.min(m, this.samples[i]!);
    return m;
  }

  /** A high lateness: the second largest held (the largest with fewer than 8), 0 when empty. */
  get high(): number {
    if (this.count === 0) return 0;
    let a = -Infinity;
    let b = -Infinity;
    for (let i = 0; i < this.count; i++) {
      const v = this.samples[i]!;
      if (v > a) {
        b = a;
        a = v;
      } else if (v > b) b = v;
    }
    return this.count >= 8 ? b : a;
  }

  /** The jitter: high minus min. */
  get jitter(): number {
    return this.high - this.min;
  }
}
