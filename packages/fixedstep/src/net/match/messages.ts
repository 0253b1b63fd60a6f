/**
 * The quick-match protocol (`/match` on `fixedstep serve`): a client queues for a game, accepts the
 * match the server proposes (a ready check), and gets the relay room to play in and the ticket that
 * seats it there. Declared once (`net/wire`), family 0x60.
 * @module
 */
import { ERROR_FIELDS, MAX_TICKET_BYTES, type ErrorMessage } from '../wire/common.js';
import { bytes, hex64, name, u32, uint } from '../wire/fields.js';
import { defineProtocol } from '../wire/protocol.js';

/** The quick-match protocol's version (byte 0 of every message is 0x60 | this). */
export const MATCH_VERSION = 1;

/** Most players a quick match may ask for (the relay's default room limit). */
export const MAX_MATCH_PLAYERS = 16;

/** Longest wait a client may ask for, in ms (10 minutes); a server may cap it lower. */
export const MAX_MATCH_TIMEOUT_MS = 600_000;

/** Client → server: wait for a match. One per connection. */
export interface MatchQueueRequest {
  type: 'queue';
  /** Game id (1–32 of `A–Z a–z 0–9 _ - .`). */
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

/** Client → server: yes, I play the match just found (the ready check). */
export interface MatchAcceptMessage {
  type: 'accept';
}

/** Client → server: stop waiting (closing the connection does the same). */
export interface MatchCancelRequest {
  type: 'cancel';
}

/** A message a matchmaking client sends. */
export type MatchClientMessage = MatchQueueRequest | MatchAcceptMessage | MatchCancelRequest;

/**
 * Server → client: the request is in the queue; `timeoutMs` is the wait the server granted. Sent
 * again when a match fell through because another player did not accept: back in the queue, in
 * the place it had.
 */
export interface MatchQueuedMessage {
  type: 'queued';
  /** The wait left, in ms (the request's, or the server's cap if lower). */
  timeoutMs: number;
}

/** Server → client: a match of `players` is ready; answer `accept` within `acceptMs` or lose it. */
export interface MatchProposedMessage {
  type: 'found';
  players: number;
  /** Time to accept, in ms. */
  acceptMs: number;
}

/**
 * Server → client: every player accepted. Connect to the relay's room `room` (`/ws/<room>`) with
 * `ticket` in the hello: the room's game, players and seed, and this player's slot, come from the
 * ticket, so nobody else can set the room up first. `order` (0 to `players` − 1) is this player's
 * slot, the first to have queued 0. The room name and the ticket are random: knowing them is what
 * lets one in.
 */
export interface MatchFoundMessage {
  type: 'matched';
  /** The relay room to join. */
  room: string;
  /** Player slots of the room. */
  players: number;
  /** This client's slot, 0 to `players` − 1. */
  order: number;
  /** The room's seed, as the matchmaker fixed it. */
  seed: number;
  /** The hello's `ticket`: it seats this player, in this room, with this setup. */
  ticket: Uint8Array;
}

/** Server → client: nobody compatible came within the wait. */
export interface MatchNoneMessage {
  type: 'no-match';
}

/** Server → client: the request was cancelled, as asked. */
export interface MatchCancelledMessage {
  type: 'cancelled';
}

/** A message the matchmaking server sends. `queued` and `found` may come again; the others end it. */
export type MatchServerMessage =
  | MatchQueuedMessage
  | MatchProposedMessage
  | MatchFoundMessage
  | MatchNoneMessage
  | MatchCancelledMessage
  | ErrorMessage;

/** Any quick-match message. */
export type MatchMessage = MatchClientMessage | MatchServerMessage;

/** The quick-match protocol: encode, decode, sizes (see `net/wire`). */
export const MATCH_PROTOCOL = defineProtocol<MatchMessage, Record<string, number>>({
  name: 'quick match',
  family: 0x60,
  version: MATCH_VERSION,
  limits: {},
  messages: {
    queue: {
      code: 0x01,
      from: 'client',
      fields: {
        game: name(),
        gameVersion: uint({ max: 0x7fffffff }),
        input: hex64(),
        minPlayers: uint({ min: 1, max: MAX_MATCH_PLAYERS }),
        maxPlayers: uint({ min: 1, max: MAX_MATCH_PLAYERS }),
        timeoutMs: uint({ min: 1, max: MAX_MATCH_TIMEOUT_MS }),
      },
      check: (m) =>
        m.minPlayers > m.maxPlayers
          ? ['minPlayers', `${m.minPlayers} is above maxPlayers (${m.maxPlayers})`]
          : undefined,
    },
    accept: { code: 0x02, from: 'client', fields: {} },
    cancel: { code: 0x03, from: 'client', fields: {} },
    queued: {
      code: 0x11,
      from: 'server',
      fields: { timeoutMs: uint({ max: MAX_MATCH_TIMEOUT_MS }) },
    },
    found: {
      code: 0x12,
      from: 'server',
      fields: { players: uint({ min: 1, max: MAX_MATCH_PLAYERS }), acceptMs: uint({ min: 1 }) },
    },
    matched: {
      code: 0x13,
      from: 'server',
      fields: {
        room: name(),
        players: uint({ min: 1, max: MAX_MATCH_PLAYERS }),
        order: uint({ max: MAX_MATCH_PLAYERS - 1 }),
        seed: u32(),
        ticket: bytes({ max: MAX_TICKET_BYTES }),
      },
      check: (m) =>
        m.order < m.players ? undefined : ['order', `${m.order} of ${m.players} players`],
    },
    'no-match': { code: 0x14, from: 'server', fields: {} },
    cancelled: { code: 0x15, from: 'server', fields: {} },
    error: { code: 0x16, from: 'server', fields: ERROR_FIELDS },
  },
});
