/**
 * The relay sessions' options, counters and events: what {@link NetSession} and its kinds
 * (lockstep, rollback, spectator) take and tell.
 * @module
 */
import type { ButtonInput } from '../../sim/buttons.js';
import type { AnyGameDefinition, GameSetup } from '../../sim/game.js';
import { BUTTON_WORD, type InputSchema } from '../../sim/input-schema.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import type { DesyncMessage, WelcomeMessage } from '../relay/messages.js';
import type { LeaveReason } from '../wire/common.js';
import { emptyLinkStats, type LinkStats } from './link-stats.js';
import type { Transport } from '../transport.js';
import type { SessionEvent } from './events.js';

/**
 * What a relay session (lockstep, rollback, spectator) tells its owner: the events every session
 * shares ({@link SessionEvent}: welcome, running, error, closed) and the relay's own:
 * - `desync` — the relay found that the players' states differ (also kept in `desyncs`);
 * - `leave` — another member of the room left (`peer`, and why).
 */
export type NetEvent =
  | SessionEvent<WelcomeMessage>
  | { type: 'desync'; desync: DesyncMessage }
  | { type: 'leave'; peer: number; reason: LeaveReason };

/** The game setup a welcome describes: the room's seed, players and option bytes. */
export function setupFromWelcome(welcome: WelcomeMessage): GameSetup {
  return Object.freeze({ seed: welcome.seed, players: welcome.players, options: welcome.config });
}

/** Options every network session takes. */
export interface NetSessionOptions<I = ButtonInput> {
  /** The pipe to the server. */
  transport: Transport;
  /**
   * The clock frames and pings are measured on (`performanceClock()` in a browser, the
   * scheduler's clock in a simulated network). Only differences matter.
   */
  clock: Clock;
  /** Room to join (created by the first hello). */
  room: string;
  /**
   * The game: a definition (id, version, input schema and how to build it all come from it), or
   * its id — then give `gameVersion`, `createSimulation` and, unless it is `BUTTON_WORD`, `input`.
   * Every member of a room must run the same game, version and input schema.
   */
  game: string | AnyGameDefinition;
  /** The game's version, when `game` is an id. */
  gameVersion?: number;
  /** The input schema, when `game` is an id. Default `BUTTON_WORD`. */
  input?: InputSchema<I>;
  /** Player slots, when this session creates the room (default: the game's minimum). */
  players?: number;
  /** The game's seed, when this session creates the room (default: the server picks). */
  seed?: number;
  /** Display name (at most 32 UTF-8 bytes). */
  name?: string;
  /** Reconnect token from an earlier welcome: take back that slot. */
  token?: Uint8Array;
  /**
   * A quick-match ticket (`quickMatch`'s `ticket`): the room, its setup and this player's seat
   * come from it; `players` and `seed` are then ignored.
   */
  ticket?: Uint8Array;
  /**
   * Spectators: the room's invite token (`welcome.invite` of one of its players). The relay lets
   * no spectator in without it.
   */
  invite?: Uint8Array;
  /**
   * Builds the simulation from the welcome (its seed, `players` and `config` bytes). Default, with
   * a game definition: `game.create(setupFromWelcome(welcome))`.
   */
  createSimulation?(welcome: WelcomeMessage): Simulation<I>;
  /**
   * The local player's input for `tick` — called exactly once per tick, in tick order, some
   * ticks before the tick is simulated (the input delay). `sim` is the current state (read it,
   * never step it). Default: the schema's neutral input (nothing pressed).
   *
   * From an `InputSampler` fed by device adapters:
   * `sampler.sample({ isBeforeUpdateEnd: (t) => t <= clock.now() }, 0)` gives the tick being
   * issued every event up to now, so each press reaches exactly one tick (as precisely as the
   * frames that issue ticks allow).
   */
  localInput?: (tick: number, sim: Simulation<I>) => I;
  /**
   * The most ticks one {@link NetSession.frame} steps forward: the catch-up budget after a
   * background tab, a late join or a hitch. Default 32. Resimulation after a rollback is not
   * counted (it is bounded by the prediction window).
   */
  maxTicksPerFrame?: number;
  /** Clock sync probe interval, in ms. Default 250 (the first four go 50 ms apart). */
  pingIntervalMs?: number;
  /**
   * Keep the `save()` of each of the last this many confirmed ticks, so the server can pin a
   * desync to its exact tick and diff both sides' states. Default 180. 0 saves only at hash
   * report ticks (the server can then only name the report tick).
   */
  forensicsWindow?: number;
  /**
   * Never simulate past this tick (tests, benchmarks, a match of fixed length). It is the
   * session's end: `finished` resolves once the state at this tick is confirmed. Default: none
   * (the session ends only when its owner calls `leave()`).
   */
  stopAt?: number;
  /**
   * Events ({@link NetEvent}): welcome, running, desync, error, leave, closed. An error also
   * rejects `finished` when it is fatal and comes before the session's end.
   */
  onEvent?: (event: NetEvent) => void;
}

