/**
 * The animation-frame driver every chapter runs on. On the simulated display it moves a virtual
 * clock forward by the real time that passed (at most {@link LabDriverOptions.maxFrameMs} per
 * frame, so a background tab pauses it); on the real clock it hands the chapter the page's own
 * `requestAnimationFrame` times, minus the time spent paused. Either way it then asks the chapter
 * to draw.
 */

export interface DriverHooks {
  /** Simulated display: move virtual time forward by `ms`. */
  advance(ms: number): void;
  /** Real clock: one display frame at `tMs` from the start of the real-clock run. */
  realFrame(tMs: number): void;
  /** Draw the current state. Called on every animation frame. */
  render(): void;
}

export interface LabDriverOptions {
  /** The most virtual time one animation frame may add, ms. Default 100. */
  maxFrameMs?: number;
  /**
   * On the real clock, a gap between animation frames longer than this (a background tab, a
   * breakpoint) is treated as a pause instead of being handed to the loops. Default: no limit
   * (the loops see real hidden tabs and hitches).
   */
  maxRealGapMs?: number;
}

export class LabDriver {
  private raf = 0;
  private last: number | undefined;
  private running = false;
  private paused = false;
  private offScreen = false;
  private real = false;
  private period = 0;
  private realStart: number | undefined;
  private pausedTotal = 0;
  private pausedAt: number | undefined;
  private readonly maxFrameMs: number;
  private readonly maxRealGapMs: number;

  constructor(
    private readonly hooks: DriverHooks,
    options: LabDriverOptions = {},
  ) {
    this.maxFrameMs = options.maxFrameMs ?? 100;
    this.maxRealGapMs = options.maxRealGapMs ?? Infinity;
  }

  start(): void {
    if (this.running) return;
    this.running = true;
    this.raf = requestAnimationFrame(this.frame);
  }

  destroy(): void {
    this.running = false;
    cancelAnimationFrame(this.raf);
  }

  get isPaused(): boolean {
    return this.paused;
  }

  get isReal(): boolean {
    return this.real;
  }

  /** The page's display rate as measured from animation frames, Hz (0 until known). */
  get measuredHz(): number {
    return this.period > 0 ? Math.round(1000 / this.period) : 0;
  }

  setPaused(paused: boolean): void {
    if (paused === this.paused) return;
    const was = this.halted;
    this.paused = paused;
    this.haltChanged(was);
  }

  /**
   * Stop time while none of the chapter's demos is on screen, and go on when one is: not a pause
   * the reader sees or makes ({@link isPaused} stays as it is), like a background tab.
   */
  setOffScreen(off: boolean): void {
    if (off === this.offScreen) return;
    const was = this.halted;
    this.offScreen = off;
    this.haltChanged(was);
  }

  /** Time stands: paused by the reader, or the demos are off screen. */
  private get halted(): boolean {
    return this.paused || this.offScreen;
  }

  /** The real clock leaves out the time time stood. */
  private haltChanged(was: boolean): void {
    const halted = this.halted;
    if (halted === was || !this.real) return;
    const now = performance.now();
    if (halted) this.pausedAt = now;
    else if (this.pausedAt !== undefined) {
      this.pausedTotal += now - this.pausedAt;
      this.pausedAt = undefined;
    }
  }

  /** Switch between the simulated display and the real clock; turning it on starts a new run. */
  setReal(on: boolean): void {
    this.real = on;
    if (on) this.restartReal();
  }

  /** Start the real-clock time line again at zero (with the next animation frame). */
  restartReal(): void {
    this.realStart = undefined;
    this.pausedTotal = 0;
    this.pausedAt = this.halted ? performance.now() : undefined;
  }

  /**
   * Where "now" is on the real-clock time line, ms (for stamping an input between frames), or
   * undefined before its first frame.
   */
  realNow(): number | undefined {
    if (this.realStart === undefined) return undefined;
    const now = this.pausedAt ?? performance.now();
    return now - this.realStart - this.pausedTotal;
  }

  /** Real time since the last animation frame, ms, capped like a frame (for stamping inputs). */
  sinceLastFrame(): number {
    if (this.last === undefined || this.halted) return 0;
    return Math.min(Math.max(0, performance.now() - this.last), this.maxFrameMs);
  }

  private readonly frame = (now: number): void => {
    if (!this.running) return;
    this.raf = requestAnimationFrame(this.frame);
    const last = this.last;
    this.last = now;
    const dt = last === undefined ? 0 : now - last;
    if (last !== undefined) this.period = this.period === 0 ? dt : this.period * 0.95 + dt * 0.05;
    if (this.real) {
      if (this.realStart === undefined) this.realStart = now;
      else if (!this.halted && dt > this.maxRealGapMs) this.pausedTotal += dt - this.period;
      if (!this.halted) this.hooks.realFrame(now - this.realStart - this.pausedTotal);
    } else if (!this.halted && last !== undefined) {
      this.hooks.advance(Math.min(Math.max(0, dt), this.maxFrameMs));
    }
    this.hooks.render();
  };
}
