import type { Simulation } from '../sim/simulation.js';
import { Timestep } from '../time/timestep.js';
import { ByteWriter } from '../det/bytes.js';
import { interleave, type ButtonInput } from '../sim/buttons.js';
import { BUTTON_WORD, type InputSchema } from '../sim/input-schema.js';
import { gameSetup, type AnyGameDefinition, type GameSetup } from '../sim/game.js';
import { FORMAT_VERSION, MAX_STRING_BYTES, gcd, low32, utf8Length } from './codec.js';
import { assembleReplay } from './format.js';
import type { ReplayHeader } from './format.js';

/** What a {@link ReplayRecorder} needs to know before the first tick. */
export interface ReplayRecorderOptions<I = ButtonInput> {
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
  /** What each player's input is (its descriptor is stored in the header). Default `BUTTON_WORD`. */
  input?: InputSchema<I>;
  /**
   * Store the state hash every this many ticks (a positive integer). Default: every 10 s of game
   * time (600 ticks at 60 Hz) — 8 bytes each, so 48 bytes a minute. Verification names the first
   * bad checkpoint; add `tickHashes` to name the exact first bad tick.
   */
  checkpointEvery?: number;
  /**
   * Store a `save()` snapshot every this many ticks (a positive multiple of `checkpointEvery`, or
   * 0 for none). Default 0: a replay is its inputs and seeds, and a player builds keyframes for
   * seeking by re-simulation when it opens one. Stored keyframes only help a game too slow to
   * re-simulate; each costs a `save()` and its bytes.
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
export class ReplayRecorder<I = ButtonInput> {
  /** The header that will be written (and that a factory will get back). */
  readonly header: ReplayHeader;
  /** The input schema. */
  readonly input: InputSchema<I>;
  /** See {@link ReplayRecorderOptions.checkpointEvery}. */
  readonly checkpointEvery: number;
  /** See {@link ReplayRecorderOptions.keyframeEvery}. */
  readonly keyframeEvery: number;
  /** See {@link ReplayRecorderOptions.tickHashes}. */
  readonly withTickHashes: boolean;

  private readonly streams: ByteWriter[] = [];
  /**
   * Per player, `words` words each: the coded value of the open run and of the run before it (the
   * button word interleaved); and per player the open run's length.
   */
  private readonly runValue: Uint32Array;
  private readonly prevValue: Uint32Array;
  private readonly runLength: Float64Array;
  private readonly scratch: Uint32Array;
  private readonly scratchRun = new Uint32Array(64);
  private readonly words: number;
  private readonly checkpoints = new ByteWriter(256);
  private readonly keyframes = new ByteWriter(256);
  private readonly tickHashSink: ByteWriter | null;
  private ticks = 0;
  private started = false;
  private initialHash = 0n;
  private last: RecordableSimulation | null = null;

  /**
   * A recorder for a run of `game` started with `setup` (or with `players` names and `seed`): game
   * id, version, tick rate, input schema, seed and options all come from the definition.
   */
  static forGame<I>(
    game: AnyGameDefinition & { readonly input: InputSchema<I> },
    setup: GameSetup | { readonly seed: number },
    players: readonly string[],
    extra: Pick<ReplayRecorderOptions, 'checkpointEvery' | 'keyframeEvery' | 'tickHashes'> = {},
  ): ReplayRecorder<I> {
    const s = 'players' in setup ? setup : gameSetup(game, players.length, setup.seed);
    if (s.players !== players.length) {
      throw new RangeError(
        `ReplayRecorder.forGame: ${players.length} player names for a setup of ${s.players} players`,
      );
    }
    return new ReplayRecorder<I>({
      gameId: game.id,
      gameVersion: String(game.version),
      tickRate: game.tickRate,
      seeds: [s.seed],
      config: s.options,
      players,
      input: game.input,
      ...extra,
    });
  }