/** Counters of a session; all cumulative except the current delays. */
export interface NetSessionStats extends LinkStats {
  /** Calls of {@link NetSession.frame}. */
  frames: number;
  /** Ticks stepped forward (not counting resimulation). */
  ticks: number;
  /** Most forward ticks in one frame. */
  maxTicksInFrame: number;
  /** Frames that wanted to step but could not (missing inputs, or the prediction window full). */
  stallFrames: number;
  /** Stalls: runs of consecutive stalled frames. */
  stalls: number;
  /** Rollbacks (rollback sessions). */
  rollbacks: number;
  /** Ticks resimulated by rollbacks. */
  resimulatedTicks: number;
  /** Deepest rollback, in ticks. */
  maxRollbackDepth: number;
  /** Confirmed inputs of this player that differ from what it sent (filled after the deadline). */
  replacedInputs: number;
  /** Input delay in ticks now (lockstep: adaptive to RTT; rollback: fixed). */
  inputDelay: number;
  /** Rollback: ticks ahead of the server clock now. */
  lead: number;
  /** Lockstep / spectator: ticks behind the server clock now (adaptive jitter buffer). */
  playoutDelay: number;
  hashesReported: number;
  /** Messages from the server that could not be decoded. */
  badMessages: number;
}

/** A session's counters at the start: all zero. */
export function emptyNetStats(): NetSessionStats {
  return {
    frames: 0,
    ticks: 0,
    maxTicksInFrame: 0,
    stallFrames: 0,
    stalls: 0,
    rollbacks: 0,
    resimulatedTicks: 0,
    maxRollbackDepth: 0,
    replacedInputs: 0,
    inputDelay: 0,
    lead: 0,
    playoutDelay: 0,
    ...emptyLinkStats(),
    hashesReported: 0,
    badMessages: 0,
  };
}

/**
 * The game a session's options name: its id, version and input schema, and how to build it from
 * a welcome (the options' `createSimulation`, else the definition's `create`).
 */
export function resolveGame<I>(options: NetSessionOptions<I>): {
  gameId: string;
  gameVersion: number;
  schema: InputSchema<I>;
  build: (welcome: WelcomeMessage) => Simulation<I>;
} {
  const game = options.game;
  if (typeof game === 'string') {
    if (options.gameVersion === undefined || options.createSimulation === undefined) {
      throw new RangeError(
        'NetSession: with a game id, give gameVersion and createSimulation (or pass the game definition)',
      );
    }
    return {
      gameId: game,
      gameVersion: options.gameVersion,
      schema: options.input ?? (BUTTON_WORD as unknown as InputSchema<I>),
      build: options.createSimulation.bind(options),
    };
  }
  const create = options.createSimulation?.bind(options);
  return {
    gameId: game.id,
    gameVersion: game.version,
    schema: game.input as InputSchema<I>,
    build: create ?? ((w: WelcomeMessage) => game.create(setupFromWelcome(w)) as Simulation<I>),
  };
}
