import type http from 'node:http';
import type { Duplex } from 'node:stream';
import { WebSocketServer } from 'ws';
import {
  DEFAULT_PROTOCOL_LIMITS,
  nodeWebSocketTransport,
  performanceClock,
  type Relay,
  type RelayCatalog,
  type RelayOptions,
} from 'fixedstep';
import { createRelay } from './catalog.js';

/** Options of {@link attachRelay}: the relay's, plus where and how often. */
export interface RelayEndpointOptions extends Partial<Omit<RelayOptions, 'catalog'>> {
  /** URL path of the WebSocket endpoint. Default `/ws`. */
  path?: string;
  /** Games the relay offers. Default: the game registry. */
  catalog?: RelayCatalog;
  /** How often the relay's clock is advanced, in ms. Default 8 (about twice per 60 Hz tick). */
  updateIntervalMs?: number;
  /**
   * Browser origins allowed to connect (the `Origin` header), e.g. `['http://localhost:8080']`.
   * Default: any (the relay holds no secrets; every message is validated anyway).
   */
  allowedOrigins?: readonly string[];
}

/** A relay attached to an HTTP server, from {@link attachRelay}. */
export interface RelayEndpoint {
  readonly relay: Relay;
  readonly path: string;
  /** Stop: close every connection (error SHUTDOWN), detach from the server, stop the timer. */
  close(): Promise<void>;
}

/**
 * Attaches the multiplayer relay to `server` at `path` (default `/ws`), on the same port as the
 * lab: WebSocket upgrades on that path become relay connections (binary frames, at most one
 * snapshot-sized message — `ws` refuses larger frames before they are buffered); other upgrade
 * paths get a 404 unless another handler is listening. The relay runs on the process's monotonic
 * clock, advanced every `updateIntervalMs`.
 */
export function attachRelay(
  server: http.Server,
  options: RelayEndpointOptions = {},
): RelayEndpoint {
  const { path = '/ws', updateIntervalMs = 8, allowedOrigins, ...relayOptions } = options;
  const clock = relayOptions.clock ?? performanceClock();
  const relay = createRelay({ ...relayOptions, clock });
  const wss = new WebSocketServer({
    noServer: true,
    maxPayload: relayOptions.limits?.maxMessageBytes ?? DEFAULT_PROTOCOL_LIMITS.maxMessageBytes,
    perMessageDeflate: false,
  });
  const refuse = (socket: Duplex, status: string) => {
    socket.write(`HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n`);
    socket.destroy();
  };
  const onUpgrade = (req: http.IncomingMessage, socket: Duplex, head: Buffer) => {
    const pathname = (req.url ?? '/').split('?')[0];
    if (pathname !== path) {
      // Another handler may own this path; answer only when nobody else listens.
      if (server.listenerCount('upgrade') === 1) refuse(socket, '404 Not Found');
      return;
    }
    const origin = req.headers.origin;
    if (allowedOrigins && origin !== undefined && !allowedOrigins.includes(origin)) {
      refuse(socket, '403 Forbidden');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      relay.accept(nodeWebSocketTransport(ws));
    });
  };
  server.on('upgrade', onUpgrade);
  const timer = setInterval(() => {
    relay.update(clock.now());
  }, updateIntervalMs);
  timer.unref();
  let closed: Promise<void> | undefined;
  return {
    relay,
    path,
    close: () =>
      (closed ??= new Promise<void>((resolve) => {
        clearInterval(timer);
        server.off('upgrade', onUpgrade);
        relay.close();
        for (const ws of wss.clients) ws.terminate();
        wss.close(() => {
          resolve();
        });
      })),
  };
}
