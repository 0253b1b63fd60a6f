import { ByteWriter } from '../det/bytes.js';
import { Fnv1a64 } from '../det/hash.js';
import { Timestep } from '../time/timestep.js';
import { deinterleave } from '../sim/buttons.js';
import { BUTTON_WORD, inputSchemaFromDescriptor, type InputSchema } from '../sim/input-schema.js';
import {
  CHECKSUM_BYTES,
  Cursor,
  FILE_HEADER_BYTES,
  FORMAT_VERSION,
  MAGIC,
  MAX_DESCRIPTOR_BYTES,
  OLDEST_FORMAT_VERSION,
  MAX_STRING_BYTES,
  SECTION_HEADER_BYTES,
  Section,
  gcd,
  low32,
  sectionName,
} from './codec.js';
import { ReplayError } from './errors.js';

/**
 * Everything a game needs to rebuild the start of a recorded run: who, what, how fast, which
 * seeds, which configuration. A replay's factory gets this and returns a fresh simulation at tick 0.
 */
export interface ReplayHeader {
  /** The replay format version of the file (1 or 2). */
  readonly formatVersion: number;
  /** Which game (or scene) recorded this, e.g. `'ctf'`. 1–255 bytes of UTF-8. */
  readonly gameId: string;
  /** The game's version, e.g. `'1.4.0'`: a replay only replays on the same simulation code. 0–255 bytes of UTF-8. */
  readonly gameVersion: string;
  /** The fixed step is `stepNumerator / stepDenominator` seconds (lowest terms, e.g. 1/60). */
  readonly stepNumerator: number;
  /** See {@link ReplayHeader.stepNumerator}. */
  readonly stepDenominator: number;
  /** The seeds of the game's random number generators, u32 each, in the game's own order. */
  readonly seeds: readonly number[];
  /** Opaque configuration bytes the game gave the recorder (e.g. its canonical config bytes). */
  readonly config: Uint8Array;
  /** One name per player; the count is the number of inputs per tick. 0–255 bytes of UTF-8 each. */
  readonly players: readonly string[];
  /**
   * What each player's input is: the schema the recorder was given (format 2 stores its
   * descriptor), or `BUTTON_WORD` for a format-1 file. Each tick holds `input.words` u32 words per
   * player.
   */
  readonly input: InputSchema<unknown>;
}

/**
 * Upper bounds a reader enforces before it allocates or loops: a file that exceeds one is refused
 * with a `'TOO_LARGE'` {@link ReplayError}. Every bound can be raised or lowered per call.
 */
export interface ReplayLimits {
  /** Largest file, in bytes. Default 64 MiB. */
  maxFileBytes: number;
  /** Most ticks. Default 5 184 000 (24 hours at 60 Hz). Also bounds how long verification may run. */
  maxTicks: number;
  /** Most players. Default 64. */
  maxPlayers: number;
  /** Most seeds. Default 64. */
  maxSeeds: number;
  /** Largest configuration blob, in bytes. Default 1 MiB. */
  maxConfigBytes: number;
  /** Largest keyframe snapshot, in bytes. Default 16 MiB. */
  maxKeyframeBytes: number;
  /**
   * Most keyframes. Default 100 000. Each parsed keyframe costs an object and a view (about 200
   * bytes) however small its snapshot, so this bounds that memory: a 46 MB file of 5 million empty
   * keyframes would otherwise take about a gigabyte.
   */
  maxKeyframes: number;
}

/** The limits {@link readReplay} uses unless told otherwise. */
export const DEFAULT_REPLAY_LIMITS: Readonly<ReplayLimits> = Object.freeze({
  maxFileBytes: 64 * 1024 * 1024,
  maxTicks: 5_184_000,
  maxPlayers: 64,
  maxSeeds: 64,
  maxConfigBytes: 1024 * 1024,
  maxKeyframeBytes: 16 * 1024 * 1024,
  maxKeyframes: 100_000,
});

