/**
 * What every networked session shares: its phases, its events, and the error that ends it —
 * reported once as an `error` event and once as the rejection of its `finished` promise.
 * @module
 */
import type { ErrorMessage, NetErrorCode } from '../wire/common.js';

/**
 * Where a networked session is (lockstep, rollback, spectator and state-sync sessions alike):
 * - `'connecting'` — its join (hello) is sent, repeated until the server answers;
 * - `'waiting'` — welcomed: it holds the room's setup and waits for the match to start (relay)
 *   or for the first snapshot (state sync);
 * - `'running'` — it steps (or predicts) ticks;
 * - `'closed'` — its transport closed, from either end: it does nothing more.
 *
 * Reaching its end is no phase: see the session's `finished` promise and `isFinished`.
 */
export type SessionPhase = 'connecting' | 'waiting' | 'running' | 'closed';

/**
 * Why a session failed: a code the server sent (its {@link NetErrorCode}: `WRONG_ROOM`,
 * `BAD_TOKEN`, `ROOM_FULL`, `GAME_MISMATCH`, `SHUTDOWN` …), or one of the session's own:
 * - `'CLOSED'` — the transport closed before the session's end, without the server saying why;
 * - `'BAD_WELCOME'` — the welcome describes a game this client cannot build (the game's `create`
 *   or `load` threw, the snapshot is at another tick, the room ticks at another rate).
 */
export type SessionErrorCode = NetErrorCode | 'CLOSED' | 'BAD_WELCOME';

/**
 * An error of a networked session: what its `error` event carries, and what its `finished`
 * promise rejects with when the error is fatal. Its message names the cause (for a server's
 * error, `CODE: the server's words`).
 */
export class SessionError extends Error {
  /**
   * @param code — why (see {@link SessionErrorCode}).
   * @param message — the cause, in words.
   * @param fatal — whether it ends the session (every local one does; a server's non-fatal
   *   error is a warning, e.g. a first strike for inputs outside the tick window).
   */
  constructor(
    readonly code: SessionErrorCode,
    message: string,
    readonly fatal = true,
  ) {
    super(message);
    this.name = 'SessionError';
  }

  /** The session error a server's `error` message means (its code, fatality and words). */
  static fromServer(m: ErrorMessage): SessionError {
    return new SessionError(m.code, `${m.code}: ${m.message}`, m.fatal);
  }
}

/**
 * What every networked session tells its owner (its `onEvent` option), in this order over its
 * life:
 * - `welcome` — the server admitted it: `welcome` is the room's setup, slot, reconnect token …;
 * - `running` — the phase became `'running'`, from `tick` (a relay session once the match's start
 *   time is known; a state-sync session with its first snapshot);
 * - `error` — something went wrong: every error the server sends (fatal or not) and every local
 *   failure (`BAD_WELCOME`, `CLOSED`). A fatal one that comes before the session's end also
 *   rejects `finished` with the same {@link SessionError};
 * - `closed` — the transport closed (`reason` as the transport gives it); always the last event.
 *
 * Each kind of session adds its own events to these (see `NetEvent`, `StateSyncEvent`).
 *
 * @typeParam W — the session's welcome message.
 */
export type SessionEvent<W> =
  | { type: 'welcome'; welcome: W }
  | { type: 'running'; tick: number }
  | { type: 'error'; error: SessionError }
  | { type: 'closed'; reason: string };
