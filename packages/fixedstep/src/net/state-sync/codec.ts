/**
 * The state-sync wire format: its own version byte and message types, so neither the relay's
 * protocol nor this one mistakes the other's messages (docs/network.md, "State sync", has the
 * table).
 *
 * Every message is `[version u8 = 0x81][type u8][fields…]`. Field encodings are the relay
 * protocol's: canonical LEB128 varints of u32, little-endian fixed-width integers, finite
 * canonical float64 milliseconds, byte fields and strings with a varint length, inputs XOR-delta
 * coded against the previous tick with the button word bit-interleaved.
 *
 * {@link decodeStateSyncMessage} reads through the one {@link ByteReader} with a failure hook that
 * throws {@link ProtocolError} — and nothing else, whatever the bytes — and checks every count and
 * length against {@link StateSyncLimits} before it allocates.
 * @module
 */
import {
  NAME_PATTERN,
  ProtocolError,
  Reader,
  TOKEN_BYTES,
  Writer,
  protocolFailure,
  writeInputs,
} from '../protocol.js';

/**
 * Byte 0 of every state-sync message. The top bit is set so the relay (protocol versions 1–3) refuses a
 * state-sync message as another version, and this side refuses the relay's.
 */
export const STATE_SYNC_VERSION = 0x81;

/** Message type bytes (byte 1): 0x0_ client → server, 0x1_ server → client. */
export const StateSyncType = {
  join: 0x01,
  input: 0x02,
  ack: 0x03,
  ping: 0x04,
  resync: 0x05,
  leave: 0x06,
  welcome: 0x11,
  snapshot: 0x12,
  pong: 0x13,
  error: 0x14,
} as const;

/** The name of a state-sync message type. */
export type StateSyncKind = keyof typeof StateSyncType;

/** Size bounds the decoder enforces before it allocates anything. */
export interface StateSyncLimits {
  /** Largest message, in bytes. Default 1 MiB + 1 KiB (a full snapshot and its header). */
  maxMessageBytes: number;
  /** Largest world state (a snapshot's size), in bytes. Default 1 MiB. */
  maxStateBytes: number;
  /** Most ticks of inputs in one `input` message. Default 64. */
  maxInputTicks: number;
  /** Most u32 words of one player's input for one tick. Default 16. */
  maxInputWords: number;
  /** Most players of a room. Default 64 (a game's `maxPlayers` is at most 64). */
  maxPlayers: number;
  /** Largest game option bytes, in bytes. Default 256. */
  maxConfigBytes: number;
}

/** The default {@link StateSyncLimits}. */
export const DEFAULT_STATE_SYNC_LIMITS: Readonly<StateSyncLimits> = Object.freeze({
  maxMessageBytes: (1 << 20) + 1024,
  maxStateBytes: 1 << 20,
  maxInputTicks: 64,
  maxInputWords: 16,
  maxPlayers: 64,
  maxConfigBytes: 256,
});

/** Longest player name, in UTF-8 bytes. */
const MAX_NAME_BYTES = 32;
/** Longest error text, in UTF-8 bytes. */
const MAX_ERROR_TEXT_BYTES = 200;

/** Why the server refused something (the `error` message's code). */
export type StateSyncErrorCode =
  | 'BAD_MESSAGE'
  | 'TOO_LARGE'
  | 'RATE_LIMIT'
  | 'NOT_JOINED'
  | 'WRONG_ROOM'
  | 'SPOOFED_PLAYER'
  | 'BAD_INPUT'
  | 'TICK_WINDOW'
  | 'ROOM_FULL'
  | 'UNKNOWN_GAME'
  | 'GAME_MISMATCH'
  | 'BAD_JOIN'
  | 'BAD_TOKEN'
  | 'TIMEOUT'
  | 'SERVER_FULL'
  | 'INTERNAL'
  | 'SHUTDOWN';

const ERROR_CODES: readonly StateSyncErrorCode[] = [
  'BAD_MESSAGE',
  'TOO_LARGE',
  'RATE_LIMIT',
  'NOT_JOINED',
  'WRONG_ROOM',
  'SPOOFED_PLAYER',
  'BAD_INPUT',
  'TICK_WINDOW',
  'ROOM_FULL',
  'UNKNOWN_GAME',
  'GAME_MISMATCH',
  'BAD_JOIN',
  'BAD_TOKEN',
  'TIMEOUT',
  'SERVER_FULL',
  'INTERNAL',
  'SHUTDOWN',
];