/** Options of {@link readReplay}. */
export interface ReadReplayOptions {
  /** Bounds to enforce; missing fields take {@link DEFAULT_REPLAY_LIMITS}. */
  limits?: Partial<ReplayLimits>;
  /** Refuse (`'WRONG_GAME'`) a replay of another game id. */
  gameId?: string;
  /** Refuse (`'WRONG_GAME'`) a replay of another game version: an exact string, or a test. */
  gameVersion?: string | ((version: string) => boolean);
}

/** Where a section lies in the file (for tools such as `fixedstep replay info`). */
export interface ReplaySectionInfo {
  /** The section id byte. */
  readonly id: number;
  /** Its name (`'GAME'`, `'INPUTS'`, …, or `'ancillary 0x..'`). */
  readonly name: string;
  /** Byte offset of the section header (id byte) in the file. */
  readonly offset: number;
  /** Payload length in bytes (the 5-byte section header not included). */
  readonly length: number;
}

/** A stored snapshot: the `save()` bytes of the simulation after tick `tick`. */
export interface ReplayKeyframe {
  /** The state is the one after this many ticks (a multiple of `keyframeEvery`, ≥ 1). */
  readonly tick: number;
  /** The `save()` bytes; a view into the file's bytes — copy before handing them to anything that may keep or mutate them. */
  readonly bytes: Uint8Array;
  /** Byte offset of the snapshot in the file. */
  readonly offset: number;
}

/**
 * A parsed, validated replay. Reading it keeps views into the file's bytes (keyframes, config),
 * so do not mutate the bytes you parsed. Memory is bounded by the file size: inputs stay
 * run-length encoded and are looked up by binary search or read in order by a cursor.
 */
export class Replay {
  /** @internal */
  constructor(
    /** Who, what, how fast, which seeds: what a factory needs. */
    readonly header: ReplayHeader,
    /** Ticks recorded: inputs exist for ticks 0 … tickCount − 1. */
    readonly tickCount: number,
    /** The state hash after the last tick (after tick `tickCount`; at tick 0 for an empty replay). */
    readonly finalHash: bigint,
    /** A checkpoint hash is stored after every tick that is a multiple of this (tick 0 included). */
    readonly checkpointEvery: number,
    /** A keyframe is stored after every tick that is a multiple of this (tick 0 excluded); 0 = none. */
    readonly keyframeEvery: number,
    /** `checkpoints[i]` is the state hash after tick `i × checkpointEvery`. */
    readonly checkpoints: BigUint64Array,
    /** Keyframes in tick order. */
    readonly keyframes: readonly ReplayKeyframe[],
    /** Optional: `tickHashes[t − 1]` is the low 32 bits of the state hash after tick t, for t = 1 … tickCount. */
    readonly tickHashes: Uint32Array | null,
    /** The sections, in file order. */
    readonly sections: readonly ReplaySectionInfo[],
    /** The file's length in bytes. */
    readonly byteLength: number,
    private readonly runStarts: readonly Uint32Array[],
    private readonly runValues: readonly Uint32Array[],
  ) {}

  /** Number of players (inputs per tick). */
  get playerCount(): number {
    return this.header.players.length;
  }

  /** u32 words per player per tick (`header.input.words`). */
  get words(): number {
    return this.header.input.words;
  }

  /**
   * The button word of `player` at tick `tick` (the input of the step from tick `tick` to
   * `tick + 1`): the whole input for a schema without axes.
   */
  input(tick: number, player: number): number {
    this.checkTick(tick);
    const starts = this.runStarts[player];
    const values = this.runValues[player];
    if (starts === undefined || values === undefined || !Number.isInteger(player)) {
      throw new RangeError(
        `Replay.input: player must be an integer from 0 to ${this.playerCount - 1}, got ${String(player)}`,
      );
    }
    return values[findRun(starts, tick) * this.words]!;
  }

  /** Every player's button word at tick `tick`, written into `out` (which is returned). */
  inputsAt(tick: number, out: number[] = []): number[] {
    this.checkTick(tick);
    out.length = this.playerCount;
    for (let p = 0; p < this.playerCount; p++) {
      out[p] = this.runValues[p]![findRun(this.runStarts[p]!, tick) * this.words]!;
    }
    return out;
  }

