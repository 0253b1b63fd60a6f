/**
 * The state-sync session's options, counters, corrections and events: what
 * {@link StateSyncSession} takes and tells.
 * @module
 */
import type { GameSetup } from '../../sim/game.js';
import type { GameDefinition } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import type { Transport } from '../transport.js';
import type { ResyncReason, StateSyncLimits, StateWelcomeMessage } from '../state-sync/messages.js';
import type { StateSyncRender } from '../state-sync/render.js';
import type { SessionEvent } from './events.js';
import { emptyLinkStats, type LinkStats } from './link-stats.js';

/**
 * What a state-sync session tells its owner: the events every session shares
 * ({@link SessionEvent}: welcome, running, error, closed) and its own:
 * - `bad-snapshot` — a snapshot could not be used (nothing was applied); a whole one was asked
 *   for;
 * - `late-inputs` — the server says more of our inputs came after their tick was stepped (it used
 *   its missing-input rule instead); `late` is the total so far. With `lead: 'auto'` the session
 *   runs further ahead.
 */
export type StateSyncEvent =
  | SessionEvent<StateWelcomeMessage>
  | { type: 'bad-snapshot'; reason: ResyncReason; message: string; tick: number }
  | { type: 'late-inputs'; late: number; tick: number };

/** Options of a {@link StateSyncSession}. */
export interface StateSyncSessionOptions<I, S extends Simulation<I>> {
  /** The pipe to the server. */
  transport: Transport;
  /** The clock frames and probes are measured on (`performanceClock()`; a `ManualClock` in tests). */
  clock: Clock;
  /** Room to join (the first join creates it). */
  room: string;
  /** The game: id, version, input schema, tick rate and how to build it. */
  game: GameDefinition<I, S>;
  /** Play a slot, or watch. Default `'player'`. */
  role?: 'player' | 'spectator';
  /** Player slots, when this session creates the room (default: the game's minimum). */
  players?: number;
  /** The game's seed, when this session creates the room (default: the server picks). */
  seed?: number;
  /** Display name (at most 32 UTF-8 bytes). */
  name?: string;
  /** Reconnect token from an earlier welcome: take that slot back. */
  token?: Uint8Array;
  /**
   * Spectators: the room's invite token (`welcome.invite` of one of its players). The server lets
   * no spectator in without it.
   */
  invite?: Uint8Array;
  /**
   * Builds the client's own copy of the game from the room's setup. Default `game.create(setup)`.
   * It need not be the server's exact code: every snapshot replaces the client's state (the tests
   * give clients a game that drifts on purpose).
   */
  createSimulation?: (setup: GameSetup) => S;
  /**
   * The local player's input for `tick`, called once per tick, in order, just before the client
   * predicts that tick (so it shows at once). `sim` is the predicted state (read it, never step
   * it). Default: the neutral input.
   */
  localInput?: (tick: number, sim: S) => I;
  /** What to draw, for {@link StateSyncSession.render}. Without it the session only predicts. */
  render?: StateSyncRender<S>;
  /**
   * How far behind the server clock other entities are drawn, in ms: `'auto'` (default) takes the
   * snapshot interval plus a high lateness of recent snapshots (one-way delay and jitter), so the
   * snapshot after the drawn moment is nearly always in; it moves gradually, never backwards.
   */
  renderDelay?: number | 'auto';
  /** Half-life of the correction offset, ms (0: corrections show at once). Default 80. */
  smoothingHalfLifeMs?: number;
  /** Called after every reconciliation that moved the own entities (needs `render`). */
  onCorrection?: (correction: StateSyncCorrection) => void;
  /**
   * Ticks to predict ahead of the server clock, so an input reaches the server before its tick is
   * stepped. `'auto'` (default): the larger of half a high round trip plus two ticks and the
   * largest lead the server's lateness reports asked for in the last 2 minutes (docs/network.md).
   */
  lead?: number | 'auto';
  /** Most ticks the prediction may run past the newest snapshot; then it waits. Default 120. */
  maxPrediction?: number;
  /** Most forward ticks per {@link StateSyncSession.frame}. Default 32. */
  maxTicksPerFrame?: number;
  /** Clock probe interval, ms. Default 250 (the first four go 50 ms apart). */
  pingIntervalMs?: number;
  /** Snapshots kept as delta bases. Default 64. */
  baseHistory?: number;
  /** Size limits of the messages this client decodes. Default: the protocol's. */
  limits?: Partial<StateSyncLimits>;
  /**
   * Events ({@link StateSyncEvent}): welcome, running, bad-snapshot, error, closed. An error also
   * rejects `finished` when it is fatal and comes before the session's end.
   */
  onEvent?: (event: StateSyncEvent) => void;
}

/** What a reconciliation changed of the own player's drawn numbers. */
export interface StateSyncCorrection {
  /** The predicted tick it was corrected at, and the snapshot's tick it replayed from. */
  tick: number;
  snapshotTick: number;
  /** The largest change of any own number (game units). */
  size: number;
  /**
   * Whether it was drawn at once (larger than `render.teleport`: a respawn, a teleport) instead
   * of gliding.
   */
  snapped: boolean;
}

/** Counters of a state-sync session. */
export interface StateSyncSessionStats extends LinkStats {
  frames: number;
  /** Forward ticks predicted (resimulation not counted). */
  ticks: number;
  /** Snapshots received and applied: whole, delta-coded. */
  fullSnapshots: number;
  deltaSnapshots: number;
  /** Snapshots older than one already applied (reordered on the way): not applied. */
  staleSnapshots: number;
  /** Snapshots refused (damaged, wrong base, unloadable); each asked for a resync. */
  badSnapshots: number;
  /** Reconciliations: a snapshot loaded and the unacknowledged inputs applied again. */
  reconciliations: number;
  /** Ticks resimulated by reconciliations, and the most in one. */
  resimulatedTicks: number;
  maxResimulated: number;
  /** Corrections of the own player's drawn numbers above 1e-9, and the largest (game units). */
  corrections: number;
  maxCorrection: number;
  /** Frames that could not predict further (no snapshot for `maxPrediction` ticks). */
  stallFrames: number;
  /** Frames whose render time was past the newest snapshot (the render delay was too short). */
  starvedFrames: number;
  /** Of our ticks, how many the server stepped without our input (it says so in snapshots). */
  filledInputs: number;
  /** Of those, the inputs that did come, after their tick (late; the server counts them). */
  lateInputs: number;
  /** Inputs issued (ticks this player had an input for). */
  issuedInputs: number;
  /**
   * The fewest ticks by which our inputs reached the server before their tick was stepped, in the
   * newest snapshot's report (negative: late by that many).
   */
  slack: number;
  /** Ticks predicted ahead of the server clock now; render delay now (ms); measured jitter (ms). */
  lead: number;
  renderDelayMs: number;
  jitterMs: number;
  /** Messages that did not decode. */
  badMessages: number;
}

/** A state-sync session's counters at the start: all zero. */
export function emptyStateSyncStats(): StateSyncSessionStats {
  return {
    frames: 0,
    ticks: 0,
    fullSnapshots: 0,
    deltaSnapshots: 0,
    staleSnapshots: 0,
    badSnapshots: 0,
    reconciliations: 0,
    resimulatedTicks: 0,
    maxResimulated: 0,
    corrections: 0,
    maxCorrection: 0,
    stallFrames: 0,
    starvedFrames: 0,
    filledInputs: 0,
    lateInputs: 0,
    issuedInputs: 0,
    slack: 0,
    lead: 0,
    renderDelayMs: 0,
    jitterMs: 0,
    ...emptyLinkStats(),
    badMessages: 0,
  };
}
