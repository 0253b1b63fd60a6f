import { realpathSync } from 'node:fs';
import { realpath, stat } from 'node:fs/promises';
import http from 'node:http';
import type { AddressInfo } from 'node:net';
import path from 'node:path';
import Fastify, { type FastifyInstance, type FastifyReply } from 'fastify';
import { loadGames, type LoadedGames } from './games/load.js';
import fastifyStatic from '@fastify/static';
import { gameCatalog, type AnyGameDefinition } from 'fixedstep';
import { highscoreApi, highscoreRoutes, type HighscoreApi } from './highscores.js';
import { attachRelay, type RelayEndpoint, type RelayEndpointOptions } from './relay/endpoint.js';
import {
  attachStateSync,
  type StateSyncEndpoint,
  type StateSyncEndpointOptions,
} from './state-sync/endpoint.js';
import {
  attachSignalling,
  type SignallingEndpoint,
  type SignallingEndpointOptions,
} from './signalling/endpoint.js';
import {
  attachMatchmaking,
  type MatchEndpoint,
  type MatchmakingEndpointOptions,
} from './match/endpoint.js';
import { MatchTickets } from './match/tickets.js';
import {
  Admission,
  admissionOptionsFromEnv,
  trustedProxy,
  type OriginPolicy,
  type TrustedProxy,
} from './http/admission.js';
import type { HighscoreStore, PreparedStore } from './store/store.js';
import { StoreOpening } from './store/opening.js';
import { VerifierPool } from './verify/pool.js';
import { DEFAULT_HTTP_LIMITS, type HttpLimits } from './http/limits.js';
import { ServerMetrics } from './http/metrics.js';
import { DOCS_CONTENT_SECURITY_POLICY, SECURITY_HEADERS } from './http/security.js';

/** Options of {@link createServer}. */
export interface ServerOptions {
  /** TCP port; 0 picks a free one. Default 8080. */
  port?: number;
  /** Interface to listen on. Default `127.0.0.1` (this machine only); `0.0.0.0` for the network. */
  host?: string;
  /** The built lab (or any static site) to serve at `/`. Default: none (an API-only server). */
  root?: string;
  /**
   * The built API reference, served at `/docs/` (looked up per request, so a reference built while
   * the server runs shows on the next reload; until then `/docs/` says how to build it).
   */
  docs?: string;
  /**
   * The games the highscore API and the relay offer: definitions, or what `loadGames` returned
   * (whose module URLs the verification workers import). Default: the built-in games.
   */
  games?: LoadedGames | readonly AnyGameDefinition[];
  /**
   * Where highscores and their replays go. A promise is fine: the server listens at once and the
   * highscore API answers 503 `STORE_STARTING` until it resolves. A {@link PreparedStore} (from
   * `prepareStore`) is better: the server opens it, and while it cannot (a PostgreSQL server that
   * is down) tries again with a growing wait (see {@link storeRetry}), until it opens or the server
   * closes. Default: no highscore API.
   */
  store?: HighscoreStore | Promise<HighscoreStore> | PreparedStore;
  /**
   * The waits between attempts to open a {@link PreparedStore}, in ms: the first, doubled after
   * each failure up to the longest, each taken between half and all of it (jitter, so a
   * deployment's processes do not knock on their database together). Default 1000 and 30 000.
   */
  storeRetry?: { firstMs?: number; maxMs?: number };
  /**
   * Liveness: once a {@link PreparedStore} has failed to open for this many ms, `/healthz` answers
   * 503 (so an orchestrator that probes it restarts the process). 0: never. Default
   * `FIXEDSTEP_STORE_LIVENESS_MS`, else 300 000 (5 minutes). A store that cannot open for a reason
   * a restart cannot cure (the folder in use by another process, a newer schema) is not retried
   * and does not fail liveness: `/readyz` says why.
   */
  storeLivenessMs?: number;
  /** Close the store when the server closes. Default true. */
  closeStore?: boolean;
  /** The relay at `/ws` (`false`: none). Default: on, over the same games. */
  relay?: boolean | RelayEndpointOptions;
  /**
   * State-sync rooms at `/state/<room>` (the talk's network model: the server runs the game and
   * sends the world), in worker threads (`false`: none). Default: on, one worker, over the same
   * games when they came from `loadGames` (workers import games from modules; plain definitions
   * given as `games` cannot cross into a worker, so then state sync is off unless this names its
   * `games` modules).
   */
  stateSync?: boolean | StateSyncEndpointOptions;
  /**
   * WebRTC signalling at `/signal` (offers, answers and ICE candidates between peers, and a tunnel
   * when no direct route is found; see docs/webrtc.md), `false`: none. Default: on.
   */
  signalling?: boolean | SignallingEndpointOptions;
  /** The quick-match queue at `/match` (see docs/network.md), `false`: none. Default: on. */
  matchmaking?: boolean | MatchmakingEndpointOptions;

