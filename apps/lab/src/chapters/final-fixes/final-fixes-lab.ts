/**
 * The model behind chapter 8, "Final fixes": two benches on one virtual clock.
 *
 * 1. The spiral of death: the chapter 1 ball on a slow machine, after a hitch, under the slides'
 *    accumulator (no clamp), the final fixes (clamp at 1 s) and FixedLoop (clamp, step cap and an
 *    overload policy). The display waits for all the work a loop asks for, as a page would; the
 *    rigs run at most 5 s of it per frame and count the rest as owed, so a spiral is safe to show.
 * 2. A clock that jumps backwards: a variable Δt, the slides' accumulator, the final fixes and
 *    FixedLoop reading a wall clock that is set back now and then.
 *
 * No DOM here: the tests drive it exactly as the page does.
 */
import {
  BallScene,
  SceneRig,
  STALL_WORK_MS,
  backwardsRig,
  jumpingClock,
  spiralRig,
  type BackwardsLoop,
  type SpiralLoop,
} from '@fixedstep/games';
import { FixedLoop, type DisplayEvent, type OverloadPolicy } from 'fixedstep';
import { VirtualLab } from '../../shell/virtual-lab.js';

export { STALL_WORK_MS };

export interface BenchLoop<Id extends string> {
  readonly id: Id;
  readonly title: string;
  readonly tagline: string;
  readonly color: string;
  /** Fixed loops have an alpha to interpolate with. */
  readonly fixed: boolean;
}

export const SPIRAL_LOOPS: readonly BenchLoop<SpiralLoop>[] = [
  {
    id: 'noclamp',
    title: 'No clamp',
    tagline: 'the slides’ accumulator: acc += dt',
    color: '#a78bfa',
    fixed: true,
  },
  {
    id: 'clamp',
    title: 'Clamp at 1 s',
    tagline: 'the final fixes: acc = clamp(acc + dt, 0, 1.0)',
    color: '#34d399',
    fixed: true,
  },
  {
    id: 'fixed',
    title: 'FixedLoop',
    tagline: 'clamp at 0.25 s, at most 8 steps a frame, an overload policy',
    color: '#38bdf8',
    fixed: true,
  },
];

export const BACKWARDS_LOOPS: readonly BenchLoop<BackwardsLoop>[] = [
  {
    id: 'variable',
    title: 'Variable Δt',
    tagline: 'dt = now − last: a negative step',
    color: '#f87171',
    fixed: false,
  },
  {
    id: 'naive',
    title: 'Accumulator, as on the slides',
    tagline: 'acc += dt: the debt must be paid first',
    color: '#a78bfa',
    fixed: true,
  },
  {
    id: 'final',
    title: 'Final fixes',
    tagline: 'dt = max(0, now − last)',
    color: '#34d399',
    fixed: true,
  },
  {
    id: 'fixed',
    title: 'FixedLoop',
    tagline: 'a backward reading counts as 0 and is counted',
    color: '#38bdf8',
    fixed: true,
  },
];

/** Machines to choose from: what one 30 ms update costs. */
export const MACHINES = [
  { id: 'fast', costMs: 10, label: 'Fast', title: 'An update costs 10 ms: a third of the step' },
  { id: 'busy', costMs: 25, label: 'Busy', title: 'An update costs 25 ms: nearly the whole step' },
  {
    id: 'slow',
    costMs: 40,
    label: 'Slow',
    title: 'An update costs 40 ms: more than the 30 ms it simulates',
  },
] as const;

export const POLICIES: readonly OverloadPolicy[] = ['catch-up', 'drop', 'reset'];

export interface FinalSettings {
  /** What one update costs on this machine, ms. */
  costMs: number;
  /** FixedLoop's overload policy. */
  overload: OverloadPolicy;
  /** Hitches of the spiral bench's display. */
  hitches: DisplayEvent[];
  /** When the backwards bench's clock jumps back, display ms. */
  backJumps: number[];
  /** How far it jumps back each time, ms. */
  backMs: number;
}

export function defaultFinalSettings(): FinalSettings {
  return {
    costMs: 40,
    overload: 'drop',
    hitches: [{ kind: 'hitch', atMs: 1000, durationMs: 1000 }],
    backJumps: [3000],
    backMs: 1500,
  };
}

/** The chart keeps this much history, ms. */
export const HISTORY_MS = 40_000;

/** Per frame: time, steps asked for (and the loop's simulated time, s). */
function pushTrim(a: number[], width: number, ...v: number[]): void {
  a.push(...v);
  if (a.length > 30_000 * width) a.splice(0, a.length - 15_000 * width);
}

/** One run of a bench: a rig plus what the page shows. */
export class BenchRun<Id extends string> {
  /** Per frame: display time (ms), steps asked for, simulated time (s), clock reading (ms). */
  readonly frames: number[] = [];
  /** Per frame: display time (ms), ball x, y, interpolated x, y. */
  readonly trail: number[] = [];
  private lastSim = 0;
  private lastProgressAt = 0;
  /** Whether simulated time ever went down. */
  reversed = false;
  /** The longest display time with no simulated progress, ms. */
  frozenMs = 0;
  /** The most negative Δt a loop was handed, ms (0 if none). */
  minDtMs = 0;

