import type { Loop } from './loop.js';
import { Timestep } from './timestep.js';

/**
 * What happens when more steps are due in one frame than {@link FixedLoopOptions.maxStepsPerFrame}:
 * - `'catch-up'` — run the cap now and keep the rest in the accumulator for later frames (bounded
 *   by the clamp). Simulated time catches up with real time; no time is lost unless clamped.
 * - `'drop'` — run the cap and drop the whole steps beyond it (the fraction of a step is kept).
 *   Simulated time falls behind real time by exactly the dropped amount, which is counted.
 * - `'reset'` — run the cap and drop everything else in the accumulator, fraction included.
 */
export type OverloadPolicy = 'catch-up' | 'drop' | 'reset';

/**
 * What happens to the time a tab spends hidden (see {@link FixedLoop.setHidden}):
 * - `'pause'` — hidden time is dropped (counted as `hidden`); on return the loop goes on where it
 *   stopped, with no burst of catch-up steps.
 * - `'clamp'` — hidden time is treated like any other frame time: the clamp and the overload
 *   policy decide how much of it is simulated.
 */
export type HiddenPolicy = 'pause' | 'clamp';

/** Why time was dropped. */
export type DropReason = 'clamp' | 'overload' | 'hidden';

export interface FixedLoopOptions {
  /**
   * The fixed step: a {@link Timestep}, a tick rate in Hz, or a game definition (anything with a
   * `tickRate`), so the rate is declared once, by the game.
   */
  step: Timestep | number | { readonly tickRate: number };
  /**
   * Upper bound of the accumulator, in milliseconds. Default 250.
   *
   * The talk clamps at 1.0 s. We default to 0.25 s, as most engines do: after a hitch the loop
   * owes at most a quarter of a second of steps (15 at 60 Hz) instead of 60, so the catch-up burst
   * cannot itself become the next hitch (the "spiral of death"). Must be at least one step.
   */
  maxAccumulatorMs?: number;
  /** The most steps one frame may run (a positive integer). Default 8. */
  maxStepsPerFrame?: number;
  /** What to do when more steps are due than the cap. Default `'catch-up'`. */
  overload?: OverloadPolicy;
  /** What to do with time spent in a hidden tab. Default `'pause'`. */
  hidden?: HiddenPolicy;
  /**
   * Hysteresis, as a fraction of a step in [0, 0.5]. Default 0.
   *
   * When the display rate is close to the tick rate, jitter makes the accumulator hover around one
   * step, and frames alternate between 0 and 2 steps. With hysteresis `h`, a step may run up to
   * `h` steps early, so a frame that is a little short still gets its one step. The tick law
   * becomes `ticks = floor(elapsed / step + h)`; alpha is shifted by `h` so rendering stays smooth.
   * Input sampling shifts with it: an event at time t goes to tick `floor(t / step + h)`, the same
   * on every display (see {@link FixedLoop.isBeforeUpdateEnd}).
   */
  hysteresis?: number;
  /**
   * Time scale, a finite number from 0 to 64. Default 1. It changes how many steps run per second
   * of real time, never the step size, so the simulation stays deterministic.
   */
  timeScale?: number;
  /** Called whenever time is dropped, with the amount in milliseconds and the reason. */
  onDrop?: (ms: number, reason: DropReason) => void;
  /**
   * Where the loop reports a likely mistake in how it is fed, once per kind — clock readings that
   * run back or stand still (a frame *delta*, jittering or constant, passed to
   * {@link FixedLoop.frame}, which expects a *timestamp*), or input events timestamped on another
   * time line than the frames (a key press would wait seconds for its tick). Default `console.warn`; `null` to stay silent (production).
   * Reporting never changes what the loop does.
   */
  onWarning?: ((message: string) => void) | null;
}

/** What {@link FixedLoopOptions.onWarning} may report. */
export type LoopWarning = 'delta-as-timestamp' | 'input-time-line';

const POLICIES: readonly OverloadPolicy[] = ['catch-up', 'drop', 'reset'];
const HIDDEN: readonly HiddenPolicy[] = ['pause', 'clamp'];

