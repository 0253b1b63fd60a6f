/**
 * What every protocol shares: the one list of refusal codes, and the fields of the messages that
 * mean the same in each (joining a room, an error, a clock probe).
 * @module
 */
import type { ProtocolError } from './error.js';
import {
  bytes,
  flag,
  hex64,
  inputs,
  name,
  oneOf,
  optional,
  text,
  time,
  u32,
  uint,
  type Field,
} from './fields.js';

/** Reconnect, invite and match tokens are exactly this long. */
export const TOKEN_BYTES = 16;
/** Longest player name, in UTF-8 bytes. */
export const MAX_PLAYER_NAME_BYTES = 32;
/** Longest error text, in UTF-8 bytes. */
export const MAX_ERROR_TEXT_BYTES = 200;
/** Longest quick-match ticket, in bytes (see the server's match tickets). */
export const MAX_TICKET_BYTES = 192;

/**
 * Why a server refused something or closed a connection — one list for every protocol (the
 * `error` message's code). Appended to, never reordered: a code's byte keeps its meaning.
 */
export const NET_ERROR_CODES = [
  /** Bytes that do not decode (the text names the field). */
  'BAD_MESSAGE',
  /** A message, or a count in it, above a limit. */
  'TOO_LARGE',
  /** More messages or bytes a second than a connection may send. */
  'RATE_LIMIT',
  /** A room message before joining one. */
  'NOT_IN_ROOM',
  /** A message for another room than the connection's (its URL names the room). */
  'WRONG_ROOM',
  /** Inputs or a leave for another player. */
  'SPOOFED_PLAYER',
  /** Inputs, acks or hashes for ticks outside the window the server takes. */
  'TICK_WINDOW',
  /** Every player slot (or spectator seat) of the room is taken, or held for its owner. */
  'ROOM_FULL',
  /** The server offers no game of that id. */
  'UNKNOWN_GAME',
  /** The server plays another version or input schema of the game. */
  'GAME_MISMATCH',
  /** A join that cannot be honoured (a player count outside the game's, a spectator with no room …). */
  'BAD_HELLO',
  /** A reconnect, invite or match token that is not this room's. */
  'BAD_TOKEN',
  /** No member could send a late joiner the room's state. */
  'NO_SNAPSHOT',
  /** Too long without a message (a hello, a join, any sign of life). */
  'TIMEOUT',
  /** The server holds as many rooms or connections as it may. */
  'SERVER_FULL',
  /** A message the server does not expect now. */
  'UNEXPECTED',
  /** A bug on the server: this connection is closed, the others go on. */
  'INTERNAL',
  /** The server is shutting down: try another. */
  'SHUTDOWN',
  /** An input outside the game's input schema. */
  'BAD_INPUT',
  /** Another protocol version: reload the page or update fixedstep. */
  'BAD_VERSION',
  /** Signalling: the room already has a host. */
  'ROOM_TAKEN',
  /** Signalling: no room of that name (its host has not arrived or has left). */
  'NO_ROOM',
  /** Signalling: no peer of that id in the room. */
  'NO_PEER',
  /** Quick match: a player range outside the game's. */
  'BAD_PLAYERS',
  /** Quick match: the queue holds as many players as it may. */
  'QUEUE_FULL',
  /** This client address holds its share of rooms, connections or tickets already. */
  'ADDRESS_LIMIT',
  /** The room was closed to make room: nobody had played in it for a while. */
  'IDLE',
  /** Quick match: the match was not accepted in time. */
  'NO_SHOW',
] as const;

/** One of {@link NET_ERROR_CODES}. */
export type NetErrorCode = (typeof NET_ERROR_CODES)[number];

/**
 * The code a server answers undecodable bytes with: `TOO_LARGE`; `BAD_VERSION` for another version
 * of its own protocol (an older client: reload the page or update); `BAD_MESSAGE` for anything
 * else (another protocol's message, noise).
 */
export function refusalCode(error: ProtocolError, bytes: Uint8Array, header: number): NetErrorCode {
  if (error.code === 'TOO_LARGE') return 'TOO_LARGE';
  const ownFamily = bytes.length > 0 && (bytes[0]! & 0xe0) === (header & 0xe0);
  return error.code === 'BAD_VERSION' && ownFamily ? 'BAD_VERSION' : 'BAD_MESSAGE';
}

/** Why a member left a room (a relay `leave` message's reason). */
export const LEAVE_REASONS = ['left', 'closed', 'dropped', 'timeout', 'replaced'] as const;
/** One of {@link LEAVE_REASONS}: on its own, its connection closed, dropped, silent, or replaced by a reconnect. */
export type LeaveReason = (typeof LEAVE_REASONS)[number];

