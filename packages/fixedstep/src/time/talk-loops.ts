import type { Loop, LoopKind } from './loop.js';

/**
 * The talk's loops, written as on the slides so the lab can show what each gets wrong. They keep
 * the slides' float arithmetic on purpose. Use {@link FixedLoop} in real code.
 */
abstract class TalkLoop implements Loop {
  abstract readonly kind: LoopKind;
  dt = 0;
  alpha = 0;
  updates = 0;
  lastSteps = 0;
  /** The loop's time line in ms (last clock reading, or sum of deltas). */
  nowMs = 0;
  private started = false;

  /** `dt = GetCurrentTime() - lastUpdateTime; lastUpdateTime = now` — no sanitising. */
  frame(nowMs: number): number {
    if (!this.started) {
      this.started = true;
      this.nowMs = nowMs;
      return this.advance(0);
    }
    const dt = nowMs - this.nowMs;
    return this.advance(dt, nowMs);
  }

  advance(dtMs: number, nowMs = this.nowMs + dtMs): number {
    this.nowMs = nowMs;
    const n = this.onFrame(dtMs);
    this.lastSteps = n;
    this.updates += n;
    return n;
  }

  protected abstract onFrame(dtMs: number): number;
  abstract readonly simTime: number;
  abstract isBeforeUpdateEnd(timeMs: number, j: number): boolean;
}

/**
 * One update per rendered frame and no time at all (`velocity += acceleration`): the game was
 * tuned for `designHz`, so each update is handed `1 / designHz` s. "The faster the computer, the
 * faster time runs": at 144 Hz it runs 2.4× faster than at 60 Hz.
 */
export class FrameLockedLoop extends TalkLoop {
  readonly kind = 'frame-locked' as const;
  constructor(readonly designHz = 60) {
    super();
    this.dt = 1 / designHz;
  }
  protected onFrame(): number {
    return 1;
  }
  get simTime(): number {
    return this.updates / this.designHz;
  }
  isBeforeUpdateEnd(timeMs: number): boolean {
    return timeMs <= this.nowMs;
  }
}

/**
 * The naive real-time loop: one update per frame with the frame's Δt, whatever it is — huge after
 * a hitch, negative when the clock jumps back. Unpredictable physics, exploding springs, tunnelling.
 */
export class VariableLoop extends TalkLoop {
  readonly kind = 'variable' as const;
  private time = 0;
  protected onFrame(dtMs: number): number {
    this.dt = dtMs / 1000;
    this.time += this.dt;
    return 1;
  }
  get simTime(): number {
    return this.time;
  }
  isBeforeUpdateEnd(timeMs: number): boolean {
    return timeMs <= this.nowMs;
  }
}

/**
 * The accumulator as on the slides: `accumulator += dt; while (accumulator > TIME_STEP) …`.
 * No clamp, no cap, no guard against a negative Δt: a long hitch runs every owed step at once
 * (the spiral of death), a clock that jumps back freezes the game, a NaN stops it for good.
 */
export class NaiveFixedLoop extends TalkLoop {
  readonly kind: LoopKind = 'fixed-naive';
  /** The accumulator in ms (a float, as on the slides). */
  accumulator = 0;
  private frameAcc = 0;
  constructor(readonly stepMs = 30) {
    super();
    this.dt = stepMs / 1000;
  }
  protected addTime(dtMs: number): void {
    this.accumulator += dtMs;
  }
  protected onFrame(dtMs: number): number {
    this.addTime(dtMs);
    this.frameAcc = this.accumulator;
    let n = 0;
    while (this.accumulator > this.stepMs) {
      this.accumulator -= this.stepMs;
      n++;
    }
    this.alpha = this.accumulator > 0 ? Math.min(this.accumulator / this.stepMs, 1 - 1e-12) : 0;
    return n;
  }
  get simTime(): number {
    return this.updates * this.dt;
  }
  isBeforeUpdateEnd(timeMs: number, j: number): boolean {
    return this.nowMs - timeMs > this.frameAcc - (j + 1) * this.stepMs;
  }
}

/**
 * The talk's final fixes: `dt = max(0, now - last)` and
 * `accumulator = clamp(accumulator + dt, 0, MAX_ACCUM_TIME)` with `MAX_ACCUM_TIME = 1.0 s`.
 */
export class FinalFixedLoop extends NaiveFixedLoop {
  override readonly kind = 'fixed-final' as const;
  constructor(
    stepMs = 30,
    readonly maxAccumMs = 1000,
  ) {
    super(stepMs);
  }
  protected override addTime(dtMs: number): void {
    this.accumulator = Math.min(Math.max(this.accumulator + Math.max(0, dtMs), 0), this.maxAccumMs);
  }
}