/**
 * Why a client asks for a full snapshot:
 * - `'bad-delta'` — a delta did not decode (damaged bytes);
 * - `'hash-mismatch'` — a delta decoded, but the result's hash is not the one the server sent
 *   (a damaged delta, or one applied to the wrong base);
 * - `'no-base'` — the delta's base snapshot is not here (never arrived, or no longer kept);
 * - `'unloadable'` — the state did not load into the game (the game refused its bytes).
 */
export type ResyncReason = 'bad-delta' | 'hash-mismatch' | 'no-base' | 'unloadable';
const RESYNC_REASONS: readonly ResyncReason[] = [
  'bad-delta',
  'hash-mismatch',
  'no-base',
  'unloadable',
];

// ------------------------------------------------------------------------------------ messages

/** Client → server, first message: join (or create) a room. Repeated until welcomed. */
export interface JoinMessage {
  type: 'join';
  /** Room name: 1–32 of `A–Z a–z 0–9 _ - .`; the first join creates the room. */
  room: string;
  role: 'player' | 'spectator';
  /** Game id and version: a room plays one game, one version. */
  game: string;
  gameVersion: number;
  /** The client's input schema id (`InputSchema.id`, 16 hex digits). */
  input: string;
  /** Player slots when this join creates the room (0: the game's minimum). */
  players: number;
  /** The game's seed when this join creates the room (absent: the server picks one). */
  seed?: number;
  /** A reconnect token from an earlier welcome: take back that player slot. */
  token?: Uint8Array;
  /** Display name, at most 32 UTF-8 bytes. */
  name: string;
}

/**
 * Client → server: my inputs for ticks `tick … tick + inputs.length / words − 1` (a redundant
 * window that survives loss), and the newest snapshot I hold.
 */
export interface StateInputMessage {
  type: 'input';
  /** The player slot these inputs are for: the server refuses any but the sender's own. */
  player: number;
  /** Tick of the newest snapshot the client holds and verified (-1: none): the next delta's base. */
  ack: number;
  tick: number;
  /** u32 words per tick: the input schema's `words`. */
  words: number;
  inputs: Uint32Array;
}

/** Client → server: the newest snapshot I hold (spectators, and players with nothing to send). */
export interface StateAckMessage {
  type: 'ack';
  /** Tick of the newest verified snapshot (-1: none). */
  ack: number;
}

/** Client → server: clock probe; `time` is the client's clock in ms. */
export interface StatePingMessage {
  type: 'ping';
  id: number;
  time: number;
}

/** Client → server: my last delta could not be used; send a full snapshot. */
export interface ResyncMessage {
  type: 'resync';
  reason: ResyncReason;
}

/** Client → server: I leave (the server frees my slot at once). */
export interface StateLeaveMessage {
  type: 'leave';
}

/** Server → client: you are in. A full snapshot follows. */
export interface StateWelcomeMessage {
  type: 'welcome';
  /** Your player slot, or -1 for a spectator. */
  slot: number;
  /** Player slots (inputs per tick). */
  players: number;
  /** The room's seed: with `players` and `config`, the game's setup. */
  seed: number;
  /** Ticks per second. */
  tickRate: number;
  /** The server sends a snapshot every this many ticks. */
  snapshotEvery: number;
  /** Server time (ms) at which tick 0 began: tick t begins at `startAt + t × step`. */
  startAt: number;
  /** The first tick the server takes inputs from you for. */
  inputFrom: number;
  /** The game's canonical option bytes. */
  config: Uint8Array;
  /** Your reconnect token (players; empty for spectators). */
  token: Uint8Array;
}

/**
 * Server → client: the world at `tick`, as the game's canonical bytes — whole (`base` -1), or
 * delta-coded against the snapshot of tick `base`, the newest one the client acknowledged — plus
 * the clock: the tick, and how long after the tick's time (`startAt + tick × step`) it was sent.
 */
export interface StateSnapshotMessage {
  type: 'snapshot';
  /** The state's tick (the state after `tick` steps). */
  tick: number;
  /** The base snapshot's tick for a delta (older than `tick`); -1: a full snapshot. */
  base: number;
  /**
   * When it was sent, in whole microseconds after the tick's time `startAt + tick × step` on the
   * server clock (the server steps a tick when its time has come, then sends at once).
   */
  sendDelayUs: number;
  /** The next tick the server needs an input from you for (at least `tick`; `tick` for spectators). */
  inputAck: number;
  /** How many of your ticks the server stepped without your input (filled by the missing rule). */
  filled: number;
  /** Byte length of the state. */
  size: number;
  /** FNV-1a 64 of the state's bytes: the client checks what it rebuilt against it. */
  hash: bigint;
  /** The state's bytes (full), or the delta's runs (see `encodeDelta`). */
  payload: Uint8Array;
}

