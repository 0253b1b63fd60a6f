import type { AnyGameDefinition } from 'fixedstep';
import type { LoadedGames } from './games/load.js';
import type { HighscoreStore } from './store/store.js';
import { createServer, type FixedstepServer } from './app.js';

/** Options of {@link startServer}. */
export interface ServeOptions {
  /** TCP port; 0 picks a free one. Default 8080. */
  port?: number;
  /** Interface to listen on. Default `127.0.0.1` (this machine only); `0.0.0.0` for the network. */
  host?: string;
  /** Directory to serve (the built lab, `apps/lab/dist`). */
  root: string;
  /** The built API reference, served at `/docs/` (see {@link ServerOptions.docs}). */
  docs?: string;
  /** A highscore store: with it, the highscore API is served too. */
  store?: HighscoreStore | Promise<HighscoreStore>;
  /** The games of the highscore API. Default: the built-in games. */
  games?: LoadedGames | readonly AnyGameDefinition[];
}

/** A running server, from {@link startServer}. */
export type RunningServer = FixedstepServer;

/**
 * Serves a built lab (static files: GET and HEAD, no path traversal nor symlinks out of the root,
 * ETag revalidation, security headers) with `/healthz`, `/readyz` and `/metrics`, and the
 * highscore API when a store is given — no relay, no state sync, no matchmaking (attach them with `attachRelay(server.server)`, `attachStateSync(server.server)`, `attachMatchmaking(server.server)`).
 * {@link createServer} with `relay: false, stateSync: false, signalling: false, matchmaking: false`.
 */
export function startServer(options: ServeOptions): Promise<RunningServer> {
  return createServer({
    ...options,
    relay: false,
    stateSync: false,
    signalling: false,
    matchmaking: false,
  });
}

export { displayHost, DOCS_NOT_BUILT } from './app.js';
