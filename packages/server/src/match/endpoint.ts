import type http from 'node:http';
import type { Duplex } from 'node:stream';
import { WebSocketServer, type RawData, type WebSocket } from 'ws';
import {
  MAX_MATCH_MESSAGE_BYTES,
  MatchmakingError,
  decodeMatchClientMessage,
  encodeMatchMessage,
  performanceClock,
  type AnyGameDefinition,
  type Clock,
  type MatchErrorCode,
  type MatchServerMessage,
  type RelayCatalog,
} from 'fixedstep';
import { gameCatalog } from '../relay/catalog.js';
import {
  clientAddress,
  originAllowed,
  trustedProxyList,
  type OriginPolicy,
  type TrustedProxy,
} from '../relay/endpoint.js';
import { claimUpgradePaths, shouldRefuseUpgrade } from '../http/upgrade-paths.js';
import { MatchQueue, DEFAULT_MATCHMAKING_LIMITS, type MatchmakingLimits } from './queue.js';

/** Options of {@link attachMatchmaking}. */
export interface MatchmakingEndpointOptions {
  /** URL path of the WebSocket endpoint. Default `/match`. */
  path?: string;
  /** The games that may be queued for. Default: the game registry (or `catalog`). */
  games?: readonly AnyGameDefinition[];
  /** The relay catalog to check requests against (takes precedence over `games`). */
  catalog?: RelayCatalog;
  /** Queue bounds; missing fields take {@link DEFAULT_MATCHMAKING_LIMITS}. */
  limits?: Partial<MatchmakingLimits>;
  /** Browser origins allowed to connect, as the relay's (default `'same-origin'`). */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a trusted proxy's header, as the relay does. Default: none. */
  trustProxy?: TrustedProxy;
  /** How long a new connection may take to send its request, in ms. Default 10 000. */
  requestTimeoutMs?: number;
  /** The clock waits are measured on. Default the process's monotonic clock. */
  clock?: Clock;
  /** Random bytes for room names. Default `crypto.randomBytes`. */
  randomBytes?: (n: number) => Uint8Array;
}

/** Matchmaking attached to an HTTP server, from {@link attachMatchmaking}. */
export interface MatchmakingEndpoint {
  /** The queue (e.g. its `size` for a dashboard). */
  readonly queue: MatchQueue<unknown>;
  /** The URL path it answers, e.g. `/match`. */
  readonly path: string;
  /** Open matchmaking connections (waiting or not yet sent their request). */
  readonly connections: number;
  /** Tell every waiting client (error `SHUTDOWN`), close every connection, detach. */
  close(): Promise<void>;
}

interface Connection {
  end(message: MatchServerMessage): void;
}

/**
 * Attaches the quick-match queue to `server` at `path` (default `/match`), beside the relay's
 * `/ws`: a client sends one JSON `queue` request (see `quickMatch` in fixedstep), is told
 * `queued`, and later `matched` (a fresh room name, the player count, its order), `no-match` or
 * `cancelled`; then the server closes the connection. Closing it first cancels. A refused request
 * gets an `error` naming the field or the cap. Upgrades from other sites' pages get 403, past the
 * connection caps (twice the waiting caps, so a client over the waiting cap still hears why) 429 or
 * 503; other paths are left to other endpoints (404 when nobody owns them).
 */