/**
 * The production fixed-step loop: the talk's accumulator with its final fixes, and what a real
 * game needs beyond them.
 *
 * - Time is an integer count of ticks; simulated time is `tick × step`, never a float sum.
 * - Frame time is quantised to whole nanoseconds and accumulated as integers, so with no
 *   overload, after any sequence of frames, `ticks = floor(elapsed / step)` exactly.
 * - A frame Δt that is negative, NaN or infinite counts as 0 (time never runs backwards).
 * - The accumulator is clamped; a cap on steps per frame applies an explicit overload policy; all
 *   dropped time is counted per reason and reported through `onDrop`.
 * - Pause, resume, single-step, a deterministic time scale, a hidden-tab policy, hysteresis.
 *
 * It allocates nothing per frame.
 *
 * @example
 * const loop = new FixedLoop({ step: 60 });
 * function onFrame(now: number) {
 *   const n = loop.frame(now);
 *   for (let i = 0; i < n; i++) world.step(loop.dt);
 *   render(loop.alpha);
 * }
 */
export class FixedLoop implements Loop {
  /** Which loop this is: the production fixed-step loop. */
  readonly kind = 'fixed' as const;
  /** The fixed step (exact), from {@link FixedLoopOptions.step}. Never changes. */
  readonly step: Timestep;
  /** Upper bound of the accumulator, in ms (see {@link FixedLoopOptions.maxAccumulatorMs}). */
  readonly maxAccumulatorMs: number;
  /** The most steps one frame runs (see {@link FixedLoopOptions.maxStepsPerFrame}). */
  readonly maxStepsPerFrame: number;
  /** What happens to steps beyond the cap (see {@link OverloadPolicy}). */
  readonly overload: OverloadPolicy;
  /** What happens to time spent hidden (see {@link HiddenPolicy}). */
  readonly hiddenPolicy: HiddenPolicy;
  /** Hysteresis, as a fraction of a step in [0, 0.5] (see {@link FixedLoopOptions.hysteresis}). */
  readonly hysteresis: number;

  private readonly unitsPerNs: number;
  private readonly unitsPerStep: number;
  private readonly maxUnits: number;
  private readonly hystUnits: number;
  private readonly onDrop: ((ms: number, reason: DropReason) => void) | undefined;

  private acc = 0; // units
  private accAtFrame = 0; // units: the accumulator before this frame's steps were taken off
  private nowNs = 0; // the loop's time line: last clock reading, or sum of deltas
  private started = false;
  private scale = 1;
  private paused = false;
  private isHidden = false;
  private skipNext = false;
  private pendingSingleSteps = 0;
  private frameWasPaused = false;

  private tickCount = 0;
  private frameCount = 0;
  private steps = 0;
  private maxSteps = 0;
  private droppedClamp = 0; // units
  private droppedOverload = 0; // units
  private droppedHidden = 0; // units
  private pausedNs = 0;
  private invalid = 0;
  private backwards = 0;
  /** Early clock readings that ran back, for the delta-as-timestamp check. */
  private stuckReadings = 0;
  /** Consecutive early readings equal to the last one, for the same check (a constant delta). */
  private stillReadings = 0;
  private readonly warn: ((message: string) => void) | null;
  private readonly warned = new Set<LoopWarning>();

  constructor(options: FixedLoopOptions) {
    this.step = Timestep.from(options.step);
    this.unitsPerNs = this.step.unitsPerNs;
    this.unitsPerStep = this.step.unitsPerStep;

    this.maxAccumulatorMs = options.maxAccumulatorMs ?? 250;
    const maxNs = Math.round(this.maxAccumulatorMs * 1e6);
    // Within a nanosecond of one step (e.g. 1000 / 30 ms for a 30 Hz step) counts as one step.
    this.maxUnits = Math.max(maxNs * this.unitsPerNs, this.unitsPerStep);
    if (
      !Number.isFinite(this.maxAccumulatorMs) ||
      (maxNs + 1) * this.unitsPerNs < this.unitsPerStep ||
      maxNs > 3.6e12
    ) {
      throw new RangeError(
        `FixedLoop: maxAccumulatorMs must be from one step (${this.step.ms} ms) to 1 hour, got ${String(this.maxAccumulatorMs)}`,
      );
    }

    this.maxStepsPerFrame = options.maxStepsPerFrame ?? 8;
    if (
      !Number.isInteger(this.maxStepsPerFrame) ||
      this.maxStepsPerFrame < 1 ||
      this.maxStepsPerFrame > 100_000
    ) {
      throw new RangeError(
        `FixedLoop: maxStepsPerFrame must be an integer from 1 to 100000, got ${String(this.maxStepsPerFrame)}`,
      );
    }

    this.overload = options.overload ?? 'catch-up';
    if (!POLICIES.includes(this.overload)) {
      throw new RangeError(
        `FixedLoop: overload must be one of ${POLICIES.join(', ')}, got ${this.overload as string}`,
      );
    }
    this.hiddenPolicy = options.hidden ?? 'pause';
    if (!HIDDEN.includes(this.hiddenPolicy)) {
      throw new RangeError(
        `FixedLoop: hidden must be one of ${HIDDEN.join(', ')}, got ${this.hiddenPolicy as string}`,
      );
    }

    this.hysteresis = options.hysteresis ?? 0;
    if (!(this.hysteresis >= 0 && this.hysteresis <= 0.5)) {
      throw new RangeError(
        `FixedLoop: hysteresis must be from 0 to 0.5 of a step, got ${String(this.hysteresis)}`,
      );
    }
    this.hystUnits = Math.round(this.hysteresis * this.unitsPerStep);
    this.onDrop = options.onDrop;
    this.warn =
      options.onWarning === undefined
        ? (m) => {
            console.warn(m);
          }
        : options.onWarning;
    this.setTimeScale(options.timeScale ?? 1);
  }

