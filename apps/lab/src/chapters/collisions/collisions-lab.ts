/**
 * The model behind chapter 3, "Collisions": the firing range of `@fixedstep/games` under a
 * variable Δt and under a fixed step, on one simulated display, driven to a virtual time. No DOM
 * here, so tests drive it exactly as the page does.
 *
 * As in chapter 1, virtual time runs at real speed while the page plays and "Skip" jumps it;
 * every change of a setting (speed, wall, display, a hitch) rebuilds both rigs and replays them
 * from zero to the current virtual time — deterministic, so the numbers repeat exactly.
 */
import {
  ShotStatus,
  WallRangeRig,
  wallRule,
  type RangeLoopKind,
  type WallRange,
  type WallRule,
} from '@fixedstep/games';
import type { DisplayEvent } from 'fixedstep';
import { VirtualLab } from '../../shell/virtual-lab.js';

/** The talk's TIME_STEP, the fixed loop's step. */
export const STEP_MS = 30;
/** The fixed step in seconds. */
export const STEP_S = STEP_MS / 1000;
/** Radius of every fired body. Metres. */
export const RADIUS = 0.1;
/** One shot every so often. Seconds. */
export const FIRE_EVERY_S = 0.1;
/** Lanes the shots cycle through. */
export const LANES = 18;

/** A slider's range: min, max, step, default. */
export interface SliderSpec {
  min: number;
  max: number;
  step: number;
  initial: number;
}

/** Speed of the bodies. m/s. */
export const SPEED: SliderSpec = { min: 10, max: 150, step: 1, initial: 60 };
/** Wall thickness. Metres. */
export const WALL: SliderSpec = { min: 0.1, max: 8, step: 0.1, initial: 3.5 };
/** Display jitter, percent of the period. */
export const JITTER: SliderSpec = { min: 0, max: 50, step: 1, initial: 30 };

/** The display rates offered for the simulated display. */
export const DISPLAY_RATES = [30, 60, 144] as const;
export type DisplayRate = (typeof DISPLAY_RATES)[number];

/** A hitch: no display frame for this long. */
export const HITCH_MS = 250;
/** The most one real frame may move virtual time (a real tab in the background pauses it). */
export const MAX_REAL_FRAME_MS = 100;

export interface RangePanelSpec {
  readonly id: RangeLoopKind;
  readonly title: string;
  readonly tagline: string;
}

export const PANELS: readonly RangePanelSpec[] = [
  {
    id: 'variable',
    title: 'Variable Δt',
    tagline: 'one step per display frame, Δt = the frame’s length',
  },
  {
    id: 'fixed',
    title: 'Fixed step',
    tagline: `the accumulator pays frames out in steps of ${STEP_MS} ms`,
  },
];

/** Everything that decides the numbers. Two labs with equal settings and time are identical. */
export interface CollisionsSettings {
  /** m/s. */
  speed: number;
  /** Wall thickness, m. */
  wall: number;
  hz: DisplayRate;
  /** Display jitter as a fraction of the period, 0 to 0.5. */
  jitter: number;
  /** Hitches, at virtual times. */
  events: DisplayEvent[];
}

export function defaultSettings(): CollisionsSettings {
  return {
    speed: SPEED.initial,
    wall: WALL.initial,
    hz: 30,
    jitter: JITTER.initial / 100,
    events: [],
  };
}

/** When the "A hiccup" experiment's hitch comes. ms from the start. */
export const EXPERIMENT_HITCH_AT_MS = 2000;

/**
 * One of the page's "Things to try". It sets everything its text assumes — speed, wall, display,
 * jitter, hitches, which twin is drawn — and starts again from zero, so what it says comes true
 * whatever was clicked before.
 */
export interface Experiment {
  readonly title: string;
  readonly text: string;
  /** The button's label. */
  readonly action: string;
  /** The settings it starts over with. */
  readonly settings: Readonly<CollisionsSettings>;
  /** Draw the CCD twins. */
  readonly ccd: boolean;
}

const DEFAULT_DISPLAY = { hz: 30, jitter: JITTER.initial / 100 } as const;

