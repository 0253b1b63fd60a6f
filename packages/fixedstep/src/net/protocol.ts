/**
 * The network protocol: compact binary messages (docs/network.md has the table).
 *
 * Every message is `[version u8][type u8][fields…]`. Integers are unsigned LEB128 varints of at
 * most 32 bits (canonical: no redundant zero bytes), hashes are 8 bytes little-endian, clock
 * readings are float64 milliseconds, strings and byte fields carry a varint length. Inputs are
 * XOR-delta coded against the previous tick of the same player and bit-interleaved (a ButtonInput's
 * "down" and "pressed" bits side by side), so a held button costs one byte a tick.
 *
 * {@link decodeMessage} checks every size against {@link ProtocolLimits} before it allocates, and
 * throws only {@link ProtocolError} — whatever the bytes.
 */
import { ByteReader, ByteWriter, type ByteReadProblem } from '../det/bytes.js';
import { deinterleave, interleave } from '../sim/buttons.js';

/**
 * The protocol version this code writes and reads (byte 0 of every message). Version 2 added the
 * input schema: the hello names it, inputs carry `words` u32 words per player per tick, and the
 * welcome carries the room's seed. Version 3 made the confirmed stream lean (no room number, the
 * input ack relative to the message's end, players and words in one varint, and over a reliable
 * transport each tick sent once, XOR-coded against the tick before it), added the room's invite
 * token to the welcome (spectators join only with it), and lets the server ping a silent client.
 */
export const PROTOCOL_VERSION = 3;

/**
 * Most u32 words of one player's input per tick, on the wire: `confirmed` packs players and words
 * into one varint `(players − 1) × 16 + (words − 1)`.
 */
export const MAX_WIRE_INPUT_WORDS = 16;

/** Message type bytes (byte 1 of every message). */
export const MessageType = {
  hello: 0x01,
  welcome: 0x02,
  start: 0x03,
  input: 0x04,
  confirmed: 0x05,
  ack: 0x06,
  hash: 0x07,
  desync: 0x08,
  ping: 0x09,
  pong: 0x0a,
  leave: 0x0b,
  error: 0x0c,
  'snapshot-request': 0x0d,
  snapshot: 0x0e,
  'hashes-request': 0x0f,
  hashes: 0x10,
} as const;

export type MessageKind = keyof typeof MessageType;

/** Size bounds the decoder enforces before allocating anything. */
export interface ProtocolLimits {
  /** Largest message, in bytes. Default 1 MiB + 1 KiB (a snapshot plus its header). */
  maxMessageBytes: number;
  /** Largest snapshot (a late joiner's state, desync forensics), in bytes. Default 1 MiB. */
  maxSnapshotBytes: number;
  /** Most ticks of inputs in one `input` message. Default 64. */
  maxInputTicks: number;
  /** Most ticks in one `confirmed` message. Default 64. */
  maxConfirmedTicks: number;
  /** Most players of a room. Default 16. */
  maxPlayers: number;
  /** Most hashes in one `hashes` message or request. Default 512. */
  maxHashes: number;
  /** Most groups (sides) in a `desync` message. Default 16. */
  maxGroups: number;
  /** Most peers listed in a `desync` message, all groups together. Default 256. */
  maxPeers: number;
  /** Largest game configuration, in bytes. Default 256. */
  maxConfigBytes: number;
  /** Most u32 words of one player's input for one tick (the input schema's `words`). Default 16. */
  maxInputWords: number;
}

export const DEFAULT_PROTOCOL_LIMITS: Readonly<ProtocolLimits> = Object.freeze({
  maxMessageBytes: (1 << 20) + 1024,
  maxSnapshotBytes: 1 << 20,
  maxInputTicks: 64,
  maxConfirmedTicks: 64,
  maxPlayers: 16,
  maxHashes: 512,
  maxGroups: 16,
  maxPeers: 256,
  maxConfigBytes: 256,
  maxInputWords: 16,
});

/** Room names and game ids: 1–32 of `A–Z a–z 0–9 _ - .`. */
export const NAME_PATTERN = /^[A-Za-z0-9_.-]{1,32}$/;
/** Longest player name, in UTF-8 bytes. */
export const MAX_PLAYER_NAME_BYTES = 32;
/** Longest error text, in UTF-8 bytes. */
export const MAX_ERROR_TEXT_BYTES = 200;
/** Reconnect tokens are exactly this long (or absent). */
export const TOKEN_BYTES = 16;

