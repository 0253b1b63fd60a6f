import type { Loop } from '../time/loop.js';
import type { ButtonInput, ButtonSampler } from './input.js';

export interface RunnerOptions {
  /** The loop that decides how many updates each frame runs. */
  loop: Loop;
  /** One update of the simulation: `dt` in seconds (the fixed step, for a fixed loop). */
  update: (dt: number, input: ButtonInput) => void;
  /** Draw the current state; `alpha` in [0, 1) interpolates from the previous state. */
  render?: (alpha: number) => void;
  /** Where per-update input comes from. Without one, every update gets input 0. */
  input?: ButtonSampler;
}

/**
 * Ties a loop, an input sampler, a simulation's update and a renderer together: one call per
 * display frame. Allocates nothing per frame.
 *
 * @example
 * const runner = new Runner({ loop: new FixedLoop({ step: 60 }), update: (dt, input) => world.step(dt, input) });
 * new FrameDriver(animationFrameScheduler(), (now) => runner.frame(now)).start();
 */
export class Runner {
  readonly loop: Loop;
  private readonly update: (dt: number, input: ButtonInput) => void;
  private readonly render: ((alpha: number) => void) | undefined;
  private readonly input: ButtonSampler | undefined;

  constructor(options: RunnerOptions) {
    this.loop = options.loop;
    this.update = options.update;
    this.render = options.render;
    this.input = options.input;
  }

  /** Feed one display frame by a clock reading in ms. Returns the number of updates run. */
  frame(nowMs: number): number {
    return this.run(this.loop.frame(nowMs));
  }

  /** Feed one display frame by its Δt in ms. Returns the number of updates run. */
  advance(dtMs: number): number {
    return this.run(this.loop.advance(dtMs));
  }

  private run(n: number): number {
    const loop = this.loop;
    for (let j = 0; j < n; j++) {
      this.update(loop.dt, this.input ? this.input.sample(loop, j) : 0);
    }
    this.render?.(loop.alpha);
    return n;
  }
}
