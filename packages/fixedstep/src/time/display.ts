import { Random } from '../det/random.js';

/** A stretch of time on a simulated display: a hitch (no frame for a while) or a hidden tab. */
export interface DisplayEvent {
  kind: 'hitch' | 'hidden';
  /** When it starts, in ms from the display's start. */
  atMs: number;
  /** How long it lasts, in ms. */
  durationMs: number;
}

export interface SimulatedDisplayOptions {
  /** Refresh rate in Hz (e.g. 30, 59.94, 60, 144, 240). */
  hz: number;
  /** Frame-to-frame jitter as a fraction of the period, uniform in ±jitter (0 to 0.9). Default 0. */
  jitter?: number;
  /** Seed of the jitter. Default 1. */
  seed?: number;
  /** Hitches and hidden-tab periods. */
  events?: readonly DisplayEvent[];
  /** Time of the first frame, in ms. Default 0. */
  startMs?: number;
}

/** One frame of a {@link SimulatedDisplay}. */
export interface DisplayFrame {
  /** The frame's timestamp, in ms. */
  readonly time: number;
  /** The page was hidden since the previous frame (hand it to `loop.setHidden`). */
  readonly wasHidden: boolean;
}

/**
 * A display that exists only as numbers: frame timestamps at a chosen rate, with seeded jitter,
 * hitches, hidden-tab periods, and a "slow machine" whose frames wait for the work they did.
 * Repeatable: the same options give the same frames, so tests and the lab can fake any display.
 */
export class SimulatedDisplay {
  readonly hz: number;
  readonly periodMs: number;
  readonly jitter: number;
  private readonly rng: Random;
  private readonly events: DisplayEvent[];
  private t: number;
  private readonly start: number;
  private started = false;
  private frame = { time: 0, wasHidden: false };

  constructor(options: SimulatedDisplayOptions) {
    if (!(Number.isFinite(options.hz) && options.hz >= 1 && options.hz <= 1000)) {
      throw new RangeError(
        `SimulatedDisplay: hz must be from 1 to 1000, got ${String(options.hz)}`,
      );
    }
    const jitter = options.jitter ?? 0;
    if (!(jitter >= 0 && jitter <= 0.9)) {
      throw new RangeError(`SimulatedDisplay: jitter must be from 0 to 0.9, got ${String(jitter)}`);
    }
    this.hz = options.hz;
    this.periodMs = 1000 / options.hz;
    this.jitter = jitter;
    this.rng = new Random(options.seed ?? 1);
    this.start = options.startMs ?? 0;
    this.t = this.start;
    this.events = [...(options.events ?? [])].sort((a, b) => a.atMs - b.atMs);
  }

  /** The last frame's time, in ms. */
  get now(): number {
    return this.t;
  }

  /**
   * The next frame. `workMs` is how long the previous frame's work took (a slow machine): the
   * frame cannot come before it is done.
   */
  next(workMs = 0): DisplayFrame {
    if (!this.started) {
      this.started = true;
      this.frame = { time: this.t, wasHidden: false };
      return this.frame;
    }
    const u = this.jitter === 0 ? 0 : this.rng.range(-this.jitter, this.jitter);
    let next = this.t + Math.max(this.periodMs * (1 + u), workMs > 0 ? workMs : 0);
    let wasHidden = false;
    for (const e of this.events) {
      const at = this.start + e.atMs;
      if (at >= this.t && at < next) {
        next = Math.max(next, at + e.durationMs + this.periodMs * 0.5);
        if (e.kind === 'hidden') wasHidden = true;
      }
    }
    this.t = next;
    this.frame = { time: next, wasHidden };
    return this.frame;
  }
}