/** Why the server refused something (the `error` message's code). */
export type NetErrorCode =
  | 'BAD_MESSAGE'
  | 'TOO_LARGE'
  | 'RATE_LIMIT'
  | 'NOT_IN_ROOM'
  | 'WRONG_ROOM'
  | 'SPOOFED_PLAYER'
  | 'TICK_WINDOW'
  | 'ROOM_FULL'
  | 'UNKNOWN_GAME'
  | 'GAME_MISMATCH'
  | 'BAD_HELLO'
  | 'BAD_TOKEN'
  | 'NO_SNAPSHOT'
  | 'TIMEOUT'
  | 'SERVER_FULL'
  | 'UNEXPECTED'
  | 'INTERNAL'
  | 'SHUTDOWN'
  | 'BAD_INPUT';

const ERROR_CODES: readonly NetErrorCode[] = [
  'BAD_MESSAGE',
  'TOO_LARGE',
  'RATE_LIMIT',
  'NOT_IN_ROOM',
  'WRONG_ROOM',
  'SPOOFED_PLAYER',
  'TICK_WINDOW',
  'ROOM_FULL',
  'UNKNOWN_GAME',
  'GAME_MISMATCH',
  'BAD_HELLO',
  'BAD_TOKEN',
  'NO_SNAPSHOT',
  'TIMEOUT',
  'SERVER_FULL',
  'UNEXPECTED',
  'INTERNAL',
  'SHUTDOWN',
  'BAD_INPUT',
];

/** Why a peer left (the `leave` message's reason). */
export type LeaveReason = 'left' | 'closed' | 'dropped' | 'timeout' | 'replaced';
const LEAVE_REASONS: readonly LeaveReason[] = ['left', 'closed', 'dropped', 'timeout', 'replaced'];

// ------------------------------------------------------------------------------------ messages

/** Client → server, first message: join (or create) a room. */
export interface HelloMessage {
  type: 'hello';
  /** Room name (see {@link NAME_PATTERN}); the first hello creates it. */
  room: string;
  role: 'player' | 'spectator';
  /** Game id and version: a room plays one game, and every member must run the same version. */
  game: string;
  gameVersion: number;
  /**
   * The id of the client's input schema (`InputSchema.id`, 16 hex digits): the room refuses a
   * client whose inputs it would read differently.
   */
  input: string;
  /** Player slots of the room when this hello creates it (0: the game's minimum). */
  players: number;
  /** The game's seed when this hello creates it (absent: the server picks one). */
  seed?: number;
  /**
   * Players: a reconnect token from an earlier `welcome` (take back that slot). Spectators: the
   * room's invite token (`welcome.invite` of one of its players) — required.
   */
  token?: Uint8Array;
  /** Display name, at most 32 UTF-8 bytes. */
  name: string;
}

/** Server → client: you are in. */
export interface WelcomeMessage {
  type: 'welcome';
  /** The room's number: every later message about the room carries it. */
  room: number;
  /** Your peer id in the room: players have their slot, spectators 64 and up. */
  peer: number;
  /** Your player slot, or -1 for a spectator. */
  slot: number;
  /** Player slots (inputs per tick). */
  players: number;
  /** The room's seed: with `players` and `config`, the game's setup. */
  seed: number;
  /** Ticks per second. */
  tickRate: number;
  /** Report a state hash every this many ticks. */
  hashEvery: number;
  /** How long after a tick's time the server waits for a missing input before filling it. */
  deadlineMs: number;
  /** The first tick the server takes inputs from you for. */
  inputFrom: number;
  /** The tick of the initial state: the snapshot's, or 0. */
  startTick: number;
  /** The game's canonical configuration bytes. */
  config: Uint8Array;
  /** Your reconnect token (players only; empty for spectators). */
  token: Uint8Array;
  /**
   * The room's invite token (players only; empty for spectators): a spectator's hello must carry
   * it. Hand it only to people you invite: room names are often guessable.
   */
  invite: Uint8Array;
  /** Server time (ms) when tick 0 began, once the match has started. */
  startAt?: number;
  /** A late joiner's initial state (`save()` bytes at {@link startTick}). */
  snapshot?: Uint8Array;
}

/** Server → client: the match starts; tick 0 begins at server time `startAt` (ms). */
export interface StartMessage {
  type: 'start';
  room: number;
  startAt: number;
}

/**
 * Client → server: my inputs for ticks `tick … tick + inputs.length / words - 1` (a redundant
 * window), `words` u32 words a tick.
 */
export interface InputMessage {
  type: 'input';
  room: number;
  player: number;
  /** The next confirmed tick I need (I have every confirmed tick before it). */
  ack: number;
  tick: number;
  /** u32 words per tick: the input schema's `words`. */
  words: number;
  inputs: Uint32Array;
}

/**
 * Server → client: the final inputs of every player, for ticks `tick …`, tick-major. It names no
 * room: a connection is in one room only.
 */
