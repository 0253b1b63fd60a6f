/**
 * The relay on the server's HTTP port: WebSocket upgrades on `/ws/<room>` become relay connections.
 * @module
 */
import type http from 'node:http';
import {
  MAX_SEND_EVERY,
  RELAY_PROTOCOL,
  Relay,
  gameCatalog,
  performanceClock,
  type AnyGameDefinition,
  type GameCatalog,
  type RelayOptions,
} from 'fixedstep';
import { GAMES } from '@fixedstep/games';
import { endpointAdmission, type SurfaceOptions } from '../http/admission.js';
import { RoomHostEndpoint, splitHostOptions } from '../http/room-host-endpoint.js';

/** How often the relay's clock is advanced, in ms: about twice per 60 Hz tick. */
export const RELAY_UPDATE_MS = 8;

/** Options of {@link attachRelay}: the relay's, plus where, how often, and whom to let in. */
export interface RelayEndpointOptions
  extends Partial<Omit<RelayOptions, 'catalog'>>, SurfaceOptions {
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
}

/** The relay's catalog over the game registry (or `games`). */
export function registryCatalog(games: readonly AnyGameDefinition[] = GAMES): GameCatalog {
  return gameCatalog(games);
}

/**
 * `FIXEDSTEP_SEND_EVERY`: the relay's network rate, as ticks per send (`RelayOptions.sendEvery`,
 * 1 to 6); unset, 1. Anything else is refused at start.
 */
export function sendEveryFromEnv(
  env: Readonly<Record<string, string | undefined>>,
): number | undefined {
  const text = env.FIXEDSTEP_SEND_EVERY;
  if (text === undefined || text === '') return undefined;
  const n = Number(text);
  if (!(Number.isInteger(n) && n >= 1 && n <= MAX_SEND_EVERY)) {
    throw new RangeError(
      `FIXEDSTEP_SEND_EVERY must be an integer from 1 to ${MAX_SEND_EVERY}, got "${text}"`,
    );
  }
  return n;
}

/** A {@link Relay} over the game registry (the catalog may be replaced, e.g. by test games). */
export function createRelay(
  options: Omit<RelayOptions, 'catalog'> & { catalog?: GameCatalog },
): Relay {
  return new Relay({ ...options, catalog: options.catalog ?? registryCatalog() });
}

/** The relay attached to an HTTP server (see {@link attachRelay}). */
export class RelayEndpoint extends RoomHostEndpoint<Relay> {
  constructor(server: http.Server, options: RelayEndpointOptions = {}) {
    const { env, surface, host } = splitHostOptions(options);
    const { path = '/ws', updateIntervalMs = RELAY_UPDATE_MS, ...relayOptions } = host;
    const clock = relayOptions.clock ?? performanceClock();
    // The network rate may come from the environment (a deployment's choice, not the game's).
    const sendEvery = relayOptions.sendEvery ?? sendEveryFromEnv(env);
    const relay = createRelay({
      ...relayOptions,
      clock,
      ...(sendEvery !== undefined ? { sendEvery } : {}),
    });
    super(
      server,
      {
        path,
        rooms: 'optional',
        maxPayload: RELAY_PROTOCOL.largest('client', {
          ...RELAY_PROTOCOL.limits,
          ...relayOptions.limits,
        }),
        protocol: RELAY_PROTOCOL,
        admission: endpointAdmission(surface, env),
      },
      relay,
      clock,
      updateIntervalMs,
    );
  }

  /** The relay its connections play through. */
  get relay(): Relay {
    return this.host;
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
