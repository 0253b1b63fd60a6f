/**
 * Quick match, the client: {@link quickMatch} waits in the server's queue (`/match`), accepts the
 * match it proposes, and resolves with the relay room to play in and the ticket that seats this
 * player there.
 * @module
 */
import {
  abortReason,
  type AbortSignalLike,
  type WebSocketClassLike,
  type WebSocketLike,
} from '../platform.js';
import type { NetErrorCode } from '../wire/common.js';
import { ProtocolError } from '../wire/error.js';
import {
  MATCH_PROTOCOL,
  type MatchClientMessage,
  type MatchQueueRequest,
  type MatchServerMessage,
} from './messages.js';

/** Why {@link quickMatch} failed: the server's code, `NO_MATCH` (the wait ended) or `CONNECTION`. */
export type MatchFailure = NetErrorCode | 'NO_MATCH' | 'CONNECTION';

/** A refused or failed quick match; `code` says why (see {@link MatchFailure}). */
export class MatchmakingError extends Error {
  readonly code: MatchFailure;
  /** An error with a code and a message naming what was wrong. */
  constructor(code: MatchFailure, message: string) {
    super(message);
    this.name = 'MatchmakingError';
    this.code = code;
  }
}

function send(ws: WebSocketLike, m: MatchClientMessage): void {
  if (ws.readyState === 1) ws.send(MATCH_PROTOCOL.encode(m));
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
  signal?: AbortSignalLike;
  /** The WebSocket class. Default the global one (browsers, Node 22+; in Node 20 pass `ws`'s). */
  WebSocketClass?: WebSocketClassLike;
  /**
   * Called when the server has queued the request, with the wait it granted (ms) — and again, with
   * the wait left, if a proposed match fell through because another player did not accept.
   */
  onQueued?: (timeoutMs: number) => void;
  /** Called when a match of `players` is proposed; this client accepts it at once. */
  onFound?: (players: number) => void;
}

/**
 * A match found by {@link quickMatch}: join the relay's room `room` (`/ws/<room>`) as a player with
 * `ticket` in the hello (a session's `ticket` option) — the room's setup and this player's slot come
 * from it.
 */
export interface QuickMatchResult {
  /** The relay room to join (random, unguessable). */
  room: string;
  /** Player slots of the room. */
  players: number;
  /** This client's slot, 0 to `players` − 1 (0 queued first). */
  order: number;
  /** The room's seed, as the matchmaker fixed it. */
  seed: number;
  /** The hello's `ticket`: a secret that seats this player in this room. */
  ticket: Uint8Array;
}

/**
 * Waits in the server's quick-match queue for `minPlayers`–`maxPlayers` players of the same game,
 * version and input schema, accepts the match the server proposes (its ready check: a player who
 * does not accept in time is dropped, the others keep their place), and resolves with the room and
 * this player's ticket. Rejects with a {@link MatchmakingError}: `NO_MATCH` when the wait ends
 * without one, the server's code when it refuses the request, `CONNECTION` when the socket fails;
 * with `signal.reason` when aborted (the server is told to cancel). Touches no simulation state:
 * the deterministic match starts when the players join the room.
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
  let frame: Uint8Array;
  try {
    // Refuse bad arguments here, with the words the server would use.
    frame = MATCH_PROTOCOL.encode(request);
  } catch (error) {
    return Promise.reject(
      new MatchmakingError('BAD_MESSAGE', error instanceof Error ? error.message : String(error)),
    );
  }
  const signal = options.signal;
  if (signal?.aborted) return Promise.reject(abortReason(signal));
  const Ctor: WebSocketClassLike | undefined = options.WebSocketClass ?? globalThis.WebSocket;
  if (typeof Ctor !== 'function') {
    return Promise.reject(
      new TypeError('quickMatch: no WebSocket here (in Node 20 pass WebSocketClass from "ws")'),
    );
  }
  return new Promise<QuickMatchResult>((resolve, reject) => {
    const ws = new Ctor(options.url);
    ws.binaryType = 'arraybuffer';
    let settled = false;
    // A server that never answers must not hold the promise forever.
    const timer = setTimeout(() => {
      finish(new MatchmakingError('NO_MATCH', `no answer from ${options.url} within the wait`));
    }, request.timeoutMs + 15_000);
    const onAbort = () => {
      send(ws, { type: 'cancel' });
      finish(abortReason(signal!));
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
      ws.send(frame);
    });
    ws.addEventListener('message', (event) => {
      let m: MatchServerMessage;
      try {
        if (!(event.data instanceof ArrayBuffer)) {
          throw new MatchmakingError('BAD_MESSAGE', 'the server sent a text frame');
        }
        m = MATCH_PROTOCOL.decode(new Uint8Array(event.data), {
          from: 'server',
        }) as MatchServerMessage;
      } catch (error) {
        finish(
          error instanceof ProtocolError
            ? new MatchmakingError('BAD_MESSAGE', error.message)
            : (error as Error),
        );
        return;
      }
      switch (m.type) {
        case 'queued':
          options.onQueued?.(m.timeoutMs);
          break;
        case 'found':
          options.onFound?.(m.players);
          send(ws, { type: 'accept' });
          break;
        case 'matched':
          finish({
            room: m.room,
            players: m.players,
            order: m.order,
            seed: m.seed,
            ticket: m.ticket,
          });
          break;
        case 'no-match':
          finish(new MatchmakingError('NO_MATCH', `no match within ${request.timeoutMs} ms`));
          break;
        case 'cancelled':
          finish(new MatchmakingError('NO_MATCH', 'the server cancelled the request'));
          break;
        case 'error':
          finish(new MatchmakingError(m.code, m.message));
          break;
      }
    });
    ws.addEventListener('close', (event) => {
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
