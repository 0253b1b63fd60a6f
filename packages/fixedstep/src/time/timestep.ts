/**
 * A fixed simulation step, held as an exact rational number of nanoseconds.
 *
 * Why rational: 1/60 s is 16 666 666.6… ns, which no float or integer holds exactly. The loop
 * counts time in *units* of `1 / unitsPerNs` nanoseconds, chosen so that one step is a whole
 * number of units (`unitsPerStep`). Every frame delta is first quantised to whole nanoseconds,
 * then multiplied by `unitsPerNs`; from there on all arithmetic is on integers below 2^53, so
 * "ticks run = floor(elapsed / step)" holds exactly, with no drift, forever.
 */
export class Timestep {
  /** The step in seconds, as passed to a simulation's update. Constant for the life of a loop. */
  readonly seconds: number;
  /** The step in milliseconds (for display). */
  readonly ms: number;
  /** Ticks per second (may be non-integer, e.g. 33.33… for a 0.03 s step). */
  readonly hz: number;
  /** How many loop units make one nanosecond (a positive integer). */
  readonly unitsPerNs: number;
  /** How many loop units make one step (a positive integer). */
  readonly unitsPerStep: number;

  private constructor(unitsPerStep: number, unitsPerNs: number, seconds: number) {
    this.unitsPerStep = unitsPerStep;
    this.unitsPerNs = unitsPerNs;
    this.seconds = seconds;
    this.ms = seconds * 1000;
    this.hz = 1 / seconds;
  }

  /**
   * A step of `1 / hz` seconds. `hz` must be an integer from 1 to 100 000.
   * @example Timestep.fromHz(60) // 16.67 ms
   */
  static fromHz(hz: number): Timestep {
    if (!Number.isInteger(hz) || hz < 1 || hz > 100_000) {
      throw new RangeError(
        `Timestep.fromHz: tick rate must be an integer from 1 to 100000 Hz, got ${String(hz)}`,
      );
    }
    const g = gcd(1_000_000_000, hz);
    return new Timestep(1_000_000_000 / g, hz / g, 1 / hz);
  }

  /**
   * A step of `ms` milliseconds, which must be a whole number of nanoseconds from 1 µs to 10 s.
   * @example Timestep.fromMs(30) // the talk's TIME_STEP = 0.03
   */
  static fromMs(ms: number): Timestep {
    const ns = Math.round(ms * 1e6);
    if (
      !Number.isFinite(ms) ||
      ns < 1000 ||
      ns > 10_000_000_000 ||
      Math.abs(ns - ms * 1e6) > 1e-6 * Math.max(1, ns)
    ) {
      throw new RangeError(
        `Timestep.fromMs: step must be from 0.001 to 10000 ms in whole nanoseconds, got ${String(ms)}`,
      );
    }
    return new Timestep(ns, 1, ns / 1e9);
  }

  /**
   * Accepts a Timestep, a number of ticks per second, or anything with a `tickRate` — a game
   * definition, so the tick rate is written in one place: `new FixedLoop({ step: game })`.
   */
  static from(step: Timestep | number | { readonly tickRate: number }): Timestep {
    if (typeof step === 'number') return Timestep.fromHz(step);
    if (step instanceof Timestep) return step;
    const given: unknown = step; // JavaScript callers may pass anything
    if (typeof given === 'object' && given !== null && 'tickRate' in given) {
      return Timestep.fromHz((given as { tickRate: number }).tickRate);
    }
    throw new RangeError('Timestep.from: expects a Timestep, a tick rate in Hz, or { tickRate }');
  }

  /** Simulated time in seconds after `tick` steps: a product, never a running float sum. */
  timeAt(tick: number): number {
    return tick * this.seconds;
  }
}

function gcd(a: number, b: number): number {
  while (b !== 0) {
    const t = a % b;
    a = b;
    b = t;
  }
  return a;
}