  /**
   * Browser origins allowed to open a WebSocket (the `Origin` header) to any surface — the relay,
   * state sync, signalling, quick match —, e.g. `['https://game.example']`. Default
   * `'same-origin'`: pages of this server only (or `FIXEDSTEP_ALLOWED_ORIGINS`).
   */
  allowedOrigins?: OriginPolicy;
  /**
   * A trusted reverse proxy (see `TrustedProxy`), or just the header it puts the client's address
   * in (`x-forwarded-for`) for a proxy on loopback — for every surface's per-address caps and the
   * highscore API's rate limit. Unset: the socket's address (or `FIXEDSTEP_PROXY_HEADER`).
   */
  trustProxy?: string | TrustedProxy;
  /**
   * WebSockets at once from one client address, every surface together. Default
   * `MAX_SOCKETS_PER_ADDRESS` (or `FIXEDSTEP_MAX_SOCKETS_PER_ADDRESS`).
   */
  maxSocketsPerAddress?: number;
  /** WebSockets at once, every surface together. Default `MAX_SOCKETS`. */
  maxSockets?: number;
  /**
   * The quick-match ticket secret, shared by every process of a deployment (the one that matches
   * and the ones whose relays seat the players). Default `FIXEDSTEP_MATCH_SECRET`, else random for
   * this process.
   */
  matchSecret?: string;
  /** Where `FIXEDSTEP_*` settings are read from. Default `process.env`. */
  env?: Readonly<Record<string, string | undefined>>;
  /** Highscore submissions (that passed the pre-check) per client address per minute. Default 20. */
  submissionsPerMinute?: number;
  /** Verification workers and queue. Default: cores − 1 workers (at least 1), 32 waiting. */
  verification?: { workers?: number; maxQueue?: number } | VerifierPool;
  /**
   * The `Content-Security-Policy` of every answer. Default `CONTENT_SECURITY_POLICY` (the
   * lab's: scripts, styles and WebAssembly from this origin, WebSockets, no framing, no eval).
   */
  contentSecurityPolicy?: string;
  /** HTTP limits and timeouts; missing fields take {@link DEFAULT_HTTP_LIMITS}. */
  limits?: Partial<HttpLimits>;
  /** Where unexpected errors are reported. Default `console.error`. */
  log?: (message: string, error?: unknown) => void;
}

/** A running server, from {@link createServer}. */
export interface FixedstepServer {
  /** Where to open it, e.g. `http://localhost:8080/`. */
  readonly url: string;
  /** The port actually bound. */
  readonly port: number;
  /** The Node HTTP server (e.g. to attach more WebSocket endpoints). */
  readonly server: http.Server;
  /** The fastify instance (routes may be added before the first request). */
  readonly app: FastifyInstance;
  /** The relay, unless `relay: false`. */
  readonly relay: RelayEndpoint | undefined;
  /** The state-sync rooms, unless off (see {@link ServerOptions.stateSync}). */
  readonly stateSync: StateSyncEndpoint | undefined;
  /** WebRTC signalling, unless `signalling: false`. */
  readonly signalling: SignallingEndpoint | undefined;
  /** The quick-match queue, unless `matchmaking: false`. */
  readonly matchmaking: MatchEndpoint | undefined;
  /** The admission every WebSocket surface shares (origins, addresses, sockets per address). */
  readonly admission: Admission;
  /** The Prometheus metrics served at `/metrics`. */
  readonly metrics: ServerMetrics;
  /** Resolves once the highscore store is open (rejects if it failed; no-op without a store). */
  readonly storeReady: Promise<void>;
  /** True from the start of {@link close} on (readiness then answers 503). */
  readonly draining: boolean;
  /**
   * Drain before a shutdown: readiness goes false (a balancer takes the server off); the relay,
   * state sync and signalling make no new rooms and close waiting ones, their running rooms go on
   * until they end or `timeoutMs` has passed (then `SHUTDOWN`); quick match refuses new requests
   * and matches the players already waiting until none is left or the time is up. HTTP keeps
   * answering. Call {@link close} after.
   */
  drain(timeoutMs: number): Promise<void>;
  /**
   * Graceful shutdown: readiness goes false, no new connections, new submissions get 503, the queued
   * verifications finish and are answered, the relay tells its clients (SHUTDOWN), the store closes.
   */
  close(): Promise<void>;
}

