/**
 * The model behind chapter 4, "Physics": the spring under six integrators side by side and a
 * rope you can poke, stepped by one fixed-step loop on a simulated display, driven to a virtual
 * time. No DOM here, so tests drive it exactly as the page does.
 *
 * As in chapter 1, virtual time runs at real speed while the page plays and "Skip" jumps it;
 * changing the step, a stiffness or the rope's integrator rebuilds everything and replays from
 * zero to the current virtual time, pokes included — deterministic, so numbers repeat exactly.
 */
import {
  OscillatorRace,
  Rope,
  SceneRig,
  TalkSpring,
  makeLoop,
  ropeOmegaMax,
  type RaceLane,
  type RopePoke,
} from '@fixedstep/games';
import {
  INTEGRATOR_INFO,
  INTEGRATOR_METHODS,
  SimulatedDisplay,
  type IntegratorMethod,
  type Loop,
} from 'fixedstep';
import { VirtualLab } from '../../shell/virtual-lab.js';

/** The step slider, ms. The talk's TIME_STEP is 30 ms. */
export const STEP = { min: 5, max: 100, step: 1, initial: 30 } as const;
/** Spring stiffness choices for the 1 kg mass, N/m (a slider walks this ladder). */
export const STIFFNESS = [
  1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 3000, 4000, 5000, 6000, 8000, 10000,
] as const;
/** The default: k = 20 N/m, ω = √20 ≈ 4.47 rad/s, ω·dt ≈ 0.134 at 30 ms. */
export const STIFFNESS_INITIAL = 20;
/** The oscillator's mass, kg. */
export const MASS = 1;
/** The oscillator starts stretched by 1 m, at rest. */
export const X0 = 1;
/** Link stiffness choices for the rope, N/m. */
export const ROPE_STIFFNESS = [10, 20, 40, 60, 80, 100, 150, 200, 250, 300, 500, 1000] as const;
export const ROPE_STIFFNESS_INITIAL = 40;
/** The rope: beads (pins included) and the mass of each, kg. */
export const ROPE_BEADS = 16;
export const ROPE_BEAD_MASS = 0.1;
/** A lane whose energy grows past this many times its start stops ("exploded"). */
export const EXPLODE_AT = 1e9;
/** The simulated display. */
export const DISPLAY_HZ = 60;
/** The most one real frame may move virtual time. */
export const MAX_REAL_FRAME_MS = 100;
/** The energy plot keeps at most about this many samples per method (older ones thin out). */
export const PLOT_SAMPLES = 1200;

/** A poke at a virtual time (delivered to the first step of the first frame after it). */
export interface TimedPoke extends RopePoke {
  atMs: number;
}

/** The poke that starts the rope swinging, so it moves before anyone touches it. */
export const SCRIPTED_POKES: readonly TimedPoke[] = [{ atMs: 1000, bead: 5, dvx: 1.5, dvy: 4 }];

/** Everything that decides the numbers. Two labs with equal settings and time are identical. */
export interface PhysicsSettings {
  /** The fixed step, ms. */
  stepMs: number;
  /** The oscillator's spring, N/m (mass 1 kg). */
  stiffness: number;
  /** The rope's integrator. */
  ropeMethod: IntegratorMethod;
  /** The rope's link stiffness, N/m. */
  ropeStiffness: number;
  /** The reader's pokes (the scripted one is always there). */
  pokes: TimedPoke[];
}

export function defaultSettings(): PhysicsSettings {
  return {
    stepMs: STEP.initial,
    stiffness: STIFFNESS_INITIAL,
    ropeMethod: 'semi-implicit-euler',
    ropeStiffness: ROPE_STIFFNESS_INITIAL,
    pokes: [],
  };
}

/** ω of the oscillator, rad/s. */
export function omegaOf(stiffness: number): number {
  return Math.sqrt(stiffness / MASS);
}

/** ω·dt of the rope's fastest mode. */
export function ropeOmegaDt(ropeStiffness: number, stepMs: number): number {
  return (
    ropeOmegaMax({ stiffness: ropeStiffness, mass: ROPE_BEAD_MASS, count: ROPE_BEADS }) *
    (stepMs / 1000)
  );
}