export const EXPERIMENTS: readonly Experiment[] = [
  {
    title: 'The talk’s rule, exactly',
    text: `Set the wall to exactly one step: at 60 m/s and ${STEP_MS} ms that is 1.8 m. Every overlap is now detected — and still about 44\u00a0% of the bodies, almost half, go through the fixed-step wall, pushed out on the far side.`,
    action: 'Wall = v·dt',
    settings: { speed: 60, wall: 1.8, ...DEFAULT_DISPLAY, events: [] },
    ccd: false,
  },
  {
    title: 'A hiccup',
    text: `On a steady 60 Hz display each variable step is 17 ms, 1 m at 60 m/s: nothing goes through the 3.5 m wall. Two seconds in, the display stalls for ${HITCH_MS} ms, so the variable loop’s next step is at least ${HITCH_MS} ms long: a body on its way jumps ${(60 * HITCH_MS) / 1000} m or more at once and lands beyond the wall. The fixed loop pays the same time out in ordinary ${STEP_MS} ms steps, and nothing changes.`,
    action: 'Drop a hitch',
    settings: {
      speed: 60,
      wall: 3.5,
      hz: 60,
      jitter: 0,
      events: [{ kind: 'hitch', atMs: EXPERIMENT_HITCH_AT_MS, durationMs: HITCH_MS }],
    },
    ccd: false,
  },
  {
    title: 'A smooth fast display',
    text: 'Switch the display to 144 Hz without jitter, at 60 m/s against the 3.5 m wall. Now the variable steps are 7 ms short and nothing tunnels — on this machine. The fixed step behaves the same on every machine, which is what lets you choose the wall once.',
    action: '144 Hz, no jitter',
    settings: { speed: 60, wall: 3.5, hz: 144, jitter: 0, events: [] },
    ccd: false,
  },
  {
    title: 'Bullets',
    text: 'At 150 m/s against a 0.5 m wall, a body moves 4.5 m per step: discrete detection misses most hits whatever the loop. With CCD each body is swept along its path and stopped at the time of impact: none goes through. The panels now draw the CCD twins.',
    action: 'Fire bullets',
    settings: { speed: 150, wall: 0.5, ...DEFAULT_DISPLAY, events: [] },
    ccd: true,
  },
];

/** The numbers one panel shows. */
export interface RangeReadouts {
  /** Bodies fired. */
  fired: number;
  /** Bodies through the wall, discrete detection only. */
  through: number;
  /** Bodies resolved (bounced or through), discrete detection only. */
  resolved: number;
  /** through / resolved (NaN before the first). */
  share: number;
  /** Bodies through the wall with CCD. */
  ccdThrough: number;
  /** Bodies resolved with CCD. */
  ccdResolved: number;
  /** Steps run by the last display frame. */
  steps: number;
  /** The Δt of the last step, ms. */
  lastDtMs: number;
  /** The longest step so far, ms. */
  maxDtMs: number;
  /** Simulated time, s. */
  simS: number;
}

/** One panel: a rig (discrete and CCD twins) plus what the view draws. */
export class RangePanel {
  lastSteps = 0;
  constructor(
    readonly spec: RangePanelSpec,
    readonly rig: WallRangeRig,
  ) {}

  /** The range to draw: with or without CCD. */
  range(ccd: boolean): WallRange {
    return ccd ? this.rig.continuous : this.rig.discrete;
  }

  /** Record a display frame the rig has just run. */
  recordFrame(steps: number): void {
    this.lastSteps = steps;
  }

  readouts(): RangeReadouts {
    const d = this.rig.discrete;
    const c = this.rig.continuous;
    const resolved = d.through + d.bounced;
    return {
      fired: d.fired,
      through: d.through,
      resolved,
      share: d.share,
      ccdThrough: c.through,
      ccdResolved: c.through + c.bounced,
      steps: this.lastSteps,
      lastDtMs: this.rig.loop.dt * 1000,
      maxDtMs: this.rig.maxDt * 1000,
      simS: d.time,
    };
  }
}

function makeRig(
  kind: RangeLoopKind,
  s: Pick<CollisionsSettings, 'speed' | 'wall'>,
  display: { hz: number; jitter?: number; events?: DisplayEvent[] },
): WallRangeRig {
  return new WallRangeRig({
    loop: kind,
    stepMs: STEP_MS,
    display: { seed: 7, ...display },
    range: {
      speed: s.speed,
      wall: s.wall,
      radius: RADIUS,
      fireEvery: FIRE_EVERY_S,
      lanes: LANES,
      seed: 1,
    },
  });
}

/** One loop's counts at a setting: discrete detection and the CCD twin, each of its own resolved. */
export interface LoopResult {
  through: number;
  resolved: number;
  ccdThrough: number;
  ccdResolved: number;
}

/** The display a result was measured on: the variable-Δt loop's steps are its frames. */
export interface ResultDisplay {
  /** The simulated display's rate, Hz, or the page's real frames. */
  hz: number | 'real';
  /** Frame jitter, a fraction of the period (0 on the real clock: it has its own). */
  jitter: number;
  /** Hitches the display had. */
  hitches: number;
}

/** The result of a run at one setting, for the per-setting table and the chart's points. */
export interface SettingResult {
  speed: number;
  wall: number;
  /** The display it ran on (the fixed step does not depend on it; the variable Δt does). */
  display: ResultDisplay;
  /** Virtual time the setting ran for, s. */
  seconds: number;
  variable: LoopResult;
  fixed: LoopResult;
  /** What geometry predicts for the fixed step. */
  theoryShare: number;
}

/** The two panels on one simulated display, at a virtual time. */
export class CollisionsLab extends VirtualLab<CollisionsSettings> {
  private panels: RangePanel[] = [];
  /** Results of earlier settings (latest per speed and wall), oldest first. */
  readonly history: SettingResult[] = [];

  constructor(settings: CollisionsSettings = defaultSettings()) {
    super(cloneSettings(settings));
    this.build();
  }

