/**
 * Quick match: the messages of the server's matchmaking endpoint (`/match` on `fixedstep serve`)
 * and a client, {@link quickMatch}, that waits in its queue until enough compatible players are
 * found and resolves with the relay room they were given.
 *
 * The messages are JSON text frames, not the relay's binary protocol: a client sends one request
 * and gets one answer per match, never per tick, so readability costs nothing here. They are still
 * bounded — at most {@link MAX_MATCH_MESSAGE_BYTES} bytes, every field checked, unknown fields
 * refused — and a frame that breaks a rule is answered with a {@link MatchmakingError} naming it.
 * Client and server decode with the same functions, so the two cannot drift apart.
 * @module
 */
import { NAME_PATTERN } from './protocol.js';

/** Largest matchmaking message, in UTF-8 bytes (either direction). Larger frames are refused. */
export const MAX_MATCH_MESSAGE_BYTES = 512;

/** Most players a quick match may ask for (the relay's default room limit). */
export const MAX_MATCH_PLAYERS = 16;

/** Longest wait a client may ask for, in ms (10 minutes); a server may cap it lower. */
export const MAX_MATCH_TIMEOUT_MS = 600_000;

/** Why a matchmaking request was refused (the `code` of an `error` message). */
export type MatchErrorCode =
  /** Not a well-formed message (the text says which field). */
  | 'BAD_MESSAGE'
  /** The server offers no game of that id. */
  | 'UNKNOWN_GAME'
  /** The server plays another version or input schema of the game. */
  | 'GAME_MISMATCH'
  /** The player range does not fit the game's. */
  | 'BAD_PLAYERS'
  /** The queue holds as many waiting players as it may. */
  | 'QUEUE_FULL'
  /** This client address already has as many waiting players as it may. */
  | 'TOO_MANY_FROM_ADDRESS'
  /** The server is shutting down. */
  | 'SHUTDOWN';

/** Client → server: wait for a match. One per connection. */
export interface MatchQueueRequest {
  /** The message kind. */
  type: 'queue';
  /** Game id (see {@link NAME_PATTERN}). */
  game: string;
  /** Game version: only players of the same version are matched. */
  gameVersion: number;
  /** The input schema's id (`InputSchema.id`, 16 hex digits): only equal ones are matched. */
  input: string;
  /** Fewest players the client will play with (itself included), 1–16. */
  minPlayers: number;
  /** Most players the client will play with, `minPlayers`–16. */
  maxPlayers: number;
  /** How long to wait, in ms, before the server answers `no-match` (1 to 600 000). */
  timeoutMs: number;
}

/** Client → server: stop waiting (closing the connection does the same). */
export interface MatchCancelRequest {
  /** The message kind. */
  type: 'cancel';
}

/** A message a matchmaking client sends. */
export type MatchClientMessage = MatchQueueRequest | MatchCancelRequest;

/** Server → client: the request is in the queue; `timeoutMs` is the wait the server granted. */
export interface MatchQueuedMessage {
  /** The message kind. */
  type: 'queued';
  /** The wait granted, in ms (the request's, or the server's cap if lower). */
  timeoutMs: number;
}

/**
 * Server → client: a match. Connect to the relay's room `room` (e.g. `/ws/<room>`) as a player of
 * a `players`-player room. `order` (0 to `players` − 1) is the client's place in the match, the
 * same on no two clients (the first to have queued is 0) — e.g. to pick who names the seed. The
 * room name is random (18 bytes from a cryptographic source): knowing it is what lets one in.
 */
export interface MatchFoundMessage {
  /** The message kind. */
  type: 'matched';
  /** The relay room to join (see {@link NAME_PATTERN}). */
  room: string;
  /** Player slots of the room (the hello's `players`). */
  players: number;
  /** This client's place, 0 to `players` − 1. */
  order: number;
}

/** Server → client: nobody compatible came within the wait. */
export interface MatchNoneMessage {
  /** The message kind. */
  type: 'no-match';
}

/** Server → client: the request was cancelled, as asked. */
export interface MatchCancelledMessage {
  /** The message kind. */
  type: 'cancelled';
}

