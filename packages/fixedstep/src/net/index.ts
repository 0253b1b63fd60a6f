/**
 * Networking: a compact binary protocol, transports (in-memory, a simulated lossy link, WebSocket),
 * client sessions (lockstep, rollback, spectator, sync test), NTP-style clock sync, and the relay
 * server core with desync forensics, and a quick-match client ({@link quickMatch}). See
 * docs/network.md.
 * @module
 */
export * from './wire/index.js';
export {
  PROTOCOL_VERSION,
  MAX_WIRE_INPUT_WORDS,
  MAX_SEND_EVERY,
  INPUT_DATAGRAM_EVERY,
  CONFIRMED_DATAGRAM_EVERY,
  REDUNDANT_TICKS,
  MAX_DATAGRAM_BYTES,
  DEFAULT_PROTOCOL_LIMITS,
  RELAY_PROTOCOL,
  encodeMessage,
  decodeMessage,
  decodeFrame,
  peekMessageType,
} from './relay/messages.js';
export type {
  MessageKind,
  ProtocolLimits,
  NetMessage,
  HelloMessage,
  WelcomeMessage,
  StartMessage,
  InputMessage,
  ConfirmedMessage,
  AckMessage,
  HashMessage,
  DesyncMessage,
  LeaveMessage,
  SnapshotRequestMessage,
  SnapshotMessage,
  HashesRequestMessage,
  HashesMessage,
} from './relay/messages.js';
export { fetchWithRetry, parseRetryAfter } from './http-retry.js';
export type { FetchRetry, FetchRetryOptions } from './http-retry.js';
export { EventScheduler } from './scheduler.js';
export type { ScheduledEvent } from './scheduler.js';
export { BaseTransport, memoryPair, SimulatedLink } from './transport.js';
export type { Transport, LinkConditions, LinkStats, SimulatedLinkOptions } from './transport.js';
export { webSocketTransport, connectWebSocket, nodeWebSocketTransport } from './websocket.js';
export type { WebSocketTransportOptions, NodeWebSocketLike } from './websocket.js';
export type {
  AbortSignalLike,
  WebSocketLike,
  WebSocketClassLike,
  WebSocketMessageEventLike,
  WebSocketCloseEventLike,
  FetchInitLike,
  FetchResponseLike,
  FetchInit,
  FetchResponse,
} from './platform.js';
export { ClockSync } from './clock-sync.js';
export * from './sessions/index.js';
export { diffSnapshots } from './forensics.js';
export type { SnapshotDiff } from './forensics.js';
export * from './room/index.js';
export { gameCatalog, MATCH_ROOM_PREFIX } from './room/game-join.js';
export type {
  HostedGame,
  GameCatalog,
  MatchTicket,
  TicketVerifier,
  GameRoomSetup,
} from './room/game-join.js';
export {
  Relay,
  DEFAULT_DEADLINE_MS,
  DEFAULT_HASH_EVERY,
  DEFAULT_START_DELAY_MS,
  DEFAULT_MAX_AHEAD_TICKS,
  DEFAULT_MAX_BEHIND_TICKS,
  DEFAULT_HISTORY_TICKS,
  DEFAULT_MAX_MATCH_TICKS,
  DEFAULT_START_LIVENESS_MS,
  DEFAULT_SNAPSHOT_TIMEOUT_MS,
  DEFAULT_FORENSICS_TIMEOUT_MS,
  DEFAULT_HASH_TIMEOUT_MS,
  DEFAULT_MAX_DESYNC_RECORDS,
  DEFAULT_MAX_FORENSICS_BYTES,
} from './relay/relay.js';
export type {
  RelayOptions,
  RelayDrainOptions,
  RelayEvent,
  RelayStats,
  RoomInfo,
} from './relay/relay.js';
export { RelayRoom, RelayMember } from './relay/room.js';
export type { RelaySettings, RelayRoomEvents } from './relay/room.js';
export { DesyncDetector } from './relay/forensics.js';
export type { DesyncRecord } from './relay/forensics.js';
export { SimulatedMatch, relayGameOf } from './match.js';
export type {
  MatchGame,
  MatchClientSpec,
  SimulatedMatchOptions,
  MatchClientResult,
  MatchResult,
} from './match.js';
export {
  MAX_MATCH_PLAYERS,
  MAX_MATCH_TIMEOUT_MS,
  MATCH_VERSION,
  MATCH_PROTOCOL,
} from './match/messages.js';
export type {
  MatchQueueRequest,
  MatchAcceptMessage,
  MatchCancelRequest,
  MatchClientMessage,
  MatchQueuedMessage,
  MatchProposedMessage,
  MatchFoundMessage,
  MatchNoneMessage,
  MatchCancelledMessage,
  MatchServerMessage,
  MatchMessage,
} from './match/messages.js';
export { MatchmakingError, quickMatch } from './match/client.js';
export type { MatchFailure, QuickMatchOptions, QuickMatchResult } from './match/client.js';
export * from './state-sync/index.js';
export * from './webrtc/index.js';