  /** Every player's whole input at tick `tick` as words (`playerCount × words`), into `out`. */
  wordsAt(tick: number, out = new Uint32Array(this.playerCount * this.words)): Uint32Array {
    this.checkTick(tick);
    const w = this.words;
    for (let p = 0; p < this.playerCount; p++) {
      const r = findRun(this.runStarts[p]!, tick) * w;
      for (let k = 0; k < w; k++) out[p * w + k] = this.runValues[p]![r + k]!;
    }
    return out;
  }

  /** A cursor that reads the inputs tick after tick in O(1) each. */
  inputCursor(): ReplayInputCursor {
    return new ReplayInputCursor(this.runStarts, this.runValues, this.tickCount, this.words);
  }

  /** Number of input runs (stretches of ticks with an unchanged input) of `player`. */
  runCount(player: number): number {
    return this.runStarts[player]?.length ?? 0;
  }

  /** The checkpoint hash after `tick`, or undefined if `tick` is not a checkpoint tick. */
  checkpointAt(tick: number): bigint | undefined {
    if (!Number.isInteger(tick) || tick < 0 || tick % this.checkpointEvery !== 0) return undefined;
    return this.checkpoints[tick / this.checkpointEvery];
  }

  /** The stored low 32 bits of the hash after `tick`, or undefined (no per-tick hashes, or tick 0). */
  tickHashAt(tick: number): number | undefined {
    if (this.tickHashes === null || !Number.isInteger(tick) || tick < 1) return undefined;
    return this.tickHashes[tick - 1];
  }

  /** The last keyframe at or before `tick`, or undefined if there is none (start from tick 0). */
  keyframeAtOrBefore(tick: number): ReplayKeyframe | undefined {
    if (this.keyframeEvery === 0 || tick < this.keyframeEvery) return undefined;
    const i = Math.min(Math.floor(tick / this.keyframeEvery), this.keyframes.length) - 1;
    return this.keyframes[i];
  }

  private checkTick(tick: number): void {
    if (!Number.isInteger(tick) || tick < 0 || tick >= this.tickCount) {
      throw new RangeError(
        `Replay: tick must be an integer from 0 to ${this.tickCount - 1}, got ${String(tick)}`,
      );
    }
  }
}

