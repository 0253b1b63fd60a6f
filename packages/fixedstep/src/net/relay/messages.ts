/**
 * The relay protocol (lockstep and rollback through `/ws/<room>`): its messages, declared once.
 * docs/network.md has the table; {@link RELAY_PROTOCOL} encodes and decodes them.
 *
 * Version 6 lets a client send a batch frame too (its messages of one frame — inputs, ack, clock
 * probe, hash — as one datagram), and over a datagram transport both sides send in paced groups
 * of ticks with a bounded redundancy window ({@link INPUT_DATAGRAM_EVERY},
 * {@link CONFIRMED_DATAGRAM_EVERY}, {@link REDUNDANT_TICKS}); the
 * messages themselves are version 5's. Version 5 sends the server's messages to one connection in a flush as one WebSocket frame (a
 * batch frame, type byte 0x1f: each message's length, then its bytes) and tells each connection
 * the room's network rate in its welcome (`sendEvery`: confirmed ticks go out in groups of that
 * many, and a player sends its inputs in groups of that many too). Version 4 declares the messages as data (`net/wire`): one error list with the other protocols,
 * the quick-match ticket in the hello, and `confirmed` as version 3 sent it — no room number, the
 * input ack relative to the message's end, players and words in one varint, the delta flag in the
 * row count — six bytes of header for a tick of held buttons. Version 3 added the input schema's
 * words, the seed and the invite token; clients of older versions are refused with `BAD_VERSION`.
 * @module
 */
import {
  ERROR_FIELDS,
  PING_FIELDS,
  PONG_FIELDS,
  LEAVE_REASONS,
  checkInputRun,
  inputRunFields,
  joinFields,
  tokenField,
  type ErrorMessage,
  type JoinFields,
  type LeaveReason,
  type PingMessage,
  type PongMessage,
} from '../wire/common.js';
import {
  bytes,
  carried,
  flag,
  inputs,
  list,
  oneOf,
  optional,
  packed,
  struct,
  time,
  u32,
  u64,
  u64s,
  uint,
} from '../wire/fields.js';
import { defineProtocol } from '../wire/protocol.js';

/** The relay protocol's version (byte 0 of every message is this, its family being 0x00). */
export const PROTOCOL_VERSION = 6;

/**
 * The type byte of a batch frame: several messages in one frame (the server's since version 5, a
 * client's since version 6).
 */
export const BATCH_TYPE = 0x1f;

/**
 * Over a datagram transport (WebRTC's unreliable channel, a simulated lossy link) a player sends its
 * new inputs in groups of at most this many ticks, and a changed input at once. Each datagram costs
 * ~70 bytes of DTLS, SCTP and TURN headers plus, often, an SCTP acknowledgement of as many bytes
 * back: at a datagram a tick that was 8–12 KB/s a direction for 1–3 KB/s of messages. Inputs cannot
 * wait much longer: the rollback lead sends a tick's input about one one-way trip before the relay
 * needs it, with one or two ticks to spare, and a held input the relay must wait for delays every
 * other player's input of that tick. 2 (30 Hz at 60 Hz): a lost datagram costs two ticks.
 */
export const INPUT_DATAGRAM_EVERY = 2;

/**
 * Over a datagram transport the relay sends confirmed ticks in groups of at most this many, and a
 * tick whose row changed (someone's input changed: what a player must see soon) at once and again
 * with the next tick, so one lost datagram costs a tick, not a group. Unchanged ticks only confirm
 * what the receiver predicted: 4 (15 Hz at 60 Hz) keeps its prediction window (30 ticks) far off.
 */
export const CONFIRMED_DATAGRAM_EVERY = 4;

/**
 * Over a datagram transport, the most ticks a message repeats that were already sent and are not
 * yet acknowledged (the redundancy window), besides the new ones: each tick rides in about
 * `REDUNDANT_TICKS / INPUT_DATAGRAM_EVERY` datagrams before it is only resent when the peer's ack stops
 * moving. 12 ticks (200 ms) outlasts the relay's deadline for a late input (100 ms) past the lead.
 */
