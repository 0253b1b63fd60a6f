/**
 * The state-sync protocol (`/state/<room>`: the server runs the game and sends the world): its
 * messages, declared once (`net/wire`); docs/network.md, "State sync", has the table.
 *
 * Its header byte is of its own family (0x80), so neither the relay nor state sync mistakes the
 * other's messages. Version 2 declares the messages as data, shares the join and the error list
 * with the relay, and adds the room's invite token (spectators need it). Version 3 adds the
 * snapshot's codec: the game's bytes, or its state schema's words (`schema-codec.ts`).
 * @module
 */
import {
  ERROR_FIELDS,
  PING_FIELDS,
  PONG_FIELDS,
  checkInputRun,
  inputRunFields,
  joinFields,
  tokenField,
  type ErrorMessage,
  type JoinFields,
  type PingMessage,
  type PongMessage,
} from '../wire/common.js';
import { bytes, oneOf, time, u32, u64, uint, type Field } from '../wire/fields.js';
import { defineProtocol } from '../wire/protocol.js';

/** The state-sync protocol's version (byte 0 of every message is 0x80 | this). */
export const STATE_SYNC_VERSION = 4;

/** Size bounds the decoder enforces before it allocates anything. */
export interface StateSyncLimits {
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
  maxStateBytes: 1 << 20,
  maxInputTicks: 64,
  maxInputWords: 16,
  maxPlayers: 64,
  maxConfigBytes: 256,
});

/**
 * Why a client asks for a full snapshot:
 * - `'bad-delta'` — a delta did not decode (damaged bytes);
 * - `'hash-mismatch'` — a delta decoded, but the result's hash is not the one the server sent
 *   (a damaged delta, or one applied to the wrong base);
 * - `'no-base'` — the delta's base snapshot is not here (never arrived, or no longer kept);
 * - `'unloadable'` — the state did not load into the game (the game refused its bytes).
 */
export type ResyncReason = 'bad-delta' | 'hash-mismatch' | 'no-base' | 'unloadable';
const RESYNC_REASONS = ['bad-delta', 'hash-mismatch', 'no-base', 'unloadable'] as const;

/** The bound of a snapshot's `slack` (ticks either way). */
export const MAX_SLACK = 255;

/**
 * How a snapshot's payload is coded:
 * - `'bytes'` — the game's `save()` bytes, whole or as XOR runs against the base (`delta.ts`);
 * - `'schema'` — the game's state schema's words (`StateSchema.quantise`), as bits against the
 *   base's words, or against nothing for a full one (`schema-codec.ts`).
 */
export type SnapshotCodec = 'bytes' | 'schema';
const SNAPSHOT_CODECS = ['bytes', 'schema'] as const;

// ------------------------------------------------------------------------------------ messages

/** Client → server, first message: join (or create) a room. Repeated until welcomed. See {@link JoinFields}. */
export interface JoinMessage extends JoinFields {
  type: 'join';
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
  /**
   * The room's invite token (players; empty for spectators): a spectator's join must carry it.
   * Hand it only to people you invite.
   */
  invite: Uint8Array;
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
   * A snapshot older than `base` that the client holds too (schema codec: columns that
   * `extrapolate` are predicted from it and the base); -1: none.
   */
  older: number;
  /**
   * When it was sent, in whole microseconds after the tick's time `startAt + tick × step` on the
   * server clock (the server steps a tick when its time has come, then sends at once).
   */
  sendDelayUs: number;
  /** The next tick the server needs an input from you for (at least `tick`; `tick` for spectators). */
  inputAck: number;
  /** How many of your ticks the server stepped without your input (filled by the missing rule). */
  filled: number;
  /** Of those, how many inputs came later (late: dropped). */
  late: number;
  /**
   * The fewest ticks by which your inputs that arrived since your previous snapshot came before
   * their tick was stepped (negative: late by that many), within ±{@link MAX_SLACK};
   * {@link MAX_SLACK} when none arrived.
   */
  slack: number;
  /** How `payload` is coded. */
  codec: SnapshotCodec;
  /** Byte length of the state (`'schema'`: of its words, 4 bytes each). */
  size: number;
  /** FNV-1a 64 of the state's bytes (`'schema'`: of its words): the client checks what it rebuilt against it. */
  hash: bigint;
  /**
   * `'bytes'`: the state's bytes (full), or the delta's runs (see `encodeDelta`); `'schema'`: the
   * bits of `encodeSchemaDelta`.
   */
  payload: Uint8Array;
}

/** Any state-sync message. */
export type StateSyncMessage =
  | JoinMessage
  | StateInputMessage
  | StateAckMessage
  | PingMessage
  | ResyncMessage
  | StateLeaveMessage
  | StateWelcomeMessage
  | StateSnapshotMessage
  | PongMessage
  | ErrorMessage;

/** The name of a state-sync message type. */
export type StateSyncKind = StateSyncMessage['type'];

// ------------------------------------------------------------------------------------ declaration

