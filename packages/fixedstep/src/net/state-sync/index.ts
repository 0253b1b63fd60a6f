/**
 * State sync — the talk's network model: a server-authoritative room runs the game and sends the
 * world state (delta-coded against each client's acknowledged snapshot) and the clock; clients
 * predict their own player, reconcile on every snapshot, and draw the rest between snapshots.
 * See docs/network.md, "State sync".
 * @module
 */
export {
  STATE_SYNC_VERSION,
  StateSyncType,
  DEFAULT_STATE_SYNC_LIMITS,
  encodeStateSyncMessage,
  decodeStateSyncMessage,
  peekStateSyncType,
} from './codec.js';
export type {
  StateSyncKind,
  StateSyncLimits,
  StateSyncErrorCode,
  ResyncReason,
  StateSyncMessage,
  JoinMessage,
  StateInputMessage,
  StateAckMessage,
  StatePingMessage,
  ResyncMessage,
  StateLeaveMessage,
  StateWelcomeMessage,
  StateSnapshotMessage,
  StatePongMessage,
  StateErrorMessage,
} from './codec.js';
export { encodeDelta, deltaBytes, applyDelta } from './delta.js';
export { StateSyncRoom } from './room.js';
export type {
  StateSyncView,
  StateSyncRoomOptions,
  StateSyncRoomEvent,
  StateSyncRoomStats,
} from './room.js';
export { StateSyncServer } from './server.js';
export type {
  StateSyncGame,
  StateSyncRoomDefaults,
  StateSyncServerOptions,
  StateSyncServerEvent,
} from './server.js';
export { StateSyncSession } from './session.js';
export type {
  StateSyncPhase,
  StateSyncEvent,
  StateSyncSessionOptions,
  StateSyncSessionStats,
  StateSyncCorrection,
} from './session.js';
export { SnapshotTimeline, CorrectionSmoother, LatenessWindow } from './render.js';
export type { StateSyncRender } from './render.js';
