/**
 * The model behind chapter 7, "Debugging": one recording of button presses replayed on four
 * simulated displays (30, 60, 144, 240 Hz, with jitter) under a variable Δt and under a fixed
 * step, with a hash of every run's state. Under the fixed step the hashes agree tick for tick.
 * No DOM here: the tests drive it exactly as the page does.
 *
 * The reader can record a session of their own: while recording, every press goes to every run
 * at the same virtual time; when it stops, the recording replays from zero on every display.
 */
import {
  InputRecorder,
  JumperScene,
  SceneRig,
  TickHashes,
  debugSceneConfig,
  demoRecording,
  jitterSeed,
  loopKindOf,
  recordingLength,
  type MovementLoop,
  type ScriptedInput,
} from '@fixedstep/games';
import {
  DEFAULT_JITTER,
  RATES,
  STEP_MS,
  type LoopInfo,
  type Source,
} from '../movement/movement-lab.js';

// Chapter 2's four displays, step and loops, replayed here from a recording.
export {
  DEFAULT_JITTER,
  RATES,
  STEP_MS,
  sourceLabel,
  type LoopInfo,
  type Rate,
  type Source,
} from '../movement/movement-lab.js';
import { VirtualLab } from '../../shell/virtual-lab.js';

/** A recording stops by itself after this long, ms. */
export const MAX_RECORDING_MS = 30_000;
/** The divergence chart samples every this many ms of virtual time. */
export const SAMPLE_MS = 50;
/** The divergence chart keeps this much history, ms. */
export const CHART_WINDOW_MS = 20_000;

export const LOOPS: readonly LoopInfo[] = [
  {
    id: 'variable',
    title: 'Variable Δt',
    tagline: 'no ticks to line up: each display’s state at its last frame',
    fixed: false,
  },
  {
    id: 'fixed',
    title: 'Fixed step',
    tagline: `FixedLoop, ${STEP_MS} ms steps: each display’s state at the same tick`,
    fixed: true,
  },
];

export interface DebugSettings {
  /** Frame jitter as a fraction of the period, 0 to 0.3. */
  jitter: number;
  /** The button events replayed on every display. */
  recording: ScriptedInput[];
}

export function defaultDebugSettings(): DebugSettings {
  return { jitter: DEFAULT_JITTER, recording: demoRecording() };
}

/** Keep an array of (t, x, y) triples from growing without end. */
function trim(a: number[], max = 12_000): void {
  if (a.length > max) a.splice(0, a.length - max / 2);
}

/** One run of the recording: a loop on one display, hashing its state after every update. */
export class DebugTrack {
  readonly rig: SceneRig<JumperScene>;
  /** Hashes of the last ticks (the fixed step's ticks; a variable run's updates). */
  readonly hashes = new TickHashes(512);
  /** Simulated time (ms), x, y after every update, the latest few thousand. */
  readonly path: number[] = [];
  /** The hash of the state before any update (tick 0). */
  readonly initialHash: string;

  constructor(
    readonly loop: LoopInfo,
    readonly source: Source,
    jitter: number,
    script: readonly ScriptedInput[],
  ) {
    const hz = source === 'real' ? 60 : source;
    this.rig = new SceneRig({
      loop: { kind: loopKindOf(loop.id), stepMs: STEP_MS },
      display: { hz, jitter: source === 'real' ? 0 : jitter, seed: jitterSeed(hz) },
      scene: new JumperScene(debugSceneConfig()),
      script,
      onUpdate: (scene, l) => {
        this.hashes.push(scene.hash());
        // A fixed step's update k ends at k × step exactly (integer ticks, no float sums).
        const t = loop.fixed ? this.hashes.latest * STEP_MS : l.simTime * 1000;
        this.path.push(t, scene.x, scene.y);
        trim(this.path);
      },
    });
    this.initialHash = this.rig.scene.hash();
  }

  get scene(): JumperScene {
    return this.rig.scene;
  }

  /** The hash after tick `k` (0: the start), if still held. */
  hashAt(k: number): string | undefined {
    return k === 0 ? this.initialHash : this.hashes.at(k);
  }

  /** Ticks (fixed) or updates (variable) run so far. */
  get ticks(): number {
    return this.hashes.latest;
  }

