/**
 * WebRTC signalling on the server's HTTP port: WebSocket upgrades on `/signal/<room>` become
 * connections to a {@link SignallingHub} (the room core's, in `fixedstep`).
 * @module
 */
import type http from 'node:http';
import {
  SIGNAL_PROTOCOL,
  SignallingHub,
  performanceClock,
  type IceServerConfig,
  type SignallingHubOptions,
} from 'fixedstep';
import { endpointAdmission, type SurfaceOptions } from '../http/admission.js';
import { RoomHostEndpoint, splitHostOptions } from '../http/room-host-endpoint.js';

/** How often the hub's liveness and time-outs are checked, ms. */
export const SIGNALLING_UPDATE_MS = 250;

/** Options of {@link attachSignalling}: the hub's, plus where and whom to let in. */
export interface SignallingEndpointOptions extends Partial<SignallingHubOptions>, SurfaceOptions {
  /** URL path of the WebSocket endpoint: a room is at `<path>/<room>`. Default `/signal`. */
  path?: string;
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
export class SignallingEndpoint extends RoomHostEndpoint<SignallingHub> {
  constructor(server: http.Server, options: SignallingEndpointOptions = {}) {
    const { env, surface, host } = splitHostOptions(options);
    const { path = '/signal', ...hubOptions } = { ...iceServersFromEnv(env), ...host };
    const clock = hubOptions.clock ?? performanceClock();
    const hub = new SignallingHub({ ...hubOptions, clock });
    super(
      server,
      {
        path,
        // The room in the URL lets a balancer send a room's host and joiners to one process.
        rooms: 'required',
        maxPayload: SIGNAL_PROTOCOL.largest('client', {
          ...SIGNAL_PROTOCOL.limits,
          ...hubOptions.limits,
        }),
        protocol: SIGNAL_PROTOCOL,
        admission: endpointAdmission(surface, env),
      },
      hub,
      clock,
      SIGNALLING_UPDATE_MS,
    );
  }

  /** The hub its connections go to. */
  get hub(): SignallingHub {
    return this.host;
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
