/**
 * Render interpolation for many bodies at once: the state of the last two ticks in typed arrays,
 * blended by the loop's alpha. Render-side only: it never writes simulation state.
 * @module
 */

/**
 * Holds `fields` numbers per body (e.g. x and y, or x, y and angle) for the previous and the
 * current tick, and blends them for drawing. Zero garbage per frame: every array is allocated once,
 * in the constructor (and again only by {@link reserve}).
 *
 * Each tick: call {@link beginTick} before stepping, then {@link store} every live body's
 * values after. Each frame: {@link interpolate} with the loop's alpha and draw from {@link out}.
 * A body stored for the first time (or after a tick without a store — it appeared) is drawn at its
 * current values, never blended from stale ones; call {@link snap} after a teleport.
 *
 * @example
 * const view = new InterpolationBuffer({ fields: 2, capacity: 10_000 });
 * // per tick:
 * view.beginTick(); sim.step(inputs); for (const b of bodies) view.store(b.id, b.x, b.y);
 * // per frame:
 * const xy = view.interpolate(loop.alpha); // xy[2 * id], xy[2 * id + 1]
 */
export class InterpolationBuffer {
  /** Numbers per body. */
  readonly fields: number;
  private prev: Float64Array;
  private curr: Float64Array;
  private output: Float64Array;
  /** Per body: the tick it was last stored at (0: never). */
  private storedAt: Uint32Array;
  /** Per body: stored at the tick before its current store (so it may be blended). */
  private blend: Uint8Array;
  private tick = 2; // storedAt 0 means never: tick − 1 must never be 0
  private angles: Uint8Array;
  private readonly hasAngles: boolean;
  private highest = -1;

  constructor(options: {
    /** Numbers per body, 1–16. */
    fields: number;
    /** Bodies to make room for (grows on demand with {@link reserve}). */
    capacity: number;
    /** Field indices that are angles in radians: blended along the shorter arc. */
    angleFields?: readonly number[];
  }) {
    const { fields, capacity } = options;
    if (!Number.isInteger(fields) || fields < 1 || fields > 16) {
      throw new RangeError(
        `InterpolationBuffer: fields must be an integer from 1 to 16, got ${String(fields)}`,
      );
    }
    if (!Number.isInteger(capacity) || capacity < 0 || capacity > 1 << 24) {
      throw new RangeError(
        `InterpolationBuffer: capacity must be an integer from 0 to 2^24, got ${String(capacity)}`,
      );
    }
    this.fields = fields;
    this.angles = new Uint8Array(fields);
    for (const f of options.angleFields ?? []) {
      if (!Number.isInteger(f) || f < 0 || f >= fields) {
        throw new RangeError(`InterpolationBuffer: angle field ${String(f)} is not a field index`);
      }
      this.angles[f] = 1;
    }
    this.hasAngles = this.angles.includes(1);
    this.prev = new Float64Array(capacity * fields);
    this.curr = new Float64Array(capacity * fields);
    this.output = new Float64Array(capacity * fields);
    this.storedAt = new Uint32Array(capacity);
    this.blend = new Uint8Array(capacity);
  }

  /** Bodies there is room for. */
  get capacity(): number {
    return this.storedAt.length;
  }

  /** The blended values of the last {@link interpolate}: body `i`'s field `f` at `out[i × fields + f]`. */
  get out(): Float64Array {
    return this.output;
  }

  /** Make room for at least `capacity` bodies (allocates; call it outside the frame loop). */
  reserve(capacity: number): void {
    if (capacity <= this.capacity) return;
    const grow = (a: Float64Array) => {
      const b = new Float64Array(capacity * this.fields);
      b.set(a);
      return b;
    };
    this.prev = grow(this.prev);
    this.curr = grow(this.curr);
    this.output = grow(this.output);
    const s = new Uint32Array(capacity);
    s.set(this.storedAt);
    this.storedAt = s;
    const b = new Uint8Array(capacity);
    b.set(this.blend);
    this.blend = b;
  }

  /** A new tick begins: what was current becomes previous. Call once before each step. */
  beginTick(): void {
    const n = (this.highest + 1) * this.fields;
    this.prev.set(this.curr.subarray(0, n));
    this.tick++;
  }