/** Index of the run containing `tick`: the last start ≤ tick. `starts[0]` is 0. */
function findRun(starts: Uint32Array, tick: number): number {
  let lo = 0;
  let hi = starts.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >>> 1;
    if (starts[mid]! <= tick) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

/** Reads a replay's inputs in tick order, O(1) per tick, allocating nothing. */
export class ReplayInputCursor {
  private readonly runIndex: Uint32Array;
  private t = 0;

  /** @internal */
  constructor(
    private readonly starts: readonly Uint32Array[],
    private readonly values: readonly Uint32Array[],
    private readonly tickCount: number,
    /** u32 words per player per tick. */
    readonly words: number,
  ) {
    this.runIndex = new Uint32Array(starts.length);
  }

  /** The tick whose inputs {@link next} reads. */
  get tick(): number {
    return this.t;
  }

  /** Move to `tick` (0 … tickCount). */
  seek(tick: number): void {
    if (!Number.isInteger(tick) || tick < 0 || tick > this.tickCount) {
      throw new RangeError(
        `ReplayInputCursor.seek: tick must be from 0 to ${this.tickCount}, got ${String(tick)}`,
      );
    }
    this.t = tick;
    for (let p = 0; p < this.starts.length; p++) {
      this.runIndex[p] = tick < this.tickCount ? findRun(this.starts[p]!, tick) : 0;
    }
  }

  /** Write each player's button word of the current tick into `out` and move to the next tick. */
  next(out: number[]): void {
    const t = this.t;
    if (t >= this.tickCount) throw new RangeError('ReplayInputCursor.next: past the last tick');
    const w = this.words;
    for (let p = 0; p < this.starts.length; p++) {
      out[p] = this.values[p]![this.run(p, t) * w]!;
    }
    this.t = t + 1;
  }

  /** Write every player's words of the current tick into `out` (`players × words`) and move on. */
  nextWords(out: Uint32Array): void {
    const t = this.t;
    if (t >= this.tickCount) throw new RangeError('ReplayInputCursor.next: past the last tick');
    const w = this.words;
    for (let p = 0; p < this.starts.length; p++) {
      const r = this.run(p, t) * w;
      const values = this.values[p]!;
      for (let k = 0; k < w; k++) out[p * w + k] = values[r + k]!;
    }
    this.t = t + 1;
  }

  private run(p: number, t: number): number {
    const starts = this.starts[p]!;
    let r = this.runIndex[p]!;
    if (r + 1 < starts.length && starts[r + 1]! <= t) r++;
    this.runIndex[p] = r;
    return r;
  }
}

/** A {@link Timestep} for a replay's step (1/n s for an integer n, or a whole number of nanoseconds). */
export function replayTimestep(header: ReplayHeader): Timestep {
  const num = header.stepNumerator;
  const den = header.stepDenominator;
  if (num === 1 && den <= 100_000) return Timestep.fromHz(den);
  const ns = (num * 1e9) / den;
  if (Number.isInteger(ns)) return Timestep.fromMs(ns / 1e6);
  throw new RangeError(`replayTimestep: a step of ${num}/${den} s is not a whole number of ns`);
}

// --------------------------------------------------------------------------- reading

/**
 * Parse and validate a replay file. Checks, in this order: size limit, magic, format version,
 * declared length (truncation, trailing bytes), checksum, then every section's structure and
 * every cross-section count, and the game id/version if the caller expects one.
 *
 * Throws a {@link ReplayError} — and only that — for any bad file; never allocates more than the
 * file size allows before a check (memory stays O(file size)), and runs in O(file size).
 */
export function readReplay(bytes: Uint8Array, options: ReadReplayOptions = {}): Replay {
  if (!(bytes instanceof Uint8Array)) {
    throw new TypeError('readReplay: bytes must be a Uint8Array');
  }
  const limits: ReplayLimits = { ...DEFAULT_REPLAY_LIMITS, ...options.limits };
  const size = bytes.length;
  if (size > limits.maxFileBytes) {
    throw new ReplayError('TOO_LARGE', `file is ${size} bytes, limit ${limits.maxFileBytes}`, 0);
  }
  for (let i = 0; i < MAGIC.length; i++) {
    if (i >= size) {
      throw new ReplayError('TRUNCATED', `file ends inside the magic after ${size} bytes`, size);
    }
    if (bytes[i] !== MAGIC[i]) throw new ReplayError('BAD_MAGIC', 'not a fixedstep replay', i);
  }
  if (size < FILE_HEADER_BYTES) {
    throw new ReplayError(
      'TRUNCATED',
      `file header needs ${FILE_HEADER_BYTES} bytes, got ${size}`,
      size,
    );
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const version = view.getUint32(8, true);
  if (version < OLDEST_FORMAT_VERSION || version > FORMAT_VERSION) {
    throw new ReplayError(
      'UNSUPPORTED_VERSION',
      `format version ${version}, this reader knows ${OLDEST_FORMAT_VERSION} to ${FORMAT_VERSION}`,
      8,
    );
  }
  const declared = view.getUint32(12, true);
  if (declared < FILE_HEADER_BYTES + CHECKSUM_BYTES) {
    throw new ReplayError('CORRUPT', `declared file length ${declared} is below the minimum`, 12);
  }
  if (declared > limits.maxFileBytes) {
    throw new ReplayError(
      'TOO_LARGE',
      `declared file length ${declared}, limit ${limits.maxFileBytes}`,
      12,
    );
  }
  if (size < declared) {
    throw new ReplayError('TRUNCATED', `file declares ${declared} bytes, got ${size}`, size);
  }
  if (size > declared) {
    throw new ReplayError(
      'TRAILING_DATA',
      `${size - declared} bytes after the declared end of the file (${declared} bytes)`,
      declared,
    );
  }
  const end = declared - CHECKSUM_BYTES;
  const stored = view.getBigUint64(end, true);
  const computed = new Fnv1a64().update(bytes.subarray(0, end)).digest();
  if (stored !== computed) {
    throw new ReplayError(
      'BAD_CHECKSUM',
      `checksum ${hex(stored)} stored, ${hex(computed)} computed over bytes 0–${end - 1}`,
      end,
    );
  }
  return new Parser(bytes, end, limits, options, version).parse();
}

/** Throws `'WRONG_GAME'` unless the header is of the game id and version the caller expects. @internal */
export function checkGame(header: ReplayHeader, want: ReadReplayOptions, offset = -1): void {
  const { gameId, gameVersion } = header;
  if (want.gameId !== undefined && want.gameId !== gameId) {
    throw new ReplayError(
      'WRONG_GAME',
      `replay of game "${gameId}", expected "${want.gameId}"`,
      offset,
    );
  }
  const v = want.gameVersion;
  if (v !== undefined && (typeof v === 'string' ? v !== gameVersion : !v(gameVersion))) {
    throw new ReplayError(
      'WRONG_GAME',
      `replay of ${gameId} version "${gameVersion}", expected ${typeof v === 'string' ? `"${v}"` : 'another version'}`,
      offset,
    );
  }
}

function hex(h: bigint): string {
  return h.toString(16).padStart(16, '0');
}

/** Walks the sections of a file whose length and checksum are already known good. */
class Parser {
  private header: ReplayHeader | null = null;
  private tickCount = 0;
  private finalHash = 0n;
  private checkpointEvery = 1;
  private keyframeEvery = 0;
  private runStarts: Uint32Array[] = [];
  private runValues: Uint32Array[] = [];
  private checkpoints = new BigUint64Array(0);
  private keyframes: ReplayKeyframe[] = [];
  private tickHashes: Uint32Array | null = null;
  private readonly sections: ReplaySectionInfo[] = [];

  constructor(
    private readonly bytes: Uint8Array,
    private readonly end: number,
    private readonly limits: ReplayLimits,
    private readonly options: ReadReplayOptions,
    private readonly version: number,
  ) {}

  parse(): Replay {
    const file = new Cursor(this.bytes, FILE_HEADER_BYTES, this.end, 'file');
    let last = 0;
    while (file.pos < this.end) {
      const at = file.pos;
      if (file.remaining < SECTION_HEADER_BYTES) {
        file.corrupt(`${file.remaining} stray bytes where a section header (5 bytes) should start`);
      }
      const id = file.u8('section id');
      const length = file.u32('section length');
      const name = sectionName(id);
      if (length > file.remaining) {
        file.corrupt(
          `section ${name} declares ${length} bytes, only ${file.remaining} left`,
          at + 1,
        );
      }
      if (id === 0 || (id > Section.TICK_HASHES && id < 0x80)) {
        file.corrupt(`unknown critical section id 0x${id.toString(16)}`, at);
      }
      if (id <= last) {
        file.corrupt(
          `section ${name} is out of order or repeated (after ${sectionName(last)})`,
          at,
        );
      }
      // Sections 1–5 are required and come in order: jumping past one means it is missing.
      for (let missing = last + 1; missing < Math.min(id, Section.TICK_HASHES); missing++) {
        file.corrupt(`section ${sectionName(missing)} is missing (found ${name})`, at);
      }
      last = id;
      this.sections.push({ id, name, offset: at, length });
      const c = new Cursor(this.bytes, file.pos, file.pos + length, `section ${name}`);
      this.section(id, c);
      file.pos += length;
    }
    if (last < Section.KEYFRAMES) {
      file.corrupt(`section ${sectionName(last + 1)} is missing (file ends)`);
    }
    return new Replay(
      this.header!,
      this.tickCount,
      this.finalHash,
      this.checkpointEvery,
      this.keyframeEvery,
      this.checkpoints,
      this.keyframes,
      this.tickHashes,
      this.sections,
      this.end + CHECKSUM_BYTES,
      this.runStarts,
      this.runValues,
    );
  }

  private section(id: number, c: Cursor): void {
    switch (id) {
      case Section.GAME:
        this.game(c);
        break;
      case Section.TICKS:
        this.ticks(c);
        break;
      case Section.INPUTS:
        this.inputs(c);
        break;
      case Section.CHECKPOINTS:
        this.checkpointSection(c);
        break;
      case Section.KEYFRAMES:
        this.keyframeSection(c);
        break;
      case Section.TICK_HASHES:
        this.tickHashSection(c);
        break;
      default:
        return; // ancillary: skipped
    }
    c.done();
  }

  private tooLarge(what: string, value: number, limit: number, at: number): never {
    throw new ReplayError('TOO_LARGE', `${what} is ${value}, limit ${limit}`, at);
  }

  private game(c: Cursor): void {
    const sectionAt = c.pos;
    const gameId = c.string('game id');
    if (gameId.length === 0) c.corrupt('game id is empty', sectionAt);
    const gameVersion = c.string('game version');
    const numAt = c.pos;
    const stepNumerator = c.varint('step numerator');
    const stepDenominator = c.varint('step denominator');
    if (stepNumerator === 0 || stepDenominator === 0) {
      c.corrupt(`step ${stepNumerator}/${stepDenominator} s has a zero term`, numAt);
    }
    if (gcd(stepNumerator, stepDenominator) !== 1) {
      c.corrupt(`step ${stepNumerator}/${stepDenominator} s is not in lowest terms`, numAt);
    }
    const seedsAt = c.pos;
    const seedCount = c.varint('seed count');
    if (seedCount > this.limits.maxSeeds) {
      this.tooLarge('seed count', seedCount, this.limits.maxSeeds, seedsAt);
    }
    c.need(seedCount * 4, `${seedCount} seeds`);
    const seeds: number[] = [];
    for (let i = 0; i < seedCount; i++) seeds.push(c.u32('seed'));
    const configAt = c.pos;
    const configLength = c.varint('config length');
    if (configLength > this.limits.maxConfigBytes) {
      this.tooLarge('config length', configLength, this.limits.maxConfigBytes, configAt);
    }
    const config = c.bytes(configLength, 'config');
    const playersAt = c.pos;
    const playerCount = c.varint('player count');
    if (playerCount === 0) c.corrupt('player count is 0', playersAt);
    if (playerCount > this.limits.maxPlayers) {
      this.tooLarge('player count', playerCount, this.limits.maxPlayers, playersAt);
    }
    c.need(playerCount, `${playerCount} player names`);
    const players: string[] = [];
    for (let p = 0; p < playerCount; p++) players.push(c.string(`name of player ${p}`));
    let input: InputSchema<unknown> = BUTTON_WORD;
    if (this.version >= 2) {
      const at = c.pos;
      const descriptor = c.bytes(
        c.count('input schema length', MAX_DESCRIPTOR_BYTES),
        'input schema',
      );
      try {
        input = inputSchemaFromDescriptor(descriptor);
      } catch (e) {
        c.corrupt((e as Error).message, at);
      }
    }
    this.header = Object.freeze({
      formatVersion: this.version,
      gameId,
      gameVersion,
      stepNumerator,
      stepDenominator,
      seeds: Object.freeze(seeds),
      config,
      players: Object.freeze(players),
      input,
    });

    checkGame(this.header, this.options, sectionAt);
  }

  private ticks(c: Cursor): void {
    const at = c.pos;
    this.tickCount = c.u32('tick count');
    if (this.tickCount > this.limits.maxTicks) {
      this.tooLarge('tick count', this.tickCount, this.limits.maxTicks, at);
    }
    this.finalHash = c.u64('final hash');
    const nAt = c.pos;
    this.checkpointEvery = c.varint('checkpoint interval');
    if (this.checkpointEvery === 0) c.corrupt('checkpoint interval is 0', nAt);
    const mAt = c.pos;
    this.keyframeEvery = c.varint('keyframe interval');
    if (this.keyframeEvery % this.checkpointEvery !== 0) {
      c.corrupt(
        `keyframe interval ${this.keyframeEvery} is not a multiple of the checkpoint interval ${this.checkpointEvery}`,
        mAt,
      );
    }
  }

  private inputs(c: Cursor): void {
    const players = this.header!.players.length;
    const words = this.header!.input.words;
    const schema = this.header!.input;
    const ticks = this.tickCount;
    const prev = new Uint32Array(words);
    for (let p = 0; p < players; p++) {
      const lengthAt = c.pos;
      const length = c.varint(`input stream length of player ${p}`);
      if (length > c.remaining) {
        c.corrupt(
          `input stream of player ${p} declares ${length} bytes, ${c.remaining} left`,
          lengthAt,
        );
      }
      const s = new Cursor(this.bytes, c.pos, c.pos + length, `section INPUTS, player ${p}`);
      c.pos += length;
      // Every run takes at least words + 1 bytes: the arrays are bounded by the stream's length.
      const cap = Math.min(Math.floor(length / (words + 1)), ticks);
      const starts = new Uint32Array(cap);
      const values = new Uint32Array(cap * words);
      prev.fill(0);
      let t = 0;
      let r = 0;
      while (t < ticks) {
        if (s.pos >= s.limit) s.corrupt(`stream ends at tick ${t} of ${ticks}`);
        const at = s.pos;
        let changed = false;
        for (let k = 0; k < words; k++) {
          const d = s.varint(k === 0 ? 'run change' : `run change of word ${k}`);
          if (d !== 0) changed = true;
          // XOR deltas; word 0, the button word, is coded interleaved (see `interleave`).
          prev[k] = (prev[k]! ^ d) >>> 0;
        }
        if (!changed && r > 0) s.corrupt(`run ${r} repeats the previous value (non-canonical)`, at);
        const n = s.varint('run length');
        if (n >= ticks - t) {
          s.corrupt(`run ${r} of ${n + 1} ticks at tick ${t} overruns the ${ticks} ticks`, at);
        }
        starts[r] = t;
        values[r * words] = deinterleave(prev[0]!);
        for (let k = 1; k < words; k++) values[r * words + k] = prev[k]!;
        const problem = schema.problem(values, r * words);
        if (problem !== undefined) s.corrupt(`run ${r} at tick ${t}: ${problem}`, at);
        r++;
        t += n + 1;
      }
      s.done();
      this.runStarts.push(starts.slice(0, r));
      this.runValues.push(values.slice(0, r * words));
    }
  }

  private checkpointSection(c: Cursor): void {
    const count = Math.floor(this.tickCount / this.checkpointEvery) + 1;
    if (c.remaining !== count * 8) {
      c.corrupt(
        `holds ${c.remaining} bytes, ${count} checkpoints (ticks 0 to ${this.tickCount} every ${this.checkpointEvery}) need ${count * 8}`,
      );
    }
    const cps = new BigUint64Array(count);
    for (let i = 0; i < count; i++) cps[i] = c.u64('checkpoint hash');
    if (this.tickCount % this.checkpointEvery === 0 && cps[count - 1] !== this.finalHash) {
      c.corrupt(
        `the checkpoint at the last tick ${this.tickCount} differs from the final hash`,
        c.pos - 8,
      );
    }
    this.checkpoints = cps;
  }

  private keyframeSection(c: Cursor): void {
    const m = this.keyframeEvery;
    const count = m === 0 ? 0 : Math.floor(this.tickCount / m);
    if (count > this.limits.maxKeyframes) {
      this.tooLarge('keyframe count', count, this.limits.maxKeyframes, c.pos);
    }
    // Each keyframe takes at least its 1-byte length: check before allocating anything per keyframe.
    if (count > c.remaining) {
      c.corrupt(`${count} keyframes expected but only ${c.remaining} bytes`);
    }
    for (let i = 0; i < count; i++) {
      const at = c.pos;
      const length = c.varint(`keyframe ${i} length`);
      if (length > this.limits.maxKeyframeBytes) {
        this.tooLarge(`keyframe ${i} length`, length, this.limits.maxKeyframeBytes, at);
      }
      const offset = c.pos;
      const bytes = c.bytes(length, `keyframe ${i}`);
      this.keyframes.push(Object.freeze({ tick: (i + 1) * m, bytes, offset }));
    }
  }

  private tickHashSection(c: Cursor): void {
    const ticks = this.tickCount;
    if (c.remaining !== ticks * 4) {
      c.corrupt(`holds ${c.remaining} bytes, ${ticks} tick hashes need ${ticks * 4}`);
    }
    const start = c.pos;
    const hashes = new Uint32Array(ticks);
    for (let t = 0; t < ticks; t++) hashes[t] = c.u32('tick hash');
    const n = this.checkpointEvery;
    for (let i = 1; i < this.checkpoints.length; i++) {
      if (hashes[i * n - 1] !== low32(this.checkpoints[i]!)) {
        c.corrupt(
          `tick hash of tick ${i * n} disagrees with its checkpoint`,
          start + (i * n - 1) * 4,
        );
      }
    }
    if (ticks > 0 && hashes[ticks - 1] !== low32(this.finalHash)) {
      c.corrupt(
        `tick hash of the last tick disagrees with the final hash`,
        start + (ticks - 1) * 4,
      );
    }
    this.tickHashes = hashes;
  }
}

// --------------------------------------------------------------------------- writing

/** What {@link assembleReplay} lays out: every section's payload, already encoded where noted. @internal */
export interface ReplayParts {
  header: Omit<ReplayHeader, 'formatVersion'>;
  tickCount: number;
  finalHash: bigint;
  checkpointEvery: number;
  keyframeEvery: number;
  /** Per player, the encoded run stream (without its length prefix). */
  inputStreams: readonly Uint8Array[];
  /** The CHECKPOINTS payload. */
  checkpoints: Uint8Array;
  /** The KEYFRAMES payload. */
  keyframes: Uint8Array;
  /** The TICK_HASHES payload, or null to leave the section out. */
  tickHashes: Uint8Array | null;
}

/** Lays out a whole file — header, sections, checksum — in one exact-size allocation. @internal */
export function assembleReplay(parts: ReplayParts): Uint8Array {
  const h = parts.header;
  const game = new ByteWriter(64 + h.config.length);
  game.str(h.gameId);
  game.str(h.gameVersion);
  game.varint(h.stepNumerator);
  game.varint(h.stepDenominator);
  game.varint(h.seeds.length);
  for (const s of h.seeds) game.u32(s);
  game.varint(h.config.length);
  game.bytes(h.config);
  game.varint(h.players.length);
  for (const name of h.players) game.str(name);
  game.varint(h.input.descriptor.length);
  game.bytes(h.input.descriptor);

  const ticks = new ByteWriter(32);
  ticks.u32(parts.tickCount);
  ticks.u64(parts.finalHash);
  ticks.varint(parts.checkpointEvery);
  ticks.varint(parts.keyframeEvery);

  let inputLength = 0;
  for (const s of parts.inputStreams) inputLength += s.length + 5;
  const inputs = new ByteWriter(inputLength);
  for (const s of parts.inputStreams) {
    inputs.varint(s.length);
    inputs.bytes(s);
  }

  const sections: [number, Uint8Array][] = [
    [Section.GAME, game.peek()],
    [Section.TICKS, ticks.peek()],
    [Section.INPUTS, inputs.peek()],
    [Section.CHECKPOINTS, parts.checkpoints],
    [Section.KEYFRAMES, parts.keyframes],
  ];
  if (parts.tickHashes !== null) sections.push([Section.TICK_HASHES, parts.tickHashes]);

  let total = FILE_HEADER_BYTES + CHECKSUM_BYTES;
  for (const [, payload] of sections) total += SECTION_HEADER_BYTES + payload.length;
  if (total > 0xffffffff)
    throw new RangeError(`replay: ${total} bytes is above the 4 GiB format limit`);
  const out = new Uint8Array(total);
  const view = new DataView(out.buffer);
  out.set(MAGIC, 0);
  view.setUint32(8, FORMAT_VERSION, true);
  view.setUint32(12, total, true);
  let pos = FILE_HEADER_BYTES;
  for (const [id, payload] of sections) {
    out[pos] = id;
    view.setUint32(pos + 1, payload.length, true);
    out.set(payload, pos + SECTION_HEADER_BYTES);
    pos += SECTION_HEADER_BYTES + payload.length;
  }
  view.setBigUint64(pos, new Fnv1a64().update(out.subarray(0, pos)).digest(), true);
  return out;
}

export { MAX_STRING_BYTES };