  // ---------------------------------------------------------------- feeding frames

  /**
   * Feed one frame by a clock reading in ms. Readings are quantised to whole nanoseconds before
   * they are subtracted, so deltas telescope exactly. A reading that is NaN or infinite counts as
   * no time; a reading earlier than the last one counts as no time and becomes the new baseline
   * (the talk's `dt = max(0, now - last)`).
   * @returns how many steps to run now.
   */
  frame(nowMs: number): number {
    if (!Number.isFinite(nowMs)) {
      this.invalid++;
      return this.accumulate(0);
    }
    const ns = Math.round(nowMs * 1e6);
    if (!this.started) {
      this.started = true;
      this.nowNs = ns;
      return this.accumulate(0);
    }
    let dt = ns - this.nowNs;
    this.nowNs = ns;
    if (dt < 0) {
      this.backwards++;
      dt = 0;
      this.checkReadings(nowMs);
    } else if (dt === 0) {
      this.checkStill(nowMs);
    } else {
      this.stillReadings = 0;
    }
    return this.accumulate(dt);
  }

  /**
   * A frame delta passed where a timestamp belongs looks like a clock that keeps running back:
   * readings of a few ms that jitter around one value. Three backward steps among the first sixty
   * frames, each to a reading under 10 s, is no real clock (a clock that is paused stands still
   * without going back; a clock set back once is one step).
   */
  private checkReadings(nowMs: number): void {
    if (this.frameCount >= 60 || this.warn === null || nowMs >= 10_000) return;
    if (++this.stuckReadings >= 3) {
      this.warnOnce(
        'delta-as-timestamp',
        `FixedLoop.frame(nowMs) expects a clock reading in ms (a requestAnimationFrame timestamp, performance.now()), but ${this.stuckReadings} of the first ${this.frameCount + 1} readings ran back (last ${nowMs} ms): if your engine gives you a frame delta, call loop.advance(deltaMs, nowMs) instead.`,
      );
    }
  }

  /**
   * A constant frame delta passed where a timestamp belongs never runs back: it stands still, and
   * no tick ever runs. A clock can stand still too (paused, or a simulated clock not advanced),
   * but not at a reading under a second — a page open for less than a second — for thirty
   * frames in a row among the first sixty; a frame delta is just such a reading (16.7 ms).
   * A reading of 0 is a clock that has not started, not a delta.
   */
  private checkStill(nowMs: number): void {
    if (this.frameCount >= 60 || this.warn === null || !(nowMs > 0 && nowMs < 1000)) return;
    if (++this.stillReadings >= 30) {
      this.warnOnce(
        'delta-as-timestamp',
        `FixedLoop.frame(nowMs) expects a clock reading in ms (a requestAnimationFrame timestamp, performance.now()), but the last ${this.stillReadings} readings were all ${nowMs} ms: the clock does not advance, so no tick runs (tick ${this.tick}). That is a constant frame delta, not a timestamp: call loop.advance(deltaMs, nowMs) instead.`,
      );
    }
  }

  private warnOnce(kind: LoopWarning, message: string): void {
    if (this.warn === null || this.warned.has(kind)) return;
    this.warned.add(kind);
    this.warn(message);
  }