/** What a method does at this ω·dt. */
export type Stability = 'grows' | 'stable' | 'unstable' | 'damped';

/**
 * Explicit Euler grows at any ω·dt; backward Euler never grows and damps; the others are stable
 * below their limit (2 for semi-implicit Euler and the Verlets, 2√2 for RK4).
 */
export function stabilityOf(method: IntegratorMethod, omegaDt: number): Stability {
  const limit = INTEGRATOR_INFO[method].stabilityLimit;
  if (limit === 0) return 'grows';
  if (limit === Infinity) return 'damped';
  return omegaDt < limit ? 'stable' : 'unstable';
}

/** Energy ratio samples of every method over time, thinned as they grow. */
export class EnergyHistory {
  readonly t: number[] = [];
  readonly series: number[][];
  private stride = 1;

  constructor(readonly methods: readonly IntegratorMethod[]) {
    this.series = methods.map(() => []);
  }

  /** Every `stride`-th tick is kept; the stride doubles when the buffer fills. */
  record(race: OscillatorRace): void {
    if (race.tick % this.stride !== 0) return;
    this.t.push(race.time);
    race.lanes.forEach((lane, i) => this.series[i]!.push(race.energyRatio(lane)));
    if (this.t.length > PLOT_SAMPLES) {
      this.stride *= 2;
      const keep = (a: number[]) => {
        let m = 0;
        for (let k = 0; k < a.length; k++) {
          // Keep the samples on the new grid (their tick is a multiple of the new stride).
          if (Math.round(this.t[k]! / race.dt) % this.stride === 0) a[m++] = a[k]!;
        }
        a.length = m;
      };
      for (const s of this.series) keep(s);
      keep(this.t);
    }
  }
}

/** The last {@link capacity} (x, v) states of each lane, oldest first: the phase portraits' trails. */
export class PhaseTrails {
  private readonly data: Float64Array[];
  private start = 0;
  size = 0;

  constructor(
    lanes: number,
    readonly capacity: number,
  ) {
    this.data = Array.from({ length: lanes }, () => new Float64Array(2 * capacity));
  }

  record(race: OscillatorRace): void {
    const i = (this.start + this.size) % this.capacity;
    if (this.size === this.capacity) this.start = (this.start + 1) % this.capacity;
    else this.size++;
    race.lanes.forEach((lane, k) => {
      const d = this.data[k]!;
      d[2 * i] = lane.state.x[0]!;
      d[2 * i + 1] = lane.state.v[0]!;
    });
  }

  /** The `j`-th state (oldest first) of lane `k`: x (m) and v (m/s). */
  x(k: number, j: number): number {
    return this.data[k]![2 * ((this.start + j) % this.capacity)]!;
  }
  v(k: number, j: number): number {
    return this.data[k]![2 * ((this.start + j) % this.capacity) + 1]!;
  }
}

/** How many steps of each lane the phase portraits keep. */
export const TRAIL_STEPS = 360;

/**
 * One run: a fixed-step loop, the six-lane oscillator race and the rope, stepped together. Pokes
 * queued with {@link poke} go to the first step of the next frame.
 */
export class PhysicsRun {
  readonly loop: Loop;
  readonly race: OscillatorRace;
  readonly rope: Rope;
  readonly energy: EnergyHistory;
  readonly trails: PhaseTrails;
  /** Real time of the last frame, ms. */
  realMs = 0;
  /** Steps of the last frame. */
  lastSteps = 0;
  private pending: RopePoke[] = [];

  constructor(readonly settings: Readonly<PhysicsSettings>) {
    const dt = settings.stepMs / 1000;
    this.loop = makeLoop({ kind: 'fixed', stepMs: settings.stepMs });
    this.race = new OscillatorRace({
      omega: omegaOf(settings.stiffness),
      dt,
      x0: X0,
      v0: 0,
      methods: INTEGRATOR_METHODS,
      explodeAt: EXPLODE_AT,
    });
    this.rope = new Rope({
      dt,
      integrator: settings.ropeMethod,
      stiffness: settings.ropeStiffness,
      count: ROPE_BEADS,
      mass: ROPE_BEAD_MASS,
    });
    this.energy = new EnergyHistory(INTEGRATOR_METHODS);
    this.energy.record(this.race);
    this.trails = new PhaseTrails(this.race.lanes.length, TRAIL_STEPS);
    this.trails.record(this.race);
  }

