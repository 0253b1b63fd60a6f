import {
  ButtonSampler,
  SimulatedDisplay,
  type ButtonInput,
  type Loop,
  type SimulatedDisplayOptions,
} from 'fixedstep';
import type { Game } from '../game.js';

/** A button going down or up at a real time (the shape of the scenes' `ScriptedInput`). */
export interface TimedButton {
  /** ms from the start. */
  timeMs: number;
  /** 0–15. */
  button: number;
  down: boolean;
}

/** Options of a {@link RunnerRig}. */
export interface RunnerRigOptions {
  /** The game (the runner, or any one-player {@link Game}). */
  game: Game;
  /** The loop that turns display frames into updates. */
  loop: Loop;
  /** The simulated display feeding the loop. */
  display: SimulatedDisplayOptions;
  /** Button events at real times (ms from the start), sampled per update. */
  script?: readonly TimedButton[];
  /** Called after every update with the game (e.g. to trace hashes or heights). */
  onUpdate?: (game: Game) => void;
}

/**
 * One game, one loop, one simulated display and a timestamped input script — the runner's
 * counterpart of the ball scene's `LoopRig`. Every update gets the input a {@link ButtonSampler}
 * assigns it. A loop whose Δt is the game's step calls `step()` (the deterministic path); any other
 * loop calls `update(dt)` (the variable-Δt demo).
 */
export class RunnerRig {
  readonly game: Game;
  readonly loop: Loop;
  readonly display: SimulatedDisplay;
  readonly sampler = new ButtonSampler();
  /** Real time of the last frame, ms from the start. */
  realMs = 0;
  private readonly script: TimedButton[];
  private scriptAt = 0;
  private readonly startMs: number;
  private readonly onUpdate: ((game: Game) => void) | undefined;
  private readonly inputs: ButtonInput[] = [0];

  constructor(options: RunnerRigOptions) {
    this.game = options.game;
    this.loop = options.loop;
    this.display = new SimulatedDisplay(options.display);
    this.script = [...(options.script ?? [])].sort((a, b) => a.timeMs - b.timeMs);
    this.onUpdate = options.onUpdate;
    this.startMs = this.display.now;
  }

  /** Take the display's next frame: queue the script's events up to it, run the updates due. */
  frame(): number {
    const t = this.display.next().time - this.startMs;
    this.realMs = t;
    while (this.scriptAt < this.script.length && this.script[this.scriptAt]!.timeMs <= t) {
      const e = this.script[this.scriptAt++]!;
      this.sampler.push(e.timeMs, e.button, e.down);
    }
    const loop = this.loop;
    const game = this.game;
    const n = loop.frame(t);
    const fixed = loop.dt === game.info.stepSeconds;
    for (let j = 0; j < n; j++) {
      this.inputs[0] = this.sampler.sample(loop, j);
      if (fixed) game.step(this.inputs);
      else game.update(loop.dt, this.inputs);
      this.onUpdate?.(game);
    }
    return n;
  }

  /** Take display frames until `ms` of real time from the start have passed. */
  runUntil(ms: number): void {
    while (this.realMs < ms) this.frame();
  }
}
