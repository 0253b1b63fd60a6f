import type { DisplayEvent } from 'fixedstep';
import { BallButtons, BallScene, type BallConfig } from './ball.js';
import { SceneRig } from './movement-rig.js';
import type { LoopSpec, ScriptedInput } from './loops.js';

export { makeLoop } from './loops.js';
export type { LoopSpec, ScriptedInput } from './loops.js';

/** The loop chapter's script: two throws and a push to the right, all in the first 3 s. */
export function defaultBallScript(): ScriptedInput[] {
  return [
    { timeMs: 400, button: BallButtons.throw, down: true },
    { timeMs: 470, button: BallButtons.throw, down: false },
    { timeMs: 1210, button: BallButtons.right, down: true },
    { timeMs: 1710, button: BallButtons.right, down: false },
    { timeMs: 2300, button: BallButtons.throw, down: true },
    { timeMs: 2310, button: BallButtons.throw, down: false },
  ];
}

export interface LoopRigOptions {
  loop: LoopSpec;
  display: { hz: number; jitter?: number; seed?: number; events?: DisplayEvent[] };
  scene?: Partial<BallConfig>;
  script?: ScriptedInput[];
  /** A slow machine: what one update costs in ms of real time. Default 0. */
  updateCostMs?: number;
  /** The most updates one frame actually executes before the page is called stalled. Default 5000. */
  stallGuard?: number;
  /** Record the state after every update (for tests). Default false. */
  trace?: boolean;
}

/**
 * One loop, one ball scene and one simulated display: a {@link SceneRig} with the loop chapter's
 * script unless given another, a stall guard of 5000 updates, and a trace of the states. Unlike a
 * plain `SceneRig`, the display waits only for the work of the updates that ran (those past the
 * guard are owed, not worked on). The lab draws it; the tests assert on it; the bench times it.
 */
export class LoopRig extends SceneRig<BallScene> {
  /** States after each update, when tracing: update i at [i*6, i*6+6). */
  readonly trace: number[];

  constructor(options: LoopRigOptions) {
    const trace: number[] = [];
    super({
      loop: options.loop,
      display: options.display,
      scene: new BallScene(options.scene),
      script: options.script ?? defaultBallScript(),
      updateCostMs: options.updateCostMs,
      stallGuard: options.stallGuard ?? 5000,
      onUpdate: options.trace
        ? (scene) => {
            for (const v of scene.state) trace.push(v);
          }
        : undefined,
    });
    this.trace = trace;
  }

  override frameAt(tMs: number, wasHidden = false): number {
    const n = super.frameAt(tMs, wasHidden);
    this.workMs = n * this.costMs;
    return n;
  }
}