/** Whether a store option is one the server opens itself (and may retry). */
/**
 * Under `createServer` every surface shares one admission: an origin or proxy setting given to one
 * surface alone would be ignored, so it is refused with a sentence saying where it goes.
 */
function refuseSurfaceAdmission(options: ServerOptions): void {
  const surfaces = {
    relay: options.relay,
    stateSync: options.stateSync,
    signalling: options.signalling,
    matchmaking: options.matchmaking,
  };
  for (const [surface, given] of Object.entries(surfaces)) {
    if (typeof given !== 'object') continue;
    for (const key of ['allowedOrigins', 'trustProxy'] as const) {
      if (key in given && (given as Record<string, unknown>)[key] !== undefined) {
        throw new TypeError(
          `createServer: set ${key} on createServer itself, not on ${surface}: ` +
            'every WebSocket surface shares one admission',
        );
      }
    }
  }
}

/** The host to print in a URL: loopback and wildcard addresses are best opened as `localhost`. */
export function displayHost(host: string): string {
  if (['127.0.0.1', '::1', '0.0.0.0', '::', 'localhost', ''].includes(host)) return 'localhost';
  return host.includes(':') ? `[${host}]` : host;
}

/** What `/docs/` answers while the API reference is not built. */
export const DOCS_NOT_BUILT =
  'The API reference is not built yet. Build it with `npm run docs` (in the fixedstep repository), then reload this page.';

function isInside(root: string, file: string): boolean {
  const rel = path.relative(root, file);
  return rel !== '' && !rel.startsWith('..') && !path.isAbsolute(rel);
}

/** A static-file guard for @fastify/static: the file's real path (symlinks resolved) must lie inside the root. */
function insideRoot(root: string) {
  return (pathName: string): boolean => {
    let file: string;
    try {
      file = realpathSync(path.join(root, decodeURIComponent(pathName)));
    } catch {
      return true; // missing: @fastify/static answers 404
    }
    return file === root || isInside(root, file);
  };
}

function text(reply: FastifyReply, status: number, message: string): FastifyReply {
  return reply
    .code(status)
    .header('Content-Type', 'text/plain; charset=utf-8')
    .header('Cache-Control', 'no-store')
    .send(`${status} ${message}\n`);
}

/**
 * Creates and starts the fixedstep server: the lab and the API reference (static files), the
 * highscore API (verification in worker threads, scores and replays in the store), the relay at
 * `/ws`, `/healthz`, `/readyz` and `/metrics`, with security headers, connection caps and timeouts.
 * Rejects with a clear message when the port is taken.
 */
