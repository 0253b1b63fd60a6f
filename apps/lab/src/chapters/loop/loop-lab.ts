/**
 * The model behind chapter 1, "The loop": five loops on one ball scene and one simulated display,
 * driven to a virtual time. No DOM here, so tests drive it exactly as the page does.
 *
 * Virtual time runs at real speed while the page plays; "Skip" jumps it. Every control that
 * changes the display (rate, jitter, slow machine, a hitch, a hidden tab, a throw) rebuilds the
 * rigs and replays them from zero to the current virtual time: everything is deterministic, so
 * the replay lands on exactly the state a live run would have reached, and numbers repeat.
 */
import {
  LoopRig,
  defaultBallScript,
  BallButtons,
  type LoopSpec,
  type ScriptedInput,
} from '@fixedstep/games';
import {
  FinalFixedLoop,
  FixedLoop,
  NaiveFixedLoop,
  fnv1a64Hex,
  type DisplayEvent,
  type Loop,
  type LoopKind,
} from 'fixedstep';
import { DISPLAY_RATES, type DisplayRate } from '../../shell/display-clock.js';
import { VirtualLab } from '../../shell/virtual-lab.js';

/** The display rates offered. */
export { DISPLAY_RATES, type DisplayRate };

/** The talk's TIME_STEP, used by every fixed loop here so their ticks line up. */
export const STEP_MS = 30;
/** The hash of each panel's state is also taken right after this update (4.5 s at 30 ms). */
export const CHECKPOINT_TICK = 150;
/** What one update costs on the "slow machine": more than a 30 ms step, so naive loops spiral. */
export const SLOW_UPDATE_COST_MS = 40;
/**
 * A frame with more work than this is one the page could not run: the rig gives up on the rest
 * and counts it as owed ("stalled"). 5 s is about when a browser offers to kill the page.
 */
export const STALL_WORK_MS = 5000;
/** The scripted throws repeat with this period, so the ball keeps moving. */
export const SCRIPT_PERIOD_MS = 8000;
/** The script is generated up to this virtual time. */
export const SCRIPT_HORIZON_MS = 60 * 60 * 1000;
/** How far back the fading trail reaches, ms of virtual time. */
export const TRAIL_MS = 600;
/** How far back the steps-per-frame chart reaches, ms of virtual time. */
export const HISTORY_MS = 3000;
/** The most one real frame may move virtual time (a real tab in the background pauses it). */
export const MAX_REAL_FRAME_MS = 100;

export interface PanelSpec {
  readonly kind: LoopKind;
  /** Stable id for test ids and CSS. */
  readonly id: string;
  readonly title: string;
  readonly tagline: string;
  /** Fixed loops have an alpha to interpolate with. */
  readonly fixed: boolean;
  readonly loop: LoopSpec;
}

export const PANELS: readonly PanelSpec[] = [
  {
    kind: 'frame-locked',
    id: 'frame-locked',
    title: 'Frame-locked',
    tagline: 'one update per frame, no clock',
    fixed: false,
    loop: { kind: 'frame-locked' },
  },
  {
    kind: 'variable',
    id: 'variable',
    title: 'Variable Δt',
    tagline: 'one update per frame, Δt = frame time',
    fixed: false,
    loop: { kind: 'variable' },
  },
  {
    kind: 'fixed-naive',
    id: 'fixed-naive',
    title: 'Fixed step',
    tagline: 'the accumulator, as on the slides',
    fixed: true,
    loop: { kind: 'fixed-naive', stepMs: STEP_MS },
  },
  {
    kind: 'fixed-final',
    id: 'fixed-final',
    title: 'Fixed + final fixes',
    tagline: 'max(0, Δt), clamp at 1 s',
    fixed: true,
    loop: { kind: 'fixed-final', stepMs: STEP_MS },
  },
  {
    kind: 'fixed',
    id: 'fixed',
    title: 'FixedLoop',
    tagline: 'integer ticks, step cap, overload policy',
    fixed: true,
    loop: { kind: 'fixed', stepMs: STEP_MS },
  },
];

