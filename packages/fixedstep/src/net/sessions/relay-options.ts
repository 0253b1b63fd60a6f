/**
 * The relay sessions' options, counters and events: what {@link NetSession} and its kinds
 * (lockstep, rollback, spectator) take and tell.
 * @module
 */
import type { ButtonInput } from '../../sim/buttons.js';
import type { AnyGameDefinition, GameSetup } from '../../sim/game.js';
import type { InputSchema } from '../../sim/input-schema.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import type { DesyncMessage, WelcomeMessage } from '../relay/messages.js';
import type { ErrorMessage, LeaveReason } from '../wire/common.js';
import type { Transport } from '../transport.js';

/** Where a session is. */
export type NetPhase = 'connecting' | 'waiting' | 'running' | 'closed';

/** What a session tells its owner about. */
export type NetEvent =
  | { type: 'welcome'; welcome: WelcomeMessage }
  | { type: 'start'; startAt: number }
  | { type: 'desync'; desync: DesyncMessage }
  | { type: 'error'; error: ErrorMessage }
  | { type: 'leave'; peer: number; reason: LeaveReason }
  | { type: 'closed'; reason: string };

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
  /** Never simulate past this tick (tests, benchmarks, a match of fixed length). */
  stopAt?: number;
  /** Events: welcome, start, desync, error, leave, closed. */
  onEvent?: (event: NetEvent) => void;
}

/** Counters of a session; all cumulative except the current delays. */
export interface NetSessionStats {
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
  /** Round trip to the server, min and high of the window, in ms. */
  rtt: number;
  rttHigh: number;
  messagesSent: number;
  messagesReceived: number;
  bytesSent: number;
  bytesReceived: number;
  hashesReported: number;
  /** Messages from the server that could not be decoded. */
  badMessages: number;
}