/** Server → client: the probe's `id` and `time`, and the server's clock when it answered. */
export interface StatePongMessage {
  type: 'pong';
  id: number;
  time: number;
  serverTime: number;
}

/** Server → client: something was refused; `fatal` means the connection is being closed. */
export interface StateErrorMessage {
  type: 'error';
  code: StateSyncErrorCode;
  fatal: boolean;
  message: string;
}

/** Any state-sync message. */
export type StateSyncMessage =
  | JoinMessage
  | StateInputMessage
  | StateAckMessage
  | StatePingMessage
  | ResyncMessage
  | StateLeaveMessage
  | StateWelcomeMessage
  | StateSnapshotMessage
  | StatePongMessage
  | StateErrorMessage;

// ------------------------------------------------------------------------------------ writer

const encoder = new TextEncoder();

/** `s` cut to at most `max` UTF-8 bytes on a character boundary, control characters blanked. */
function truncateUtf8(s: string, max: number): string {
  // eslint-disable-next-line no-control-regex
  let t = s.replace(/[\u0000-\u001f\u007f]/g, ' ');
  while (encoder.encode(t).length > max) t = t.slice(0, -1);
  return t;
}

/**
 * The bytes of a message. Throws a RangeError for a message that breaks the format's rules (a
 * value out of range, a bad name, a count above the default limits): a bug in the sender, not bad
 * data.
 */
export function encodeStateSyncMessage(m: StateSyncMessage): Uint8Array {
  const limits = DEFAULT_STATE_SYNC_LIMITS;
  const w = new Writer(m.type === 'snapshot' ? m.payload.length + 48 : 64, 'state sync');
  w.u8(STATE_SYNC_VERSION);
  w.u8(StateSyncType[m.type]);
  const check = (ok: boolean, what: string) => {
    if (!ok) throw new RangeError(`state sync: cannot encode ${m.type}: ${what}`);
  };
  switch (m.type) {
    case 'join':
      check(NAME_PATTERN.test(m.room), `room name "${m.room}"`);
      check(NAME_PATTERN.test(m.game), `game id "${m.game}"`);
      check(/^[0-9a-f]{16}$/.test(m.input), `input schema id "${m.input}"`);
      check(encoder.encode(m.name).length <= MAX_NAME_BYTES, 'name too long');
      check(m.token === undefined || m.token.length === TOKEN_BYTES, 'token length');
      check(m.players >= 0 && m.players <= limits.maxPlayers, 'players');
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
    case 'input': {
      check(m.words >= 1 && m.words <= limits.maxInputWords, 'words');
      const ticks = m.inputs.length / m.words;
      check(Number.isInteger(ticks) && ticks >= 1 && ticks <= limits.maxInputTicks, 'input count');
      check(m.player >= 0 && m.player < limits.maxPlayers, 'player');
      w.varint(m.player);
      w.varint(m.ack + 1);
      w.varint(m.tick);
      w.varint(m.words);
      w.varint(ticks);
      writeInputs(w, m.inputs, m.words, m.words);
      break;
    }
    case 'ack':
      w.varint(m.ack + 1);
      break;
    case 'ping':
      w.varint(m.id);
      w.f64(m.time);
      break;
    case 'resync':
      w.u8(RESYNC_REASONS.indexOf(m.reason));
      break;
    case 'leave':
      break;
    case 'welcome':
      check(m.players >= 1 && m.players <= limits.maxPlayers, 'players');
      check(m.slot >= -1 && m.slot < m.players, 'slot');
      check(m.config.length <= limits.maxConfigBytes, 'config too large');
      check(m.token.length === 0 || m.token.length === TOKEN_BYTES, 'token length');
      w.varint(m.slot + 1);
      w.varint(m.players);
      w.u32(m.seed);
      w.varint(m.tickRate);
      w.varint(m.snapshotEvery);
      w.f64(m.startAt);
      w.varint(m.inputFrom);
      w.field(m.config);
      w.field(m.token);
      break;
    case 'snapshot':
      check(m.size <= limits.maxStateBytes, 'state too large');
      check(m.base < m.tick, 'base must be older than the snapshot');
      check(m.base >= 0 || m.payload.length === m.size, 'a full snapshot carries the whole state');
      check(m.inputAck >= m.tick, 'input ack before the tick');
      // Ticks relative to `tick` (one byte each, however long the match has run).
      w.varint(m.tick);
      w.varint(m.base < 0 ? 0 : m.tick - m.base);
      w.varint(m.sendDelayUs);
      w.varint(m.inputAck - m.tick);
      w.varint(m.filled);
      w.varint(m.size);
      w.u64(m.hash);
      w.field(m.payload);
      break;
    case 'pong':
      w.varint(m.id);
      w.f64(m.time);
      w.f64(m.serverTime);
      break;
    case 'error': {
      const code = ERROR_CODES.indexOf(m.code);
      check(code >= 0, `error code ${m.code}`);
      w.u8(code);
      w.u8(m.fatal ? 1 : 0);
      w.str(truncateUtf8(m.message, MAX_ERROR_TEXT_BYTES));
      break;
    }
  }
  return w.finish();
}

