/**
 * A surface whose connections a room host takes — the relay (`/ws`) and signalling (`/signal`):
 * the host's options split from the surface's, the host advanced on a timer, drained and closed
 * with the surface.
 * @module
 */
import type http from 'node:http';
import type { WebSocket } from 'ws';
import { nodeWebSocketTransport, type Clock, type ConnectionInfo, type Transport } from 'fixedstep';
import {
  roomCapsFromEnv,
  type EndpointAdmissionOptions,
  type SurfaceOptions,
} from './admission.js';
import {
  WebSocketEndpoint,
  type UpgradeInfo,
  type WebSocketEndpointSetup,
} from './websocket-endpoint.js';

/** What {@link RoomHostEndpoint} needs of its host (the room core's `RoomHost`: a relay, a hub). */
export interface EndpointHost {
  accept(transport: Transport, info: ConnectionInfo): number;
  update(now: number): void;
  drain(options: { timeoutMs?: number }): Promise<void>;
  close(): void;
}

/** The settings of a room host's options that the environment may give (the room core's caps). */
type RoomCaps = ReturnType<typeof roomCapsFromEnv>;

/**
 * A room host's surface options, split: where settings are read from (`env`), how the surface
 * admits (`surface`, for `endpointAdmission`), and the rest for the host — with the room core's
 * caps from the environment under the ones given.
 */
export function splitHostOptions<O extends SurfaceOptions>(
  options: O,
): {
  env: Readonly<Record<string, string | undefined>>;
  surface: EndpointAdmissionOptions;
  host: RoomCaps & Omit<O, keyof SurfaceOptions>;
} {
  const { env = process.env, admission, allowedOrigins, trustProxy, ...host } = options;
  return {
    env,
    surface: {
      ...(admission !== undefined ? { admission } : {}),
      ...(allowedOrigins !== undefined ? { allowedOrigins } : {}),
      ...(trustProxy !== undefined ? { trustProxy } : {}),
    },
    host: { ...roomCapsFromEnv(env), ...host },
  };
}

/**
 * A {@link WebSocketEndpoint} whose connections go to a room host, advanced every
 * `updateIntervalMs` on `clock`; it drains with the host and closes it.
 */
export abstract class RoomHostEndpoint<H extends EndpointHost> extends WebSocketEndpoint {
  private readonly timer: ReturnType<typeof setInterval>;

  constructor(
    server: http.Server,
    setup: WebSocketEndpointSetup,
    /** The room host its connections go to. */
    protected readonly host: H,
    clock: Clock,
    updateIntervalMs: number,
  ) {
    super(server, setup);
    this.timer = setInterval(() => {
      host.update(clock.now());
    }, updateIntervalMs);
    this.timer.unref();
  }

  protected connected(ws: WebSocket, info: UpgradeInfo): void {
    this.host.accept(nodeWebSocketTransport(ws), info);
  }

  /**
   * Graceful shutdown (the HTTP server calls it on SIGTERM, before {@link close}): no new rooms,
   * waiting rooms closed, rooms in play kept until their members have left or `timeoutMs` has
   * passed (the host's default: 25 000), then `SHUTDOWN`. Resolves when no room is left.
   */
  drain(timeoutMs?: number): Promise<void> {
    return this.host.drain(timeoutMs === undefined ? {} : { timeoutMs });
  }

  protected stop(): void {
    clearInterval(this.timer);
    this.host.close();
  }
}
