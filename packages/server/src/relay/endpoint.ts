/**
 * The relay on the server's HTTP port: WebSocket upgrades on `/ws/<room>` become relay connections.
 * @module
 */
import type http from 'node:http';
import type { WebSocket } from 'ws';
import {
  RELAY_PROTOCOL,
  Relay,
  gameCatalog,
  nodeWebSocketTransport,
  performanceClock,
  type AnyGameDefinition,
  type GameCatalog,
  type RelayOptions,
} from 'fixedstep';
import { GAMES } from '@fixedstep/games';
import {
  endpointAdmission,
  roomCapsFromEnv,
  type Admission,
  type OriginPolicy,
  type TrustedProxy,
} from '../http/admission.js';
import { WebSocketEndpoint, type UpgradeInfo } from '../http/websocket-endpoint.js';

/** How often the relay's clock is advanced, in ms: about twice per 60 Hz tick. */
export const RELAY_UPDATE_MS = 8;

/** Options of {@link attachRelay}: the relay's, plus where, how often, and whom to let in. */
export interface RelayEndpointOptions extends Partial<Omit<RelayOptions, 'catalog'>> {
  /**
   * URL path of the WebSocket endpoint. Default `/ws`. A room is named in the URL — `/ws/<room>`
   * or `/ws?room=<room>` — so a load balancer can route by room without reading the protocol;
   * the connection's hello must then be for that room.
   */
  path?: string;
  /** Games the relay offers. Default: the game registry. */
  catalog?: GameCatalog;
  /** How often the relay's clock is advanced, in ms. Default {@link RELAY_UPDATE_MS}. */
  updateIntervalMs?: number;
  /** The server's admission (shared by every surface). Default: one of its own from the options below. */
  admission?: Admission;
  /** Browser origins allowed to connect (see {@link OriginPolicy}). Default `'same-origin'`. */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a proxy's header (see {@link TrustedProxy}). Default: none. */
  trustProxy?: TrustedProxy;
  /**
   * Where options not given here are read from (`FIXEDSTEP_*`: origins, proxy, the room core's
   * caps), so a container is configured without code. Default `process.env`; pass `{}` to ignore it.
   */
  env?: Readonly<Record<string, string | undefined>>;
}

/** The relay's catalog over the game registry (or `games`). */
export function registryCatalog(games: readonly AnyGameDefinition[] = GAMES): GameCatalog {
  return gameCatalog(games);
}

/** A {@link Relay} over the game registry (the catalog may be replaced, e.g. by test games). */
export function createRelay(
  options: Omit<RelayOptions, 'catalog'> & { catalog?: GameCatalog },
): Relay {
  return new Relay({ ...options, catalog: options.catalog ?? registryCatalog() });
}

/** The relay attached to an HTTP server (see {@link attachRelay}). */
export class RelayEndpoint extends WebSocketEndpoint {
  readonly relay: Relay;
  private readonly timer: ReturnType<typeof setInterval>;

  constructor(server: http.Server, options: RelayEndpointOptions = {}) {
    const { env = process.env, ...given } = options;
    const {
      path = '/ws',
      updateIntervalMs = RELAY_UPDATE_MS,
      admission,
      allowedOrigins,
      trustProxy,
      ...relayOptions
    } = { ...roomCapsFromEnv(env), ...given };
    const clock = relayOptions.clock ?? performanceClock();
    const relay = createRelay({ ...relayOptions, clock });
    super(server, {
      path,
      rooms: 'optional',
      maxPayload: RELAY_PROTOCOL.largest('client', {
        ...RELAY_PROTOCOL.limits,
        ...relayOptions.limits,
      }),
      protocol: RELAY_PROTOCOL,
      admission: endpointAdmission(
        {
          ...(admission !== undefined ? { admission } : {}),
          ...(allowedOrigins !== undefined ? { allowedOrigins } : {}),
          ...(trustProxy !== undefined ? { trustProxy } : {}),
        },
        env,
      ),
    });
    this.relay = relay;
    this.timer = setInterval(() => {
      relay.update(clock.now());
    }, updateIntervalMs);
    this.timer.unref();
  }

  protected connected(ws: WebSocket, info: UpgradeInfo): void {
    this.relay.accept(nodeWebSocketTransport(ws), info);
  }

  /**
   * Graceful shutdown (the HTTP server calls it on SIGTERM, before {@link close}): no new rooms,
   * waiting rooms closed, running matches go on for up to `timeoutMs` (default 25 000), then
   * `SHUTDOWN`. Resolves when no room is left.
   */
  drain(timeoutMs?: number): Promise<void> {
    return this.relay.drain(timeoutMs === undefined ? {} : { timeoutMs });
  }

  protected stop(): void {
    clearInterval(this.timer);
    this.relay.close();
  }
}

/**
 * Attaches the multiplayer relay to `server` at `path` (default `/ws`, and `/ws/<room>`), on the
 * same port as the lab: WebSocket upgrades on that path become relay connections (binary frames,
 * at most the largest message a client may send — `ws` refuses larger frames before buffering
 * them); other upgrade paths get a 404 unless another handler is listening. The relay runs on the
 * process's monotonic clock, advanced every `updateIntervalMs`. Admission is the server's (origin,
 * client address, the per-address share of sockets); options not given are read from the
 * environment.
 */
export function attachRelay(
  server: http.Server,
  options: RelayEndpointOptions = {},
): RelayEndpoint {
  return new RelayEndpoint(server, options);
}
