/** Options of a {@link CorrectionSmoother}. */
export interface CorrectionSmootherOptions {
  /**
   * Rendered frames over which a correction blends out. Default 6 (100 ms at 60 Hz). 1 draws the
   * corrected value at once (no smoothing).
   */
  frames?: number;
  /**
   * A correction that moves a value by more than this (Euclidean distance over its dimensions, in
   * the game's units) is drawn at once, not blended: a respawn or a teleport should jump. Default
   * Infinity (always blend).
   */
  snapDistance?: number;
  /** Values per entity: 2 for (x, y), 3 for (x, y, angle) … Default 2. */
  dimensions?: number;
}

interface Blend {
  offset: Float64Array;
  left: number;
}

/**
 * Render-side smoothing of rollback corrections. When a rollback moves something on screen — the
 * remote player was predicted to run on, the confirmed input says they turned — drawing the
 * corrected position at once makes it jump. Tell the smoother both positions (`correct`) and draw
 * `apply(id, position)` instead of the position: it starts at the mispredicted place and blends
 * linearly to the corrected one over `frames` rendered frames, following the entity as it moves.
 *
 * It only changes what is drawn: it never reads or writes simulation state, so it cannot affect
 * determinism, replays or hashes. Feed it from `RollbackSession`'s `onCorrection` (the `before`
 * and `after` state bytes of the current tick; decode the positions with the game's layout) and
 * call {@link frame} once per rendered frame.
 */
export class CorrectionSmoother {
  /** Rendered frames over which a correction blends out. */
  readonly frames: number;
  /** Corrections longer than this (game units) are drawn at once. */
  readonly snapDistance: number;
  /** Values per entity. */
  readonly dimensions: number;
  private readonly blends = new Map<number, Blend>();

  /** Throws a RangeError naming a bad option. */
  constructor(options: CorrectionSmootherOptions = {}) {
    this.frames = options.frames ?? 6;
    this.snapDistance = options.snapDistance ?? Infinity;
    this.dimensions = options.dimensions ?? 2;
    if (!(Number.isInteger(this.frames) && this.frames >= 1 && this.frames <= 600)) {
      throw new RangeError(
        `CorrectionSmoother: frames must be an integer from 1 to 600, got ${this.frames}`,
      );
    }
    if (!(this.snapDistance > 0)) {
      throw new RangeError(
        `CorrectionSmoother: snapDistance must be > 0, got ${this.snapDistance}`,
      );
    }
    if (!(Number.isInteger(this.dimensions) && this.dimensions >= 1 && this.dimensions <= 16)) {
      throw new RangeError(
        `CorrectionSmoother: dimensions must be an integer from 1 to 16, got ${this.dimensions}`,
      );
    }
  }

  /**
   * A rollback moved entity `id` from `predicted` (what was drawn) to `corrected` (the new state):
   * from now on {@link apply} starts at what is drawn now and blends to the corrected value over
   * `frames` frames. A correction during a blend starts from where the blend had got to.
   */
  correct(id: number, predicted: ArrayLike<number>, corrected: ArrayLike<number>): void {
    const d = this.dimensions;
    if (predicted.length < d || corrected.length < d) {
      throw new RangeError(
        `CorrectionSmoother.correct: entity ${id} needs ${d} values per position`,
      );
    }
    const current = this.blends.get(id);
    const offset = new Float64Array(d);
    let squared = 0;
    for (let k = 0; k < d; k++) {
      const jump = predicted[k]! - corrected[k]!;
      if (!Number.isFinite(jump)) {
        throw new RangeError(`CorrectionSmoother.correct: entity ${id} has a non-finite value`);
      }
      squared += jump * jump;
      offset[k] = jump + (current ? (current.offset[k]! * current.left) / this.frames : 0);
    }
    if (Math.sqrt(squared) > this.snapDistance || this.frames === 1) {
      this.blends.delete(id);
      return;
    }
    this.blends.set(id, { offset, left: this.frames });
  }

  /** One rendered frame has passed: every blend moves one step towards the true values. */
  frame(): void {
    for (const [id, b] of this.blends) {
      b.left--;
      if (b.left <= 0) this.blends.delete(id);
    }
  }

  /**
   * The value to draw for entity `id` whose true (simulated, interpolated) value is `value`:
   * `value + offset × left / frames`. Written into `out` (default a new array) and returned.
   */
  apply(
    id: number,
    value: ArrayLike<number>,
    out: number[] = new Array<number>(this.dimensions),
  ): number[] {
    const b = this.blends.get(id);
    const f = b ? b.left / this.frames : 0;
    for (let k = 0; k < this.dimensions; k++) {
      out[k] = value[k]! + (b ? b.offset[k]! * f : 0);
    }
    return out;
  }

  /** Whether entity `id` is still being blended. */
  isBlending(id: number): boolean {
    return this.blends.has(id);
  }

  /** Forget every blend (a new match, a seek in a replay). */
  clear(): void {
    this.blends.clear();
  }
}