/** Server → client: the request was refused; the server closes the connection after it. */
export interface MatchErrorMessage {
  /** The message kind. */
  type: 'error';
  /** Why, as a code. */
  code: MatchErrorCode;
  /** Why, in words: names the field, value or cap. */
  message: string;
}

/** A message the matchmaking server sends. Each but `queued` is the last on its connection. */
export type MatchServerMessage =
  | MatchQueuedMessage
  | MatchFoundMessage
  | MatchNoneMessage
  | MatchCancelledMessage
  | MatchErrorMessage;

/** A refused or failed matchmaking request; `code` says why (see {@link MatchErrorCode}). */
export class MatchmakingError extends Error {
  /** Why; `NO_MATCH` when the wait ended without one, `CONNECTION` when the socket failed. */
  readonly code: MatchErrorCode | 'NO_MATCH' | 'CONNECTION';
  /** An error with a code and a message naming what was wrong. */
  constructor(code: MatchErrorCode | 'NO_MATCH' | 'CONNECTION', message: string) {
    super(message);
    this.name = 'MatchmakingError';
    this.code = code;
  }
}

/** Encodes a matchmaking message as one JSON text frame. */
export function encodeMatchMessage(message: MatchClientMessage | MatchServerMessage): string {
  return JSON.stringify(message);
}

const ERROR_CODES: readonly MatchErrorCode[] = [
  'BAD_MESSAGE',
  'UNKNOWN_GAME',
  'GAME_MISMATCH',
  'BAD_PLAYERS',
  'QUEUE_FULL',
  'TOO_MANY_FROM_ADDRESS',
  'SHUTDOWN',
];

function bad(message: string): MatchmakingError {
  return new MatchmakingError('BAD_MESSAGE', message);
}

/** Parses one frame into an object with a string `type` and only the `allowed` fields. */
function parseObject(text: string): Record<string, unknown> & { type: string } {
  if (typeof text !== 'string') throw bad('a matchmaking message is a JSON text frame');
  // A UTF-16 unit is at most 3 UTF-8 bytes: measure exactly only when it could be too long.
  if (
    text.length > MAX_MATCH_MESSAGE_BYTES &&
    (text.length > MAX_MATCH_MESSAGE_BYTES * 3 ||
      new TextEncoder().encode(text).length > MAX_MATCH_MESSAGE_BYTES)
  ) {
    throw bad(`a matchmaking message is at most ${MAX_MATCH_MESSAGE_BYTES} bytes`);
  }
  let value: unknown;
  try {
    value = JSON.parse(text);
  } catch {
    throw bad('a matchmaking message is JSON; this frame is not');
  }
  if (typeof value !== 'object' || value === null || Array.isArray(value)) {
    throw bad('a matchmaking message is a JSON object');
  }
  const object = value as Record<string, unknown>;
  const type = object.type;
  if (typeof type !== 'string') throw bad('a matchmaking message has a string "type"');
  return { ...object, type };
}

function onlyFields(object: Record<string, unknown>, fields: readonly string[]): void {
  for (const key of Object.keys(object)) {
    if (key !== 'type' && !fields.includes(key)) {
      throw bad(`a "${String(object.type)}" message has no field "${key.slice(0, 32)}"`);
    }
  }
}

function integer(object: Record<string, unknown>, key: string, min: number, max: number): number {
  const v = object[key];
  if (typeof v !== 'number' || !Number.isInteger(v) || v < min || v > max) {
    const shown = typeof v === 'string' ? JSON.stringify(v.slice(0, 32)) : String(v);
    throw bad(`"${key}" must be an integer from ${min} to ${max}, got ${shown}`);
  }
  return v;
}

function pattern(object: Record<string, unknown>, key: string, re: RegExp, what: string): string {
  const v = object[key];
  if (typeof v !== 'string' || !re.test(v)) {
    const shown = typeof v === 'string' ? JSON.stringify(v.slice(0, 40)) : String(v);
    throw bad(`"${key}" must be ${what}, got ${shown}`);
  }
  return v;
}

const INPUT_ID = /^[0-9a-f]{16}$/;
const ROOM_TEXT = 'a name of 1-32 of A-Z a-z 0-9 _ - .';