export interface ConfirmedMessage {
  type: 'confirmed';
  /**
   * The next tick the server needs an input from you for; never before the end of this message
   * (`tick + ticks`), which is what spectators are sent.
   */
  inputAck: number;
  tick: number;
  players: number;
  /** u32 words per player per tick: the input schema's `words` (1–16). */
  words: number;
  /**
   * `ticks × players × words` words: player p's input for tick `tick + k` starts at
   * `inputs[(k * players + p) * words]`. When {@link delta} is set, each word is XORed with the
   * same word of tick `tick − 1`.
   */
  inputs: Uint32Array;
  /**
   * The words are XORed with tick `tick − 1`'s, which the receiver already has: the server sends
   * this only over a reliable transport, continuing the previous confirmed message on the same
   * connection. A receiver without tick `tick − 1` ignores the message; the server resends from
   * its ack, uncoded, when the ack stops moving.
   */
  delta: boolean;
}

/** Client → server: I have every confirmed tick before `ack` (spectators; idle players). */
export interface AckMessage {
  type: 'ack';
  room: number;
  ack: number;
}

/** Client → server: the hash of my state at `tick` (the state after `tick` steps). */
export interface HashMessage {
  type: 'hash';
  room: number;
  tick: number;
  hash: bigint;
}

/** Server → client: states diverged; the first differing state is at `tick`. */
export interface DesyncMessage {
  type: 'desync';
  room: number;
  /** First tick whose state differs (the step from `tick - 1` diverged). */
  tick: number;
  /** Whether `tick` was pinned exactly (per-tick hashes), or is the coarse report tick. */
  exact: boolean;
  /** The periodic report tick at which the divergence was seen. */
  reportTick: number;
  /** Index into `groups` of the majority, or -1 when there is none (two sides, or a tie). */
  majority: number;
  /** Each side: the hash its members had at `tick` (or at `reportTick`), and who they are. */
  groups: { hash: bigint; peers: number[] }[];
}

/**
 * Clock sync probe; `time` is the sender's clock (ms). Client → server, answered with a pong; and
 * server → client, a liveness probe of a member that has been silent (the client answers with a
 * pong whose `serverTime` is its own clock).
 */
export interface PingMessage {
  type: 'ping';
  id: number;
  time: number;
}

/**
 * The answer to a ping: the probe's `id` and `time`, with the answering side's clock (ms) as
 * `serverTime`.
 */
export interface PongMessage {
  type: 'pong';
  id: number;
  time: number;
  serverTime: number;
}

/** Either way: a peer leaves the room (the client about itself; the server about anyone). */
export interface LeaveMessage {
  type: 'leave';
  room: number;
  peer: number;
  reason: LeaveReason;
}

/** Server → client: something was refused; `fatal` means the connection is being closed. */
export interface ErrorMessage {
  type: 'error';
  code: NetErrorCode;
  message: string;
  fatal: boolean;
}

/** Server → client: send me your state at `tick` (-1: your latest confirmed state). */
export interface SnapshotRequestMessage {
  type: 'snapshot-request';
  room: number;
  id: number;
  tick: number;
}

/** Client → server: the answer to a snapshot request (empty bytes: not available). */
export interface SnapshotMessage {
  type: 'snapshot';
  room: number;
  id: number;
  tick: number;
  bytes: Uint8Array;
}

/** Server → client: send me your per-tick state hashes for `from … from + count - 1`. */
export interface HashesRequestMessage {
  type: 'hashes-request';
  room: number;
  id: number;
  from: number;
  count: number;
}

/** Client → server: per-tick state hashes from `from` (as many as I still have). */
export interface HashesMessage {
  type: 'hashes';
  room: number;
  id: number;
  from: number;
  hashes: BigUint64Array;
}

export type NetMessage =
  | HelloMessage
  | WelcomeMessage
  | StartMessage
  | InputMessage
  | ConfirmedMessage
  | AckMessage
  | HashMessage
  | DesyncMessage
  | PingMessage
  | PongMessage
  | LeaveMessage
  | ErrorMessage
  | SnapshotRequestMessage
  | SnapshotMessage
  | HashesRequestMessage
  | HashesMessage;

// ------------------------------------------------------------------------------------ errors

/**
 * What is wrong with received bytes:
 * - `'TOO_LARGE'` — the message, or a count or length inside it, is above a {@link ProtocolLimits} bound;
 * - `'TRUNCATED'` — the bytes end inside a field;
 * - `'BAD_VERSION'` — another protocol version;
 * - `'BAD_TYPE'` — an unknown message type;
 * - `'BAD_VALUE'` — a field breaks a rule (non-canonical varint, bad UTF-8, a name with other
 *   characters, a count that does not add up, a non-finite time …);
 * - `'TRAILING_BYTES'` — bytes left over after the last field.
 */
