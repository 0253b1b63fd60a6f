import { MAX_BUTTONS, downBit } from 'fixedstep';
import type { ScriptedInput } from './loops.js';
import {
  JumperButtons,
  JumperScene,
  jitterSeed,
  loopKindOf,
  type JumperConfig,
} from './movement.js';
import type { MovementLoop } from './movement.js';
import { SceneRig } from './movement-rig.js';

/** The debugging chapter's level: the jumper with three coins at seeded places. */
export function debugSceneConfig(): Partial<JumperConfig> {
  return { coins: 3, seed: 7, coinBottom: 1.2 };
}

const L = JumperButtons.left;
const R = JumperButtons.right;
const J = JumperButtons.jump;

/** Press `button` at `at` ms and let it go `holdMs` later. */
function hold(at: number, button: number, holdMs: number): ScriptedInput[] {
  return [
    { timeMs: at, button, down: true },
    { timeMs: at + holdMs, button, down: false },
  ];
}

/**
 * A recorded session of about 9 s — what a player did, as timestamped button events: run right
 * with a few jumps, turn back, jump again. The debugging chapter replays it on every display.
 */
export function demoRecording(): ScriptedInput[] {
  return [
    ...hold(300, R, 2100),
    ...hold(700, J, 260),
    ...hold(1750, J, 120),
    ...hold(2900, L, 1500),
    ...hold(3300, J, 300),
    ...hold(4800, R, 900),
    ...hold(5000, J, 200),
    ...hold(6200, L, 1100),
    ...hold(6500, J, 320),
    ...hold(7800, R, 400),
    ...hold(7900, J, 150),
  ].sort((a, b) => a.timeMs - b.timeMs);
}

/** How long the demo recording lasts, ms (its last event). */
export function recordingLength(recording: readonly ScriptedInput[]): number {
  let end = 0;
  for (const e of recording) end = Math.max(end, e.timeMs);
  return end;
}

/**
 * Collects a player's button events as a recording: timestamped downs and ups, in time order,
 * with repeats of a held button ignored and every held button let go when it stops.
 */
export class InputRecorder {
  readonly events: ScriptedInput[] = [];
  private held = 0;

  /** Record `button` going down or up at `timeMs` (ms from the start of the recording). */
  push(timeMs: number, button: number, down: boolean): ScriptedInput | undefined {
    const bit = downBit(button);
    if (down === ((this.held & bit) !== 0)) return undefined; // a repeat, or an up with no down
    const last = this.events[this.events.length - 1];
    const t = last && timeMs < last.timeMs ? last.timeMs : timeMs;
    this.held ^= bit;
    const e = { timeMs: t, button, down };
    this.events.push(e);
    return e;
  }

  /** Let go of every held button at `timeMs`; returns the release events added. */
  finish(timeMs: number): ScriptedInput[] {
    const out: ScriptedInput[] = [];
    for (let b = 0; b < MAX_BUTTONS; b++) {
      if (this.held & downBit(b)) {
        const e = this.push(timeMs, b, false);
        if (e) out.push(e);
      }
    }
    return out;
  }
}

/**
 * Hashes of the last `capacity` ticks of a run, by tick number (ticks count from 1: tick k is the
 * state after the k-th update).
 */
export class TickHashes {
  private readonly hashes: string[];
  private last = 0;

  constructor(readonly capacity = 256) {
    this.hashes = new Array<string>(capacity).fill('');
  }

  /** The latest tick recorded. */
  get latest(): number {
    return this.last;
  }

  push(hash: string): void {
    this.last++;
    this.hashes[this.last % this.capacity] = hash;
  }

  /** The hash after tick `k`, if still held. */
  at(k: number): string | undefined {
    if (k < 1 || k > this.last || k <= this.last - this.capacity) return undefined;
    return this.hashes[k % this.capacity];
  }
}

export interface RecordingRunOptions {
  loop: MovementLoop;
  hz: number;
  /** Frame jitter as a fraction of the period. Default 0.2. */
  jitter?: number;
  /** Fixed step, ms. Default 30. */
  stepMs?: number;
  recording?: readonly ScriptedInput[];
  /** How long to run, ms of display time. Default: the recording plus 1.5 s. */
  durationMs?: number;
}

export interface RecordingRun {
  rig: SceneRig<JumperScene>;
  /** The hash after every update, in order. */
  hashes: string[];
}

/**
 * The debugging scene builder: a recording replayed on one simulated display under one loop,
 * hashing the state after every update.
 */
export function runRecording(options: RecordingRunOptions): RecordingRun {
  const recording = options.recording ?? demoRecording();
  const hashes: string[] = [];
  const rig = new SceneRig({
    loop: { kind: loopKindOf(options.loop), stepMs: options.stepMs ?? 30 },
    display: { hz: options.hz, jitter: options.jitter ?? 0.2, seed: jitterSeed(options.hz) },
    scene: new JumperScene(debugSceneConfig()),
    script: recording,
    onUpdate: (scene) => hashes.push(scene.hash()),
  });
  rig.runFor(options.durationMs ?? recordingLength(recording) + 1500);
  return { rig, hashes };
}