/** Everything that decides the numbers. Two labs with equal settings and time are identical. */
export interface LoopLabSettings {
  hz: DisplayRate;
  /** Frame jitter as a fraction of the period, 0 to 0.3. */
  jitter: number;
  /** Each update costs {@link SLOW_UPDATE_COST_MS} of real time. */
  slow: boolean;
  /** Hitches and hidden-tab periods, at virtual times. */
  events: DisplayEvent[];
  /** Extra throws pressed by the reader, at virtual times. */
  throws: number[];
}

export function defaultSettings(): LoopLabSettings {
  return { hz: 60, jitter: 0, slow: false, events: [], throws: [] };
}

/** The default script repeated every {@link SCRIPT_PERIOD_MS}, plus the reader's throws. */
export function labScript(throws: readonly number[]): ScriptedInput[] {
  const base = defaultBallScript();
  const out: ScriptedInput[] = [];
  for (let t0 = 0; t0 < SCRIPT_HORIZON_MS; t0 += SCRIPT_PERIOD_MS) {
    for (const e of base) out.push({ ...e, timeMs: t0 + e.timeMs });
  }
  for (const t of throws) {
    out.push({ timeMs: t, button: BallButtons.throw, down: true });
    out.push({ timeMs: t + 50, button: BallButtons.throw, down: false });
  }
  // Stable, so a release never overtakes its press.
  return out.sort((a, b) => a.timeMs - b.timeMs);
}

/** A fixed-size ring of numeric records, oldest first. */
export class Ring {
  readonly data: Float64Array;
  private start = 0;
  size = 0;
  constructor(
    readonly capacity: number,
    readonly width: number,
  ) {
    if (!(Number.isInteger(width) && width >= 1 && width <= 5)) {
      throw new RangeError(`Ring: width must be from 1 to 5, got ${String(width)}`);
    }
    this.data = new Float64Array(capacity * width);
  }
  /** Append a record (fields beyond `width` are ignored); the oldest goes when full. */
  push(a: number, b = 0, c = 0, d = 0, e = 0): void {
    const i = ((this.start + this.size) % this.capacity) * this.width;
    if (this.size === this.capacity) this.start = (this.start + 1) % this.capacity;
    else this.size++;
    const w = this.width;
    const data = this.data;
    data[i] = a;
    if (w > 1) data[i + 1] = b;
    if (w > 2) data[i + 2] = c;
    if (w > 3) data[i + 3] = d;
    if (w > 4) data[i + 4] = e;
  }
  /** Field `f` of the `k`-th record, oldest first. */
  get(k: number, f: number): number {
    return this.data[((this.start + k) % this.capacity) * this.width + f]!;
  }
  clear(): void {
    this.start = 0;
    this.size = 0;
  }
}

/** The numbers one panel shows. */
export interface PanelReadouts {
  /** Simulated time, seconds, as the loop understands it. */
  simS: number;
  /** Real (virtual display) time of the last frame, seconds. */
  realS: number;
  /** simS / realS (NaN before the first frame). */
  ratio: number;
  /** Updates the loop asked for in the last frame. */
  steps: number;
  /** The most updates asked for by one frame. */
  maxSteps: number;
  /** Updates run so far. */
  updates: number;
  /** Real time dropped by the loop, ms; undefined for the loops with no accumulator. */
  droppedMs: number | undefined;
  /** State hash now (FNV-1a 64 of the ball's state bytes). */
  hash: string;
  /** State hash right after update {@link CHECKPOINT_TICK}, once reached. */
  checkpointHash: string | undefined;
  stalled: boolean;
  /** Updates asked for but never run (stalled page). */
  owed: number;
}

// Trail record fields.
const T_TIME = 0;
const T_RAW_X = 1;
const T_RAW_Y = 2;
const T_INT_X = 3;
const T_INT_Y = 4;

/** One panel: a rig plus what the view draws (trail, steps per frame) and the checkpoint hash. */
export class PanelRun {
  /** Per display frame: time, raw x, raw y, interpolated x, interpolated y. */
  readonly trail = new Ring(1024, 5);
  /** Per display frame: time (ms), updates asked for. */
  readonly history = new Ring(2048, 2);
  checkpointHash: string | undefined;
  private ran = 0;
  private readonly cpBytes = new Float64Array(6);