/**
 * A tick before the message's `tick`, carried as the distance back (one byte however long the
 * match); -1 (none: a full snapshot) as 0.
 */
function tickBefore(): Field<number> {
  return {
    kind: 'varint ticks back (0: none)',
    minBytes: 1,
    maxBytes: () => 5,
    problem: (v, m) =>
      typeof v === 'number' && Number.isInteger(v) && v >= -1 && v < (m.tick as number)
        ? undefined
        : `${String(v)} is not -1 or a tick before ${String(m.tick)}`,
    write: (w, v, m) => void w.varint(v < 0 ? 0 : (m.tick as number) - v),
    read(r, m) {
      const at = r.pos;
      const back = r.varint(r.fieldName);
      if (back > (m.tick as number))
        r.fail('invalid', `${back} ticks before tick ${String(m.tick)}`, at);
      return back === 0 ? -1 : (m.tick as number) - back;
    },
    sample: (rng, m) =>
      (m.tick as number) === 0 || rng.int(2) === 0 ? -1 : (m.tick as number) - 1,
  };
}

/** The state-sync protocol: encode, decode, sizes (see `net/wire`). */
export const STATE_SYNC_PROTOCOL = defineProtocol<StateSyncMessage, StateSyncLimits>({
  name: 'state sync',
  family: 0x80,
  version: STATE_SYNC_VERSION,
  limits: DEFAULT_STATE_SYNC_LIMITS,
  messages: {
    join: { code: 0x01, from: 'client', fields: joinFields('maxPlayers') },
    input: {
      code: 0x02,
      from: 'client',
      fields: {
        player: uint({ max: 'maxPlayers' }),
        ack: uint({ min: -1 }),
        tick: uint(),
        ...inputRunFields(),
      },
      check: checkInputRun,
    },
    ack: { code: 0x03, from: 'client', fields: { ack: uint({ min: -1 }) } },
    ping: { code: 0x04, from: 'client', fields: PING_FIELDS },
    resync: { code: 0x05, from: 'client', fields: { reason: oneOf(RESYNC_REASONS) } },
    leave: { code: 0x06, from: 'client', fields: {} },
    welcome: {
      code: 0x11,
      from: 'server',
      fields: {
        slot: uint({ min: -1 }),
        players: uint({ min: 1, max: 'maxPlayers' }),
        seed: u32(),
        tickRate: uint({ min: 1, max: 100_000 }),
        snapshotEvery: uint({ min: 1, max: 1 << 16 }),
        startAt: time(),
        inputFrom: uint(),
        config: bytes({ max: 'maxConfigBytes' }),
        token: tokenField(),
        invite: tokenField(),
      },
      check: (m) =>
        m.slot < m.players ? undefined : ['slot', `${m.slot} of ${m.players} players`],
    },
    snapshot: {
      code: 0x12,
      from: 'server',
      fields: {
        tick: uint(),
        base: tickBefore(),
        older: tickBefore(),
        sendDelayUs: uint(),
        inputAck: uint({ base: (m) => m.tick as number }),
        filled: uint(),
        late: uint(),
        slack: uint({ min: -MAX_SLACK, max: MAX_SLACK }),
        codec: oneOf(SNAPSHOT_CODECS),
        size: uint({ max: 'maxStateBytes' }),
        hash: u64(),
        // A delta may be a little longer than the state it codes.
        payload: bytes({ max: (l) => l.maxStateBytes! + 16 }),
      },
      check: (m) =>
        m.older >= 0 && !(m.older < m.base)
          ? ['older', `${m.older} is not a tick before the base ${m.base}`]
          : m.codec === 'bytes' && m.base < 0 && m.payload.length !== m.size
            ? ['payload', `a full snapshot of ${m.payload.length} bytes says ${m.size}`]
            : m.codec === 'schema' && m.size % 4 !== 0
              ? ['size', `${m.size} bytes of schema words is not a whole number of words`]
              : undefined,
    },
    pong: { code: 0x13, from: 'server', fields: PONG_FIELDS },
    error: { code: 0x14, from: 'server', fields: ERROR_FIELDS },
  },
});

/** The bytes of a state-sync message (a RangeError for one that breaks the protocol: a sender bug). */
export function encodeStateSyncMessage(m: StateSyncMessage): Uint8Array {
  return STATE_SYNC_PROTOCOL.encode(m);
}

/**
 * Decodes one state-sync message. Throws a {@link ProtocolError} — and nothing else — for any
 * bytes that are not exactly one valid message within `limits`.
 */
export function decodeStateSyncMessage(
  bytes: Uint8Array,
  limits: Readonly<StateSyncLimits> = DEFAULT_STATE_SYNC_LIMITS,
): StateSyncMessage {
  return STATE_SYNC_PROTOCOL.decode(bytes, { limits });
}

/** The message type of `bytes` without decoding the rest (undefined: not a state-sync message). */
export function peekStateSyncType(bytes: Uint8Array): StateSyncKind | undefined {
  return STATE_SYNC_PROTOCOL.peek(bytes);
}
