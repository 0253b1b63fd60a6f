/**
 * What the main thread and a state-sync worker tell each other (structured clones; the bytes of a
 * message travel as a transferred ArrayBuffer). One list for both sides.
 * @internal
 */
import type { RoomHostOptions, StateSyncRoomDefaults } from 'fixedstep';

/** What a worker is started with (`workerData`). */
export interface WorkerSetup {
  /**
   * Modules the worker imports its games from (each one's `GAMES`, `games` or default export); a
   * later module's game replaces an earlier one's of the same id.
   */
  games: readonly string[];
  /** Room options (plain data only: no functions cross threads). */
  room: Omit<StateSyncRoomDefaults, 'view'>;
  /** The room core's options (caps, liveness …). */
  host: Omit<RoomHostOptions, 'randomU32'>;
  updateIntervalMs: number;
}

/** Main thread → worker. */
export type ToWorker =
  | { t: 'open'; id: number; room: string; address: string }
  | { t: 'data'; id: number; bytes: ArrayBuffer }
  | { t: 'close'; id: number; reason: string }
  /** The main thread is responsive (see `RoomHost.heartbeat`). */
  | { t: 'beat' }
  /** Drain (see `RoomHost.drain`): no new rooms; running ones end by `timeoutMs`. */
  | { t: 'drain'; timeoutMs: number }
  | { t: 'stop' };

/** A worker's rooms now, and its counters since it started (rooms that ended included). */
export interface StateSyncWorkerStats {
  /** Rooms open. */
  rooms: number;
  /** Player seats with a connected member, over every room. */
  players: number;
  /** Ticks stepped. */
  ticks: number;
  /** Bytes of every snapshot message sent (headers included). */
  snapshotBytes: number;
  /** Inputs that came after their tick was stepped: dropped, the server's stand-in value kept. */
  lateInputs: number;
  /** Player-ticks stepped without that player's input (the stand-in value). */
  filledInputs: number;
}

/** Worker → main thread. */
export type FromWorker =
  | { t: 'ready'; games: string[] }
  | { t: 'fatal'; message: string }
  | { t: 'send'; id: number; bytes: ArrayBuffer }
  | { t: 'close'; id: number; reason: string }
  | { t: 'room-created'; room: string; game: string; players: number }
  | { t: 'room-removed'; room: string }
  | { t: 'room-failed'; room: string; message: string }
  /** Sent every second (STATS_INTERVAL_MS), for `/metrics`. */
  | { t: 'stats'; stats: StateSyncWorkerStats }
  /** The drain is done: no room left. */
  | { t: 'drained' }
  | { t: 'stopped' };

/** How often a worker sends its {@link StateSyncWorkerStats}. */
export const STATS_INTERVAL_MS = 1000;