  constructor(options: ReplayRecorderOptions<I>) {
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
    this.checkpointEvery = options.checkpointEvery ?? Math.max(1, Math.round(10 * step.hz));
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
    this.input = options.input ?? (BUTTON_WORD as unknown as InputSchema<I>);
    if (typeof this.input !== 'object' || !(this.input.descriptor instanceof Uint8Array)) {
      throw new RangeError(
        'ReplayRecorder: input must be an input schema (defineInput or BUTTON_WORD)',
      );
    }
    this.words = this.input.words;
    this.header = Object.freeze({
      formatVersion: FORMAT_VERSION,
      gameId,
      gameVersion,
      stepNumerator: num / g,
      stepDenominator: den / g,
      seeds: Object.freeze([...seeds]),
      config: config.slice(),
      players: Object.freeze([...players]),
      input: this.input,
    });
    const n = players.length;
    for (let p = 0; p < n; p++) this.streams.push(new ByteWriter(64));
    this.runValue = new Uint32Array(n * this.words);
    this.prevValue = new Uint32Array(n * this.words);
    this.runLength = new Float64Array(n);
    this.scratch = new Uint32Array(n * this.words);
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
   * Record one tick: call right after `sim.step(inputs)`, with the same inputs (one per player,
   * of the recorder's schema). Takes the hash at checkpoint ticks (and the snapshot at keyframe
   * ticks). Throws a RangeError, recording nothing, for an input the schema cannot hold.
   */
  record(inputs: readonly I[], sim: RecordableSimulation): void {
    const n = this.streams.length;
    if (inputs.length !== n) {
      throw new RangeError(`ReplayRecorder.record: ${inputs.length} inputs for ${n} players`);
    }
    for (let p = 0; p < n; p++) {
      try {
        this.input.encode(inputs[p]!, this.scratch, p * this.words);
      } catch (e) {
        throw new RangeError(
          `ReplayRecorder.record: input of player ${p}: ${(e as Error).message}`,
          { cause: e },
        );
      }
    }
    this.recordWords(this.scratch, sim);
  }

  /**
   * {@link record} with the inputs already encoded: `players × words` u32 words, player-major
   * (what `InputSampler.sampleWords` and the network sessions hold).
   */
  recordWords(words: ArrayLike<number>, sim: RecordableSimulation): void {
    if (!this.started)
      throw new Error('ReplayRecorder.record: call start(sim) before the first step');
    const n = this.streams.length;
    const w = this.words;
    if (words.length !== n * w) {
      throw new RangeError(
        `ReplayRecorder.recordWords: ${words.length} words for ${n} players of ${w} words`,
      );
    }
    const tick = this.ticks + 1;
    if (sim.tick !== tick) {
      throw new RangeError(
        `ReplayRecorder.record: the simulation is at tick ${sim.tick}, expected ${tick} (record once per step, after it)`,
      );
    }
    if (tick > 0xffffffff) throw new RangeError('ReplayRecorder.record: 2^32 - 1 ticks recorded');
    for (let i = 0; i < words.length; i++) {
      const v = words[i]!;
      if (!Number.isInteger(v) || v < 0 || v > 0xffffffff) {
        throw new RangeError(
          `ReplayRecorder.record: input of player ${Math.floor(i / w)} is not a u32: ${String(v)}`,
        );
      }
    }
    for (let p = 0; p < n; p++) {
      const problem = this.input.problem(words, p * w);
      if (problem !== undefined) {
        throw new RangeError(`ReplayRecorder.record: input of player ${p}: ${problem}`);
      }
    }
    for (let p = 0; p < n; p++) {
      const at = p * w;
      let same = this.ticks > 0;
      for (let k = 0; k < w; k++) {
        const v = k === 0 ? interleave(words[at]!) : words[at + k]! >>> 0;
        if (v !== this.runValue[at + k]) same = false;
        this.scratchRun[k] = v;
      }
      if (this.ticks === 0) {
        for (let k = 0; k < w; k++) this.runValue[at + k] = this.scratchRun[k]!;
        this.runLength[p] = 1;
      } else if (same) {
        this.runLength[p]!++;
      } else {
        this.closeRun(this.streams[p]!, p);
        for (let k = 0; k < w; k++) {
          this.prevValue[at + k] = this.runValue[at + k]!;
          this.runValue[at + k] = this.scratchRun[k]!;
        }
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

  /** Write player `p`'s open run (its change against the run before, then its length) to `out`. */
  private closeRun(out: ByteWriter, p: number): void {
    const at = p * this.words;
    for (let k = 0; k < this.words; k++) {
      out.varint((this.runValue[at + k]! ^ this.prevValue[at + k]!) >>> 0);
    }
    out.varint(this.runLength[p]! - 1);
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
      const out = new ByteWriter(s.length + 5 * (this.words + 1));
      out.bytes(s.peek());
      this.closeRun(out, p);
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