  /**
   * Feed one frame by its Δt in ms — the entry point for engines that only give frame deltas,
   * with the same exact integer time as {@link frame}. Negative, NaN or infinite Δt counts as 0;
   * a Δt is quantised to whole nanoseconds. Deltas above 2^53 ns (104 days) lose exactness in the
   * counters.
   *
   * The loop's time line — where input events are placed on ticks — is the sum of the deltas,
   * unless `nowMs` gives this frame's clock reading: pass it whenever input events carry
   * timestamps (`event.timeStamp` in a browser), or they land on the wrong ticks.
   * @returns how many steps to run now.
   */
  advance(dtMs: number, nowMs?: number): number {
    this.started = true;
    let dt = Math.round(dtMs * 1e6);
    if (!(dt >= 0) || dt === Infinity) {
      if (dtMs < 0) this.backwards++;
      else this.invalid++;
      dt = 0;
    }
    if (nowMs !== undefined && Number.isFinite(nowMs)) this.nowNs = Math.round(nowMs * 1e6);
    else this.nowNs += dt;
    return this.accumulate(dt);
  }

  private accumulate(dtNs: number): number {
    this.frameCount++;
    this.frameWasPaused = this.paused;

    if (this.isHidden || this.skipNext) {
      this.skipNext = false;
      if (this.hiddenPolicy === 'pause') {
        if (dtNs > 0) this.drop(this.scaled(dtNs) * this.unitsPerNs, 'hidden');
        dtNs = 0;
      }
    }

    if (this.paused) {
      this.pausedNs += dtNs;
      const n = this.pendingSingleSteps;
      this.pendingSingleSteps = 0;
      this.accAtFrame = this.acc;
      return this.took(n);
    }

    let a = this.acc + this.scaled(dtNs) * this.unitsPerNs;
    if (a > this.maxUnits) {
      this.drop(a - this.maxUnits, 'clamp');
      a = this.maxUnits;
    }
    this.accAtFrame = a;

    const p = this.unitsPerStep;
    const due = floorDiv(a + this.hystUnits, p);
    let n = due;
    if (due > this.maxStepsPerFrame) {
      n = this.maxStepsPerFrame;
      if (this.overload === 'drop') {
        const excess = (due - n) * p;
        this.drop(excess, 'overload');
        a -= excess;
      } else if (this.overload === 'reset') {
        const rest = a - n * p;
        if (rest > 0) this.drop(rest, 'overload');
        a = n * p;
      }
    }
    this.acc = a - n * p;
    return this.took(n);
  }

  private took(n: number): number {
    this.tickCount += n;
    this.steps = n;
    if (n > this.maxSteps) this.maxSteps = n;
    return n;
  }

  private scaled(dtNs: number): number {
    return this.scale === 1 ? dtNs : Math.round(dtNs * this.scale);
  }

  private drop(units: number, reason: DropReason): void {
    if (reason === 'clamp') this.droppedClamp += units;
    else if (reason === 'overload') this.droppedOverload += units;
    else this.droppedHidden += units;
    this.onDrop?.(units / this.unitsPerNs / 1e6, reason);
  }

  // ---------------------------------------------------------------- controls

  /** Stop simulated time: frames still arrive, but no steps run until {@link resume}. */
  pause(): void {
    this.paused = true;
  }

  /** Resume after {@link pause}. The time spent paused is not simulated (see {@link pausedMs}). */
  resume(): void {
    this.paused = false;
    this.pendingSingleSteps = 0;
  }

  /** Whether the loop is paused ({@link pause}). */
  get isPaused(): boolean {
    return this.paused;
  }

  /** While paused: run exactly one step on the next frame. Ignored while running. */
  singleStep(): void {
    if (this.paused) this.pendingSingleSteps++;
  }

  /**
   * Set the time scale (0 to 64): how fast simulated time runs against real time. The step size
   * never changes, so the same ticks with the same inputs still give the same state.
   */
  setTimeScale(scale: number): void {
    if (!(Number.isFinite(scale) && scale >= 0 && scale <= 64)) {
      throw new RangeError(
        `FixedLoop: time scale must be a finite number from 0 to 64, got ${String(scale)}`,
      );
    }
    this.scale = scale;
  }

  /** The time scale: simulated seconds per real second (0 to 64; see {@link setTimeScale}). */
  get timeScale(): number {
    return this.scale;
  }

  /**
   * Tell the loop the page is hidden (or visible again). With the `'pause'` policy, the time the
   * page spends hidden — including the long first frame after it returns — is dropped and counted,
   * so there is no fast-forward storm on return.
   */
  setHidden(hidden: boolean): void {
    if (this.isHidden && !hidden) this.skipNext = true;
    this.isHidden = hidden;
  }

  /** Whether the loop was told the page is hidden ({@link setHidden}). */
  get hidden(): boolean {
    return this.isHidden;
  }

  // ---------------------------------------------------------------- reading

  /** The Δt in seconds for every step: the fixed step. */
  get dt(): number {
    return this.step.seconds;
  }