/**
 * Decodes a client's frame (what the server does with each one). Throws a
 * {@link MatchmakingError} `BAD_MESSAGE` naming the field for anything else: too long, not JSON,
 * an unknown type or field, a value out of range, `minPlayers` above `maxPlayers`.
 */
export function decodeMatchClientMessage(text: string): MatchClientMessage {
  const o = parseObject(text);
  if (o.type === 'cancel') {
    onlyFields(o, []);
    return { type: 'cancel' };
  }
  if (o.type !== 'queue') {
    throw bad(`unknown message type ${JSON.stringify(o.type.slice(0, 32))}`);
  }
  onlyFields(o, ['game', 'gameVersion', 'input', 'minPlayers', 'maxPlayers', 'timeoutMs']);
  const m: MatchQueueRequest = {
    type: 'queue',
    game: pattern(o, 'game', NAME_PATTERN, ROOM_TEXT),
    gameVersion: integer(o, 'gameVersion', 0, 0x7fffffff),
    input: pattern(o, 'input', INPUT_ID, '16 lower-case hex digits (InputSchema.id)'),
    minPlayers: integer(o, 'minPlayers', 1, MAX_MATCH_PLAYERS),
    maxPlayers: integer(o, 'maxPlayers', 1, MAX_MATCH_PLAYERS),
    timeoutMs: integer(o, 'timeoutMs', 1, MAX_MATCH_TIMEOUT_MS),
  };
  if (m.minPlayers > m.maxPlayers) {
    throw bad(`minPlayers (${m.minPlayers}) is above maxPlayers (${m.maxPlayers})`);
  }
  return m;
}

/**
 * Decodes a server's frame (what {@link quickMatch} does). Throws a {@link MatchmakingError}
 * `BAD_MESSAGE` for anything that is not one of {@link MatchServerMessage}.
 */
export function decodeMatchServerMessage(text: string): MatchServerMessage {
  const o = parseObject(text);
  switch (o.type) {
    case 'queued':
      onlyFields(o, ['timeoutMs']);
      return { type: 'queued', timeoutMs: integer(o, 'timeoutMs', 1, MAX_MATCH_TIMEOUT_MS) };
    case 'matched': {
      onlyFields(o, ['room', 'players', 'order']);
      const players = integer(o, 'players', 1, MAX_MATCH_PLAYERS);
      return {
        type: 'matched',
        room: pattern(o, 'room', NAME_PATTERN, ROOM_TEXT),
        players,
        order: integer(o, 'order', 0, players - 1),
      };
    }
    case 'no-match':
    case 'cancelled':
      onlyFields(o, []);
      return { type: o.type };
    case 'error': {
      onlyFields(o, ['code', 'message']);
      const code = o.code;
      if (typeof code !== 'string' || !(ERROR_CODES as readonly string[]).includes(code)) {
        throw bad(`unknown error code ${JSON.stringify(code)}`);
      }
      if (typeof o.message !== 'string') throw bad('an error message has a string "message"');
      return { type: 'error', code: code as MatchErrorCode, message: o.message };
    }
    default:
      throw bad(`unknown message type ${JSON.stringify(o.type.slice(0, 32))}`);
  }
}

/** Options of {@link quickMatch}. */
export interface QuickMatchOptions {
  /** The matchmaking endpoint, e.g. `ws://localhost:8080/match` (`wss:` behind TLS). */
  url: string;
  /** Game id, as in the relay's hello. */
  game: string;
  /** Game version: only players of the same version are matched. */
  gameVersion: number;
  /** The game's input schema (only its `id` is sent): only equal schemas are matched. */
  input: { readonly id: string };
  /** Fewest players to play with, this client included. */
  minPlayers: number;
  /** Most players to play with. Default `minPlayers`. */
  maxPlayers?: number;
  /** How long to wait for a match, in ms (the server may grant less). Default 30 000. */
  timeoutMs?: number;
  /** Aborting it cancels the wait: the promise rejects with the signal's reason. */
  signal?: AbortSignal;
  /** The WebSocket class. Default the global one (browsers, Node 22+; in Node 20 pass `ws`'s). */
  WebSocketClass?: new (url: string) => WebSocket;
  /** Called once the server has queued the request, with the wait it granted (ms). */
  onQueued?: (timeoutMs: number) => void;
}

