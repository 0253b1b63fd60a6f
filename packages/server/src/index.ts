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
export { clientAddress, addressKey } from './http/client-address.js';
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
  gameCatalog,
  createRelay,
  connectNodeWebSocket,
  relayEndpointOptionsFromEnv,
} from './relay/index.js';
export type {
  RelayEndpoint,
  RelayEndpointOptions,
  TrustedProxy,
  OriginPolicy,
} from './relay/index.js';
export { attachStateSync } from './state-sync/index.js';
export type { StateSyncEndpoint, StateSyncEndpointOptions } from './state-sync/index.js';
export { attachSignalling, SignallingHub } from './signalling/index.js';
export type { SignallingEndpoint, SignallingEndpointOptions } from './signalling/index.js';
export { attachMatchmaking, MatchQueue, DEFAULT_MATCHMAKING_LIMITS } from './match/index.js';
export type {
  MatchmakingEndpoint,
  MatchmakingEndpointOptions,
  MatchmakingLimits,
} from './match/index.js';
export { printable, cleanName } from './text.js';
