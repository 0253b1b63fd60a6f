import type { Simulation } from '../sim/simulation.js';
import { Timestep } from '../time/timestep.js';
import { ByteWriter } from '../det/bytes.js';
import { interleave } from '../sim/buttons.js';
import { MAX_STRING_BYTES, gcd, low32, utf8Length } from './codec.js';
import { assembleReplay } from './format.js';
import type { ReplayHeader } from './format.js';

/** What a {@link ReplayRecorder} needs to know before the first tick. */
export interface ReplayRecorderOptions {
  /** Which game or scene (1–255 bytes of UTF-8), checked by readers that expect one. */
  gameId: string;
  /** The game's version (0–255 bytes of UTF-8): a replay only replays on the same simulation code. */
  gameVersion: string;
  /**
   * The fixed step: a {@link Timestep}, or an integer tick rate in Hz. Stored as an exact
   * rational number of seconds (1/60, 3/100, …).
   */
  tickRate: Timestep | number;
  /** The seeds of every random generator the game seeds at the start (u32 each). Default none. */
  seeds?: readonly number[];
  /** Opaque configuration bytes the factory needs to rebuild the start (e.g. canonical config bytes). Default empty. */
  config?: Uint8Array;
  /** One name per player (0–255 bytes of UTF-8 each); the count is the inputs per tick. At least one. */
  players: readonly string[];
  /** Store the state hash every this many ticks (a positive integer). Default 60. */
  checkpointEvery?: number;
  /**
   * Store a `save()` snapshot every this many ticks, for seeking (a positive multiple of
   * `checkpointEvery`, or 0 for none). Default 0. Every keyframe costs a `save()` and its bytes.
   */
  keyframeEvery?: number;
  /**
   * Also store the low 32 bits of the state hash after every tick (4 bytes a tick), so a
   * verifier can name the exact first tick that differs. Costs a `hash()` every tick. Default false.
   */
  tickHashes?: boolean;
}

/** The sub-set of {@link Simulation} the recorder reads. */
export type RecordableSimulation = Pick<Simulation, 'tick' | 'hash' | 'save'>;

/**
 * Records a run from its inputs and seeds alone: per-tick inputs (run-length compressed as they
 * arrive), a state hash every `checkpointEvery` ticks, a snapshot every `keyframeEvery` ticks.
 *
 * @example
 * const rec = new ReplayRecorder({ gameId: 'arena', gameVersion: '1', tickRate: 60, seeds: [seed], players: ['ann'] });
 * rec.start(sim);                      // at tick 0: the initial hash
 * // every tick:
 * sim.step(inputs); rec.record(inputs, sim);
 * const file = rec.finish();
 *
 * Per tick it allocates nothing beyond the amortised growth of its buffers — except what the
 * simulation's own `hash()` and `save()` allocate at checkpoints and keyframes (and every tick with
 * `tickHashes`).
 */
export class ReplayRecorder {
  /** The header that will be written (and that a factory will get back). */
  readonly header: ReplayHeader;
  /** See {@link ReplayRecorderOptions.checkpointEvery}. */
  readonly checkpointEvery: number;
  /** See {@link ReplayRecorderOptions.keyframeEvery}. */
  readonly keyframeEvery: number;
  /** See {@link ReplayRecorderOptions.tickHashes}. */
  readonly withTickHashes: boolean;

  private readonly streams: ByteWriter[] = [];
  /** Per player: the interleaved value of the open run, of the run before it, and the open run's length. */
  private readonly runValue: Uint32Array;
  private readonly prevValue: Uint32Array;
  private readonly runLength: Float64Array;
  private readonly checkpoints = new ByteWriter(256);
  private readonly keyframes = new ByteWriter(256);
  private readonly tickHashSink: ByteWriter | null;
  private ticks = 0;
  private started = false;
  private initialHash = 0n;
  private last: RecordableSimulation | null = null;

