/**
 * Shared by the replay tests: a small deterministic simulation ("arena": a few bodies, one per
 * player, driven by button inputs, plus wandering bodies driven by a seeded Random whose state is
 * part of save()), a bot that produces realistic button inputs, and recording helpers.
 */
import {
  ByteReader,
  ByteWriter,
  Random,
  ReplayRecorder,
  fnv1a64,
  isDown,
  packButtons,
  wasPressed,
} from 'fixedstep';
import type { ReplayHeader, ReplayRecorderOptions, Simulation } from 'fixedstep';

export const GAME_ID = 'arena';
export const GAME_VERSION = '1.0.0';

/** Buttons of the arena. */
export const LEFT = 0;
export const RIGHT = 1;
export const UP = 2;
export const DOWN = 3;
export const JUMP = 4;
export const FIRE = 5;

export interface ArenaConfig {
  gravity: number;
  friction: number;
  accel: number;
  jump: number;
  wander: number;
  npcs: number;
}

export const DEFAULT_CONFIG: ArenaConfig = {
  gravity: 0.05,
  friction: 0.02,
  accel: 0.3,
  jump: 4,
  wander: 0.4,
  npcs: 3,
};

const W = 1000;
const H = 600;
const R2 = 20 * 20;

/** Canonical config bytes (what goes into the replay's config blob). */
export function configBytes(c: ArenaConfig = DEFAULT_CONFIG): Uint8Array {
  return new ByteWriter(64)
    .u32(1)
    .f64(c.gravity)
    .f64(c.friction)
    .f64(c.accel)
    .f64(c.jump)
    .f64(c.wander)
    .u32(c.npcs)
    .finish();
}

/** Parses {@link configBytes}; throws a RangeError on anything else. */
export function parseConfig(bytes: Uint8Array): ArenaConfig {
  const r = new ByteReader(bytes);
  if (r.u32() !== 1) throw new RangeError('arena config: unknown version');
  const c: ArenaConfig = {
    gravity: r.f64(),
    friction: r.f64(),
    accel: r.f64(),
    jump: r.f64(),
    wander: r.f64(),
    npcs: r.u32(),
  };
  r.end();
  if (c.npcs > 16) throw new RangeError('arena config: at most 16 npcs');
  return c;
}

/** The test simulation. Deterministic: only + - * / on float64 and a seeded xoshiro. */
export class Arena implements Simulation {
  tick = 0;
  readonly n: number;
  private readonly rng: Random;
  private readonly x: Float64Array;
  private readonly y: Float64Array;
  private readonly vx: Float64Array;
  private readonly vy: Float64Array;
  private readonly score: Int32Array;

  constructor(
    readonly config: ArenaConfig,
    seed: number,
    readonly players: number,
  ) {
    this.rng = new Random(seed);
    this.n = players + config.npcs;
    this.x = new Float64Array(this.n);
    this.y = new Float64Array(this.n);
    this.vx = new Float64Array(this.n);
    this.vy = new Float64Array(this.n);
    this.score = new Int32Array(players);
    for (let i = 0; i < this.n; i++) {
      this.x[i] = this.rng.range(0, W);
      this.y[i] = this.rng.range(0, H);
    }
  }