// ------------------------------------------------------------------------------------ reader

/** The {@link ByteReader} failure hook of the state-sync format: the wire's {@link ProtocolError}. */
export const stateSyncFailure = protocolFailure;

/** The wire's reader, with state sync's stricter time (no -0) and its flag bytes. */
class StateSyncReader extends Reader {
  override time(what: string): number {
    const at = this.pos;
    const v = super.time(what);
    if (Object.is(v, -0)) this.fail('invalid', `${what} is -0 (not canonical: +0)`, at);
    return v;
  }
  flag(what: string, max: number): number {
    const at = this.pos;
    const v = this.u8(what);
    if (v > max) this.fail('invalid', `${what} 0x${v.toString(16)}`, at);
    return v;
  }
}

const TYPES: readonly (StateSyncKind | undefined)[] = (() => {
  const out: (StateSyncKind | undefined)[] = [];
  for (const [k, v] of Object.entries(StateSyncType)) out[v] = k as StateSyncKind;
  return out;
})();

/** The message type of `bytes` without decoding the rest (undefined: not a state-sync message). */
export function peekStateSyncType(bytes: Uint8Array): StateSyncKind | undefined {
  if (bytes.length < 2 || bytes[0] !== STATE_SYNC_VERSION) return undefined;
  return TYPES[bytes[1]!];
}

/**
 * Decodes one message. Throws a {@link ProtocolError} — and nothing else — for any bytes that are
 * not exactly one valid message within `limits`; sizes and counts are checked before anything is
 * allocated. Byte fields of the result are copies.
 */
export function decodeStateSyncMessage(
  bytes: Uint8Array,
  limits: Readonly<StateSyncLimits> = DEFAULT_STATE_SYNC_LIMITS,
): StateSyncMessage {
  try {
    return decodeUnchecked(bytes, limits);
  } catch (error) {
    if (error instanceof ProtocolError) throw error;
    throw new ProtocolError('BAD_VALUE', `undecodable message: ${String(error)}`);
  }
}

function decodeUnchecked(bytes: Uint8Array, limits: Readonly<StateSyncLimits>): StateSyncMessage {
  if (!(bytes instanceof Uint8Array)) throw new ProtocolError('BAD_VALUE', 'not a byte array');
  if (bytes.length > limits.maxMessageBytes) {
    throw new ProtocolError(
      'TOO_LARGE',
      `message of ${bytes.length} bytes, at most ${limits.maxMessageBytes}`,
    );
  }
  if (bytes.length < 2) throw new ProtocolError('TRUNCATED', 'shorter than a header', 0);
  if (bytes[0] !== STATE_SYNC_VERSION) {
    throw new ProtocolError(
      'BAD_VERSION',
      `version byte 0x${bytes[0]!.toString(16)}, state sync speaks 0x${STATE_SYNC_VERSION.toString(16)}`,
      0,
    );
  }
  const kind = TYPES[bytes[1]!];
  if (kind === undefined) {
    throw new ProtocolError('BAD_TYPE', `unknown message type 0x${bytes[1]!.toString(16)}`, 1);
  }
  const r = new StateSyncReader(bytes);
  const m = decodeBody(kind, r, limits);
  r.end();
  return m;
}