  /** ω·dt of the oscillator. */
  get omegaDt(): number {
    return this.race.omegaDt;
  }

  /** Alpha for drawing between the last two steps. */
  get alpha(): number {
    return this.loop.alpha;
  }

  /** Queue a poke for the next step. */
  poke(p: RopePoke): void {
    this.pending.push({ ...p });
  }

  /** One display frame at `tMs` (not earlier than the last): the loop's steps. */
  frameAt(tMs: number): number {
    this.realMs = tMs;
    const n = this.loop.frame(tMs);
    for (let j = 0; j < n; j++) {
      this.race.step();
      this.energy.record(this.race);
      this.trails.record(this.race);
      const inputs = this.pending;
      if (inputs.length > 0) this.pending = [];
      this.rope.step(inputs);
    }
    this.lastSteps = n;
    return n;
  }

  lane(method: IntegratorMethod): RaceLane {
    return this.race.lane(method);
  }
}

/** The run on a simulated display at a virtual time, with settings that replay. */
export class PhysicsLab extends VirtualLab<PhysicsSettings> {
  private runValue!: PhysicsRun;
  private display!: SimulatedDisplay;
  private nextFrame = 0;
  /** Every poke in delivery order, and the first one not yet delivered. */
  private schedule: TimedPoke[] = [];
  private pokeAt = 0;

  constructor(settings: PhysicsSettings = defaultSettings()) {
    super(cloneSettings(settings));
    this.build();
  }

  get run(): PhysicsRun {
    return this.runValue;
  }

  /** Every poke, scripted and the reader's, in time order. */
  get pokes(): TimedPoke[] {
    return [...SCRIPTED_POKES, ...this.current.pokes].sort((a, b) => a.atMs - b.atMs);
  }

  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    this.time = tMs;
    this.runTo(tMs);
  }

  /** Change settings and replay from zero to the current virtual time. */
  update(change: Partial<PhysicsSettings>): void {
    this.current = cloneSettings({ ...this.current, ...change });
    this.build();
  }

  /**
   * Poke a bead now: it is recorded, so replays have it, and reaches the first step of the next
   * frame — exactly where a replay delivers it.
   */
  poke(p: RopePoke): void {
    const timed = { ...p, atMs: this.time };
    this.current.pokes.push(timed);
    // After every poke at or before now: the order a replay's stable sort gives.
    let i = this.pokeAt;
    while (i < this.schedule.length && this.schedule[i]!.atMs <= timed.atMs) i++;
    this.schedule.splice(i, 0, timed);
  }

  /** Back to time zero with no pokes, keeping the other settings. */
  restart(): void {
    this.time = 0;
    this.current = { ...cloneSettings(this.current), pokes: [] };
    this.build();
  }

  private build(): void {
    this.runValue = new PhysicsRun(this.current);
    this.display = new SimulatedDisplay({ hz: DISPLAY_HZ });
    this.nextFrame = this.display.next(0).time;
    this.schedule = this.pokes;
    this.pokeAt = 0;
    this.runTo(this.time);
  }

  private runTo(tMs: number): void {
    const pokes = this.schedule;
    while (this.nextFrame <= tMs) {
      const t = this.nextFrame;
      // Pokes strictly before this frame (a live poke at `now` reaches the next frame too).
      while (this.pokeAt < pokes.length && pokes[this.pokeAt]!.atMs < t) {
        this.runValue.poke(pokes[this.pokeAt++]!);
      }
      this.runValue.frameAt(t);
      this.nextFrame = this.display.next(0).time;
    }
  }
}

function cloneSettings(s: PhysicsSettings): PhysicsSettings {
  return { ...s, pokes: s.pokes.map((p) => ({ ...p })) };
}

/** The run on the page's own clock (requestAnimationFrame). */
export class ClockPhysics {
  readonly run: PhysicsRun;
  private time = 0;
  private scripted = 0;