  step(inputs: readonly number[]): void {
    if (inputs.length !== this.players) throw new RangeError('arena: one input per player');
    const c = this.config;
    const { x, y, vx, vy } = this;
    for (let p = 0; p < this.players; p++) {
      const input = inputs[p]!;
      const ax = (isDown(input, RIGHT) ? 1 : 0) - (isDown(input, LEFT) ? 1 : 0);
      const ay = (isDown(input, DOWN) ? 1 : 0) - (isDown(input, UP) ? 1 : 0);
      vx[p] = vx[p]! + ax * c.accel;
      vy[p] = vy[p]! + ay * c.accel;
      if (wasPressed(input, JUMP)) vy[p] = vy[p]! - c.jump;
      if (wasPressed(input, FIRE)) this.score[p] = this.score[p]! + 1 + this.rng.int(3);
    }
    for (let i = this.players; i < this.n; i++) {
      vx[i] = vx[i]! + this.rng.range(-1, 1) * c.wander;
      vy[i] = vy[i]! + this.rng.range(-1, 1) * c.wander;
    }
    for (let i = 0; i < this.n; i++) {
      vy[i] = vy[i]! + c.gravity;
      vx[i] = vx[i]! * (1 - c.friction);
      vy[i] = vy[i]! * (1 - c.friction);
      x[i] = bounce(x[i]! + vx[i]!, W, vx, i);
      y[i] = bounce(y[i]! + vy[i]!, H, vy, i);
    }
    for (let i = 0; i < this.n; i++) {
      for (let j = i + 1; j < this.n; j++) {
        const dx = x[j]! - x[i]!;
        const dy = y[j]! - y[i]!;
        if (dx * dx + dy * dy < R2) {
          const tx = vx[i]!;
          const ty = vy[i]!;
          vx[i] = vx[j]!;
          vy[i] = vy[j]!;
          vx[j] = tx;
          vy[j] = ty;
        }
      }
    }
    this.tick++;
  }