  get runs(): RangePanel[] {
    return this.panels;
  }

  /** The rule of thumb at the current setting, for the fixed step. */
  get rule(): WallRule {
    return wallRule(this.current.speed, this.current.wall, RADIUS, STEP_S);
  }

  /** Move virtual time forward to `tMs` (never back), running the frames due. */
  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    this.time = tMs;
    this.runTo(tMs);
  }

  private runTo(tMs: number): void {
    for (const p of this.panels) {
      while (p.rig.nextFrameAt <= tMs) p.recordFrame(p.rig.frame());
    }
  }

  /** The current setting's result so far. */
  result(): SettingResult {
    const s = this.current;
    const display = { hz: s.hz, jitter: s.jitter, hitches: s.events.length };
    return resultOf(s, display, this.time / 1000, this.panels, this.rule.theoryShare);
  }

  /** Change settings and replay from zero to the current virtual time. */
  update(change: Partial<CollisionsSettings>): void {
    const next = cloneSettings({ ...this.current, ...change });
    if (next.speed !== this.current.speed || next.wall !== this.current.wall) {
      this.remember(this.result());
    }
    this.current = next;
    this.build();
  }

  /** Add a hitch starting now, and replay. */
  addHitch(durationMs = HITCH_MS): void {
    this.update({
      events: [...this.current.events, { kind: 'hitch', atMs: this.time, durationMs }],
    });
  }

  /** The display event covering the current time, if any. */
  activeEvent(): DisplayEvent | undefined {
    return this.current.events.find(
      (e) => e.atMs <= this.time && this.time < e.atMs + e.durationMs,
    );
  }

  /** Back to time zero with no hitches, keeping the other settings. */
  restart(): void {
    this.time = 0;
    this.current = { ...cloneSettings(this.current), events: [] };
    this.build();
  }

  /**
   * Start again from time zero with exactly these settings (hitches included): what an
   * experiment does, so its outcome does not depend on what was set before. Leaving a speed and
   * wall keeps its result, as {@link update} does.
   */
  startOver(settings: Readonly<CollisionsSettings>): void {
    const next = cloneSettings(settings);
    if (next.speed !== this.current.speed || next.wall !== this.current.wall) {
      this.remember(this.result());
    }
    this.time = 0;
    this.current = next;
    this.build();
  }

  /** Keep a result in the history (replacing an earlier one at the same speed and wall). */
  remember(r: SettingResult): void {
    if (r.variable.resolved + r.fixed.resolved === 0) return;
    const i = this.history.findIndex((h) => h.speed === r.speed && h.wall === r.wall);
    if (i >= 0) this.history.splice(i, 1);
    this.history.push(r);
    if (this.history.length > 40) this.history.shift();
  }

  private build(): void {
    const s = this.current;
    this.panels = PANELS.map(
      (spec) =>
        new RangePanel(spec, makeRig(spec.id, s, { hz: s.hz, jitter: s.jitter, events: s.events })),
    );
    this.runTo(this.time);
  }
}

function resultOf(
  s: Pick<CollisionsSettings, 'speed' | 'wall'>,
  display: ResultDisplay,
  seconds: number,
  panels: readonly RangePanel[],
  theoryShare: number,
): SettingResult {
  const of = (id: RangeLoopKind) => {
    const r = panels.find((p) => p.spec.id === id)?.readouts();
    return {
      through: r?.through ?? 0,
      resolved: r?.resolved ?? 0,
      ccdThrough: r?.ccdThrough ?? 0,
      ccdResolved: r?.ccdResolved ?? 0,
    };
  };
  return {
    speed: s.speed,
    wall: s.wall,
    display,
    seconds,
    variable: of('variable'),
    fixed: of('fixed'),
    theoryShare,
  };
}

function cloneSettings(s: CollisionsSettings): CollisionsSettings {
  return { ...s, events: s.events.map((e) => ({ ...e })) };
}

/** The two panels on the page's own clock (requestAnimationFrame). */
export class ClockRanges {
  readonly runs: RangePanel[];
  private time = 0;

  constructor(readonly settings: Pick<CollisionsSettings, 'speed' | 'wall'>) {
    this.runs = PANELS.map((spec) => new RangePanel(spec, makeRig(spec.id, settings, { hz: 60 })));
  }

  get timeMs(): number {
    return this.time;
  }

  get rule(): WallRule {
    return wallRule(this.settings.speed, this.settings.wall, RADIUS, STEP_S);
  }

  result(): SettingResult {
    const display = { hz: 'real' as const, jitter: 0, hitches: 0 };
    return resultOf(this.settings, display, this.time / 1000, this.runs, this.rule.theoryShare);
  }

  /** One real display frame at `tMs` from the start of this mode. */
  frameAt(tMs: number): void {
    this.time = tMs;
    for (const p of this.runs) p.recordFrame(p.rig.frameAt(tMs));
  }
}

/** Whether a body in a range is drawn as through the wall. */
export function isThrough(range: WallRange, id: number): boolean {
  return range.status[id] === ShotStatus.through;
}