  constructor(
    readonly spec: PanelSpec,
    readonly rig: LoopRig,
  ) {}

  /** Record a display frame the rig has just run (`ran` updates executed). */
  recordFrame(ran: number): void {
    const rig = this.rig;
    const loop = rig.loop;
    const scene = rig.scene;
    if (this.checkpointHash === undefined && this.ran + ran >= CHECKPOINT_TICK) {
      const k = CHECKPOINT_TICK - this.ran - 1;
      for (let f = 0; f < 6; f++) this.cpBytes[f] = rig.trace[k * 6 + f]!;
      this.checkpointHash = fnv1a64Hex(new Uint8Array(this.cpBytes.buffer));
    }
    this.ran += ran;
    rig.trace.length = 0;
    const a = this.spec.fixed ? loop.alpha : 1;
    this.trail.push(
      rig.realMs,
      scene.x,
      scene.y,
      this.spec.fixed ? scene.renderX(a) : scene.x,
      this.spec.fixed ? scene.renderY(a) : scene.y,
    );
    this.history.push(rig.realMs, loop.lastSteps);
  }

  /** Where to draw the ball now. */
  ballAt(interpolate: boolean): { x: number; y: number } {
    const s = this.rig.scene;
    if (!interpolate || !this.spec.fixed) return { x: s.x, y: s.y };
    const a = this.rig.loop.alpha;
    return { x: s.renderX(a), y: s.renderY(a) };
  }

  /** Trail points within {@link TRAIL_MS} of `nowMs`: x, y and age (0 newest … 1 oldest). */
  trailPoints(nowMs: number, interpolate: boolean, out: number[]): number[] {
    out.length = 0;
    const fx = interpolate && this.spec.fixed ? T_INT_X : T_RAW_X;
    const fy = interpolate && this.spec.fixed ? T_INT_Y : T_RAW_Y;
    for (let k = 0; k < this.trail.size; k++) {
      const age = (nowMs - this.trail.get(k, T_TIME)) / TRAIL_MS;
      if (age > 1) continue;
      out.push(this.trail.get(k, fx), this.trail.get(k, fy), Math.max(0, age));
    }
    return out;
  }

  readouts(): PanelReadouts {
    const rig = this.rig;
    const loop = rig.loop;
    const realS = rig.realMs / 1000;
    // A stalled page never ran the updates it owes: they are not simulated time.
    const simS = rig.owed > 0 ? loop.simTime - rig.owed * loop.dt : loop.simTime;
    return {
      simS,
      realS,
      ratio: rig.realMs > 0 ? simS / realS : NaN,
      steps: loop.lastSteps,
      maxSteps: rig.maxSteps,
      updates: this.ran,
      droppedMs: droppedMs(loop, rig.realMs),
      hash: rig.scene.hash(),
      checkpointHash: this.checkpointHash,
      stalled: rig.stalled,
      owed: rig.owed,
    };
  }
}

/**
 * Time a loop has let go of: the production loop counts it; for the talk's accumulators it is
 * real time minus simulated time minus what is still in the accumulator (the final fixes' clamp).
 */
export function droppedMs(loop: Loop, realMs: number): number | undefined {
  if (loop instanceof FixedLoop) return loop.droppedMs();
  if (loop instanceof NaiveFixedLoop || loop instanceof FinalFixedLoop) {
    const d = realMs - loop.updates * loop.stepMs - loop.accumulator;
    return Math.abs(d) < 1e-6 ? 0 : d;
  }
  return undefined;
}

/** A panel on the simulated display. */
class SimulatedPanel {
  readonly run: PanelRun;
  private readonly rig: LoopRig;

