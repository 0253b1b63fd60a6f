/**
 * What a state-sync session draws — the other entities between two snapshots, its own from the
 * prediction plus a decaying correction offset — reading states, never writing one.
 * @module
 */
import {
  PredictionSmoother,
  SnapshotTimeline,
  type StateSyncRender,
} from '../state-sync/render.js';

/**
 * The drawing side of a {@link StateSyncSession}, kept apart from its connection and prediction:
 * the snapshots' numbers by tick, the last two predicted ticks' numbers, the own entities and the
 * smoothing of their corrections. Without a `render` it holds nothing and draws nothing.
 * @internal
 */
export class StateSyncDrawing<S> {
  /** The numbers of the last {@link draw} (reused). */
  readonly out: Float64Array;
  /** The fractional tick the last {@link draw} drew the other entities at. */
  renderTick = -Infinity;
  /** The last {@link draw}'s blend between the previous and the current predicted tick. */
  alpha = 0;

  private readonly renderer: StateSyncRender<S> | undefined;
  private readonly timeline: SnapshotTimeline | undefined;
  private readonly scratchValues: Float64Array;
  private predPrev: Float64Array;
  private predCurr: Float64Array;
  private ownedValue: readonly number[] = [];
  private smoother = new PredictionSmoother(0);
  private ownBefore = new Float64Array(0);
  private ownAfter = new Float64Array(0);
  private lastDrawAt: number | undefined;

  /** Checks `render`'s counts: a RangeError names a wrong one. */
  constructor(render: StateSyncRender<S> | undefined) {
    this.renderer = render;
    if (render) {
      if (!(Number.isInteger(render.fields) && render.fields >= 1 && render.fields <= 16)) {
        throw new RangeError(
          `StateSyncSession: render.fields must be an integer from 1 to 16, got ${render.fields}`,
        );
      }
      if (!(
        Number.isInteger(render.entities) &&
        render.entities >= 0 &&
        render.entities <= 1 << 20
      )) {
        throw new RangeError(
          `StateSyncSession: render.entities must be an integer from 0 to 2^20, got ${render.entities}`,
        );
      }
      this.timeline = new SnapshotTimeline(render.fields, render.entities, 32);
    }
    const size = render ? render.fields * render.entities : 0;
    this.out = new Float64Array(size);
    this.scratchValues = new Float64Array(size);
    this.predPrev = new Float64Array(size);
    this.predCurr = new Float64Array(size);
  }

  /** Whether there is anything to draw (a `render` was given). */
  get enabled(): boolean {
    return this.renderer !== undefined;
  }

  /** The entities the own player controls (from `render.owned`; none for a spectator). */
  get owned(): readonly number[] {
    return this.ownedValue;
  }

  /** The own correction offset now (its largest number; 0 without corrections). */
  get correctionOffset(): number {
    return this.smoother.magnitude;
  }

  /** Whether a correction of `size` is drawn at once rather than glided (a teleport). */
  snaps(size: number): boolean {
    return !(size <= (this.renderer?.teleport ?? Infinity));
  }

  /**
   * The welcome named the own slot (-1: a spectator): find the own entities and size the smoother
   * for them. A RangeError names an entity `render.owned` gives that is not one of the entities.
   */
  welcome(slot: number, halfLifeMs: number): void {
    const r = this.renderer;
    if (!r) return;
    const owned = slot < 0 ? [] : (r.owned?.(slot) ?? [slot]);
    for (const e of owned) {
      if (!(Number.isInteger(e) && e >= 0 && e < r.entities)) {
        throw new RangeError(
          `render.owned(${slot}) names entity ${e}, not one of 0–${r.entities - 1}`,
        );
      }
    }
    this.ownedValue = owned;
    const n = owned.length * r.fields;
    this.ownBefore = new Float64Array(n);
    this.ownAfter = new Float64Array(n);
    this.smoother = new PredictionSmoother(n, halfLifeMs, r.teleport ?? Infinity);
  }

  /** A verified snapshot of `tick`, loaded into `sim`: keep its numbers to draw the others. */
  snapshot(tick: number, sim: S): void {
    if (!this.renderer || !this.timeline) return;
    this.renderer.read(sim, this.scratchValues);
    this.timeline.push(tick, this.scratchValues);
  }

  /** Before a predicted step: the current numbers become the previous tick's. */
  beforeStep(): void {
    if (!this.renderer) return;
    const swap = this.predPrev;
    this.predPrev = this.predCurr;
    this.predCurr = swap;
  }

  /** After a predicted step: read the predicted tick's numbers. */
  afterStep(sim: S): void {
    this.renderer?.read(sim, this.predCurr);
  }

  /** Before a reconciliation: remember where the own entities were predicted to be. */
  beforeReconcile(): void {
    for (let k = 0; k < this.ownBefore.length; k++)
      this.ownBefore[k] = this.predCurr[this.ownIndex(k)]!;
  }

  /** A snapshot was loaded into `sim`: its numbers are the current and the previous tick's. */
  loaded(sim: S): void {
    if (!this.renderer) return;
    this.renderer.read(sim, this.predCurr);
    this.predPrev.set(this.predCurr);
  }

  /**
   * After a reconciliation's replay: the own entities moved from where they were predicted to be;
   * the smoother takes the difference. Returns the correction's size (largest change, game units).
   */
  afterReconcile(): number {
    if (!this.renderer || this.ownedValue.length === 0) return 0;
    for (let k = 0; k < this.ownAfter.length; k++)
      this.ownAfter[k] = this.predCurr[this.ownIndex(k)]!;
    return this.smoother.correct(this.ownBefore, this.ownAfter);
  }

  /**
   * Draw at `now`: the others at `tick` (never earlier than the last draw's), the own entities
   * blended `ownAlpha` of the way from the previous predicted tick to the current (undefined: no
   * own entities drawn from the prediction) plus the correction offset. Returns whether `tick`
   * was past the newest snapshot (the render delay was too short).
   */
  draw(tick: number, ownAlpha: number | undefined, now: number): boolean {
    const r = this.renderer;
    if (!r || !this.timeline) return false;
    if (tick < this.renderTick) tick = this.renderTick;
    this.renderTick = tick;
    const starved = this.timeline.sample(tick, this.out, r.teleport ?? Infinity) === 'after';
    if (this.lastDrawAt !== undefined) this.smoother.decay(now - this.lastDrawAt);
    this.lastDrawAt = now;
    if (ownAlpha !== undefined) {
      const alpha = ownAlpha <= 0 ? 0 : ownAlpha >= 1 ? 1 : ownAlpha;
      // The state at the predicted tick is drawn at display time tick + 1: blend prev → curr.
      this.alpha = alpha;
      const f = r.fields;
      let k = 0;
      for (const e of this.ownedValue) {
        for (let j = 0; j < f; j++) {
          const i = e * f + j;
          const p = this.predPrev[i]!;
          const c = this.predCurr[i]!;
          this.out[i] = p + (c - p) * alpha + this.smoother.offset[k++]!;
        }
      }
    }
    return starved;
  }

  /** The index in a render array of the k-th owned number. */
  private ownIndex(k: number): number {
    const f = this.renderer!.fields;
    return this.ownedValue[Math.floor(k / f)]! * f + (k % f);
  }
}