  constructor(
    readonly spec: BenchLoop<Id>,
    readonly rig: SceneRig<BallScene>,
    readonly clock: (t: number) => number = (t) => t,
  ) {}

  get scene(): BallScene {
    return this.rig.scene;
  }

  /** Record the frame the rig has just run. */
  record(): void {
    const rig = this.rig;
    const t = rig.realMs;
    const sim = rig.loop.simTime;
    const clock = this.clock(t);
    if (rig.frames > 1) {
      const prevClock = this.frames[this.frames.length - 1]!;
      this.minDtMs = Math.min(this.minDtMs, clock - prevClock);
    }
    if (sim < this.lastSim - 1e-9) this.reversed = true;
    if (sim > this.lastSim + 1e-9) {
      this.frozenMs = Math.max(this.frozenMs, t - this.lastProgressAt);
      this.lastProgressAt = t;
    }
    this.lastSim = sim;
    pushTrim(this.frames, 4, t, rig.lastSteps, sim, clock);
    const s = rig.scene;
    const a = this.spec.fixed ? rig.loop.alpha : 1;
    this.trail.push(t, s.x, s.y, s.renderX(a), s.renderY(a));
    if (this.trail.length > 5 * 2048) this.trail.splice(0, 5 * 1024);
  }

  /** Trail points within `ms` of `nowMs`: x, y and age (0 newest … 1 oldest). */
  trailPoints(nowMs: number, ms: number, interpolate: boolean, out: number[]): number[] {
    out.length = 0;
    const f = interpolate && this.spec.fixed ? 3 : 1;
    for (let k = 0; k < this.trail.length; k += 5) {
      const age = (nowMs - this.trail[k]!) / ms;
      if (age > 1) continue;
      out.push(this.trail[k + f]!, this.trail[k + f + 1]!, Math.max(0, age));
    }
    return out;
  }

  /** Display time with no simulated progress so far, including now. */
  frozenUntil(nowMs: number): number {
    return Math.max(this.frozenMs, nowMs - this.lastProgressAt);
  }

  /** Frames in the last `ms` before `nowMs`. */
  framesWithin(nowMs: number, ms: number): number {
    let n = 0;
    for (let k = this.frames.length - 4; k >= 0; k -= 4) {
      if (this.frames[k]! < nowMs - ms) break;
      n++;
    }
    return n;
  }

  /** Where to draw the ball now. */
  ballAt(interpolate: boolean): { x: number; y: number } {
    const s = this.rig.scene;
    if (!interpolate || !this.spec.fixed) return { x: s.x, y: s.y };
    const a = this.rig.loop.alpha;
    return { x: s.renderX(a), y: s.renderY(a) };
  }
}

export interface SpiralReadouts {
  steps: number;
  maxSteps: number;
  stalled: boolean;
  owed: number;
  /** The longest wait between two frames so far, including the frame in progress, ms. */
  longestFrameMs: number;
  /** Frames shown in the last 2 s. */
  fps: number;
  /** Simulated over real time. */
  ratio: number;
  /** Work still in progress (the page is busy until the next frame), ms. */
  busyMs: number;
}

export interface BackwardsReadouts {
  simS: number;
  /** Display time minus simulated time, ms. */
  lagMs: number;
  reversed: boolean;
  frozenMs: number;
  minDtMs: number;
  /** Frames the loop saw the clock go back (FixedLoop counts them; undefined for the others). */
  backwardFrames: number | undefined;
}

/** Both benches on one virtual clock (or on the page's real one). */
export class FinalLab extends VirtualLab<FinalSettings> {
  spiral: BenchRun<SpiralLoop>[] = [];
  backwards: BenchRun<BackwardsLoop>[] = [];

  constructor(
    settings: FinalSettings = defaultFinalSettings(),
    readonly realClock = false,
  ) {
    super(cloneSettings(settings));
    this.build();
  }

  /** What the backwards bench's wall clock reads now, ms. */
  get clockReading(): number {
    return jumpingClock(this.current.backJumps, this.current.backMs)(this.time);
  }

