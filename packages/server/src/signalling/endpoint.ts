/**
 * WebRTC signalling on the server's HTTP port: WebSocket upgrades on `/signal/<room>` become
 * connections to a {@link SignallingHub} (the room core's, in `fixedstep`).
 * @module
 */
import type http from 'node:http';
import type { WebSocket } from 'ws';
import {
  SIGNAL_PROTOCOL,
  SignallingHub,
  nodeWebSocketTransport,
  performanceClock,
  type IceServerConfig,
  type SignallingHubOptions,
} from 'fixedstep';
import {
  endpointAdmission,
  roomCapsFromEnv,
  type Admission,
  type OriginPolicy,
  type TrustedProxy,
} from '../http/admission.js';
import { WebSocketEndpoint, type UpgradeInfo } from '../http/websocket-endpoint.js';

/** How often the hub's liveness and time-outs are checked, ms. */
export const SIGNALLING_UPDATE_MS = 250;

/** Options of {@link attachSignalling}: the hub's, plus where and whom to let in. */
export interface SignallingEndpointOptions extends Partial<SignallingHubOptions> {
  /** URL path of the WebSocket endpoint: a room is at `<path>/<room>`. Default `/signal`. */
  path?: string;
  /** The server's admission (shared by every surface). Default: one of its own. */
  admission?: Admission;
  /** Browser origins allowed to connect. Default `'same-origin'`. */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a proxy's header. Default: none. */
  trustProxy?: TrustedProxy;
  /**
   * Where options not given here are read from (`FIXEDSTEP_*`: origins, proxy, the room core's
   * caps), as for every surface. Default `process.env`; pass `{}` to ignore it.
   */
  env?: Readonly<Record<string, string | undefined>>;
}

/**
 * The STUN/TURN servers `FIXEDSTEP_ICE_SERVERS` names, as JSON — an array of `{ "urls": [...],
 * "username"?, "credential"? }` (a `urls` string is taken as one URL) — e.g.
 * `[{"urls":["stun:stun.example.org:3478"]}]`. Unset: none. Anything else throws an Error naming
 * the variable and what is wrong.
 */
export function iceServersFromEnv(env: Readonly<Record<string, string | undefined>>): {
  iceServers?: IceServerConfig[];
} {
  const text = env.FIXEDSTEP_ICE_SERVERS?.trim();
  if (!text) return {};
  const bad = (why: string): never => {
    throw new Error(
      `FIXEDSTEP_ICE_SERVERS: ${why} (give a JSON array like [{"urls":["stun:host:3478"]}])`,
    );
  };
  let list: unknown;
  try {
    list = JSON.parse(text);
  } catch {
    return bad('not JSON');
  }
  if (!Array.isArray(list)) return bad('not an array');
  const servers = list.map((item: unknown, i): IceServerConfig => {
    const o = item as Record<string, unknown> | null;
    if (typeof o !== 'object' || o === null) return bad(`entry ${i} is not an object`);
    const urls = typeof o.urls === 'string' ? [o.urls] : o.urls;
    if (!Array.isArray(urls) || urls.length === 0 || urls.some((u) => typeof u !== 'string')) {
      return bad(`entry ${i} has no urls (strings)`);
    }
    for (const key of ['username', 'credential'] as const) {
      if (o[key] !== undefined && typeof o[key] !== 'string')
        bad(`entry ${i}'s ${key} is not a string`);
    }
    return {
      urls: urls as string[],
      ...(typeof o.username === 'string' ? { username: o.username } : {}),
      ...(typeof o.credential === 'string' ? { credential: o.credential } : {}),
    };
  });
  return { iceServers: servers };
}

/** Signalling attached to an HTTP server (see {@link attachSignalling}). */
export class SignallingEndpoint extends WebSocketEndpoint {
  readonly hub: SignallingHub;
  private readonly timer: ReturnType<typeof setInterval>;

  constructor(server: http.Server, options: SignallingEndpointOptions = {}) {
    const { env = process.env, ...given } = options;
    const {
      path = '/signal',
      admission,
      allowedOrigins,
      trustProxy,
      ...hubOptions
    } = { ...roomCapsFromEnv(env), ...iceServersFromEnv(env), ...given };
    const clock = hubOptions.clock ?? performanceClock();
    const hub = new SignallingHub({ ...hubOptions, clock });
    super(server, {
      path,
      // The room in the URL lets a balancer send a room's host and joiners to one process.
      rooms: 'required',
      maxPayload: SIGNAL_PROTOCOL.largest('client', {
        ...SIGNAL_PROTOCOL.limits,
        ...hubOptions.limits,
      }),
      protocol: SIGNAL_PROTOCOL,
      admission: endpointAdmission(
        {
          ...(admission !== undefined ? { admission } : {}),
          ...(allowedOrigins !== undefined ? { allowedOrigins } : {}),
          ...(trustProxy !== undefined ? { trustProxy } : {}),
        },
        env,
      ),
    });
    this.hub = hub;
    this.timer = setInterval(() => {
      hub.update(clock.now());
    }, SIGNALLING_UPDATE_MS);
    this.timer.unref();
  }

  /**
   * Drain before a shutdown: no new rooms, waiting hosts closed, rooms with peers kept until they
   * have left or `timeoutMs` has passed (then `SHUTDOWN`). Resolves when no room is left.
   */
  drain(timeoutMs?: number): Promise<void> {
    return this.hub.drain(timeoutMs === undefined ? {} : { timeoutMs });
  }

  protected connected(ws: WebSocket, info: UpgradeInfo): void {
    this.hub.accept(nodeWebSocketTransport(ws), info);
  }

  protected stop(): void {
    clearInterval(this.timer);
    this.hub.close();
  }
}

/**
 * Attaches WebRTC signalling to `server` at `path` (default `/signal`; a room at `/signal/<room>`),
 * beside the relay's `/ws`: WebSocket upgrades there become {@link SignallingHub} connections
 * (binary frames, at most one tunnelled relay message in size), admitted as every surface is. The
 * STUN/TURN servers to announce are `iceServers` (see docs/webrtc.md).
 */
export function attachSignalling(
  server: http.Server,
  options: SignallingEndpointOptions = {},
): SignallingEndpoint {
  return new SignallingEndpoint(server, options);
}
