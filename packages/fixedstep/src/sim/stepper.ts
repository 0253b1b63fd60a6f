import type { Loop } from '../time/loop.js';
import type { ButtonInput } from './buttons.js';
import type { InputSampler } from './input.js';

/** Options of a {@link FrameStepper}. */
export interface FrameStepperOptions<I = ButtonInput> {
  /** The loop that decides how many steps each display frame runs (a `FixedLoop`, or a talk loop). */
  loop: Loop;
  /**
   * One step of the simulation: `dt` in seconds (always the fixed step for a fixed loop), the
   * local player's input for this tick, and every local player's input for this tick, in the
   * order of {@link FrameStepperOptions.inputs} (`[input]` with one source). Call
   * `sim.step([input])` — or, with several local players, `sim.step(inputs)` — here. `inputs` is
   * reused from step to step: copy it to keep it.
   */
  update: (dt: number, input: I, inputs: readonly I[]) => void;
  /** Draw the current state; `alpha` in [0, 1) interpolates from the previous state. */
  render?: (alpha: number) => void;
  /** Where each step's input comes from. Without one, every step gets `neutral`. */
  input?: InputSampler<I>;
  /**
   * Several local players' input sources instead of {@link input}, one sampler per player — two
   * players on one keyboard (each sampler attached with its own keys), or a keyboard and a
   * gamepad. Each step samples each of them for its tick, in this order.
   */
  inputs?: readonly InputSampler<I>[];
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
 *
 * @example
 * // Two players on one keyboard: one sampler each, stepped together.
 * const left = new InputSampler(input), right = new InputSampler(input);
 * attachKeyboard(window, left, { KeyW: 'up', KeyS: 'down' });
 * attachKeyboard(window, right, { ArrowUp: 'up', ArrowDown: 'down' });
 * const stepper = new FrameStepper({
 *   loop: new FixedLoop({ step: game }),
 *   inputs: [left, right],
 *   update: (_dt, _first, inputs) => sim.step(inputs),
 * });
 */
export class FrameStepper<I = ButtonInput> {
  readonly loop: Loop;
  private readonly update: (dt: number, input: I, inputs: readonly I[]) => void;
  private readonly render: ((alpha: number) => void) | undefined;
  private readonly samplers: readonly InputSampler<I>[];
  /** This step's inputs, one per local player (reused). */
  private readonly current: I[];

  constructor(options: FrameStepperOptions<I>) {
    this.loop = options.loop;
    this.update = options.update;
    this.render = options.render;
    if (options.input !== undefined && options.inputs !== undefined) {
      throw new RangeError('FrameStepper: pass input (one player) or inputs (several), not both');
    }
    if (options.inputs?.length === 0) {
      throw new RangeError('FrameStepper: inputs needs at least one sampler, got none');
    }
    this.samplers = [...(options.inputs ?? (options.input ? [options.input] : []))];
    this.current = [options.neutral ?? (0 as I)];
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
    const samplers = this.samplers;
    const current = this.current;
    for (let j = 0; j < n; j++) {
      for (let p = 0; p < samplers.length; p++) current[p] = samplers[p]!.sample(loop, j);
      this.update(loop.dt, current[0]!, current);
    }
    this.render?.(loop.alpha);
    return n;
  }
}
