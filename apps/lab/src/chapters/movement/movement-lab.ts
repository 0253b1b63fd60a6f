/**
 * The model behind chapter 2, "Movement": the same run-and-jump on four simulated displays
 * (30, 60, 144 and 240 Hz, with jitter) under a variable Δt and under a fixed step. No DOM here,
 * so the tests drive it exactly as the page does.
 *
 * Like chapter 1, virtual time runs at real speed while the page plays and "Skip" jumps it; a
 * change of settings rebuilds every run and replays it to the current virtual time, which lands
 * on exactly the state a live run would have reached. On the real clock a fifth run per loop is
 * fed the page's own animation frames.
 */
import {
  JumpMeter,
  JumperButtons,
  JumperScene,
  MOVEMENT_PERIOD_MS,
  SceneRig,
  jitterSeed,
  loopKindOf,
  movementScript,
  runMovement,
  type Jump,
  type MovementLoop,
  type ScriptedInput,
} from '@fixedstep/games';
import { DISPLAY_RATES, type DisplayRate } from '../../shell/display-clock.js';
import { VirtualLab } from '../../shell/virtual-lab.js';

/** The display rates compared. */
export const RATES = DISPLAY_RATES;
export type Rate = DisplayRate;
/** A run's display: a simulated rate, or the page's own ("real"). */
export type Source = Rate | 'real';

/** How a run's display is named: `60 Hz`, or `yours` (`yours ≈ 59 Hz` once its rate is known). */
export function sourceLabel(s: Source, hz = 0): string {
  return s === 'real' ? (hz > 0 ? `yours ≈ ${hz} Hz` : 'yours') : `${s} Hz`;
}

/** The fixed step, ms: the talk's TIME_STEP. */
export const STEP_MS = 30;
/** The script is generated up to this virtual time. */
export const SCRIPT_HORIZON_MS = 60 * 60 * 1000;
/** Default frame jitter, as a fraction of the period. */
export const DEFAULT_JITTER = 0.2;
/** How long the reader's jump button is held, ms. */
export const JUMP_HOLD_MS = 180;

export interface LoopInfo {
  readonly id: MovementLoop;
  readonly title: string;
  readonly tagline: string;
  /** Fixed loops have an alpha to interpolate with. */
  readonly fixed: boolean;
}

export const LOOPS: readonly LoopInfo[] = [
  {
    id: 'variable',
    title: 'Variable Δt',
    tagline: 'one update per frame, Δt = frame time',
    fixed: false,
  },
  {
    id: 'fixed',
    title: 'Fixed step',
    tagline: `FixedLoop, ${STEP_MS} ms steps, drawn interpolated`,
    fixed: true,
  },
];

export interface MovementSettings {
  /** Frame jitter as a fraction of the period, 0 to 0.3. */
  jitter: number;
  /** Extra jumps pressed by the reader, at virtual times. */
  jumps: number[];
}

export function defaultMovementSettings(): MovementSettings {
  return { jitter: DEFAULT_JITTER, jumps: [] };
}

/** The repeating script plus the reader's jumps. */
export function movementLabScript(jumps: readonly number[]): ScriptedInput[] {
  const out = movementScript(SCRIPT_HORIZON_MS);
  for (const t of jumps) out.push(...jumpPress(t));
  return out.sort((a, b) => a.timeMs - b.timeMs);
}

function jumpPress(t: number): ScriptedInput[] {
  return [
    { timeMs: t, button: JumperButtons.jump, down: true },
    { timeMs: t + JUMP_HOLD_MS, button: JumperButtons.jump, down: false },
  ];
}

/** One run: a loop on one display, with what the page draws (the path of the current round). */
export class Track {
  readonly rig: SceneRig<JumperScene>;
  readonly meter = new JumpMeter();
  /** Simulated time (ms), x, y after every update of the current round. */
  readonly path: number[] = [];
  private round = 0;
  private updates = 0;