function decodeBody(
  kind: StateSyncKind,
  r: StateSyncReader,
  limits: Readonly<StateSyncLimits>,
): StateSyncMessage {
  switch (kind) {
    case 'join': {
      const room = r.name('room');
      const role = r.flag('role', 1);
      const game = r.name('game');
      const gameVersion = r.varint('game version');
      const input = r.u64('input schema id').toString(16).padStart(16, '0');
      const players = r.count('players', limits.maxPlayers);
      const flags = r.flag('join flags', 3);
      const seed = flags & 1 ? r.u32('seed') : undefined;
      const token = flags & 2 ? r.bytes(TOKEN_BYTES, 'token').slice() : undefined;
      const name = r.text('name', MAX_NAME_BYTES);
      const m: JoinMessage = {
        type: 'join',
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
    case 'input': {
      const player = r.count('player', limits.maxPlayers - 1);
      const ack = r.varint('ack') - 1;
      const tick = r.varint('tick');
      const words = r.count('words', limits.maxInputWords, 1);
      const n = r.count('input count', limits.maxInputTicks, 1);
      if (tick + n - 1 > 0xffffffff) r.fail('invalid', 'tick range past 2^32');
      return {
        type: 'input',
        player,
        ack,
        tick,
        words,
        inputs: r.inputs('inputs', n, words, words),
      };
    }
    case 'ack':
      return { type: 'ack', ack: r.varint('ack') - 1 };
    case 'ping':
      return { type: 'ping', id: r.varint('id'), time: r.time('time') };
    case 'resync': {
      const at = r.pos;
      const reason = RESYNC_REASONS[r.u8('reason')];
      if (reason === undefined) r.fail('invalid', 'unknown resync reason', at);
      return { type: 'resync', reason };
    }
    case 'leave':
      return { type: 'leave' };
    case 'welcome': {
      const slotAt = r.pos;
      const slot = r.varint('slot') - 1;
      const players = r.count('players', limits.maxPlayers, 1);
      if (slot >= players) r.fail('invalid', `slot ${slot} of ${players} players`, slotAt);
      const seed = r.u32('seed');
      const tickRate = r.count('tick rate', 100_000, 1);
      const snapshotEvery = r.count('snapshot interval', 1 << 16, 1);
      const startAt = r.time('start time');
      const inputFrom = r.varint('input from');
      const config = r.field('config', limits.maxConfigBytes);
      const tokenAt = r.pos;
      const token = r.field('token', TOKEN_BYTES);
      if (token.length !== 0 && token.length !== TOKEN_BYTES) {
        r.fail('invalid', `token of ${token.length} bytes`, tokenAt);
      }
      return {
        type: 'welcome',
        slot,
        players,
        seed,
        tickRate,
        snapshotEvery,
        startAt,
        inputFrom,
        config,
        token,
      };
    }
    case 'snapshot': {
      const tick = r.varint('tick');
      const baseAt = r.pos;
      const back = r.varint('base distance');
      if (back > tick) r.fail('invalid', `base ${back} ticks before tick ${tick}`, baseAt);
      const base = back === 0 ? -1 : tick - back;
      const sendDelayUs = r.varint('send delay');
      const ackAt = r.pos;
      const inputAck = tick + r.varint('input ack');
      if (inputAck > 0xffffffff) r.fail('invalid', 'input ack past 2^32', ackAt);
      const filled = r.varint('filled inputs');
      const size = r.count('state size', limits.maxStateBytes);
      const hash = r.u64('state hash');
      const payloadAt = r.pos;
      const payload = r.field('payload', limits.maxStateBytes + 16);
      if (base < 0 && payload.length !== size) {
        r.fail('invalid', `a full snapshot of ${payload.length} bytes says ${size}`, payloadAt);
      }
      return { type: 'snapshot', tick, base, sendDelayUs, inputAck, filled, size, hash, payload };
    }
    case 'pong':
      return {
        type: 'pong',
        id: r.varint('id'),
        time: r.time('time'),
        serverTime: r.time('server time'),
      };
    case 'error': {
      const at = r.pos;
      const code = ERROR_CODES[r.u8('code')];
      if (code === undefined) r.fail('invalid', 'unknown error code', at);
      const fatal = r.flag('fatal flag', 1);
      return {
        type: 'error',
        code,
        fatal: fatal === 1,
        message: r.text('message', MAX_ERROR_TEXT_BYTES),
      };
    }
  }
}
