/**
 * Lag compensation — the Source engine's model (and Photon Fusion's lag-compensated hit boxes):
 * a player shoots at what is on its screen, and its screen shows the other entities some time in
 * the past (a snapshot interval and a half round trip behind the server, blended between
 * snapshots). Judged at the server's present, a shot that hit on screen misses. The server keeps
 * where every entity was over the last few ticks ({@link LagHistory}) and judges the shot at the
 * tick the shooter saw — which the shooter's input carries, e.g. as an axis: the issued tick minus
 * the session's `renderTick` when it fired. The rewind is bounded: a client cannot claim to have
 * seen further back than {@link LagHistory.maxRewindTicks}, so a cheat gains at most that much.
 *
 * The history is server memory, not game state: it is not saved, not hashed, not sent, and a
 * `load` (the room snapping its world) leaves it as it is.
 * @module
 */

/** Options of a {@link LagHistory}. */
export interface LagHistoryOptions {
  /** Entities recorded per tick. */
  entities: number;
  /** Numbers per entity (e.g. 2: x and y). */
  fields: number;
  /**
   * The furthest back a shot is judged, ticks (its time is clamped to `newest − this`). The
   * history keeps this many ticks and one more. E.g. 30 at 60 Hz: 500 ms.
   */
  maxRewindTicks: number;
}

/** Where entities were over the last ticks, for judging shots at the time their shooter saw. */
export class LagHistory {
  readonly entities: number;
  readonly fields: number;
  readonly maxRewindTicks: number;
  private readonly capacity: number;
  private readonly ticks: Float64Array;
  private readonly values: Float64Array;
  private newestTick = -1;

  constructor(options: LagHistoryOptions) {
    const { entities, fields, maxRewindTicks } = options;
    for (const [name, v, max] of [
      ['entities', entities, 1 << 16],
      ['fields', fields, 64],
      ['maxRewindTicks', maxRewindTicks, 1 << 12],
    ] as const) {
      if (!(Number.isInteger(v) && v >= 1 && v <= max)) {
        throw new RangeError(
          `LagHistory: ${name} must be an integer from 1 to ${max}, got ${String(v)}`,
        );
      }
    }
    this.entities = entities;
    this.fields = fields;
    this.maxRewindTicks = maxRewindTicks;
    this.capacity = maxRewindTicks + 2;
    this.ticks = new Float64Array(this.capacity).fill(-1);
    this.values = new Float64Array(this.capacity * entities * fields);
  }

  /** The newest tick recorded (-1: none). */
  get newest(): number {
    return this.newestTick;
  }

  /**
   * Record the entities at `tick` (the state after `tick` steps): `values[entity × fields +
   * field]`. Ticks go forward; recording an older tick than the newest forgets the newer ones
   * (a room that rewound its own world).
   */
  record(tick: number, values: ArrayLike<number>): void {
    if (!(Number.isInteger(tick) && tick >= 0)) {
      throw new RangeError(`LagHistory.record: tick must be an integer ≥ 0, got ${String(tick)}`);
    }
    const size = this.entities * this.fields;
    if (values.length < size) {
      throw new RangeError(`LagHistory.record: ${values.length} values, ${size} needed`);
    }
    if (tick < this.newestTick) this.ticks.fill(-1);
    const slot = tick % this.capacity;
    this.ticks[slot] = tick;
    const at = slot * size;
    for (let i = 0; i < size; i++) this.values[at + i] = values[i]!;
    this.newestTick = tick;
  }

  /**
   * The tick a shot is judged at when its shooter saw tick `seen` (fractional): `seen`, clamped
   * into the history — no further back than `maxRewindTicks` before the newest, no later than
   * the newest.
   */
  judgedAt(seen: number): number {
    const newest = this.newestTick;
    if (newest < 0) throw new RangeError('LagHistory: nothing recorded yet');
    const oldest = Math.max(0, newest - this.maxRewindTicks);
    if (!(seen >= oldest)) return oldest; // NaN too
    return seen > newest ? newest : seen;
  }

  /**
   * Entity `entity`'s numbers at fractional tick `at` (clamped by {@link judgedAt}), blended
   * linearly between the two recorded ticks around it — as a state-sync client draws others
   * between snapshots. Writes `fields` numbers to `out` and returns it.
   */
  sample(
    at: number,
    entity: number,
    out: Float64Array = new Float64Array(this.fields),
  ): Float64Array {
    if (!(Number.isInteger(entity) && entity >= 0 && entity < this.entities)) {
      throw new RangeError(`LagHistory.sample: entity ${String(entity)} of ${this.entities}`);
    }
    const t = this.judgedAt(at);
    // The recorded ticks around t (a tick not recorded — a gap — is bridged by its neighbours).
    const oldest = Math.max(0, this.newestTick - this.maxRewindTicks);
    let lo = Math.floor(t);
    while (lo >= oldest && this.ticks[lo % this.capacity] !== lo) lo--;
    let hi = Math.ceil(t);
    while (hi <= this.newestTick && this.ticks[hi % this.capacity] !== hi) hi++;
    if (lo < oldest) lo = hi;
    if (hi > this.newestTick) hi = lo;
    const size = this.entities * this.fields;
    const a = (lo % this.capacity) * size + entity * this.fields;
    const b = (hi % this.capacity) * size + entity * this.fields;
    const f = hi > lo ? (t - lo) / (hi - lo) : 0;
    for (let k = 0; k < this.fields; k++) {
      const va = this.values[a + k]!;
      out[k] = va + (this.values[b + k]! - va) * f;
    }
    return out;
  }
}