export type ProtocolErrorCode =
  'TOO_LARGE' | 'TRUNCATED' | 'BAD_VERSION' | 'BAD_TYPE' | 'BAD_VALUE' | 'TRAILING_BYTES';

/** The only error {@link decodeMessage} throws. */
export class ProtocolError extends Error {
  readonly code: ProtocolErrorCode;
  /** Byte offset where the problem was found (-1 when not about one place). */
  readonly offset: number;
  constructor(code: ProtocolErrorCode, message: string, offset = -1) {
    super(offset >= 0 ? `${code}: ${message} (at byte ${offset})` : `${code}: ${message}`);
    this.name = 'ProtocolError';
    this.code = code;
    this.offset = offset;
  }
}

// ------------------------------------------------------------------------------------ writer

const encoder = new TextEncoder();

/**
 * The shared canonical writer, with the wire's two extra rules; the relay's protocol and state
 * sync (`state-sync/codec.ts`) both write through it.
 */
export class Writer extends ByteWriter {
  /** @param label — names the format in a sender-bug error (`net`, `state sync`). */
  constructor(
    initialCapacity?: number,
    private readonly label = 'net',
  ) {
    super(initialCapacity);
  }
  /** Times must be finite (a NaN or Infinity is a sender bug). */
  override f64(v: number): this {
    if (!Number.isFinite(v)) {
      throw new RangeError(`${this.label}: cannot encode a non-finite time ${v}`);
    }
    return super.f64(v);
  }
  /** A byte field: varint length, then the bytes. */
  field(b: Uint8Array): this {
    this.varint(b.length);
    return this.bytes(b);
  }
}

// ------------------------------------------------------------------------------------ reader

const FAILURE_CODES: Readonly<Record<ByteReadProblem, ProtocolErrorCode>> = {
  truncated: 'TRUNCATED',
  invalid: 'BAD_VALUE',
  'too-large': 'TOO_LARGE',
  trailing: 'TRAILING_BYTES',
};

/** The {@link ByteReader} failure hook of the wire formats (the relay's, state sync's): a {@link ProtocolError}. */
export function protocolFailure(problem: ByteReadProblem, message: string, offset: number): never {
  throw new ProtocolError(FAILURE_CODES[problem], message, offset);
}

/**
 * The shared {@link ByteReader}, failing with {@link ProtocolError}s, plus the wire's own fields;
 * state sync's reader extends it.
 */
export class Reader extends ByteReader {
  constructor(buf: Uint8Array) {
    super(buf, { start: 2, fail: protocolFailure });
  }
  /** A finite float64 (times). */
  time(what: string): number {
    const at = this.pos;
    const v = this.f64(what);
    if (!Number.isFinite(v)) this.fail('invalid', `${what} is not a finite number`, at);
    return v;
  }
  /** Text: valid UTF-8 without control characters. */
  text(what: string, maxBytes: number): string {
    const at = this.pos;
    const s = this.str(what, maxBytes);
    // eslint-disable-next-line no-control-regex
    if (/[\u0000-\u001f\u007f]/.test(s)) this.fail('invalid', `${what} has control characters`, at);
    return s;
  }
  name(what: string): string {
    const at = this.pos;
    const s = this.text(what, 32);
    if (!NAME_PATTERN.test(s)) {
      this.fail('invalid', `${what} must be 1-32 of A-Z a-z 0-9 _ - .`, at);
    }
    return s;
  }
  /**
   * `rows` rows of `lanes` input words, each XOR-delta coded against the row before; every
   * `words`-th lane (a button word) is interleaved.
   */
  inputs(what: string, rows: number, lanes: number, words: number): Uint32Array {
    // Each word takes at least one byte: check before allocating.
    this.need(rows * lanes, what);
    const out = new Uint32Array(rows * lanes);
    for (let k = 0; k < rows; k++) {
      for (let p = 0; p < lanes; p++) {
        const v = this.varint(what);
        const d = p % words === 0 ? deinterleave(v) : v;
        const i = k * lanes + p;
        out[i] = k === 0 ? d : (out[i - lanes]! ^ d) >>> 0;
      }
    }
    return out;
  }
}

/**
 * `inputs` as rows of `lanes` words, each XOR-delta coded against the row before; every `words`-th
 * lane (a button word) interleaved. {@link Reader.inputs} reads it back.
 */
export function writeInputs(
  w: ByteWriter,
  inputs: Uint32Array,
  lanes: number,
  words: number,
): void {
  for (let i = 0; i < inputs.length; i++) {
    const v = inputs[i]! >>> 0;
    const d = i < lanes ? v : (v ^ inputs[i - lanes]!) >>> 0;
    w.varint((i % lanes) % words === 0 ? interleave(d) : d);
  }
}

