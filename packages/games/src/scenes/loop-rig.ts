import {
  ButtonSampler,
  FinalFixedLoop,
  FixedLoop,
  FrameLockedLoop,
  NaiveFixedLoop,
  SimulatedDisplay,
  Timestep,
  VariableLoop,
  type DisplayEvent,
  type DisplayFrame,
  type FixedLoopOptions,
  type Loop,
  type LoopKind,
} from 'fixedstep';
import { BallButtons, BallScene, type BallConfig } from './ball.js';

/** A scripted button event, at a real time in ms from the start. */
export interface ScriptedInput {
  timeMs: number;
  button: number;
  down: boolean;
}

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

export interface LoopSpec {
  kind: LoopKind;
  /** Step in ms for the fixed loops (default 1000/60 for 'fixed', 30 — the talk's — otherwise). */
  stepMs?: number;
  /** Options for the production loop. */
  fixed?: Partial<Omit<FixedLoopOptions, 'step'>>;
}

/** Builds one of the five loops. The talk's loops use its TIME_STEP = 0.03 s by default. */
export function makeLoop(spec: LoopSpec): Loop {
  switch (spec.kind) {
    case 'frame-locked':
      return new FrameLockedLoop(60);
    case 'variable':
      return new VariableLoop();
    case 'fixed-naive':
      return new NaiveFixedLoop(spec.stepMs ?? 30);
    case 'fixed-final':
      return new FinalFixedLoop(spec.stepMs ?? 30);
    case 'fixed':
      return new FixedLoop({
        ...spec.fixed,
        step: spec.stepMs === undefined ? 60 : stepFromMs(spec.stepMs),
      });
  }
}

/** 1000/60-style steps become a tick rate, so they stay exact; others a whole number of ns. */
function stepFromMs(ms: number): Timestep {
  const hz = 1000 / ms;
  return Math.abs(hz - Math.round(hz)) < 1e-9
    ? Timestep.fromHz(Math.round(hz))
    : Timestep.fromMs(ms);
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
 * One loop, one ball scene and one simulated display, advanced a display frame at a time, with
 * scripted inputs sampled per update through a {@link ButtonSampler}. The lab draws it; the tests
 * assert on it; the bench times it. {@link frame} takes the simulated display's next frame;
 * {@link frameAt} takes a frame time from elsewhere (the page's real clock).
 */
export class LoopRig {
  readonly loop: Loop;
  readonly scene: BallScene;
  readonly display: SimulatedDisplay;
  readonly sampler = new ButtonSampler();
  /** States after each update, when tracing: update i at [i*6, i*6+6). */
  readonly trace: number[] = [];
  private readonly script: ScriptedInput[];
  private scriptAt = 0;
  private readonly costMs: number;
  private readonly guard: number;
  private readonly tracing: boolean;
  private workMs = 0;
  private readonly startMs: number;
  private pending: DisplayFrame;
  /** Real time of the last frame, in ms from the start. */
  realMs = 0;
  /** Updates the loop asked for but the page could not run (it would have stalled). */
  owed = 0;
  /** Frames seen. */
  frames = 0;
  /** The most updates asked for by one frame. */
  maxSteps = 0;

  constructor(options: LoopRigOptions) {
    this.loop = makeLoop(options.loop);
    this.scene = new BallScene(options.scene);
    this.display = new SimulatedDisplay(options.display);
    this.script = [...(options.script ?? defaultBallScript())].sort((a, b) => a.timeMs - b.timeMs);
    this.costMs = options.updateCostMs ?? 0;
    this.guard = options.stallGuard ?? 5000;
    this.tracing = options.trace ?? false;
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

  /**
   * Advance one display frame at `tMs` from the start (not earlier than the last one);
   * `wasHidden` if the page was hidden since the last frame. Returns the number of updates run.
   */
  frameAt(tMs: number, wasHidden = false): number {
    this.realMs = tMs;
    while (this.scriptAt < this.script.length && this.script[this.scriptAt]!.timeMs <= tMs) {
      const e = this.script[this.scriptAt++]!;
      this.sampler.push(e.timeMs, e.button, e.down);
    }
    const loop = this.loop;
    if (wasHidden && loop instanceof FixedLoop) {
      loop.setHidden(true);
      loop.setHidden(false);
    }
    this.frames++;
    let n = loop.frame(tMs);
    if (n > this.maxSteps) this.maxSteps = n;
    if (n > this.guard) {
      this.owed += n - this.guard;
      n = this.guard;
    }
    for (let j = 0; j < n; j++) {
      this.scene.update(loop.dt, this.sampler.sample(loop, j));
      if (this.tracing) for (const v of this.scene.state) this.trace.push(v);
    }
    this.workMs = n * this.costMs;
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

  /** Advance frames of the simulated display until `ms` more of real time have passed. */
  runFor(ms: number): void {
    const end = this.realMs + ms;
    while (this.realMs < end) this.frame();
  }
}
