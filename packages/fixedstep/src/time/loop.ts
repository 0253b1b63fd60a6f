/**
 * What every loop does, from the talk's frame-locked loop to the production {@link FixedLoop}:
 * turn display frames into a number of updates to run now, each with a Δt.
 *
 * A loop never runs the simulation itself and never reads a clock: it is handed clock readings
 * ({@link Loop.frame}) or frame deltas ({@link Loop.advance}) and answers how many updates are
 * due. That is what lets the lab run four loops side by side on one simulated display, and lets
 * tests fake any display exactly.
 */
export interface Loop {
  /** Which loop this is. */
  readonly kind: LoopKind;
  /**
   * Feed one display frame by a clock reading in milliseconds (e.g. a `requestAnimationFrame`
   * timestamp or `performance.now()`). The first call only sets the baseline.
   * @returns how many updates to run now, each with {@link Loop.dt}.
   */
  frame(nowMs: number): number;
  /**
   * Feed one display frame by the time elapsed since the previous one, in milliseconds — for
   * engines that only hand out frame deltas. `nowMs`, the frame's clock reading, puts the loop's
   * time line where input events are timestamped (without it the time line is the sum of deltas).
   * @returns how many updates to run now, each with {@link Loop.dt}.
   */
  advance(dtMs: number, nowMs?: number): number;
  /** The Δt in seconds to pass to each update of the current frame. */
  readonly dt: number;
  /** Render interpolation factor between the previous and the current state, in [0, 1). */
  readonly alpha: number;
  /** Simulated time in seconds, as this loop understands it. */
  readonly simTime: number;
  /** Updates run so far. */
  readonly updates: number;
  /** Updates run by the last frame. */
  readonly lastSteps: number;
  /**
   * Whether an input event at `timeMs` (on the same time line as the frame readings) happened
   * before the end of update `j` (0-based) of the current frame. Lets an input sampler give each
   * event to the update whose time span contains it, whatever the frame rate.
   */
  isBeforeUpdateEnd(timeMs: number, j: number): boolean;
}

/** The four loops of the talk, then the production loop. */
export type LoopKind = 'frame-locked' | 'variable' | 'fixed-naive' | 'fixed-final' | 'fixed';