/** Server → client: something was refused; `fatal` means the connection is being closed. */
export interface ErrorMessage {
  type: 'error';
  code: NetErrorCode;
  /** The connection is being closed. */
  fatal: boolean;
  /** Why, in words (at most 200 UTF-8 bytes; longer ones are cut, control characters blanked). */
  message: string;
}

/** The fields of every protocol's `error` message. */
export const ERROR_FIELDS = {
  code: oneOf(NET_ERROR_CODES, 'an error code (NET_ERROR_CODES)'),
  fatal: flag(),
  message: text({ max: MAX_ERROR_TEXT_BYTES, clip: true }),
} satisfies { [K in Exclude<keyof ErrorMessage, 'type'>]: Field<ErrorMessage[K]> };

/** A clock probe; `time` is the sender's clock (ms). */
export interface PingMessage {
  type: 'ping';
  id: number;
  time: number;
}

/** The answer to a ping: the probe's `id` and `time`, with the answering side's clock as `serverTime`. */
export interface PongMessage {
  type: 'pong';
  id: number;
  time: number;
  serverTime: number;
}

/** The fields of a `ping`. */
export const PING_FIELDS = { id: uint(), time: time() } satisfies {
  [K in Exclude<keyof PingMessage, 'type'>]: Field<PingMessage[K]>;
};
/** The fields of a `pong`. */
export const PONG_FIELDS = { id: uint(), time: time(), serverTime: time() } satisfies {
  [K in Exclude<keyof PongMessage, 'type'>]: Field<PongMessage[K]>;
};

/**
 * What a client asks when it joins a room, the same for the relay (its `hello`) and state sync
 * (its `join`): the room core admits it.
 */
export interface JoinFields {
  /** Room name: 1–32 of `A–Z a–z 0–9 _ - .`; the first join creates the room. */
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
  /** Player slots of the room when this join creates it (0: the game's minimum). */
  players: number;
  /** The game's seed when this join creates the room (absent: the server picks one). */
  seed?: number;
  /**
   * Players: a reconnect token from an earlier welcome (take back that slot). Spectators: the
   * room's invite token (`welcome.invite` of one of its players) — required.
   */
  token?: Uint8Array;
  /**
   * A quick-match ticket (`quickMatch`'s result): the room's setup — game, players, seed — and
   * this player's slot come from it, never from whoever connects first.
   */
  ticket?: Uint8Array;
  /** Display name, at most 32 UTF-8 bytes. */
  name: string;
}

/** The fields of a join (the relay's `hello`, state sync's `join`), in wire order. */
export function joinFields(maxPlayers: string): {
  [K in keyof JoinFields]-?: Field<JoinFields[K]>;
} {
  return {
    room: name(),
    role: oneOf(['player', 'spectator'] as const),
    game: name(),
    gameVersion: uint(),
    input: hex64(),
    players: uint({ max: maxPlayers }),
    seed: optional(u32()),
    token: optional(bytes({ max: TOKEN_BYTES, sizes: [TOKEN_BYTES] })),
    ticket: optional(bytes({ max: MAX_TICKET_BYTES })),
    name: text({ max: MAX_PLAYER_NAME_BYTES }),
  };
}

/** A token field of a welcome: empty (none), or {@link TOKEN_BYTES} bytes. */
export function tokenField(): Field<Uint8Array> {
  return bytes({ max: TOKEN_BYTES, sizes: [0, TOKEN_BYTES] });
}

/**
 * A player's run of inputs (the relay's and state sync's `input`): `words` words a tick, one to
 * `maxInputTicks` ticks from `tick`.
 */
export function inputRunFields(): {
  words: Field<number>;
  inputs: Field<Uint32Array>;
} {
  return {
    words: uint({ min: 1, max: 'maxInputWords' }),
    inputs: inputs({
      lanes: (m) => m.words as number,
      words: (m) => m.words as number,
      maxLanes: (l) => l.maxInputWords!,
      rows: [1, 'maxInputTicks'],
    }),
  };
}

/** The rule between an input run's fields: a player the room has, ticks that fit 32 bits. */
export function checkInputRun(
  m: { player: number; tick: number; words: number; inputs: Uint32Array },
  l: { maxPlayers?: number },
): readonly [string, string] | undefined {
  return m.player >= l.maxPlayers!
    ? ['player', `${m.player} of at most ${l.maxPlayers} players`]
    : m.tick + m.inputs.length / m.words - 1 > 0xffffffff
      ? ['tick', 'tick range past 2^32']
      : undefined;
}
