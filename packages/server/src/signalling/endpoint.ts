import type http from 'node:http';
import type { Duplex } from 'node:stream';
import { WebSocketServer } from 'ws';
import { DEFAULT_SIGNAL_LIMITS, nodeWebSocketTransport, performanceClock } from 'fixedstep';
import { SignallingHub, type SignallingHubOptions } from './hub.js';
import { claimUpgradePaths, shouldRefuseUpgrade } from '../http/upgrade-paths.js';
import { originAllowed } from '../relay/endpoint.js';

/** Options of {@link attachSignalling}: the hub's, plus where. */
export interface SignallingEndpointOptions extends Partial<SignallingHubOptions> {
  /** URL path of the WebSocket endpoint. Default `/signal`. */
  path?: string;
  /** Browser origins allowed to connect (the `Origin` header). Default: any. */
  allowedOrigins?: readonly string[];
}

/** Signalling attached to an HTTP server, from {@link attachSignalling}. */
export interface SignallingEndpoint {
  readonly hub: SignallingHub;
  readonly path: string;
  /** Close every connection, detach from the server, stop the timer. */
  close(): Promise<void>;
}

/**
 * Attaches WebRTC signalling to `server` at `path` (default `/signal`), beside the relay's `/ws`:
 * WebSocket upgrades on that path become {@link SignallingHub} connections (binary frames, at most
 * one tunnelled relay message in size). Other paths are left to other handlers (a 404 when nobody
 * else listens). The STUN/TURN servers to announce are `iceServers` (see docs/webrtc.md).
 */
export function attachSignalling(
  server: http.Server,
  options: SignallingEndpointOptions = {},
): SignallingEndpoint {
  const { path = '/signal', allowedOrigins, ...hubOptions } = options;
  const clock = hubOptions.clock ?? performanceClock();
  const hub = new SignallingHub({ ...hubOptions, clock });
  const maxData = hubOptions.limits?.maxDataBytes ?? DEFAULT_SIGNAL_LIMITS.maxDataBytes;
  const wss = new WebSocketServer({
    noServer: true,
    maxPayload: maxData + 64,
    perMessageDeflate: false,
  });
  const refuse = (socket: Duplex, status: string) => {
    socket.write(`HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n`);
    socket.destroy();
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
    if (!originAllowed(req, allowedOrigins ?? 'any')) {
      refuse(socket, '403 Forbidden');
      return;
    }
    wss.handleUpgrade(req, socket, head, (ws) => {
      hub.accept(nodeWebSocketTransport(ws));
    });
  };
  server.on('upgrade', onUpgrade);
  const timer = setInterval(() => {
    hub.update(clock.now());
  }, 1000);
  timer.unref();
  let closed: Promise<void> | undefined;
  return {
    hub,
    path,
    close: () =>
      (closed ??= new Promise<void>((resolve) => {
        clearInterval(timer);
        server.off('upgrade', onUpgrade);
        releasePaths();
        hub.close();
        for (const ws of wss.clients) ws.terminate();
        wss.close(() => {
          resolve();
        });
      })),
  };
}