  constructor(settings: Readonly<PhysicsSettings>) {
    this.run = new PhysicsRun({ ...settings, pokes: [] });
  }

  get timeMs(): number {
    return this.time;
  }

  poke(p: RopePoke): void {
    this.run.poke(p);
  }

  frameAt(tMs: number): void {
    this.time = tMs;
    while (this.scripted < SCRIPTED_POKES.length && SCRIPTED_POKES[this.scripted]!.atMs < tMs) {
      this.run.poke(SCRIPTED_POKES[this.scripted++]!);
    }
    this.run.frameAt(tMs);
  }
}

// ----------------------------------------------------------------------------- a hitch

/** The hitch demo's spring: k = 100 N/m on 1 kg, so ω = 10 rad/s (ω·dt = 0.3 at 30 ms). */
export const HITCH_OMEGA = 10;
/** How long a hitch holds the display, ms. */
export const HITCH_MS = 250;
/** The hitch demo's display: 30 Hz with ±30 % jitter. */
export const HITCH_DISPLAY = { hz: 30, jitter: 0.3, seed: 11 } as const;
/** Seconds of x(t) the demo keeps for drawing. */
export const HITCH_WINDOW_S = 6;

/** x(t) after each update, the last {@link HITCH_WINDOW_S} seconds of it. */
export class SpringTrace {
  readonly t: number[] = [];
  readonly x: number[] = [];
  push(t: number, x: number): void {
    this.t.push(t);
    this.x.push(x);
    let drop = 0;
    while (drop < this.t.length && this.t[drop]! < t - HITCH_WINDOW_S) drop++;
    if (drop > 64) {
      this.t.splice(0, drop);
      this.x.splice(0, drop);
    }
  }
}

/** One of the two loops of the hitch demo. */
export interface HitchRun {
  readonly kind: 'variable' | 'fixed';
  readonly rig: SceneRig<TalkSpring>;
  readonly trace: SpringTrace;
}

/**
 * The talk's spring code (`v += a·dt; x += v·dt`) under a variable Δt and under a fixed 30 ms
 * step, on one jittery 30 Hz display that the user can make hitch: a hitch is one update of
 * ω·dt ≈ 2.8 for the variable loop — past the method's limit of 2, so its energy jumps —
 * and nine ordinary steps for the fixed one. Like the rest of the chapter, it replays from zero
 * whenever a hitch is added, so its numbers repeat exactly.
 */
export class HitchLab {
  readonly hitches: number[] = [];
  runs: readonly HitchRun[] = [];
  private t = 0;

  constructor() {
    this.build();
  }

  get timeMs(): number {
    return this.t;
  }

  run(kind: 'variable' | 'fixed'): HitchRun {
    return this.runs.find((r) => r.kind === kind)!;
  }

  /** Both loops up to `ms` of display time (back in time: replayed from zero). */
  advanceTo(ms: number): void {
    if (ms < this.t) {
      this.build();
      this.t = 0;
    }
    for (const r of this.runs) r.rig.advanceTo(ms);
    this.t = ms;
  }

  /** The display stops for {@link HITCH_MS} from now. */
  addHitch(): void {
    this.hitches.push(this.t);
    const t = this.t;
    this.build();
    this.t = 0;
    this.advanceTo(t);
  }

  restart(): void {
    this.hitches.length = 0;
    this.build();
    this.t = 0;
  }

  private build(): void {
    const events = this.hitches.map((atMs) => ({
      kind: 'hitch' as const,
      atMs,
      durationMs: HITCH_MS,
    }));
    this.runs = (['variable', 'fixed'] as const).map((kind): HitchRun => {
      const trace = new SpringTrace();
      const rig = new SceneRig<TalkSpring>({
        loop: kind === 'fixed' ? { kind: 'fixed', stepMs: 30 } : { kind: 'variable' },
        display: { ...HITCH_DISPLAY, events },
        scene: new TalkSpring(HITCH_OMEGA),
        onUpdate: (scene) => {
          trace.push(scene.time, scene.x);
        },
      });
      return { kind, rig, trace };
    });
  }
}