  save(): Uint8Array {
    return new ByteWriter(64 + this.n * 32)
      .u32(this.tick)
      .ints(this.rng.getState())
      .u32(this.n)
      .f64s(this.x)
      .f64s(this.y)
      .f64s(this.vx)
      .f64s(this.vy)
      .ints(this.score)
      .finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    const tick = r.u32();
    const state = new Uint32Array(4);
    r.ints(state);
    if (r.u32() !== this.n) throw new RangeError('arena.load: wrong body count');
    const x = new Float64Array(this.n);
    const y = new Float64Array(this.n);
    const vx = new Float64Array(this.n);
    const vy = new Float64Array(this.n);
    const score = new Int32Array(this.players);
    r.f64s(x);
    r.f64s(y);
    r.f64s(vx);
    r.f64s(vy);
    r.ints(score);
    r.end();
    this.rng.setState(state);
    this.tick = tick;
    this.x.set(x);
    this.y.set(y);
    this.vx.set(vx);
    this.vy.set(vy);
    this.score.set(score);
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

function bounce(p: number, max: number, v: Float64Array, i: number): number {
  if (p < 0) {
    v[i] = -v[i]!;
    return p < -max ? 0 : -p;
  }
  if (p > max) {
    v[i] = -v[i]!;
    return p > 2 * max ? max : 2 * max - p;
  }
  return p;
}

/** The factory a replay player and verifier use. */
export function arenaFactory(header: ReplayHeader): Arena {
  return new Arena(parseConfig(header.config), header.seeds[0] ?? 0, header.players.length);
}

/**
 * Realistic button inputs (ticks × players, index `t × players + p`): a direction held for 0.5–4 s
 * then released for a while, a jump tapped every 1–3 s and held a few ticks, a fire button in
 * occasional bursts. "Pressed" bits mark the tick a button goes down, as ButtonSampler does.
 */
export function botInputs(seed: number, ticks: number, players: number): Uint32Array {
  const rng = new Random(seed);
  const out = new Uint32Array(ticks * players);
  for (let p = 0; p < players; p++) {
    let down = 0;
    let dirTimer = 0;
    let jumpTimer = rng.int(120);
    let jumpHold = 0;
    let fireTimer = rng.int(300);
    let fireHold = 0;
    for (let t = 0; t < ticks; t++) {
      const before = down;
      if (--dirTimer <= 0) {
        down &= ~0b1111;
        if (rng.next() < 0.7) {
          down |= 1 << rng.int(4);
          dirTimer = 30 + rng.int(211);
        } else {
          dirTimer = 10 + rng.int(81);
        }
      }
      if (jumpHold > 0 && --jumpHold === 0) down &= ~(1 << JUMP);
      if (--jumpTimer <= 0) {
        down |= 1 << JUMP;
        jumpHold = 4 + rng.int(17);
        jumpTimer = 60 + rng.int(121);
      }
      if (fireHold > 0 && --fireHold === 0) down &= ~(1 << FIRE);
      if (--fireTimer <= 0) {
        down |= 1 << FIRE;
        fireHold = 2 + rng.int(4);
        fireTimer = rng.next() < 0.5 ? 8 + rng.int(8) : 120 + rng.int(400);
      }
      out[t * players + p] = packButtons(down, down & ~before);
    }
  }
  return out;
}

/** A recorded arena run with its reference hashes. */
export interface RecordedRun {
  bytes: Uint8Array;
  /** `hashes[t]`: the state hash after tick t (t = 0 … ticks). */
  hashes: bigint[];
  /** `saves.get(t)`: the save() bytes after tick t, for keyframe ticks. */
  saves: Map<number, Uint8Array>;
  inputs: Uint32Array;
  players: number;
}

export interface RecordOptions {
  seed?: number;
  players?: number;
  ticks: number;
  inputSeed?: number;
  inputs?: Uint32Array;
  checkpointEvery?: number;
  keyframeEvery?: number;
  tickHashes?: boolean;
  config?: ArenaConfig;
}

function recorderOptions(o: RecordOptions, players: number): ReplayRecorderOptions {
  return {
    gameId: GAME_ID,
    gameVersion: GAME_VERSION,
    tickRate: 60,
    seeds: [o.seed ?? 1],
    config: configBytes(o.config),
    players: Array.from({ length: players }, (_, i) => `player ${i + 1}`),
    checkpointEvery: o.checkpointEvery ?? 60,
    keyframeEvery: o.keyframeEvery ?? 0,
    tickHashes: o.tickHashes ?? false,
  };
}

/** Run the arena and record it. */
export function recordArena(o: RecordOptions): RecordedRun {
  const players = o.players ?? 2;
  const inputs = o.inputs ?? botInputs(o.inputSeed ?? 7, o.ticks, players);
  const sim = new Arena(o.config ?? DEFAULT_CONFIG, o.seed ?? 1, players);
  const rec = new ReplayRecorder(recorderOptions(o, players));
  const hashes = [sim.hash()];
  const saves = new Map<number, Uint8Array>();
  rec.start(sim);
  const frame: number[] = new Array<number>(players).fill(0);
  for (let t = 0; t < o.ticks; t++) {
    for (let p = 0; p < players; p++) frame[p] = inputs[t * players + p]!;
    sim.step(frame);
    rec.record(frame, sim);
    hashes.push(sim.hash());
    if (o.keyframeEvery && sim.tick % o.keyframeEvery === 0) saves.set(sim.tick, sim.save());
  }
  return { bytes: rec.finish(), hashes, saves, inputs, players };
}

/**
 * A forged replay: the given inputs (and header options), but the hashes and snapshots of
 * `reference` — what a cheater who edits inputs and keeps the checksums valid would produce.
 */
export function forge(reference: RecordedRun, o: RecordOptions): Uint8Array {
  const players = reference.players;
  const inputs = o.inputs ?? reference.inputs;
  const puppet = {
    tick: 0,
    hash: () => reference.hashes[puppet.tick]!,
    save: () => reference.saves.get(puppet.tick)!,
  };
  const rec = new ReplayRecorder(recorderOptions(o, players));
  rec.start(puppet);
  const frame: number[] = new Array<number>(players).fill(0);
  for (let t = 0; t < o.ticks; t++) {
    for (let p = 0; p < players; p++) frame[p] = inputs[t * players + p]!;
    puppet.tick++;
    rec.record(frame, puppet);
  }
  return rec.finish();
}

/** Recompute the checksum (and the declared length) of a possibly edited file, in place. */
export function reseal(bytes: Uint8Array): Uint8Array {
  if (bytes.length < 24) return bytes;
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  view.setUint32(12, bytes.length, true);
  view.setBigUint64(bytes.length - 8, fnv1a64(bytes.subarray(0, bytes.length - 8)), true);
  return bytes;
}