/** A match found by {@link quickMatch}: join the relay's room `room` as a player. */
export interface QuickMatchResult {
  /** The relay room to join (random, unguessable; connect to `/ws/<room>`). */
  room: string;
  /** Player slots of the room: send it as the hello's `players`. */
  players: number;
  /** This client's place in the match, 0 to `players` − 1 (0 queued first). */
  order: number;
}

/**
 * Waits in the server's quick-match queue for `minPlayers`–`maxPlayers` players of the same game,
 * version and input schema, and resolves with the room they were all given. Rejects with a
 * {@link MatchmakingError}: `NO_MATCH` when the wait ends without one, the server's code when it
 * refuses the request, `CONNECTION` when the socket fails; with `signal.reason` when aborted (the
 * server is told to cancel). Touches no simulation state: what happens here is not part of the
 * deterministic match, which starts when the players join the room.
 */
export function quickMatch(options: QuickMatchOptions): Promise<QuickMatchResult> {
  const maxPlayers = options.maxPlayers ?? options.minPlayers;
  const request: MatchQueueRequest = {
    type: 'queue',
    game: options.game,
    gameVersion: options.gameVersion,
    input: options.input.id,
    minPlayers: options.minPlayers,
    maxPlayers,
    timeoutMs: options.timeoutMs ?? 30_000,
  };
  try {
    // Refuse bad arguments here, with the same words the server would use.
    decodeMatchClientMessage(encodeMatchMessage(request));
  } catch (error) {
    return Promise.reject(error instanceof Error ? error : new Error(String(error)));
  }
  const signal = options.signal;
  if (signal?.aborted) return Promise.reject(signal.reason as Error);
  const Ctor = options.WebSocketClass ?? globalThis.WebSocket;
  if (typeof Ctor !== 'function') {
    return Promise.reject(
      new TypeError('quickMatch: no WebSocket here (in Node 20 pass WebSocketClass from "ws")'),
    );
  }
  return new Promise<QuickMatchResult>((resolve, reject) => {
    const ws = new Ctor(options.url);
    let settled = false;
    // A server that never answers must not hold the promise forever.
    const timer = setTimeout(() => {
      finish(new MatchmakingError('NO_MATCH', `no answer from ${options.url} within the wait`));
    }, request.timeoutMs + 15_000);
    const onAbort = () => {
      if (ws.readyState === 1) ws.send(encodeMatchMessage({ type: 'cancel' }));
      finish(signal?.reason as Error);
    };
    function finish(outcome: QuickMatchResult | Error): void {
      if (settled) return;
      settled = true;
      clearTimeout(timer);
      signal?.removeEventListener('abort', onAbort);
      try {
        ws.close(1000);
      } catch {
        // already closing
      }
      if (outcome instanceof Error) reject(outcome);
      else resolve(outcome);
    }
    signal?.addEventListener('abort', onAbort);
    ws.addEventListener('open', () => {
      ws.send(encodeMatchMessage(request));
    });
    ws.addEventListener('message', (event: MessageEvent<unknown>) => {
      let m: MatchServerMessage;
      try {
        if (typeof event.data !== 'string') throw bad('the server sent a binary frame');
        m = decodeMatchServerMessage(event.data);
      } catch (error) {
        finish(error as Error);
        return;
      }
      if (m.type === 'queued') options.onQueued?.(m.timeoutMs);
      else if (m.type === 'matched') finish({ room: m.room, players: m.players, order: m.order });
      else if (m.type === 'no-match') {
        finish(new MatchmakingError('NO_MATCH', `no match within ${request.timeoutMs} ms`));
      } else if (m.type === 'cancelled') {
        finish(new MatchmakingError('NO_MATCH', 'the server cancelled the request'));
      } else finish(new MatchmakingError(m.code, m.message));
    });
    ws.addEventListener('close', (event: CloseEvent) => {
      finish(
        new MatchmakingError(
          'CONNECTION',
          `the matchmaking connection closed (${event.code}${event.reason ? `: ${event.reason}` : ''})`,
        ),
      );
    });
    ws.addEventListener('error', () => {
      finish(new MatchmakingError('CONNECTION', `cannot reach ${options.url}`));
    });
  });
}