export const REDUNDANT_TICKS = 12;

/**
 * The largest batch frame a client sends over a datagram transport: one UDP datagram with the
 * DTLS, SCTP and TURN headers on a 1280-byte path (the data channel's `maxUnreliableBytes`, 1100,
 * less some room). Larger batches go as several frames.
 */
export const MAX_DATAGRAM_BYTES = 1000;

/**
 * Most u32 words of one player's input per tick, on the wire: `confirmed` packs players and words
 * into one varint `(players − 1) × 16 + (words − 1)`.
 */
export const MAX_WIRE_INPUT_WORDS = 16;

/** Size bounds the decoder enforces before allocating anything. */
export interface ProtocolLimits {
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

/** The default {@link ProtocolLimits}. */
export const DEFAULT_PROTOCOL_LIMITS: Readonly<ProtocolLimits> = Object.freeze({
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

// ------------------------------------------------------------------------------------ messages

/** Client → server, first message: join (or create) a room. See {@link JoinFields}. */
export interface HelloMessage extends JoinFields {
  type: 'hello';
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
  /**
   * The room's network rate, as ticks per send: the server sends confirmed ticks in groups of
   * this many (1: every tick as it closes), and a player sends its inputs in groups of this many.
   */
  sendEvery: number;
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

/** Either way: a peer leaves the room (the client about itself; the server about anyone). */
export interface LeaveMessage {
  type: 'leave';
  room: number;
  peer: number;
  reason: LeaveReason;
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

/** Any relay message. */
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

/** The name of a relay message type. */
export type MessageKind = NetMessage['type'];

// ------------------------------------------------------------------------------------ declaration

const rowsOf = (m: { inputs?: unknown; players?: unknown; words?: unknown }): number =>
  (m.inputs as Uint32Array).length / ((m.players as number) * (m.words as number));

/** Most ticks per send of a room's network rate (`sendEvery`): 6, i.e. 10 Hz at 60 Hz. */
export const MAX_SEND_EVERY = 6;

/** The relay protocol: encode, decode, sizes (see `net/wire`). */
export const RELAY_PROTOCOL = defineProtocol<NetMessage, ProtocolLimits>({
  name: 'relay',
  family: 0x00,
  version: PROTOCOL_VERSION,
  limits: DEFAULT_PROTOCOL_LIMITS,
  batch: BATCH_TYPE,
  messages: {
    hello: { code: 0x01, from: 'client', fields: joinFields('maxPlayers') },
    welcome: {
      code: 0x02,
      from: 'server',
      fields: {
        room: uint(),
        peer: uint(),
        slot: uint({ min: -1 }),
        players: uint({ min: 1, max: 'maxPlayers' }),
        seed: u32(),
        tickRate: uint({ min: 1, max: 10_000 }),
        hashEvery: uint({ min: 1, max: 1 << 20 }),
        deadlineMs: uint(),
        sendEvery: uint({ min: 1, max: MAX_SEND_EVERY }),
        inputFrom: uint(),
        startTick: uint(),
        config: bytes({ max: 'maxConfigBytes' }),
        token: tokenField(),
        invite: tokenField(),
        startAt: optional(time()),
        snapshot: optional(bytes({ max: 'maxSnapshotBytes' })),
      },
      check: (m) =>
        m.slot < m.players ? undefined : ['slot', `${m.slot} of ${m.players} players`],
    },
    start: { code: 0x03, from: 'server', fields: { room: uint(), startAt: time() } },
    input: {
      code: 0x04,
      from: 'client',
      fields: {
        room: uint(),
        player: uint({ max: 'maxPlayers' }),
        ack: uint(),
        tick: uint(),
        ...inputRunFields(),
      },
      check: checkInputRun,
    },
    confirmed: {
      code: 0x05,
      from: 'server',
      fields: {
        tick: uint(),
        players: packed('players', [
          ['words', 1, MAX_WIRE_INPUT_WORDS],
          ['players', 1, 'maxPlayers'],
        ]),
        words: carried(),
        inputs: inputs({
          lanes: (m) => (m.players as number) * (m.words as number),
          words: (m) => m.words as number,
          maxLanes: (l) => l.maxPlayers! * Math.min(MAX_WIRE_INPUT_WORDS, l.maxInputWords!),
          rows: [0, 'maxConfirmedTicks'],
          flag: 'delta',
        }),
        delta: carried(),
        // The next tick the server needs from you, as the distance past this message's end.
        inputAck: uint({ base: (m) => (m.tick as number) + rowsOf(m) }),
      },
      check: (m, l) =>
        m.words > l.maxInputWords!
          ? ['words', `${m.words}, at most ${l.maxInputWords}`]
          : undefined,
    },
    ack: { code: 0x06, from: 'client', fields: { room: uint(), ack: uint() } },
    hash: { code: 0x07, from: 'client', fields: { room: uint(), tick: uint(), hash: u64() } },
    desync: {
      code: 0x08,
      from: 'server',
      fields: {
        room: uint(),
        tick: uint(),
        exact: flag(),
        reportTick: uint(),
        majority: uint({ min: -1 }),
        groups: list(struct({ hash: u64(), peers: list(uint(), { max: 'maxPeers' }) }), {
          min: 1,
          max: 'maxGroups',
        }),
      },
      check: (m, l) => {
        if (m.majority >= m.groups.length) {
          return ['majority', `${m.majority} of ${m.groups.length} groups`];
        }
        const peers = m.groups.reduce((n, g) => n + g.peers.length, 0);
        return peers > l.maxPeers!
          ? ['groups', `${peers} peers, at most ${l.maxPeers}`]
          : undefined;
      },
    },
    ping: { code: 0x09, from: 'both', fields: PING_FIELDS },
    pong: { code: 0x0a, from: 'both', fields: PONG_FIELDS },
    leave: {
      code: 0x0b,
      from: 'both',
      fields: { room: uint(), peer: uint(), reason: oneOf(LEAVE_REASONS) },
    },
    error: { code: 0x0c, from: 'server', fields: ERROR_FIELDS },
    'snapshot-request': {
      code: 0x0d,
      from: 'server',
      fields: { room: uint(), id: uint(), tick: uint({ min: -1 }) },
    },
    snapshot: {
      code: 0x0e,
      from: 'client',
      fields: { room: uint(), id: uint(), tick: uint(), bytes: bytes({ max: 'maxSnapshotBytes' }) },
    },
    'hashes-request': {
      code: 0x0f,
      from: 'server',
      fields: { room: uint(), id: uint(), from: uint(), count: uint({ min: 1, max: 'maxHashes' }) },
    },
    hashes: {
      code: 0x10,
      from: 'client',
      fields: { room: uint(), id: uint(), from: uint(), hashes: u64s({ max: 'maxHashes' }) },
    },
  },
});

/** The bytes of a relay message (a RangeError for one that breaks the protocol: a sender bug). */
export function encodeMessage(m: NetMessage): Uint8Array {
  return RELAY_PROTOCOL.encode(m);
}

/**
 * Decodes one relay message. Throws a {@link ProtocolError} — and nothing else — for any bytes
 * that are not exactly one valid message within `limits`.
 */
export function decodeMessage(
  bytes: Uint8Array,
  limits: Readonly<ProtocolLimits> = DEFAULT_PROTOCOL_LIMITS,
): NetMessage {
  return RELAY_PROTOCOL.decode(bytes, { limits });
}

/**
 * Decodes one WebSocket frame of the server's: one message, or a batch frame's messages (protocol
 * 5 on: see `WireProtocol.split`). Throws a {@link ProtocolError} as {@link decodeMessage} does.
 */
export function decodeFrame(
  frame: Uint8Array,
  limits: Readonly<ProtocolLimits> = DEFAULT_PROTOCOL_LIMITS,
): NetMessage[] {
  return RELAY_PROTOCOL.split(frame).map((b) => decodeMessage(b, limits));
}

/** The message type of `bytes` without decoding the rest (undefined when unknown or too short). */
export function peekMessageType(bytes: Uint8Array): MessageKind | undefined {
  return RELAY_PROTOCOL.peek(bytes);
}