  constructor(
    readonly loop: LoopInfo,
    readonly source: Source,
    jitter: number,
    script: ScriptedInput[],
  ) {
    const hz = source === 'real' ? 60 : source;
    this.rig = new SceneRig({
      loop: { kind: loopKindOf(loop.id), stepMs: STEP_MS },
      display: { hz, jitter: source === 'real' ? 0 : jitter, seed: jitterSeed(hz) },
      scene: new JumperScene(),
      script,
      onUpdate: (scene, l) => {
        this.meter.observe(scene);
        if (scene.round !== this.round) {
          this.round = scene.round;
          this.path.length = 0;
        }
        this.updates++;
        // A fixed step's update k ends at k × step exactly (integer ticks, no float sums).
        const t = loop.fixed ? this.updates * STEP_MS : l.simTime * 1000;
        this.path.push(t, scene.x, scene.y);
      },
    });
  }

  get scene(): JumperScene {
    return this.rig.scene;
  }

  /**
   * Where the runner was at simulated time `tMs`: between the two updates around it when
   * interpolating, else at the last update before it. Also how many path points come before.
   */
  runnerAt(tMs: number, interpolate: boolean): { x: number; y: number; points: number } {
    const p = this.path;
    let k = p.length - 3;
    while (k > 0 && p[k]! > tMs) k -= 3;
    if (k < 0) return { x: this.rig.scene.x, y: this.rig.scene.y, points: 0 };
    const t0 = p[k]!;
    const next = k + 3;
    if (interpolate && t0 <= tMs && next < p.length) {
      const a = (tMs - t0) / (p[next]! - t0);
      return {
        x: p[k + 1]! + (p[next + 1]! - p[k + 1]!) * a,
        y: p[k + 2]! + (p[next + 2]! - p[k + 2]!) * a,
        points: k / 3 + 1,
      };
    }
    return { x: p[k + 1]!, y: p[k + 2]!, points: t0 <= tMs ? k / 3 + 1 : 0 };
  }

  /** The `k`-th completed jump (0-based), if any. */
  jump(k: number): Jump | undefined {
    return this.meter.jumps[k];
  }
}

/** What one loop's panel shows. */
export interface LoopReadouts {
  /** Which completed jump is shown (0-based; −1 before the first landing on every display). */
  jumpIndex: number;
  rows: { source: Source; jump: Jump | undefined }[];
  /** max − min over the displays, metres (NaN before the first landing). */
  apexSpread: number;
  landingSpread: number;
}

/** Spread of some numbers: max − min (NaN if any is missing). */
export function spread(values: readonly number[]): number {
  if (values.length === 0 || values.some((v) => !Number.isFinite(v))) return NaN;
  return Math.max(...values) - Math.min(...values);
}

/** The runs of both loops on the four simulated displays (plus the real one), at a virtual time. */
export class MovementLab extends VirtualLab<MovementSettings> {
  private sim = new Map<MovementLoop, Track[]>();
  private readonly real = new Map<MovementLoop, Track>();

  constructor(
    settings: MovementSettings = defaultMovementSettings(),
    readonly realClock = false,
  ) {
    super({ jitter: settings.jitter, jumps: [...settings.jumps] });
    if (realClock) {
      const script = movementLabScript([]);
      for (const loop of LOOPS) {
        const track = new Track(loop, 'real', 0, script);
        track.rig.frameAt(0); // the real time line starts here
        this.real.set(loop.id, track);
      }
    }
    this.build();
  }

  /** The runs of one loop: the four simulated displays, then the real one if on the real clock. */
  tracks(loop: MovementLoop): Track[] {
    const out = [...(this.sim.get(loop) ?? [])];
    const r = this.real.get(loop);
    if (r) out.push(r);
    return out;
  }

