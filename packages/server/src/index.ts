/**
 * @fixedstep/server — the fixedstep server as classes you can construct and embed: the HTTP app
 * (the lab, the API reference, health and metrics), highscores verified by re-simulation in worker
 * threads (scores and replays in PostgreSQL), the relay, state-sync rooms, WebRTC signalling and
 * quick match. `createServer` puts them all on one port; each endpoint also attaches alone to a
 * `node:http`, express or fastify server of your own.
 * @packageDocumentation
 * @module @fixedstep/server
 */
export { createServer, displayHost, DOCS_NOT_BUILT } from './app.js';
export type { ServerOptions, FixedstepServer } from './app.js';
export { startServer } from './serve.js';
export type { ServeOptions, RunningServer } from './serve.js';
export { DEFAULT_HTTP_LIMITS, openFileLimit } from './http/limits.js';
export type { HttpLimits } from './http/limits.js';
export { ServerMetrics } from './http/metrics.js';
export { SECURITY_HEADERS, CONTENT_SECURITY_POLICY } from './http/security.js';
export { RateLimiter } from './http/rate-limit.js';
export {
  Admission,
  addressKey,
  clientAddress,
  requestAddress,
  originAllowed,
  trustedProxy,
  trustedProxyList,
  admissionOptionsFromEnv,
  parseOriginPolicy,
  endpointAdmission,
  roomCapsFromEnv,
  DEFAULT_ORIGIN_POLICY,
  MAX_SOCKETS,
  MAX_SOCKETS_PER_ADDRESS,
  MAX_SOCKETS_PER_MINUTE,
} from './http/admission.js';
export type {
  AdmissionOptions,
  EndpointAdmissionOptions,
  SurfaceOptions,
  Admitted,
  Refused,
  OriginPolicy,
  TrustedProxy,
} from './http/admission.js';
export {
  WebSocketEndpoint,
  refuseUpgrade,
  CLOSE_UNSUPPORTED_DATA,
} from './http/websocket-endpoint.js';
export { RoomHostEndpoint, splitHostOptions } from './http/room-host-endpoint.js';
export type { EndpointHost } from './http/room-host-endpoint.js';
export type { WebSocketEndpointSetup, UpgradeInfo, RoomInPath } from './http/websocket-endpoint.js';
export { highscoreApi, highscoreRoutes, readBody } from './highscores.js';
export type { HighscoreApi, HighscoreApiOptions, ApiHandler, ApiAnswer } from './highscores.js';
export { HighscoreStore, openStore, prepareStore, TABLE_SIZE } from './store/store.js';
export type {
  HighscoreEntry,
  StoreOutcome,
  OpenStoreOptions,
  PreparedStore,
} from './store/store.js';
export type { SqlDriver, Queryable, Row } from './store/driver.js';
export { openPglite, claimDataDir, DataDirError } from './store/pglite.js';
export type { ClaimedDataDir } from './store/pglite.js';
export { openPostgres, describeDatabaseUrl } from './store/pg.js';
export {
  SubmissionError,
  precheckSubmission,
  resimulate,
  runId,
  submissionLimits,
  MAX_SUBMITTED_TICKS,
  MAX_SUBMITTED_BYTES,
  MAX_SUBMITTED_KEYFRAMES,
  MAX_CLAIMED_SCORE,
} from './verify/check.js';
export type { Precheck, Resimulation } from './verify/check.js';
export { VerifierPool } from './verify/pool.js';
export type { VerifierPoolOptions } from './verify/pool.js';
export {
  loadGames,
  importGames,
  gamesFromModule,
  resolveGamesModule,
  builtinGamesUrl,
  GamesModuleError,
} from './games/load.js';
export type { LoadedGames } from './games/load.js';
export {
  attachRelay,
  createRelay,
  registryCatalog,
  RelayEndpoint,
  RELAY_UPDATE_MS,
  connectNodeWebSocket,
} from './relay/index.js';
export type { RelayEndpointOptions, NodeWebSocketOptions } from './relay/index.js';
export {
  attachStateSync,
  StateSyncEndpoint,
  STATE_SYNC_HEARTBEAT_MS,
  STATE_SYNC_UPDATE_MS,
} from './state-sync/index.js';
export type { StateSyncEndpointOptions } from './state-sync/index.js';
export {
  attachSignalling,
  iceServersFromEnv,
  SignallingEndpoint,
  SIGNALLING_UPDATE_MS,
} from './signalling/index.js';
export type { SignallingEndpointOptions } from './signalling/index.js';
export {
  attachMatchmaking,
  MatchEndpoint,
  MatchQueue,
  MatchTickets,
  DEFAULT_MATCHMAKING_LIMITS,
  ACCEPT_MS,
  FILL_WINDOW_MS,
  isLoopbackKey,
  TICKET_LIFETIME_MS,
  MATCH_SWEEP_MS,
  MATCH_REQUEST_TIMEOUT_MS,
} from './match/index.js';
export type {
  MatchmakingEndpointOptions,
  MatchmakingLimits,
  MatchQueueOptions,
  Match,
  MatchMember,
  JoinResult,
  Proposal,
  SweepResult,
  MatchTicketsOptions,
} from './match/index.js';
export { printable, cleanName } from './text.js';