  /** Steps run so far (the tick count). */
  get tick(): number {
    return this.tickCount;
  }

  /** Steps run so far: the same as {@link tick} (the {@link Loop} interface's name). */
  get updates(): number {
    return this.tickCount;
  }

  /** Simulated time in seconds: `tick × step`. */
  get simTime(): number {
    return this.tickCount * this.step.seconds;
  }

  /**
   * Interpolation factor in [0, 1): how far real time has gone past the last step, in steps.
   * Render `previous + (current - previous) × alpha`.
   */
  get alpha(): number {
    const p = this.unitsPerStep;
    const a = this.acc + this.hystUnits;
    if (a <= 0) return 0;
    return a >= p ? (p - 1) / p : a / p;
  }

  /** Time in the accumulator (owed to the simulation), in ms. */
  get accumulatorMs(): number {
    return this.acc / this.unitsPerNs / 1e6;
  }

  /** Exact accumulator in loop units (see {@link Timestep.unitsPerStep}). */
  get accumulatorUnits(): number {
    return this.acc;
  }

  /** Frames fed so far. */
  get frames(): number {
    return this.frameCount;
  }

  /** Steps run by the last frame. */
  get lastSteps(): number {
    return this.steps;
  }

  /** The most steps any frame has run. */
  get maxStepsSeen(): number {
    return this.maxSteps;
  }

  /** Time dropped so far, in ms: for one reason, or in all. */
  droppedMs(reason?: DropReason): number {
    return this.droppedUnits(reason) / this.unitsPerNs / 1e6;
  }

  /** Exact dropped time in loop units: for one reason, or in all. */
  droppedUnits(reason?: DropReason): number {
    if (reason === 'clamp') return this.droppedClamp;
    if (reason === 'overload') return this.droppedOverload;
    if (reason === 'hidden') return this.droppedHidden;
    return this.droppedClamp + this.droppedOverload + this.droppedHidden;
  }

  /** Real time spent paused, in ms. */
  get pausedMs(): number {
    return this.pausedNs / 1e6;
  }

  /** Frames whose Δt was NaN or infinite. */
  get invalidFrames(): number {
    return this.invalid;
  }

  /** Frames whose clock ran backwards. */
  get backwardFrames(): number {
    return this.backwards;
  }

  /** The loop's time line in ms: the last clock reading, or the sum of the deltas fed. */
  get nowMs(): number {
    return this.nowNs / 1e6;
  }

  /**
   * Whether an input event at `timeMs` (ms, on the loop's time line: the readings given to
   * {@link frame}, or `advance`'s `nowMs`) happened before step `j` (0-based) of the current
   * frame ends — so a sampler gives each event to the step whose time span holds it, the same on
   * every display. An event more than 5 s ahead of the time line is reported once through
   * {@link FixedLoopOptions.onWarning} (it cannot be on it).
   */
  isBeforeUpdateEnd(timeMs: number, j: number): boolean {
    const t = Math.round(timeMs * 1e6);
    // An event more than 5 s ahead of the frames cannot be on their time line.
    if (t - this.nowNs > 5e9 && this.warn !== null) {
      this.warnOnce(
        'input-time-line',
        `FixedLoop: an input event at ${timeMs.toFixed(1)} ms is ${((t - this.nowNs) / 1e6).toFixed(0)} ms ahead of the loop's clock (${this.nowMs.toFixed(1)} ms): events and frames must share one time line (event.timeStamp and the requestAnimationFrame timestamp do). Driving the loop with advance(delta)? Pass the frame's clock reading too: advance(deltaMs, nowMs).`,
      );
    }
    if (this.frameWasPaused) return t <= this.nowNs;
    // Step j of this frame ends (accAtFrame − (j+1)·step) units before now, in scaled time.
    // With hysteresis a step may run up to h early, before its end has come; so every step's
    // input window closes h before its end, on every display alike — otherwise a press in that
    // last h would land in this step on one display and in the next on another.
    const lead = this.accAtFrame + this.hystUnits - (j + 1) * this.unitsPerStep;
    const ago = (this.nowNs - t) * this.unitsPerNs;
    return (this.scale === 1 ? ago : ago * this.scale) > lead;
  }
}

/** floor(a / b) for non-negative integers below 2^53, exact (float division can round up). */
function floorDiv(a: number, b: number): number {
  if (a < b) return 0;
  let q = Math.floor(a / b);
  if (q * b > a) q--;
  else if ((q + 1) * b <= a) q++;
  return q;
}