  constructor(spec: PanelSpec, settings: LoopLabSettings, script: ScriptedInput[]) {
    const costMs = settings.slow ? SLOW_UPDATE_COST_MS : 0;
    this.rig = new LoopRig({
      loop: spec.loop,
      display: { hz: settings.hz, jitter: settings.jitter, seed: 1, events: settings.events },
      script,
      updateCostMs: costMs,
      stallGuard: costMs > 0 ? Math.floor(STALL_WORK_MS / costMs) : 5000,
      trace: true,
    });
    this.run = new PanelRun(spec, this.rig);
  }

  /** Run every display frame due at or before `tMs`. */
  advanceTo(tMs: number): void {
    while (this.rig.nextFrameAt <= tMs) this.run.recordFrame(this.rig.frame());
  }
}

/** The five panels on one simulated display, at a virtual time. */
export class LoopLab extends VirtualLab<LoopLabSettings> {
  private panels: SimulatedPanel[] = [];

  constructor(settings: LoopLabSettings = defaultSettings()) {
    super(cloneSettings(settings));
    this.build();
  }

  get runs(): PanelRun[] {
    return this.panels.map((p) => p.run);
  }

  /** Move virtual time forward to `tMs` (never back), running the frames due. */
  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    this.time = tMs;
    for (const p of this.panels) p.advanceTo(tMs);
  }

  /** Change settings and replay from zero to the current virtual time. */
  update(change: Partial<LoopLabSettings>): void {
    this.current = cloneSettings({ ...this.current, ...change });
    this.build();
  }

  /** Add a display event starting now, and replay. */
  addEvent(kind: DisplayEvent['kind'], durationMs: number): void {
    this.update({ events: [...this.current.events, { kind, atMs: this.time, durationMs }] });
  }

  /** Add a throw now, and replay. */
  addThrow(): void {
    this.update({ throws: [...this.current.throws, this.time] });
  }

  /** The display event covering the current time, if any. */
  activeEvent(): DisplayEvent | undefined {
    return this.current.events.find(
      (e) => e.atMs <= this.time && this.time < e.atMs + e.durationMs,
    );
  }

  /** Back to time zero with no events or throws, keeping the display settings. */
  restart(): void {
    this.time = 0;
    this.current = { ...cloneSettings(this.current), events: [], throws: [] };
    this.build();
  }

  private build(): void {
    const script = labScript(this.current.throws);
    this.panels = PANELS.map((spec) => new SimulatedPanel(spec, this.current, script));
    for (const p of this.panels) p.advanceTo(this.time);
  }
}

function cloneSettings(s: LoopLabSettings): LoopLabSettings {
  return {
    hz: s.hz,
    jitter: s.jitter,
    slow: s.slow,
    events: s.events.map((e) => ({ ...e })),
    throws: [...s.throws],
  };
}

/** The five panels on the page's own clock (requestAnimationFrame). */
export class ClockLab {
  readonly runs: PanelRun[];
  private readonly rigs: LoopRig[];
  private time = 0;
  private hiddenSinceLastFrame = false;

  constructor() {
    const script = labScript([]);
    this.rigs = PANELS.map(
      (spec) =>
        new LoopRig({
          loop: spec.loop,
          display: { hz: 60 },
          script: script.map((e) => ({ ...e })),
          trace: true,
        }),
    );
    this.runs = PANELS.map((spec, i) => new PanelRun(spec, this.rigs[i]!));
  }

  get timeMs(): number {
    return this.time;
  }

  /** The page was hidden (its next frame tells the production loop). */
  markHidden(): void {
    this.hiddenSinceLastFrame = true;
  }

  /** One real display frame at `tMs` from the start of this mode. */
  frameAt(tMs: number): void {
    this.time = tMs;
    const hidden = this.hiddenSinceLastFrame;
    this.hiddenSinceLastFrame = false;
    this.rigs.forEach((rig, i) => {
      const n = rig.frameAt(tMs, hidden);
      this.runs[i]!.recordFrame(n);
    });
  }

  addThrow(): void {
    for (const rig of this.rigs) {
      rig.addInputs([
        { timeMs: this.time, button: BallButtons.throw, down: true },
        { timeMs: this.time + 50, button: BallButtons.throw, down: false },
      ]);
    }
  }
}