  /** Position at simulated time `tMs`, interpolated between the updates around it. */
  positionAt(tMs: number, interpolate = true): { x: number; y: number } {
    const p = this.path;
    let k = p.length - 3;
    while (k > 0 && p[k]! > tMs) k -= 3;
    if (k < 0) return { x: this.scene.x, y: this.scene.y };
    const next = k + 3;
    if (interpolate && p[k]! <= tMs && next < p.length) {
      const a = (tMs - p[k]!) / (p[next]! - p[k]!);
      return {
        x: p[k + 1]! + (p[next + 1]! - p[k + 1]!) * a,
        y: p[k + 2]! + (p[next + 2]! - p[k + 2]!) * a,
      };
    }
    return { x: p[k + 1]!, y: p[k + 2]! };
  }
}

export interface DebugRow {
  source: Source;
  /** Ticks (fixed) or updates (variable) so far. */
  ticks: number;
  /** Fixed: the hash at the common tick; variable: the hash of the state now. */
  hash: string | undefined;
  score: number;
}

export interface DebugReadouts {
  /** The latest tick every fixed-step run has reached (0 for the variable runs). */
  commonTick: number;
  rows: DebugRow[];
  /** Whether every row shows the same hash. */
  equal: boolean;
  /** The largest distance between two runs' runners at the latest sample, metres. */
  divergence: number;
  /** The largest distance between two runs' runners at any sample since the start, metres. */
  maxDivergence: number;
  /** When that was, ms of virtual time (NaN before any sample). */
  maxDivergenceAtMs: number;
  /** Whether any run's state has left its start (a runner moved, a coin was taken). */
  moved: boolean;
}

/** The largest distance between any two points. */
function maxDistance(points: readonly { x: number; y: number }[]): number {
  let d = 0;
  for (let i = 0; i < points.length; i++) {
    for (let j = i + 1; j < points.length; j++) {
      const a = points[i]!;
      const b = points[j]!;
      d = Math.max(d, Math.sqrt((a.x - b.x) ** 2 + (a.y - b.y) ** 2));
    }
  }
  return d;
}

export type Mode = 'replay' | 'recording';

/** Both loops on the four simulated displays (and the real one), replaying one recording. */
export class DebugLab extends VirtualLab<DebugSettings> {
  private sim = new Map<MovementLoop, DebugTrack[]>();
  private real = new Map<MovementLoop, DebugTrack>();
  private recorder: InputRecorder | undefined;
  private recordingFrom = 0;
  /** Divergence samples: time (ms), variable (m), fixed (m). */
  readonly samples: number[] = [];
  private nextSample = 0;
  /** The largest divergence sampled since the start, per loop: metres, and when (ms). */
  private readonly widest = new Map<MovementLoop, { metres: number; atMs: number }>();
  /** Whether the recording being replayed is the built-in demo. */
  demo = true;

  constructor(
    settings: DebugSettings = defaultDebugSettings(),
    readonly realClock = false,
  ) {
    super({ jitter: settings.jitter, recording: [...settings.recording] });
    this.build();
  }

  get mode(): Mode {
    return this.recorder ? 'recording' : 'replay';
  }

  /** Inputs in the recording being replayed, or recorded so far. */
  get recordedInputs(): number {
    return this.recorder ? this.recorder.events.length : this.current.recording.length;
  }

  /** Length of the recording being replayed, or recorded so far, ms. */
  get recordingMs(): number {
    return this.recorder ? this.time - this.recordingFrom : recordingLength(this.current.recording);
  }

  /** The events of the recording being replayed, or recorded so far. */
  recordingEvents(): readonly ScriptedInput[] {
    return this.recorder ? this.recorder.events : this.current.recording;
  }

  tracks(loop: MovementLoop): DebugTrack[] {
    const out = [...(this.sim.get(loop) ?? [])];
    const r = this.real.get(loop);
    if (r) out.push(r);
    return out;
  }

  private all(): DebugTrack[] {
    return [...this.tracks('variable'), ...this.tracks('fixed')];
  }

  /** Move virtual time forward to `tMs` (never back). */
  advanceTo(tMs: number): void {
    if (!(tMs > this.time)) return;
    if (this.recorder && tMs - this.recordingFrom >= MAX_RECORDING_MS) {
      this.advanceSim(this.recordingFrom + MAX_RECORDING_MS);
      this.stopRecording();
      return;
    }
    this.advanceSim(tMs);
  }

  /** Real clock: a frame of the page at `tMs`; the simulated displays keep up. */
  realFrame(tMs: number): void {
    if (tMs < this.time) return;
    this.advanceTo(tMs);
    this.time = Math.max(this.time, tMs);
    for (const t of this.real.values()) t.rig.frameAt(this.time);
    this.sample();
  }

