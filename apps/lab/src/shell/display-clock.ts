/**
 * The time line of a chapter that plays something frame by frame on a chosen display: a
 * simulated one (frames at a rate with seeded jitter, computed, so every run repeats) or the
 * page's real animation frames. It owns "now" (ms from the start) and hands each display frame's
 * time to `onFrame`, never earlier than the one before. Switching displays mid-run goes on from
 * the last frame. Used by the games, replays and rigid-bodies chapters, whose models extend
 * {@link OnDisplayClock}.
 */
import { SimulatedDisplay } from 'fixedstep';

/**
 * The simulated display rates the chapters compare and offer, Hz: a slow display, the common one,
 * two fast ones.
 */
export const DISPLAY_RATES = [30, 60, 144, 240] as const;
export type DisplayRate = (typeof DISPLAY_RATES)[number];

/** A simulated display: its rate and its frame jitter (a fraction of the period, 0–0.3). */
export interface DisplaySpec {
  hz: number;
  jitter: number;
}

export class DisplayClock {
  private display: SimulatedDisplay | undefined;
  private spec: DisplaySpec | 'real';
  private nextFrame = 0;
  private last = 0;
  private now = 0;
  private realBase: number | undefined;

  constructor(
    spec: DisplaySpec | 'real',
    private readonly onFrame: (timeMs: number) => void,
  ) {
    this.spec = spec;
    this.start(0);
  }

  /** Now: ms from the start (the last time the clock was moved to). */
  get timeMs(): number {
    return this.now;
  }

  /** The time of the last display frame handed out, ms. */
  get lastFrameMs(): number {
    return this.last;
  }

  get displaySpec(): DisplaySpec | 'real' {
    return this.spec;
  }

  /** Switch the display (rate, jitter, or the real clock), going on from the last frame. */
  setDisplay(spec: DisplaySpec | 'real'): void {
    this.spec = spec;
    this.start(this.last);
  }

  /** Simulated display: move the clock to `ms`, handing out every display frame due by then. */
  advanceTo(ms: number): void {
    if (!(ms > this.now)) return;
    this.now = ms;
    const d = this.display;
    if (!d) return;
    while (this.nextFrame <= ms) {
      this.frame(this.nextFrame);
      this.nextFrame = d.next().time;
    }
  }

  advanceBy(ms: number): void {
    this.advanceTo(this.now + ms);
  }

  /**
   * Real clock: one display frame at `realMs` on the driver's time line. The first frame after
   * switching to the real clock pins that time line to this one.
   */
  realFrame(realMs: number): void {
    if (this.spec !== 'real') return;
    this.realBase ??= realMs - this.last;
    const t = Math.max(this.last, realMs - this.realBase);
    this.now = Math.max(this.now, t);
    this.frame(t);
  }

  /** This clock's time of a real-clock reading (for stamping input events). */
  timeOfReal(realMs: number): number {
    return this.realBase === undefined ? this.now : realMs - this.realBase;
  }

  private frame(t: number): void {
    if (t < this.last) t = this.last;
    this.last = t;
    this.onFrame(t);
  }

  private start(fromMs: number): void {
    this.realBase = undefined;
    if (this.spec === 'real') {
      this.display = undefined;
      return;
    }
    const { hz, jitter } = this.spec;
    this.display = new SimulatedDisplay({ hz, jitter, seed: hz, startMs: fromMs });
    this.display.next(); // the frame at fromMs, already taken
    this.nextFrame = this.display.next().time;
  }
}

/**
 * A chapter's model that plays on a {@link DisplayClock}: its time line, what the chapter's shell
 * drives, is the clock's.
 */
export abstract class OnDisplayClock {
  protected abstract clock: DisplayClock;

  /** The model's time: ms of the display's time line since the start. */
  get timeMs(): number {
    return this.clock.timeMs;
  }

  /** The model's time of a real-clock reading (for stamping input events between frames). */
  timeOfReal(realMs: number): number {
    return this.clock.timeOfReal(realMs);
  }

  /** Simulated display: move the clock to `ms`, taking every display frame due by then. */
  advanceTo(ms: number): void {
    this.clock.advanceTo(ms);
  }

  advanceBy(ms: number): void {
    this.clock.advanceBy(ms);
  }

  /** Real clock: one display frame at `realMs` on the driver's time line (see DisplayClock). */
  realFrame(realMs: number): void {
    this.clock.realFrame(realMs);
  }
}