// ------------------------------------------------------------------------------------ encode

/**
 * The bytes of a message. Throws a RangeError for a message that breaks the protocol's rules
 * (a value out of range, a name with other characters, a count above the default limits): that is
 * a bug in the sender, not bad data.
 */
// The writer of every message but the two that carry a snapshot: encoding is synchronous and never
// re-entered, so one buffer serves them all and a message costs one allocation (the copy
// `finish()` returns). The relay encodes ~64 messages a second per player: this halves its codec.
const scratch = new Writer(256);

function check(m: NetMessage, ok: boolean, what: string): void {
  if (!ok) throw new RangeError(`net: cannot encode ${m.type}: ${what}`);
}

export function encodeMessage(m: NetMessage): Uint8Array {
  const limits = DEFAULT_PROTOCOL_LIMITS;
  const w =
    m.type === 'snapshot'
      ? new Writer(m.bytes.length + 32)
      : m.type === 'welcome'
        ? new Writer(64 + (m.snapshot?.length ?? 0))
        : scratch.reset();
  w.u8(PROTOCOL_VERSION);
  w.u8(MessageType[m.type]);
  switch (m.type) {
    case 'hello': {
      check(m, NAME_PATTERN.test(m.room), `room name "${m.room}"`);
      check(m, NAME_PATTERN.test(m.game), `game id "${m.game}"`);
      check(m, encoder.encode(m.name).length <= MAX_PLAYER_NAME_BYTES, 'name too long');
      check(m, m.token === undefined || m.token.length === TOKEN_BYTES, 'token length');
      check(m, /^[0-9a-f]{16}$/.test(m.input), `input schema id "${m.input}"`);
      w.str(m.room);
      w.u8(m.role === 'player' ? 0 : 1);
      w.str(m.game);
      w.varint(m.gameVersion);
      w.u64(BigInt(`0x${m.input}`));
      w.varint(m.players);
      w.u8((m.seed !== undefined ? 1 : 0) | (m.token !== undefined ? 2 : 0));
      if (m.seed !== undefined) w.u32(m.seed);
      if (m.token !== undefined) w.bytes(m.token);
      w.str(m.name);
      break;
    }
    case 'welcome': {
      check(m, m.config.length <= limits.maxConfigBytes, 'config too large');
      check(m, m.token.length === 0 || m.token.length === TOKEN_BYTES, 'token length');
      check(m, m.invite.length === 0 || m.invite.length === TOKEN_BYTES, 'invite length');
      check(m, m.players >= 1 && m.players <= limits.maxPlayers, 'players');
      check(m, m.slot >= -1 && m.slot < m.players, 'slot');
      w.varint(m.room);
      w.varint(m.peer);
      w.varint(m.slot + 1);
      w.varint(m.players);
      w.u32(m.seed);
      w.varint(m.tickRate);
      w.varint(m.hashEvery);
      w.varint(m.deadlineMs);
      w.varint(m.inputFrom);
      w.varint(m.startTick);
      w.field(m.config);
      w.field(m.token);
      w.field(m.invite);
      w.u8((m.startAt !== undefined ? 1 : 0) | (m.snapshot !== undefined ? 2 : 0));
      if (m.startAt !== undefined) w.f64(m.startAt);
      if (m.snapshot !== undefined) {
        check(m, m.snapshot.length <= limits.maxSnapshotBytes, 'snapshot too large');
        w.field(m.snapshot);
      }
      break;
    }
    case 'start':
      w.varint(m.room);
      w.f64(m.startAt);
      break;
    case 'input': {
      check(m, m.words >= 1 && m.words <= limits.maxInputWords, 'words');
      const ticks = m.inputs.length / m.words;
      check(
        m,
        Number.isInteger(ticks) && ticks >= 1 && ticks <= limits.maxInputTicks,
        'input count',
      );
      w.varint(m.room);
      w.varint(m.player);
      w.varint(m.ack);
      w.varint(m.tick);
      w.varint(m.words);
      w.varint(ticks);
      writeInputs(w, m.inputs, m.words, m.words);
      break;
    }
    case 'confirmed': {
      // The hottest message (one a tick to every member): no room number, the input ack as an
      // offset from the message's end, players and words in one varint, the delta flag in the
      // count. Six bytes of header for a tick of held buttons.
      check(m, m.players >= 1 && m.players <= limits.maxPlayers, 'players');
      check(
        m,
        m.words >= 1 && m.words <= Math.min(MAX_WIRE_INPUT_WORDS, limits.maxInputWords),
        'words',
      );
      const ticks = m.inputs.length / (m.players * m.words);
      check(m, Number.isInteger(ticks) && ticks <= limits.maxConfirmedTicks, 'tick count');
      check(m, m.inputAck >= m.tick + ticks, 'input ack before the end of the message');
      w.varint(m.tick);
      w.varint(m.inputAck - m.tick - ticks);
      w.varint((m.players - 1) * MAX_WIRE_INPUT_WORDS + (m.words - 1));
      w.varint(ticks * 2 + (m.delta ? 1 : 0));
      writeInputs(w, m.inputs, m.players * m.words, m.words);
      break;
    }
    case 'ack':
      w.varint(m.room);
      w.varint(m.ack);
      break;
    case 'hash':
      w.varint(m.room);
      w.varint(m.tick);
      w.u64(m.hash);
      break;
    case 'desync': {
      check(m, m.groups.length >= 1 && m.groups.length <= limits.maxGroups, 'group count');
      check(m, m.majority >= -1 && m.majority < m.groups.length, 'majority');
      w.varint(m.room);
      w.varint(m.tick);
      w.u8(m.exact ? 1 : 0);
      w.varint(m.reportTick);
      w.varint(m.majority + 1);
      w.varint(m.groups.length);
      let peers = 0;
      for (const g of m.groups) {
        peers += g.peers.length;
        w.u64(g.hash);
        w.varint(g.peers.length);
        for (const p of g.peers) w.varint(p);
      }
      check(m, peers <= limits.maxPeers, 'peer count');
      break;
    }
    case 'ping':
      w.varint(m.id);
      w.f64(m.time);
      break;
    case 'pong':
      w.varint(m.id);
      w.f64(m.time);
      w.f64(m.serverTime);
      break;
    case 'leave':
      w.varint(m.room);
      w.varint(m.peer);
      w.u8(LEAVE_REASONS.indexOf(m.reason));
      break;
    case 'error': {
      const code = ERROR_CODES.indexOf(m.code);
      check(m, code >= 0, `error code ${m.code}`);
      w.u8(code);
      w.u8(m.fatal ? 1 : 0);
      w.str(truncateUtf8(m.message, MAX_ERROR_TEXT_BYTES));
      break;
    }
    case 'snapshot-request':
      w.varint(m.room);
      w.varint(m.id);
      w.varint(m.tick + 1);
      break;
    case 'snapshot':
      check(m, m.bytes.length <= limits.maxSnapshotBytes, 'snapshot too large');
      w.varint(m.room);
      w.varint(m.id);
      w.varint(m.tick);
      w.field(m.bytes);
      break;
    case 'hashes-request':
      check(m, m.count >= 1 && m.count <= limits.maxHashes, 'hash count');
      w.varint(m.room);
      w.varint(m.id);
      w.varint(m.from);
      w.varint(m.count);
      break;
    case 'hashes':
      check(m, m.hashes.length <= limits.maxHashes, 'hash count');
      w.varint(m.room);
      w.varint(m.id);
      w.varint(m.from);
      w.varint(m.hashes.length);
      for (const h of m.hashes) w.u64(h);
      break;
  }
  return w.finish();
}