  /** Store body `i`'s values after this tick's step (up to `fields` numbers; missing ones are 0). */
  store(i: number, a: number, b = 0, c = 0, d = 0): void {
    if (!(i >= 0 && i < this.storedAt.length && Number.isInteger(i))) {
      throw new RangeError(
        `InterpolationBuffer.store: body ${String(i)} is outside the capacity ${this.capacity}`,
      );
    }
    const k = i * this.fields;
    const c0 = this.curr;
    c0[k] = a;
    if (this.fields > 1) c0[k + 1] = b;
    if (this.fields > 2) c0[k + 2] = c;
    if (this.fields > 3) c0[k + 3] = d;
    this.finishStore(i);
  }

  /** Store body `i`'s values from `values[from … from + fields)`. */
  storeFrom(i: number, values: ArrayLike<number>, from = 0): void {
    if (!(i >= 0 && i < this.storedAt.length && Number.isInteger(i))) {
      throw new RangeError(
        `InterpolationBuffer.storeFrom: body ${String(i)} is outside the capacity ${this.capacity}`,
      );
    }
    const k = i * this.fields;
    for (let f = 0; f < this.fields; f++) this.curr[k + f] = values[from + f] ?? 0;
    this.finishStore(i);
  }

  private finishStore(i: number): void {
    // Blend only a body that was also stored at the previous tick; anything else (new, reused,
    // reappeared) is drawn where it is now.
    this.blend[i] = this.storedAt[i] === this.tick - 1 ? 1 : 0;
    this.storedAt[i] = this.tick;
    if (i > this.highest) this.highest = i;
  }

  /** Draw body `i` at its current values until its next store (after a teleport or respawn). */
  snap(i: number): void {
    if (i >= 0 && i < this.blend.length) this.blend[i] = 0;
  }

  /** Whether body `i` was stored at the current tick. */
  isLive(i: number): boolean {
    return this.storedAt[i] === this.tick;
  }

  /**
   * Blend every body stored this tick: `previous + (current − previous) × alpha` (angles along
   * the shorter arc). Returns {@link out}. Bodies not stored this tick are left as they were.
   *
   * `alpha` is the loop's interpolation factor, a fraction of a step from 0 (draw the previous
   * tick) to 1 (the current one); values above 1 count as 1, and below 0 or NaN as 0. Render side
   * only: what it returns is for drawing, and must never feed back into a simulation (it depends
   * on the display's frame times, which differ between machines).
   */
  interpolate(alpha: number): Float64Array {
    const t = alpha >= 0 && alpha <= 1 ? alpha : alpha > 1 ? 1 : 0;
    const fields = this.fields;
    const prev = this.prev;
    const curr = this.curr;
    const out = this.output;
    const angles = this.angles;
    const storedAt = this.storedAt;
    const blend = this.blend;
    const tick = this.tick;
    if (!this.hasAngles && fields === 2) {
      // The common case (x, y), written out: no inner loop, no angle test.
      for (let i = 0; i <= this.highest; i++) {
        if (storedAt[i] !== tick) continue;
        const k = 2 * i;
        if (blend[i] === 0) {
          out[k] = curr[k]!;
          out[k + 1] = curr[k + 1]!;
        } else {
          const px = prev[k]!;
          const py = prev[k + 1]!;
          out[k] = px + (curr[k]! - px) * t;
          out[k + 1] = py + (curr[k + 1]! - py) * t;
        }
      }
      return out;
    }
    for (let i = 0; i <= this.highest; i++) {
      if (storedAt[i] !== tick) continue;
      const k = i * fields;
      if (blend[i] === 0) {
        for (let f = 0; f < fields; f++) out[k + f] = curr[k + f]!;
        continue;
      }
      for (let f = 0; f < fields; f++) {
        const p = prev[k + f]!;
        let d = curr[k + f]! - p;
        if (angles[f] === 1) {
          if (d > Math.PI) d -= 2 * Math.PI;
          else if (d < -Math.PI) d += 2 * Math.PI;
        }
        out[k + f] = p + d * t;
      }
    }
    return out;
  }
}
