/**
 * @fixedstep/cli — the `fixedstep` command and its server: host your games (the relay, state-sync
 * rooms, highscores verified by re-simulation in worker threads, scores and replays in
 * PostgreSQL), or attach just the relay, just the state-sync rooms or just the highscore API to a
 * `node:http`, express or fastify server of your own.
 * @packageDocumentation
 */
export { createServer, displayHost, DOCS_NOT_BUILT } from './server/app.js';
export type { ServerOptions, FixedstepServer } from './server/app.js';
export { startServer } from './serve.js';
export type { ServeOptions, RunningServer } from './serve.js';
export { DEFAULT_HTTP_LIMITS, openFileLimit } from './server/limits.js';
export type { HttpLimits } from './server/limits.js';
export { ServerMetrics } from './server/metrics.js';
export { SECURITY_HEADERS, CONTENT_SECURITY_POLICY } from './server/security.js';
export { RateLimiter } from './server/rate-limit.js';
export { clientAddress, addressKey } from './server/client-address.js';
export {
  run,
  parseArgs,
  parsePort,
  defaultLabRoot,
  MAIN_HELP,
  SERVE_HELP,
  DEFAULT_PORT,
  DEFAULT_HOST,
  EXIT_OK,
  EXIT_FAILURE,
  EXIT_USAGE,
} from './cli.js';
export type { Command, CliIo } from './cli.js';
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
export { attachRelay, gameCatalog, createRelay, connectNodeWebSocket } from './net/index.js';
export type { RelayEndpoint, RelayEndpointOptions } from './net/index.js';
export { attachStateSync } from './state-sync/index.js';
export type { StateSyncEndpoint, StateSyncEndpointOptions } from './state-sync/index.js';
export { attachSignalling, SignallingHub } from './signalling/index.js';
export type { SignallingEndpoint, SignallingEndpointOptions } from './signalling/index.js';
export { attachMatchmaking, MatchQueue, DEFAULT_MATCHMAKING_LIMITS } from './matchmaking/index.js';
export type {
  MatchmakingEndpoint,
  MatchmakingEndpointOptions,
  MatchmakingLimits,
} from './matchmaking/index.js';
export { printable, cleanName } from './text.js';
