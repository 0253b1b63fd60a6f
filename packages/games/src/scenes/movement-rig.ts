import {
  ButtonSampler,
  FixedLoop,
  SimulatedDisplay,
  type ButtonInput,
  type DisplayEvent,
  type DisplayFrame,
  type Loop,
} from 'fixedstep';
import { makeLoop, type LoopSpec, type ScriptedInput } from './loops.js';

/** What a {@link SceneRig} drives: one update with a Δt in seconds and one tick's buttons. */
export interface SteppedScene {
  update(dt: number, input: ButtonInput): void;
}

export interface SceneRigOptions<S extends SteppedScene> {
  /** The loop, or how to build one (see {@link makeLoop}). */
  loop: LoopSpec | Loop;
  /** The simulated display whose frames feed the loop. */
  display: { hz: number; jitter?: number; seed?: number; events?: readonly DisplayEvent[] };
  scene: S;
  /** Timestamped button events, ms of display time from the start. */
  script?: readonly ScriptedInput[];
  /**
   * A slow machine: what one update costs, in ms of real time. Default 0. The display's next
   * frame waits for the work of every update the loop asked for — also the ones past
   * {@link stallGuard}, which are counted as owed instead of run.
   */
  updateCostMs?: number;
  /**
   * The most updates one frame really executes (default: no limit). A loop that asks for more
   * is one whose page would have stalled; the rest are counted in {@link SceneRig.owed}.
   */
  stallGuard?: number;
  /**
   * The clock the loop reads, as a function of display time in ms (default: the display time).
   * Lets a test or the lab make the clock jump backwards while frames keep coming.
   */
  clock?: (displayMs: number) => number;
  /** Called after every update, with the update's index in its frame. */
  onUpdate?: (scene: S, loop: Loop, j: number) => void;
}

/**
 * Any stepped scene, one loop and one simulated display, advanced a display frame at a time, with
 * scripted inputs sampled per update through a {@link ButtonSampler} — the generic form of
 * `LoopRig` (which is one, over the ball scene). {@link frame} takes the simulated display's next
 * frame; {@link frameAt} takes a frame time from elsewhere (the page's real clock).
 */
export class SceneRig<S extends SteppedScene> {
  readonly loop: Loop;
  readonly scene: S;
  readonly display: SimulatedDisplay;
  readonly sampler = new ButtonSampler();
  private readonly script: ScriptedInput[];
  private scriptAt = 0;
  /** What one update costs, ms of real time. */
  protected readonly costMs: number;
  private readonly guard: number;
  private readonly clock: (displayMs: number) => number;
  private readonly onUpdate: ((scene: S, loop: Loop, j: number) => void) | undefined;
  private readonly startMs: number;
  private pending: DisplayFrame;
  /** Display time of the last frame, ms from the start. */
  realMs = 0;
  /** Display time of the frame before the last one (−1 before the second frame). */
  previousMs = -1;
  /** Frames seen. */
  frames = 0;
  /** Updates the loop asked for in the last frame. */
  lastSteps = 0;
  /** The most updates asked for by one frame. */
  maxSteps = 0;
  /** Updates run so far. */
  updates = 0;
  /** Updates asked for but never run: the page would have stalled. */
  owed = 0;
  /** Real work of the last frame, ms (updates asked for × cost). */
  workMs = 0;
  /** The longest gap between two frames so far, ms. */
  longestFrameMs = 0;

  constructor(options: SceneRigOptions<S>) {
    this.loop = 'frame' in options.loop ? options.loop : makeLoop(options.loop);
    this.scene = options.scene;
    this.display = new SimulatedDisplay({
      ...options.display,
      events: options.display.events ? [...options.display.events] : [],
    });
    this.script = [...(options.script ?? [])].sort((a, b) => a.timeMs - b.timeMs);
    this.costMs = options.updateCostMs ?? 0;
    this.guard = options.stallGuard ?? Infinity;
    this.clock = options.clock ?? ((t) => t);
    this.onUpdate = options.onUpdate;
    this.startMs = this.display.now;
    this.pending = this.display.next(0);
  }

  /** Whether the loop asked for more updates in one frame than a page could run. */
  get stalled(): boolean {
    return this.owed > 0;
  }

  /** When the simulated display's next frame comes, in ms from the start. */
  get nextFrameAt(): number {
    return this.pending.time - this.startMs;
  }

  /** Advance one frame of the simulated display. Returns the number of updates run. */
  frame(): number {
    const n = this.frameAt(this.pending.time - this.startMs, this.pending.wasHidden);
    this.pending = this.display.next(this.workMs);
    return n;
  }

  /** Run every frame of the simulated display due at or before `tMs`. */
  advanceTo(tMs: number, onFrame?: (ran: number) => void): void {
    while (this.nextFrameAt <= tMs) {
      const n = this.frame();
      onFrame?.(n);
    }
  }

  /**
   * Advance one display frame at `tMs` from the start (not earlier than the last one);
   * `wasHidden` if the page was hidden since the last frame. Returns the number of updates run.
   */
  frameAt(tMs: number, wasHidden = false): number {
    if (this.frames > 0) {
      this.previousMs = this.realMs;
      this.longestFrameMs = Math.max(this.longestFrameMs, tMs - this.realMs);
    }
    this.realMs = tMs;
    while (this.scriptAt < this.script.length && this.script[this.scriptAt]!.timeMs <= tMs) {
      const e = this.script[this.scriptAt++]!;
      this.sampler.push(this.clock(e.timeMs), e.button, e.down);
    }
    const loop = this.loop;
    if (wasHidden && loop instanceof FixedLoop) {
      loop.setHidden(true);
      loop.setHidden(false);
    }
    this.frames++;
    const asked = loop.frame(this.clock(tMs));
    this.lastSteps = asked;
    if (asked > this.maxSteps) this.maxSteps = asked;
    const n = Math.min(asked, this.guard);
    this.owed += asked - n;
    for (let j = 0; j < n; j++) {
      this.scene.update(loop.dt, this.sampler.sample(loop, j));
      this.onUpdate?.(this.scene, loop, j);
    }
    this.updates += n;
    this.workMs = asked * this.costMs;
    return n;
  }

  /** Add scripted inputs (not earlier than the last frame); they merge in time order. */
  addInputs(events: readonly ScriptedInput[]): void {
    const rest = [...this.script.slice(this.scriptAt), ...events].sort(
      (a, b) => a.timeMs - b.timeMs,
    );
    this.script.length = this.scriptAt;
    this.script.push(...rest);
  }

  /** Advance frames of the simulated display until `ms` more of display time have passed. */
  runFor(ms: number): void {
    const end = this.realMs + ms;
    while (this.realMs < end) this.frame();
  }
}
