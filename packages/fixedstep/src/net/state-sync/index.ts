/**
 * State sync — the talk's network model: a server-authoritative room runs the game and sends the
 * world state (delta-coded against each client's acknowledged snapshot) and the clock; clients
 * predict their own player, reconcile on every snapshot, and draw the rest between snapshots.
 * See docs/network.md, "State sync".
 * @module
 */
export {
  STATE_SYNC_VERSION,
  STATE_SYNC_PROTOCOL,
  MAX_SLACK,
  DEFAULT_STATE_SYNC_LIMITS,
  encodeStateSyncMessage,
  decodeStateSyncMessage,
  peekStateSyncType,
} from './messages.js';
export type {
  StateSyncKind,
  StateSyncLimits,
  SnapshotCodec,
  ResyncReason,
  StateSyncMessage,
  JoinMessage,
  StateInputMessage,
  StateAckMessage,
  ResyncMessage,
  StateLeaveMessage,
  StateWelcomeMessage,
  StateSnapshotMessage,
} from './messages.js';
export { encodeDelta, deltaBytes, applyDelta } from './delta.js';
export {
  encodeSchemaDelta,
  decodeSchemaDelta,
  predictedWords,
  BitWriter,
  BitReader,
  type Elapsed,
} from './schema-codec.js';
export {
  StateSyncRoom,
  StateSyncMember,
  DEFAULT_SNAPSHOTS_PER_SECOND,
  DEFAULT_BASE_HISTORY,
  DEFAULT_STATE_MAX_AHEAD_TICKS,
  DEFAULT_RESYNC_INTERVAL_MS,
  DEFAULT_MAX_CATCH_UP_TICKS,
} from './room.js';
export type {
  StateSyncView,
  StateSyncRoomOptions,
  StateSyncRoomEvent,
  StateSyncRoomStats,
  RoomPlacement,
} from './room.js';
export { StateSyncServer } from './server.js';
export type {
  StateSyncGame,
  StateSyncRoomDefaults,
  StateSyncServerOptions,
  StateSyncServerEvent,
} from './server.js';
export { SnapshotTimeline, PredictionSmoother, LatenessWindow } from './render.js';
export { LagHistory } from './lag.js';
export { PriorityAccumulator } from './priority.js';
export type { Limited } from './priority.js';
export type { LagHistoryOptions } from './lag.js';
export type { StateSyncRender } from './render.js';