export async function createServer(options: ServerOptions = {}): Promise<FixedstepServer> {
  const port = options.port ?? 8080;
  const host = options.host ?? '127.0.0.1';
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    throw new RangeError(`port must be an integer from 0 to 65535, got ${String(port)}`);
  }
  const limits: HttpLimits = { ...DEFAULT_HTTP_LIMITS, ...options.limits };
  const log =
    options.log ??
    ((message: string, error?: unknown) => {
      console.error(`fixedstep: ${message}`, error ?? '');
    });
  const env = options.env ?? process.env;
  // The store opens while the server listens; a prepared one is retried until it opens.
  const opening = new StoreOpening(options, env, log);
  // Observed at once: a store that fails while the server is still being set up is reported by
  // storeReady and /readyz, not as an unhandled rejection.
  const storeInput = opening.opened;
  storeInput?.catch(() => undefined);
  let root: string | undefined;
  if (options.root !== undefined) {
    try {
      root = await realpath(path.resolve(options.root));
    } catch {
      throw new Error(`cannot serve ${options.root}: no such directory`);
    }
    if (!(await stat(root)).isDirectory())
      throw new Error(`cannot serve ${options.root}: not a directory`);
  }
  const docs = options.docs === undefined ? undefined : path.resolve(options.docs);
  const gamesOption = options.games ?? (await loadGames());
  const gameList: readonly AnyGameDefinition[] = Array.isArray(gamesOption)
    ? (gamesOption as readonly AnyGameDefinition[])
    : (gamesOption as LoadedGames).games;
  const metrics = new ServerMetrics();
  refuseSurfaceAdmission(options);
  // One admission for every WebSocket surface: origins, client addresses, sockets per address.
  const fromEnv = admissionOptionsFromEnv(env);
  const trust = trustedProxy(options.trustProxy) ?? fromEnv.trustProxy;
  const admission = new Admission({
    ...fromEnv,
    ...(options.allowedOrigins !== undefined ? { allowedOrigins: options.allowedOrigins } : {}),
    ...(trust !== undefined ? { trustProxy: trust } : {}),
    ...(options.maxSocketsPerAddress !== undefined
      ? { maxSocketsPerAddress: options.maxSocketsPerAddress }
      : {}),
    ...(options.maxSockets !== undefined ? { maxSockets: options.maxSockets } : {}),
  });
  // Tickets signed by the matchmaker, checked by the relay (of this process or another's).
  const tickets = new MatchTickets({
    env,
    ...(options.matchSecret !== undefined ? { secret: options.matchSecret } : {}),
  });

  const app = Fastify({
    logger: false,
    bodyLimit: limits.maxBodyBytes,
    // The server is made here so its timeouts are Node's own: the request timeout is checked every
    // second (Node's default is every 30 s, which let a slow body live for minutes).
    serverFactory: (handler) =>
      http.createServer(
        {
          requestTimeout: limits.requestTimeoutMs,
          headersTimeout: limits.headersTimeoutMs,
          keepAliveTimeout: limits.keepAliveTimeoutMs,
          connectionsCheckingInterval: Math.min(
            1000,
            limits.requestTimeoutMs,
            limits.headersTimeoutMs,
          ),
        },
        handler,
      ),
    connectionTimeout: limits.idleTimeoutMs,
    forceCloseConnections: 'idle',
    return503OnClosing: true,
  });
  const server = app.server;
  server.maxConnections = limits.maxConnections;
  // One address's connections (half-sent requests too) hold at most its share of those.
  admission.watch(server, limits.maxConnectionsPerAddress);

  let draining = false;
  let api: HighscoreApi | undefined;
  let storeError: string | undefined;
  let store: HighscoreStore | undefined;

  app.addHook('onSend', async (request, reply, payload) => {
    for (const [k, v] of Object.entries(SECURITY_HEADERS)) reply.header(k, v);
    if (docs !== undefined && request.url.startsWith('/docs/')) {
      reply.header('Content-Security-Policy', DOCS_CONTENT_SECURITY_POLICY);
    } else if (options.contentSecurityPolicy !== undefined) {
      reply.header('Content-Security-Policy', options.contentSecurityPolicy);
    }
    // JavaScript is text/javascript (RFC 9239), whatever the static server's table says.
    if (String(reply.getHeader('content-type')).startsWith('application/javascript')) {
      reply.header('Content-Type', 'text/javascript; charset=utf-8');
    }
    // A refused body was not read to its end: close the connection instead of reading the rest.
    if (reply.statusCode === 413 || reply.statusCode === 408) reply.header('Connection', 'close');
    return payload;
  });
  app.addHook('onResponse', async (request, reply) => {
    const route = request.routeOptions.url ?? 'unmatched';
    metrics.httpRequests.inc({ method: request.method, route, status: String(reply.statusCode) });
  });
  app.setErrorHandler(
    async (error: { statusCode?: number; code?: string; message: string }, request, reply) => {
      const status = error.statusCode ?? 500;
      if (status >= 500)
        log(`error while answering ${request.method} ${request.url}: ${error.message}`);
      const code = status === 413 ? 'TOO_LARGE' : (error.code ?? 'ERROR');
      const message =
        status === 413
          ? `a request body is at most ${limits.maxBodyBytes} bytes`
          : status >= 500
            ? 'internal error'
            : error.message;
      return reply.code(status).header('Cache-Control', 'no-store').send({ error: message, code });
    },
  );

  // An empty path segment (`GET //`, `/a//b`) names nothing: 404, before any route or file lookup.
  app.addHook('onRequest', async (request, reply) => {
    if (request.url.split('?')[0]!.includes('//')) return text(reply, 404, 'Not Found');
    return undefined;
  });

  // Health: alive (unless the store has failed to open for too long), and ready to take traffic
  // (not draining, the store open and answering).
  app.get('/healthz', async (_request, reply) => {
    const stuck = store === undefined && storeError === undefined ? opening.stuck() : undefined;
    return reply
      .code(stuck === undefined ? 200 : 503)
      .header('Cache-Control', 'no-store')
      .send(
        stuck === undefined ? { status: 'ok' } : { status: 'store-unavailable', reason: stuck },
      );
  });
  app.get('/readyz', async (_request, reply) => {
    const reasons: string[] = [];
    if (draining) reasons.push('draining: the server is shutting down');
    if (options.store !== undefined) {
      if (storeError !== undefined) reasons.push(`the store failed to open: ${storeError}`);
      else if (store === undefined) reasons.push(opening.state());
      else if (!(await store.ping())) {
        metrics.storeErrors.inc();
        reasons.push('the store does not answer');
      }
    }
    return reply
      .code(reasons.length === 0 ? 200 : 503)
      .header('Cache-Control', 'no-store')
      .send({ ready: reasons.length === 0, reasons });
  });
  app.get('/metrics', async (_request, reply) =>
    reply
      .header('Content-Type', metrics.registry.contentType)
      .header('Cache-Control', 'no-store')
      .send(await metrics.registry.metrics()),
  );

  // The highscore API: registered now, answering 503 until the store is open.
  const storeReady: Promise<void> =
    storeInput === undefined
      ? Promise.resolve()
      : storeInput.then(
          (opened) => {
            store = opened;
            const verification = options.verification;
            api = highscoreApi({
              games: gamesOption,
              store: opened,
              metrics,
              log,
              ...(verification instanceof VerifierPool
                ? { verifier: verification }
                : {
                    ...(verification?.workers !== undefined
                      ? { workers: verification.workers }
                      : {}),
                    ...(verification?.maxQueue !== undefined
                      ? { maxQueue: verification.maxQueue }
                      : {}),
                  }),
              ...(trust !== undefined ? { trustProxy: trust } : {}),
              ...(options.submissionsPerMinute !== undefined
                ? { perMinute: options.submissionsPerMinute }
                : {}),
              maxBodyBytes: limits.maxBodyBytes,
            });
            // Ready means the verification workers have imported the games too.
            return api.verifier.ready();
          },
          (error: unknown) => {
            storeError = error instanceof Error ? error.message : JSON.stringify(error);
            if (!draining) log('the highscore store could not be opened', error);
            throw error;
          },
        );
  storeReady.catch(() => undefined);
  if (options.store !== undefined) {
    await app.register(
      highscoreRoutes(() => api, {
        maxBodyBytes: limits.maxBodyBytes,
        ...(trust !== undefined ? { trustProxy: trust } : {}),
      }),
    );
  }

  // Static files: the lab at /, the API reference at /docs/.
  if (docs !== undefined) {
    app.get('/docs', async (_request, reply) => reply.redirect('/docs/', 301));
    await app.register(fastifyStatic, {
      root: docs,
      prefix: '/docs/',
      decorateReply: false,
      index: ['index.html'],
      dotfiles: 'ignore',
      cacheControl: false,
      // TypeDoc's assets/ are not content-hashed: everything under /docs/ is revalidated.
      setHeaders: (res) => {
        res.setHeader('Cache-Control', 'no-cache');
      },
      allowedPath: (pathName) => insideRoot(docs)(pathName),
    });
  }
  if (root !== undefined) {
    const labRoot = root;
    await app.register(fastifyStatic, {
      root: labRoot,
      prefix: '/',
      index: ['index.html'],
      dotfiles: 'ignore',
      cacheControl: false,
      // Vite puts content-hashed files under assets/: they never change, so they may be cached for a year.
      setHeaders: (res, file) => {
        res.setHeader(
          'Cache-Control',
          path.relative(labRoot, file).startsWith(`assets${path.sep}`)
            ? 'public, max-age=31536000, immutable'
            : 'no-cache',
        );
      },
      // A directory without its slash is redirected to it (`/docs` → `/docs/`).
      redirect: true,
      allowedPath: insideRoot(labRoot),
    });
  }
  app.setNotFoundHandler(async (request, reply) => {
    const pathname = request.url.split('?')[0]!;
    if (request.method !== 'GET' && request.method !== 'HEAD') {
      return text(reply.header('Allow', 'GET, HEAD'), 405, 'Method Not Allowed');
    }
    if (docs !== undefined && pathname.startsWith('/docs/')) {
      try {
        await stat(path.join(docs, 'index.html'));
      } catch {
        return text(reply, 404, DOCS_NOT_BUILT);
      }
    }
    return text(reply, 404, 'Not Found');
  });

  // The relay on the same port.
  let relay: RelayEndpoint | undefined;
  if (options.relay !== false) {
    const relayOptions: RelayEndpointOptions =
      typeof options.relay === 'object' ? options.relay : {};
    relay = attachRelay(server, {
      catalog: gameCatalog(gameList),
      admission,
      tickets: tickets.verify,
      env,
      ...relayOptions,
    });
    metrics.watchRelay(relay.relay);
  }

  // State-sync rooms on the same port, their games in worker threads.
  let stateSync: StateSyncEndpoint | undefined;
  if (options.stateSync !== false) {
    const given: StateSyncEndpointOptions =
      typeof options.stateSync === 'object' ? options.stateSync : {};
    const modules =
      given.games ??
      (options.games === undefined
        ? undefined
        : 'modules' in options.games
          ? options.games.modules
          : null);
    if (modules !== null) {
      stateSync = attachStateSync(server, {
        workers: 1,
        admission,
        env,
        ...given,
        ...(modules !== undefined ? { games: modules } : {}),
        log: (message) => {
          log(`state sync: ${message}`);
        },
      });
      // A worker that cannot load its games is reported; HTTP and the relay keep serving.
      stateSync.ready.catch((error: unknown) => {
        log('state sync: the workers could not load their games', error);
      });
      metrics.watchStateSync(stateSync);
    }
  }

  // WebRTC signalling on the same port, for peer-to-peer matches.
  let signalling: SignallingEndpoint | undefined;
  if (options.signalling !== false) {
    signalling = attachSignalling(server, {
      admission,
      env,
      ...(typeof options.signalling === 'object' ? options.signalling : {}),
    });
  }

  // Quick match on the same port: matched players get a fresh room of the relay.
  let matchmaking: MatchEndpoint | undefined;
  if (options.matchmaking !== false) {
    matchmaking = attachMatchmaking(server, {
      games: gameList,
      admission,
      env,
      tickets,
      ...(typeof options.matchmaking === 'object' ? options.matchmaking : {}),
    });
  }

  await app.ready();
  await new Promise<void>((resolve, reject) => {
    const onError = (error: NodeJS.ErrnoException) => {
      server.off('listening', onListening);
      if (error.code === 'EADDRINUSE') {
        reject(new Error(`port ${port} on ${host} is already in use (choose another with --port)`));
      } else if (error.code === 'EACCES') {
        reject(
          new Error(`no permission to listen on port ${port} on ${host} (try a port above 1023)`),
        );
      } else if (error.code === 'EADDRNOTAVAIL' || error.code === 'ENOTFOUND') {
        reject(new Error(`cannot listen on host ${host}: no such local address`));
      } else {
        reject(error);
      }
    };
    const onListening = () => {
      server.off('error', onError);
      resolve();
    };
    server.once('error', onError);
    server.once('listening', onListening);
    server.listen(port, host);
  }).catch(async (error: unknown) => {
    opening.stop();
    void storeInput?.then(
      (opened) => (options.closeStore !== false ? opened.close() : undefined),
      () => opening.release(),
    );
    await relay?.close();
    await stateSync?.close();
    await signalling?.close();
    await matchmaking?.close();
    await app.close().catch(() => undefined);
    throw error;
  });

  const bound = (server.address() as AddressInfo).port;
  let closing: Promise<void> | undefined;
  const close = () =>
    (closing ??= (async () => {
      draining = true;
      // Stop accepting; idle keep-alive connections go now, busy ones when answered.
      const stopped = new Promise<void>((resolve) =>
        server.close(() => {
          resolve();
        }),
      );
      server.closeIdleConnections();
      await api?.drain();
      await relay?.close();
      await stateSync?.close();
      await signalling?.close();
      await matchmaking?.close();
      await api?.close();
      server.closeAllConnections();
      await stopped;
      await app.close().catch(() => undefined);
      opening.stop();
      const opened = await storeInput?.catch(() => undefined);
      if (options.closeStore !== false) await opened?.close();
      if (opened === undefined) await opening.release();
    })());
  return {
    url: `http://${displayHost(host)}:${bound}/`,
    port: bound,
    server,
    app,
    relay,
    stateSync,
    signalling,
    matchmaking,
    admission,
    metrics,
    storeReady,
    get draining() {
      return draining;
    },
    async drain(timeoutMs: number) {
      draining = true;
      await Promise.all([
        relay?.drain(timeoutMs),
        stateSync?.drain(timeoutMs),
        signalling?.drain(timeoutMs),
        matchmaking?.drain(timeoutMs),
      ]);
    },
    close,
  };
}
