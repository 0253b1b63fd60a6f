/**
 * Networking: a compact binary protocol, transports (in-memory, a simulated lossy link, WebSocket),
 * client sessions (lockstep, rollback, spectator, sync test), NTP-style clock sync, and the relay
 * server core with desync forensics, and a quick-match client ({@link quickMatch}). See
 * docs/network.md.
 * @module
 */
export {
  PROTOCOL_VERSION,
  MAX_WIRE_INPUT_WORDS,
  MessageType,
  DEFAULT_PROTOCOL_LIMITS,
  NAME_PATTERN,
  TOKEN_BYTES,
  ProtocolError,
  encodeMessage,
  decodeMessage,
  peekMessageType,
} from './protocol.js';
export type {
  MessageKind,
  ProtocolLimits,
  ProtocolErrorCode,
  NetErrorCode,
  LeaveReason,
  NetMessage,
  HelloMessage,
  WelcomeMessage,
  StartMessage,
  InputMessage,
  ConfirmedMessage,
  AckMessage,
  HashMessage,
  DesyncMessage,
  PingMessage,
  PongMessage,
  LeaveMessage,
  ErrorMessage,
  SnapshotRequestMessage,
  SnapshotMessage,
  HashesRequestMessage,
  HashesMessage,
} from './protocol.js';
export { EventScheduler } from './scheduler.js';
export type { ScheduledEvent } from './scheduler.js';
export { BaseTransport, memoryPair, SimulatedLink } from './transport.js';
export type { Transport, LinkConditions, LinkStats, SimulatedLinkOptions } from './transport.js';
export { webSocketTransport, connectWebSocket, nodeWebSocketTransport } from './websocket.js';
export type { WebSocketTransportOptions, NodeWebSocketLike } from './websocket.js';
export { ClockSync } from './clock-sync.js';
export { NetSession, LockstepSession, SpectatorSession, setupFromWelcome } from './session.js';
export type {
  NetPhase,
  NetEvent,
  NetSessionOptions,
  NetSessionStats,
  LockstepSessionOptions,
} from './session.js';
export { RollbackSession } from './rollback.js';
export type { RollbackSessionOptions, Correction } from './rollback.js';
export { SyncTestSession, SyncTestError } from './sync-test.js';
export type { SyncTestOptions, SyncTestMismatch } from './sync-test.js';
export { diffSnapshots } from './forensics.js';
export type { SnapshotDiff } from './forensics.js';
export { Relay, relayCatalog } from './relay.js';
export type {
  RelayGame,
  RelayCatalog,
  RelayOptions,
  RelayConnectionInfo,
  RelayDrainOptions,
  RelayRateLimits,
  RelayEvent,
  RelayStats,
  RoomInfo,
  DesyncRecord,
} from './relay.js';
export { SimulatedMatch, relayGameOf } from './match.js';
export type {
  MatchGame,
  MatchClientSpec,
  SimulatedMatchOptions,
  MatchClientResult,
  MatchResult,
} from './match.js';
export {
  MAX_MATCH_MESSAGE_BYTES,
  MAX_MATCH_PLAYERS,
  MAX_MATCH_TIMEOUT_MS,
  MatchmakingError,
  encodeMatchMessage,
  decodeMatchClientMessage,
  decodeMatchServerMessage,
  quickMatch,
} from './matchmaking.js';
export type {
  MatchErrorCode,
  MatchQueueRequest,
  MatchCancelRequest,
  MatchClientMessage,
  MatchQueuedMessage,
  MatchFoundMessage,
  MatchNoneMessage,
  MatchCancelledMessage,
  MatchErrorMessage,
  MatchServerMessage,
  QuickMatchOptions,
  QuickMatchResult,
} from './matchmaking.js';
export * from './state-sync/index.js';
export * from './webrtc/index.js';