  /** Move virtual time forward to `tMs` (never back), running the frames due. */
  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    this.time = tMs;
    for (const r of [...this.spiral, ...this.backwards]) {
      r.rig.advanceTo(tMs, () => {
        r.record();
      });
    }
  }

  /**
   * Real clock: a frame of the page at `tMs`. A spiral run takes it only once the work of its
   * last frame is done (and not during a hitch); the backwards runs take every frame.
   */
  realFrame(tMs: number): void {
    if (tMs < this.time) return;
    this.time = tMs;
    const hitch = this.current.hitches.some((e) => e.atMs <= tMs && tMs < e.atMs + e.durationMs);
    for (const r of this.spiral) {
      const rig = r.rig;
      if (hitch || (rig.frames > 0 && tMs < rig.realMs + rig.workMs)) continue;
      rig.frameAt(tMs);
      r.record();
    }
    for (const r of this.backwards) {
      r.rig.frameAt(tMs);
      r.record();
    }
  }

  /** Change settings and replay from zero to the current time. */
  update(change: Partial<FinalSettings>): void {
    this.current = cloneSettings({ ...this.current, ...change });
    this.build();
  }

  /** A hitch of `durationMs` starting now. */
  addHitch(durationMs: number): void {
    this.update({
      hitches: [...this.current.hitches, { kind: 'hitch', atMs: this.time, durationMs }],
    });
  }

  /** The wall clock jumps back now. */
  jumpBack(): void {
    this.update({ backJumps: [...this.current.backJumps, this.time] });
  }

  /** Back to time zero with the default events, keeping the machine, policy and jump size. */
  restart(): void {
    this.time = 0;
    const d = defaultFinalSettings();
    this.current = cloneSettings({ ...this.current, hitches: d.hitches, backJumps: d.backJumps });
    this.build();
  }

  /** The hitch covering the current time, if any. */
  activeHitch(): DisplayEvent | undefined {
    return this.current.hitches.find(
      (e) => e.atMs <= this.time && this.time < e.atMs + e.durationMs,
    );
  }

  spiralReadouts(run: BenchRun<SpiralLoop>): SpiralReadouts {
    const rig = run.rig;
    const realS = rig.realMs / 1000;
    const busy = Math.max(0, rig.realMs + rig.workMs - this.time);
    // A stalled page never ran the updates it owes: they are not simulated time.
    const simS = rig.updates * rig.loop.dt;
    return {
      steps: rig.lastSteps,
      maxSteps: rig.maxSteps,
      stalled: rig.stalled,
      owed: rig.owed,
      longestFrameMs: Math.max(rig.longestFrameMs, this.time - rig.realMs),
      fps: run.framesWithin(this.time, 2000) / 2,
      ratio: realS > 0 ? simS / realS : NaN,
      busyMs: rig.frames > 0 && this.time < rig.realMs + rig.workMs ? busy : 0,
    };
  }

  backwardsReadouts(run: BenchRun<BackwardsLoop>): BackwardsReadouts {
    const loop = run.rig.loop;
    const simS = loop.simTime;
    return {
      simS,
      lagMs: run.rig.realMs - simS * 1000,
      reversed: run.reversed,
      frozenMs: run.frozenUntil(run.rig.realMs),
      minDtMs: run.minDtMs,
      backwardFrames: loop instanceof FixedLoop ? loop.backwardFrames : undefined,
    };
  }

  private build(): void {
    const s = this.current;
    this.spiral = SPIRAL_LOOPS.map(
      (spec) =>
        new BenchRun(
          spec,
          spiralRig({
            loop: spec.id,
            updateCostMs: s.costMs,
            overload: s.overload,
            events: this.realClock ? [] : s.hitches,
          }),
        ),
    );
    const clock = jumpingClock(s.backJumps, s.backMs);
    this.backwards = BACKWARDS_LOOPS.map(
      (spec) =>
        new BenchRun(
          spec,
          backwardsRig({ loop: spec.id, jumpsAtMs: s.backJumps, backMs: s.backMs }),
          clock,
        ),
    );
    if (!this.realClock) {
      for (const r of [...this.spiral, ...this.backwards]) {
        r.rig.advanceTo(this.time, () => {
          r.record();
        });
      }
    }
  }
}

/** What the slides' accumulator (no clamp) does after a hitch on a machine: the text's numbers. */
export interface SpiralOutlook {
  /** The hitch: when, and how long, ms. */
  hitchAtMs: number;
  hitchMs: number;
  /** What one update costs, ms. */
  costMs: number;
  /** Steps asked for by the first frames after the hitch (at most five). */
  steps: number[];
  /** Whether a frame after the hitch had more work than a page can do ({@link STALL_WORK_MS}). */
  stalls: boolean;
}

/**
 * Runs the no-clamp rig of the spiral bench headless with `costMs` and the hitch `hitch` and
 * reads the steps its first frames after the hitch ask for — the same rig the bench draws, so
 * the text says what the panel will show.
 */
export function spiralOutlook(costMs: number, hitch: DisplayEvent): SpiralOutlook {
  const rig = spiralRig({ loop: 'noclamp', updateCostMs: costMs, events: [hitch] });
  const end = hitch.atMs + hitch.durationMs;
  const steps: number[] = [];
  for (let t = end; steps.length < 5 && !rig.stalled && t < end + 120_000; t += 250) {
    rig.advanceTo(t, () => {
      if (rig.realMs >= end && steps.length < 5) steps.push(rig.lastSteps);
    });
  }
  return { hitchAtMs: hitch.atMs, hitchMs: hitch.durationMs, costMs, steps, stalls: rig.stalled };
}

function cloneSettings(s: FinalSettings): FinalSettings {
  return {
    costMs: s.costMs,
    overload: s.overload,
    hitches: s.hitches.map((e) => ({ ...e })),
    backJumps: [...s.backJumps],
    backMs: s.backMs,
  };
}