  constructor(options: ReplayRecorderOptions) {
    const { gameId, gameVersion, players } = options;
    checkString('gameId', gameId, 1);
    checkString('gameVersion', gameVersion, 0);
    if (players.length < 1 || players.length > 0xffff) {
      throw new RangeError('ReplayRecorder: players must list 1 to 65535 names');
    }
    players.forEach((name, i) => {
      checkString(`players[${i}]`, name, 0);
    });
    const seeds = options.seeds ?? [];
    for (const s of seeds) {
      if (!Number.isInteger(s) || s < 0 || s > 0xffffffff) {
        throw new RangeError(`ReplayRecorder: seeds must be u32 integers, got ${String(s)}`);
      }
    }
    const config = options.config ?? new Uint8Array(0);
    if (!(config instanceof Uint8Array)) {
      throw new RangeError('ReplayRecorder: config must be a Uint8Array');
    }
    const step = Timestep.from(options.tickRate);
    // step = unitsPerStep / unitsPerNs ns = unitsPerStep / (unitsPerNs × 1e9) s, both exact integers.
    const num = step.unitsPerStep;
    const den = step.unitsPerNs * 1e9;
    const g = gcd(num, den);
    if (num / g > 0xffffffff || den / g > 0xffffffff) {
      throw new RangeError(
        `ReplayRecorder: a step of ${num / g}/${den / g} s does not fit the format`,
      );
    }
    this.checkpointEvery = options.checkpointEvery ?? 60;
    this.keyframeEvery = options.keyframeEvery ?? 0;
    if (!isInterval(this.checkpointEvery) || this.checkpointEvery < 1) {
      throw new RangeError(
        `ReplayRecorder: checkpointEvery must be a positive integer, got ${String(this.checkpointEvery)}`,
      );
    }
    if (!isInterval(this.keyframeEvery) || this.keyframeEvery % this.checkpointEvery !== 0) {
      throw new RangeError(
        `ReplayRecorder: keyframeEvery must be 0 or a positive multiple of checkpointEvery (${this.checkpointEvery}), got ${String(this.keyframeEvery)}`,
      );
    }
    this.withTickHashes = options.tickHashes ?? false;
    this.header = Object.freeze({
      formatVersion: 1,
      gameId,
      gameVersion,
      stepNumerator: num / g,
      stepDenominator: den / g,
      seeds: Object.freeze([...seeds]),
      config: config.slice(),
      players: Object.freeze([...players]),
    });
    const n = players.length;
    for (let p = 0; p < n; p++) this.streams.push(new ByteWriter(64));
    this.runValue = new Uint32Array(n);
    this.prevValue = new Uint32Array(n);
    this.runLength = new Float64Array(n);
    this.tickHashSink = this.withTickHashes ? new ByteWriter(1024) : null;
  }

  /** Ticks recorded so far. */
  get tickCount(): number {
    return this.ticks;
  }

  /** Bytes of compressed input so far (all players, open runs not counted). */
  get inputBytes(): number {
    let n = 0;
    for (const s of this.streams) n += s.length;
    return n;
  }

  /**
   * Take the initial state's hash (the checkpoint at tick 0). Call once, before the first step,
   * with the simulation at tick 0 as the factory will rebuild it from the header.
   */
  start(sim: RecordableSimulation): void {
    if (this.started) throw new Error('ReplayRecorder.start: already started');
    if (sim.tick !== 0) {
      throw new RangeError(`ReplayRecorder.start: the simulation is at tick ${sim.tick}, not 0`);
    }
    this.started = true;
    this.initialHash = BigInt.asUintN(64, sim.hash());
    this.checkpoints.u64(this.initialHash);
    this.last = sim;
  }

