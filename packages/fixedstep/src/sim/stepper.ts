import type { Loop } from '../time/loop.js';
import type { ButtonInput } from './buttons.js';
import type { InputSampler } from './input.js';

/** Options of a {@link FrameStepper}. */
export interface FrameStepperOptions<I = ButtonInput> {
  /** The loop that decides how many steps each display frame runs (a `FixedLoop`, or a talk loop). */
  loop: Loop;
  /**
   * One step of the simulation: `dt` in seconds (always the fixed step for a fixed loop) and the
   * local player's input for this tick. Call `sim.step([input])` (or your own update) here.
   */
  update: (dt: number, input: I) => void;
  /** Draw the current state; `alpha` in [0, 1) interpolates from the previous state. */
  render?: (alpha: number) => void;
  /** Where each step's input comes from. Without one, every step gets `neutral`. */
  input?: InputSampler<I>;
  /** The input of a step when there is no sampler. Default 0 (no buttons). */
  neutral?: I;
}

/**
 * Steps a simulation for each display frame: feeds the frame to the loop, runs the steps it owes
 * — each with the input sampled for its own tick — then renders with the loop's alpha. One call
 * per display frame; allocates nothing per frame (beyond what a schema with axes allocates per
 * sampled input).
 *
 * Feed it clock readings ({@link frame}: `requestAnimationFrame`'s timestamp, `performance.now()`,
 * Phaser's `time`) or, when an engine only hands out frame deltas, {@link advance} with the delta
 * and — so input timestamps still line up — the frame's clock reading.
 *
 * @example
 * const stepper = new FrameStepper({
 *   loop: new FixedLoop({ step: game }),          // the game's tick rate
 *   input: sampler,
 *   update: (_dt, input) => sim.step([input]),
 *   render: (alpha) => draw(sim, alpha),
 * });
 * new FrameDriver(animationFrameScheduler(), (now) => stepper.frame(now)).start();
 */
export class FrameStepper<I = ButtonInput> {
  readonly loop: Loop;
  private readonly update: (dt: number, input: I) => void;
  private readonly render: ((alpha: number) => void) | undefined;
  private readonly input: InputSampler<I> | undefined;
  private readonly neutral: I;

  constructor(options: FrameStepperOptions<I>) {
    this.loop = options.loop;
    this.update = options.update;
    this.render = options.render;
    this.input = options.input;
    this.neutral = options.neutral ?? (0 as I);
  }

  /** Feed one display frame by a clock reading in ms. Returns the number of steps run. */
  frame(nowMs: number): number {
    return this.run(this.loop.frame(nowMs));
  }

  /**
   * Feed one display frame by its Δt in ms (see `Loop.advance`). Pass the frame's clock reading
   * too when input events are timestamped (they are, in a browser): the loop then places them
   * on the right tick.
   */
  advance(dtMs: number, nowMs?: number): number {
    return this.run(this.loop.advance(dtMs, nowMs));
  }

  private run(n: number): number {
    const loop = this.loop;
    for (let j = 0; j < n; j++) {
      this.update(loop.dt, this.input ? this.input.sample(loop, j) : this.neutral);
    }
    this.render?.(loop.alpha);
    return n;
  }
}