/** `s` cut to at most `max` UTF-8 bytes, on a character boundary. */
function truncateUtf8(s: string, max: number): string {
  // eslint-disable-next-line no-control-regex
  let t = s.replace(/[\u0000-\u001f\u007f]/g, ' ');
  while (encoder.encode(t).length > max) t = t.slice(0, -1);
  return t;
}

// ------------------------------------------------------------------------------------ decode

const TYPES: readonly (MessageKind | undefined)[] = (() => {
  const out: (MessageKind | undefined)[] = [];
  for (const [k, v] of Object.entries(MessageType)) out[v] = k as MessageKind;
  return out;
})();

/** The message type of `bytes` without decoding the rest (undefined when unknown or too short). */
export function peekMessageType(bytes: Uint8Array): MessageKind | undefined {
  if (bytes.length < 2 || bytes[0] !== PROTOCOL_VERSION) return undefined;
  return TYPES[bytes[1]!];
}

/**
 * Decodes one message. Throws a {@link ProtocolError} — and nothing else — for any bytes that are
 * not exactly one valid message within `limits`; sizes and counts are checked before anything is
 * allocated. Byte fields of the result are copies.
 */
export function decodeMessage(
  bytes: Uint8Array,
  limits: Readonly<ProtocolLimits> = DEFAULT_PROTOCOL_LIMITS,
): NetMessage {
  try {
    return decodeUnchecked(bytes, limits);
  } catch (error) {
    if (error instanceof ProtocolError) throw error;
    // A bug here must still surface as the one documented error type.
    throw new ProtocolError('BAD_VALUE', `undecodable message: ${String(error)}`);
  }
}