  /**
   * The moment the page draws every runner at: the latest one every display has already shown,
   * minus one fixed step for the fixed-step runs (interpolation draws between the last two steps,
   * one step behind). At that moment every run has the states it needs on both sides.
   */
  drawTimeMs(loop: LoopInfo): number {
    let t = Infinity;
    for (const id of ['variable', 'fixed'] as const) {
      for (const track of this.tracks(id)) t = Math.min(t, track.rig.realMs);
    }
    return loop.fixed ? t - STEP_MS : t;
  }

  /** Move virtual time forward to `tMs` (never back), running the frames due. */
  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    this.time = tMs;
    for (const list of this.sim.values()) for (const t of list) t.rig.advanceTo(tMs);
  }

  /** Real clock: a frame of the page at `tMs`; the simulated displays keep up. */
  realFrame(tMs: number): void {
    if (tMs < this.time) return;
    this.advanceTo(tMs);
    this.time = tMs;
    for (const t of this.real.values()) t.rig.frameAt(tMs);
  }

  /** Change settings and replay the simulated displays from zero to the current time. */
  update(change: Partial<MovementSettings>): void {
    this.current = { ...this.current, ...change, jumps: [...(change.jumps ?? this.current.jumps)] };
    this.build();
  }

  /** The reader pressed Jump at the current time: every display gets it. */
  addJump(): void {
    const at = this.time;
    if (this.realClock) {
      // The real runs cannot be replayed: give everybody the press from now on.
      for (const list of this.sim.values()) for (const t of list) t.rig.addInputs(jumpPress(at));
      for (const t of this.real.values()) t.rig.addInputs(jumpPress(at));
      this.current = { ...this.current, jumps: [...this.current.jumps, at] };
    } else {
      this.update({ jumps: [...this.current.jumps, at] });
    }
  }

  /** Back to time zero with no extra jumps, keeping the jitter. */
  restart(): void {
    this.time = 0;
    this.current = { jitter: this.current.jitter, jumps: [] };
    this.build();
  }

  readouts(loop: MovementLoop): LoopReadouts {
    const tracks = this.tracks(loop);
    const jumpIndex = Math.min(...tracks.map((t) => t.meter.jumps.length)) - 1;
    const rows = tracks.map((t) => ({ source: t.source, jump: t.jump(jumpIndex) }));
    const ok = jumpIndex >= 0;
    return {
      jumpIndex,
      rows,
      apexSpread: ok ? spread(rows.map((r) => r.jump?.apex ?? NaN)) : NaN,
      landingSpread: ok ? spread(rows.map((r) => r.jump?.distance ?? NaN)) : NaN,
    };
  }

  private build(): void {
    const script = movementLabScript(this.current.jumps);
    this.sim = new Map(
      LOOPS.map((loop) => [
        loop.id,
        RATES.map((hz) => new Track(loop, hz, this.current.jitter, script)),
      ]),
    );
    for (const list of this.sim.values()) for (const t of list) t.rig.advanceTo(this.time);
  }
}

/** Display rates of the sweep chart. */
export const SWEEP_RATES = [
  24, 30, 40, 48, 50, 60, 72, 75, 85, 90, 100, 120, 144, 165, 180, 200, 240, 280, 360,
] as const;

export interface Sweep {
  hz: number[];
  apex: Record<MovementLoop, number[]>;
  landing: Record<MovementLoop, number[]>;
}

/** The first jump of the script at many display rates, under both loops (for the chart). */
export function sweep(jitter: number): Sweep {
  const out: Sweep = {
    hz: [...SWEEP_RATES],
    apex: { variable: [], fixed: [] },
    landing: { variable: [], fixed: [] },
  };
  for (const loop of LOOPS) {
    for (const hz of SWEEP_RATES) {
      const run = runMovement({
        loop: loop.id,
        hz,
        jitter,
        stepMs: STEP_MS,
        durationMs: MOVEMENT_PERIOD_MS - 100,
      });
      const j = run.meter.jumps[0];
      out.apex[loop.id].push(j?.apex ?? NaN);
      out.landing[loop.id].push(j?.distance ?? NaN);
    }
  }
  return out;
}