  /**
   * Record one tick: call right after `sim.step(inputs)`, with the same inputs (one u32 per
   * player). Takes the hash at checkpoint ticks and the snapshot at keyframe ticks.
   */
  record(inputs: readonly number[], sim: RecordableSimulation): void {
    if (!this.started)
      throw new Error('ReplayRecorder.record: call start(sim) before the first step');
    const n = this.streams.length;
    if (inputs.length !== n) {
      throw new RangeError(`ReplayRecorder.record: ${inputs.length} inputs for ${n} players`);
    }
    const tick = this.ticks + 1;
    if (sim.tick !== tick) {
      throw new RangeError(
        `ReplayRecorder.record: the simulation is at tick ${sim.tick}, expected ${tick} (record once per step, after it)`,
      );
    }
    if (tick > 0xffffffff) throw new RangeError('ReplayRecorder.record: 2^32 - 1 ticks recorded');
    for (let p = 0; p < n; p++) {
      const v = inputs[p]!;
      if (!Number.isInteger(v) || v < 0 || v > 0xffffffff) {
        throw new RangeError(
          `ReplayRecorder.record: input of player ${p} is not a u32: ${String(v)}`,
        );
      }
    }
    for (let p = 0; p < n; p++) {
      const w = interleave(inputs[p]!);
      if (this.ticks === 0) {
        this.runValue[p] = w;
        this.runLength[p] = 1;
      } else if (w === this.runValue[p]) {
        this.runLength[p]!++;
      } else {
        const s = this.streams[p]!;
        s.varint((this.runValue[p]! ^ this.prevValue[p]!) >>> 0);
        s.varint(this.runLength[p]! - 1);
        this.prevValue[p] = this.runValue[p]!;
        this.runValue[p] = w;
        this.runLength[p] = 1;
      }
    }
    this.ticks = tick;
    this.last = sim;
    const checkpoint = tick % this.checkpointEvery === 0;
    if (checkpoint || this.tickHashSink !== null) {
      const h = sim.hash();
      if (checkpoint) this.checkpoints.u64(h);
      this.tickHashSink?.u32(low32(h));
    }
    if (this.keyframeEvery !== 0 && tick % this.keyframeEvery === 0) {
      const snapshot = sim.save();
      this.keyframes.varint(snapshot.length);
      this.keyframes.bytes(snapshot);
    }
  }

  /**
   * The replay file so far. The simulation last passed to {@link record} (or {@link start}) must
   * still be at the last recorded tick: its hash is the final hash. Recording may go on after.
   */
  finish(): Uint8Array {
    const sim = this.last;
    if (sim === null) throw new Error('ReplayRecorder.finish: call start(sim) first');
    if (sim.tick !== this.ticks) {
      throw new RangeError(
        `ReplayRecorder.finish: the simulation is at tick ${sim.tick}, the last recorded tick is ${this.ticks}`,
      );
    }
    const finalHash = BigInt.asUintN(64, sim.hash());
    const streams = this.streams.map((s, p) => {
      if (this.ticks === 0) return new Uint8Array(0);
      // Close the open run on a copy, so recording can continue.
      const out = new ByteWriter(s.length + 10);
      out.bytes(s.peek());
      out.varint((this.runValue[p]! ^ this.prevValue[p]!) >>> 0);
      out.varint(this.runLength[p]! - 1);
      return out.peek();
    });
    return assembleReplay({
      header: this.header,
      tickCount: this.ticks,
      finalHash,
      checkpointEvery: this.checkpointEvery,
      keyframeEvery: this.keyframeEvery,
      inputStreams: streams,
      checkpoints: this.checkpoints.peek(),
      keyframes: this.keyframes.peek(),
      tickHashes: this.tickHashSink?.peek() ?? null,
    });
  }
}

function isInterval(n: number): boolean {
  return Number.isInteger(n) && n >= 0 && n <= 0xffffffff;
}

function checkString(what: string, s: string, min: number): void {
  if (typeof s !== 'string') throw new RangeError(`ReplayRecorder: ${what} must be a string`);
  const n = utf8Length(s);
  if (n < min || n > MAX_STRING_BYTES) {
    throw new RangeError(
      `ReplayRecorder: ${what} must be ${min} to ${MAX_STRING_BYTES} bytes of UTF-8, got ${n}`,
    );
  }
  // TextEncoder would silently turn a lone surrogate into U+FFFD: refuse it instead.
  for (let i = 0; i < s.length; i++) {
    const c = s.charCodeAt(i);
    if (c >= 0xd800 && c <= 0xdbff) {
      const d = s.charCodeAt(i + 1);
      if (d >= 0xdc00 && d <= 0xdfff) {
        i++;
        continue;
      }
    }
    if (c >= 0xd800 && c <= 0xdfff) {
      throw new RangeError(`ReplayRecorder: ${what} holds a lone surrogate at index ${i}`);
    }
  }
}