  private advanceSim(tMs: number): void {
    this.time = tMs;
    for (const list of this.sim.values()) for (const t of list) t.rig.advanceTo(tMs);
    this.sample();
  }

  /** Change the jitter (replays from zero to now). */
  setJitter(jitter: number): void {
    this.current = { ...this.current, jitter };
    this.build();
  }

  /** Replay a recording from zero. */
  load(recording: readonly ScriptedInput[], demo = false): void {
    this.recorder = undefined;
    this.current = { ...this.current, recording: [...recording] };
    this.demo = demo;
    this.restart();
  }

  /** Start a new recording from zero: the displays run live, fed the reader's presses. */
  startRecording(): void {
    this.load([]);
    this.recorder = new InputRecorder();
    this.recordingFrom = 0;
  }

  /**
   * A button went down or up, `lateMs` after the current time (the time since the last frame).
   * Only while recording; every run gets it at the same time.
   */
  press(button: number, down: boolean, lateMs = 0): boolean {
    const rec = this.recorder;
    if (!rec) return false;
    const e = rec.push(this.time - this.recordingFrom + Math.max(0, lateMs), button, down);
    if (!e) return false;
    for (const t of this.all()) t.rig.addInputs([e]);
    return true;
  }

  /** Stop recording and replay what was recorded from zero, on every display. */
  stopRecording(): void {
    const rec = this.recorder;
    if (!rec) return;
    rec.finish(this.time - this.recordingFrom);
    this.load(rec.events);
  }

  /** Back to time zero, replaying the current recording. */
  restart(): void {
    this.time = 0;
    if (this.recorder) this.recorder = new InputRecorder();
    this.build();
  }

  readouts(loop: MovementLoop): DebugReadouts {
    const tracks = this.tracks(loop);
    const fixed = loop === 'fixed';
    const commonTick = fixed ? Math.min(...tracks.map((t) => t.ticks)) : 0;
    const rows = tracks.map((t) => ({
      source: t.source,
      ticks: t.ticks,
      hash: fixed ? t.hashAt(commonTick) : t.scene.hash(),
      score: t.scene.score,
    }));
    const first = rows[0]?.hash;
    const n = this.samples.length;
    const widest = this.widest.get(loop);
    return {
      commonTick,
      rows,
      equal: first !== undefined && rows.every((r) => r.hash === first),
      divergence: n >= 3 ? this.samples[n - (fixed ? 1 : 2)]! : NaN,
      maxDivergence: widest?.metres ?? 0,
      maxDivergenceAtMs: widest?.atMs ?? NaN,
      moved: tracks.some((t) => t.scene.hash() !== t.initialHash),
    };
  }

  /** Sample the runners' divergence at every {@link SAMPLE_MS} every run has got past. */
  private sample(): void {
    const all = this.all();
    let reached = Infinity;
    for (const t of all) reached = Math.min(reached, t.rig.realMs);
    // Fixed runs are compared one step behind, where every run has the ticks on both sides.
    while (this.nextSample + 2 * STEP_MS <= reached) {
      const ts = this.nextSample;
      const v = maxDistance(this.tracks('variable').map((t) => t.positionAt(ts)));
      const f = maxDistance(this.tracks('fixed').map((t) => t.positionAt(ts)));
      this.samples.push(ts, v, f);
      this.widen('variable', v, ts);
      this.widen('fixed', f, ts);
      this.nextSample += SAMPLE_MS;
    }
    const keep = (CHART_WINDOW_MS / SAMPLE_MS) * 3;
    if (this.samples.length > keep * 2) this.samples.splice(0, this.samples.length - keep);
  }

  private widen(loop: MovementLoop, metres: number, atMs: number): void {
    const w = this.widest.get(loop);
    if (w === undefined || metres > w.metres) this.widest.set(loop, { metres, atMs });
  }

  private build(): void {
    const script = this.current.recording;
    this.sim = new Map(
      LOOPS.map((loop) => [
        loop.id,
        RATES.map((hz) => new DebugTrack(loop, hz, this.current.jitter, script)),
      ]),
    );
    if (this.realClock) {
      this.real = new Map(LOOPS.map((loop) => [loop.id, new DebugTrack(loop, 'real', 0, script)]));
      for (const t of this.real.values()) t.rig.frameAt(0); // the real time line starts here
    }
    this.samples.length = 0;
    this.widest.clear();
    this.nextSample = 0;
    for (const list of this.sim.values()) for (const t of list) t.rig.advanceTo(this.time);
    this.sample();
  }
}
