/**
 * The client sessions, one file per kind: lockstep, rollback and spectator sessions of a relay
 * room (sharing {@link NetSession}), the state-sync session, and the local sync test.
 * @module
 */
export { SessionError } from './events.js';
export type { SessionPhase, SessionErrorCode, SessionEvent } from './events.js';
export { NetSession } from './base.js';
export { setupFromWelcome } from './relay-options.js';
export type { NetEvent, NetSessionOptions, NetSessionStats } from './relay-options.js';
export type { LinkStats } from './link-stats.js';
export { LockstepSession } from './lockstep.js';
export type { LockstepSessionOptions } from './lockstep.js';
export { SpectatorSession } from './spectator.js';
export { RollbackSession } from './rollback.js';
export type { RollbackSessionOptions, Correction } from './rollback.js';
export { SyncTestSession, SyncTestError } from './sync-test.js';
export type { SyncTestOptions, SyncTestMismatch } from './sync-test.js';
export { StateSyncSession } from './state-sync.js';
export type {
  StateSyncEvent,
  StateSyncSessionOptions,
  StateSyncSessionStats,
  StateSyncCorrection,
} from './state-sync-options.js';