function decodeUnchecked(bytes: Uint8Array, limits: Readonly<ProtocolLimits>): NetMessage {
  if (!(bytes instanceof Uint8Array)) throw new ProtocolError('BAD_VALUE', 'not a byte array');
  if (bytes.length > limits.maxMessageBytes) {
    throw new ProtocolError(
      'TOO_LARGE',
      `message of ${bytes.length} bytes, at most ${limits.maxMessageBytes}`,
    );
  }
  if (bytes.length < 2) throw new ProtocolError('TRUNCATED', 'shorter than a header', 0);
  if (bytes[0] !== PROTOCOL_VERSION) {
    throw new ProtocolError(
      'BAD_VERSION',
      `protocol version ${bytes[0]}, this side speaks ${PROTOCOL_VERSION}`,
      0,
    );
  }
  const kind = TYPES[bytes[1]!];
  if (kind === undefined) {
    throw new ProtocolError('BAD_TYPE', `unknown message type 0x${bytes[1]!.toString(16)}`, 1);
  }
  const r = new Reader(bytes);
  const m = decodeBody(kind, r, limits);
  r.end();
  return m;
}

function decodeBody(kind: MessageKind, r: Reader, limits: Readonly<ProtocolLimits>): NetMessage {
  switch (kind) {
    case 'hello': {
      const room = r.name('room');
      const roleAt = r.pos;
      const role = r.u8('role');
      if (role > 1) r.fail('invalid', `role ${role}`, roleAt);
      const game = r.name('game');
      const gameVersion = r.varint('game version');
      const input = r.u64('input schema id').toString(16).padStart(16, '0');
      const players = r.count('players', limits.maxPlayers);
      const flagsAt = r.pos;
      const flags = r.u8('flags');
      if (flags > 3) r.fail('invalid', `hello flags 0x${flags.toString(16)}`, flagsAt);
      const seed = flags & 1 ? r.u32('seed') : undefined;
      let token: Uint8Array | undefined;
      if (flags & 2) {
        token = r.bytes(TOKEN_BYTES, 'token').slice();
      }
      const name = r.text('name', MAX_PLAYER_NAME_BYTES);
      const m: HelloMessage = {
        type: 'hello',
        room,
        role: role === 0 ? 'player' : 'spectator',
        game,
        gameVersion,
        input,
        players,
        name,
      };
      if (seed !== undefined) m.seed = seed;
      if (token !== undefined) m.token = token;
      return m;
    }
    case 'welcome': {
      const room = r.varint('room');
      const peer = r.varint('peer');
      const slotAt = r.pos;
      const slot = r.varint('slot') - 1;
      const players = r.count('players', limits.maxPlayers, 1);
      if (slot >= players) r.fail('invalid', `slot ${slot} of ${players} players`, slotAt);
      const seed = r.u32('seed');
      const tickRate = r.count('tick rate', 10_000, 1);
      const hashEvery = r.count('hash interval', 1 << 20, 1);
      const deadlineMs = r.varint('deadline');
      const inputFrom = r.varint('input from');
      const startTick = r.varint('start tick');
      const config = r.field('config', limits.maxConfigBytes);
      const tokenAt = r.pos;
      const token = r.field('token', TOKEN_BYTES);
      if (token.length !== 0 && token.length !== TOKEN_BYTES) {
        r.fail('invalid', `token of ${token.length} bytes`, tokenAt);
      }
      const inviteAt = r.pos;
      const invite = r.field('invite', TOKEN_BYTES);
      if (invite.length !== 0 && invite.length !== TOKEN_BYTES) {
        r.fail('invalid', `invite of ${invite.length} bytes`, inviteAt);
      }
      const flagsAt = r.pos;
      const flags = r.u8('flags');
      if (flags > 3) r.fail('invalid', `welcome flags 0x${flags.toString(16)}`, flagsAt);
      const m: WelcomeMessage = {
        type: 'welcome',
        room,
        peer,
        slot,
        players,
        seed,
        tickRate,
        hashEvery,
        deadlineMs,
        inputFrom,
        startTick,
        config,
        token,
        invite,
      };
      if (flags & 1) m.startAt = r.time('start time');
      if (flags & 2) m.snapshot = r.field('snapshot', limits.maxSnapshotBytes);
      return m;
    }
    case 'start':
      return { type: 'start', room: r.varint('room'), startAt: r.time('start time') };
    case 'input': {
      const room = r.varint('room');
      const player = r.count('player', limits.maxPlayers - 1);
      const ack = r.varint('ack');
      const tick = r.varint('tick');
      const words = r.count('words', limits.maxInputWords, 1);
      const n = r.count('input count', limits.maxInputTicks, 1);
      if (tick + n - 1 > 0xffffffff) r.fail('invalid', 'tick range past 2^32');
      const inputs = r.inputs('inputs', n, words, words);
      return { type: 'input', room, player, ack, tick, words, inputs };
    }
    case 'confirmed': {
      const tick = r.varint('tick');
      const ahead = r.varint('input ack offset');
      const shapeAt = r.pos;
      const shape = r.varint('players and words');
      const players = Math.floor(shape / MAX_WIRE_INPUT_WORDS) + 1;
      const words = (shape % MAX_WIRE_INPUT_WORDS) + 1;
      if (players > limits.maxPlayers) {
        r.fail('too-large', `${players} players, at most ${limits.maxPlayers}`, shapeAt);
      }
      if (words > limits.maxInputWords) {
        r.fail('too-large', `${words} input words, at most ${limits.maxInputWords}`, shapeAt);
      }
      const countAt = r.pos;
      const count = r.count('tick count', limits.maxConfirmedTicks * 2 + 1);
      const n = count >>> 1;
      if (tick + n + ahead > 0xffffffff) r.fail('invalid', 'tick range past 2^32', countAt);
      return {
        type: 'confirmed',
        inputAck: tick + n + ahead,
        tick,
        players,
        words,
        inputs: r.inputs('inputs', n, players * words, words),
        delta: (count & 1) === 1,
      };
    }
    case 'ack':
      return { type: 'ack', room: r.varint('room'), ack: r.varint('ack') };
    case 'hash':
      return { type: 'hash', room: r.varint('room'), tick: r.varint('tick'), hash: r.u64('hash') };
    case 'desync': {
      const room = r.varint('room');
      const tick = r.varint('tick');
      const exactAt = r.pos;
      const exact = r.u8('exact');
      if (exact > 1) r.fail('invalid', `exact flag ${exact}`, exactAt);
      const reportTick = r.varint('report tick');
      const majAt = r.pos;
      const majority = r.varint('majority') - 1;
      const n = r.count('group count', limits.maxGroups, 1);
      if (majority >= n) r.fail('invalid', `majority ${majority} of ${n} groups`, majAt);
      r.need(n * 9, 'groups');
      const groups: { hash: bigint; peers: number[] }[] = [];
      let total = 0;
      for (let g = 0; g < n; g++) {
        const hash = r.u64('group hash');
        const k = r.count('group size', limits.maxPeers - total);
        total += k;
        r.need(k, 'peers');
        const peers: number[] = [];
        for (let i = 0; i < k; i++) peers.push(r.varint('peer'));
        groups.push({ hash, peers });
      }
      return { type: 'desync', room, tick, exact: exact === 1, reportTick, majority, groups };
    }
    case 'ping':
      return { type: 'ping', id: r.varint('id'), time: r.time('time') };
    case 'pong':
      return {
        type: 'pong',
        id: r.varint('id'),
        time: r.time('time'),
        serverTime: r.time('server time'),
      };
    case 'leave': {
      const room = r.varint('room');
      const peer = r.varint('peer');
      const at = r.pos;
      const reason = LEAVE_REASONS[r.u8('reason')];
      if (reason === undefined) r.fail('invalid', 'unknown leave reason', at);
      return { type: 'leave', room, peer, reason };
    }
    case 'error': {
      const at = r.pos;
      const code = ERROR_CODES[r.u8('code')];
      if (code === undefined) r.fail('invalid', 'unknown error code', at);
      const fatalAt = r.pos;
      const fatal = r.u8('fatal');
      if (fatal > 1) r.fail('invalid', `fatal flag ${fatal}`, fatalAt);
      return {
        type: 'error',
        code,
        fatal: fatal === 1,
        message: r.text('message', MAX_ERROR_TEXT_BYTES),
      };
    }
    case 'snapshot-request':
      return {
        type: 'snapshot-request',
        room: r.varint('room'),
        id: r.varint('id'),
        tick: r.varint('tick') - 1,
      };
    case 'snapshot':
      return {
        type: 'snapshot',
        room: r.varint('room'),
        id: r.varint('id'),
        tick: r.varint('tick'),
        bytes: r.field('snapshot', limits.maxSnapshotBytes),
      };
    case 'hashes-request':
      return {
        type: 'hashes-request',
        room: r.varint('room'),
        id: r.varint('id'),
        from: r.varint('from'),
        count: r.count('count', limits.maxHashes, 1),
      };
    case 'hashes': {
      const room = r.varint('room');
      const id = r.varint('id');
      const from = r.varint('from');
      const n = r.count('hash count', limits.maxHashes);
      r.need(n * 8, 'hashes');
      const hashes = new BigUint64Array(n);
      for (let i = 0; i < n; i++) hashes[i] = r.u64('hash');
      return { type: 'hashes', room, id, from, hashes };
    }
  }
}