export function attachMatchmaking(
  server: http.Server,
  options: MatchmakingEndpointOptions = {},
): MatchmakingEndpoint {
  const {
    path = '/match',
    allowedOrigins = 'same-origin',
    trustProxy,
    requestTimeoutMs = 10_000,
  } = options;
  if (!/^\/[A-Za-z0-9_./-]*$/.test(path) || path.endsWith('/')) {
    throw new RangeError(`attachMatchmaking: path must look like /match, got "${path}"`);
  }
  const limits: MatchmakingLimits = { ...DEFAULT_MATCHMAKING_LIMITS, ...options.limits };
  const proxies = trustProxy ? trustedProxyList(trustProxy) : undefined;
  const clock = options.clock ?? performanceClock();
  const queue = new MatchQueue<Connection>({
    clock,
    catalog: options.catalog ?? gameCatalog(options.games),
    limits,
    ...(options.randomBytes ? { randomBytes: options.randomBytes } : {}),
  });
  const wss = new WebSocketServer({
    noServer: true,
    maxPayload: MAX_MATCH_MESSAGE_BYTES,
    perMessageDeflate: false,
  });
  const open = new Map<string, number>();
  let total = 0;
  const refuse = (socket: Duplex, status: string, reason = '') => {
    socket.write(
      `HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Type: text/plain\r\n` +
        `Content-Length: ${Buffer.byteLength(reason)}\r\n\r\n${reason}`,
    );
    socket.destroy();
  };

  const accept = (ws: WebSocket, address: string) => {
    let ticket: number | undefined;
    let done = false;
    const connection: Connection = {
      end(message) {
        if (done) return;
        done = true;
        clearTimeout(timer);
        ws.send(encodeMatchMessage(message));
        ws.close(1000);
      },
    };
    const fail = (code: MatchErrorCode, message: string) => {
      connection.end({ type: 'error', code, message });
    };
    const timer = setTimeout(() => {
      fail('BAD_MESSAGE', `no request within ${requestTimeoutMs} ms`);
    }, requestTimeoutMs);
    timer.unref();
    ws.on('message', (data: RawData, isBinary: boolean) => {
      if (done) return;
      if (isBinary) {
        fail('BAD_MESSAGE', 'matchmaking messages are JSON text frames, not binary');
        return;
      }
      const text = (
        Array.isArray(data)
          ? Buffer.concat(data)
          : Buffer.isBuffer(data)
            ? data
            : Buffer.from(new Uint8Array(data))
      ).toString();
      let m;
      try {
        m = decodeMatchClientMessage(text);
      } catch (error) {
        const e = error instanceof MatchmakingError ? error : undefined;
        fail('BAD_MESSAGE', e?.message ?? 'unreadable message');
        return;
      }
      if (m.type === 'cancel') {
        if (ticket !== undefined) queue.cancel(ticket);
        connection.end({ type: 'cancelled' });
        return;
      }
      if (ticket !== undefined) {
        if (queue.cancel(ticket)) fail('BAD_MESSAGE', 'one queue request per connection');
        return;
      }
      const result = queue.join(m, address, connection);
      if (!result.ok) {
        fail(result.code, result.message);
        return;
      }
      ticket = result.ticket;
      clearTimeout(timer);
      ws.send(encodeMatchMessage({ type: 'queued', timeoutMs: result.timeoutMs }));
      const match = result.match;
      if (match) {
        for (const member of match.members) {
          member.data.end({
            type: 'matched',
            room: match.room,
            players: match.players,
            order: member.order,
          });
        }
      }
    });
    ws.on('close', () => {
      clearTimeout(timer);
      if (!done && ticket !== undefined) queue.cancel(ticket);
      done = true;
      total--;
      const left = (open.get(address) ?? 1) - 1;
      if (left > 0) open.set(address, left);
      else open.delete(address);
    });
    ws.on('error', () => undefined);
  };

  const ownsPath = (pathname: string) => pathname === path;
  const releasePaths = claimUpgradePaths(server, ownsPath, path);
  const onUpgrade = (req: http.IncomingMessage, socket: Duplex, head: Buffer) => {
    const pathname = (req.url ?? '/').split('?')[0] ?? '/';
    if (!ownsPath(pathname)) {
      // Another endpoint may own this path; answer only when none does.
      if (shouldRefuseUpgrade(server, ownsPath, pathname)) refuse(socket, '404 Not Found');
      return;
    }
    if (!originAllowed(req, allowedOrigins)) {
      refuse(socket, '403 Forbidden', 'origin not allowed');
      return;
    }
    const who = clientAddress(req, trustProxy, proxies);
    if ('error' in who) {
      refuse(socket, '400 Bad Request', who.error);
      return;
    }
    if (total >= 2 * limits.maxWaiting) {
      refuse(socket, '503 Service Unavailable', 'too many matchmaking connections');
      return;
    }
    if ((open.get(who.address) ?? 0) >= 2 * limits.maxWaitingPerAddress) {
      refuse(socket, '429 Too Many Requests', 'too many matchmaking connections from you');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      // Counted once open (a failed handshake never gets here, so never leaks a count).
      total++;
      open.set(who.address, (open.get(who.address) ?? 0) + 1);
      accept(ws, who.address);
    });
  };
  server.on('upgrade', onUpgrade);
  const sweep = setInterval(() => {
    for (const member of queue.expire()) member.data.end({ type: 'no-match' });
  }, 100);
  sweep.unref();
  let closed: Promise<void> | undefined;
  return {
    queue,
    path,
    get connections() {
      return total;
    },
    close: () =>
      (closed ??= new Promise<void>((resolve) => {
        clearInterval(sweep);
        server.off('upgrade', onUpgrade);
        releasePaths();
        for (const c of queue.clear()) {
          c.end({ type: 'error', code: 'SHUTDOWN', message: 'the server is shutting down' });
        }
        for (const ws of wss.clients) ws.terminate();
        wss.close(() => {
          resolve();
        });
      })),
  };
}
