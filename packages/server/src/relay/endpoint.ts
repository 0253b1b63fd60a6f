import type http from 'node:http';
import net from 'node:net';
import type { Duplex } from 'node:stream';
import { WebSocketServer } from 'ws';
import {
  DEFAULT_PROTOCOL_LIMITS,
  NAME_PATTERN,
  nodeWebSocketTransport,
  performanceClock,
  type Relay,
  type RelayCatalog,
  type RelayOptions,
} from 'fixedstep';
import { createRelay } from './catalog.js';
import { claimUpgradePaths, shouldRefuseUpgrade } from '../http/upgrade-paths.js';

/**
 * Where the client address of a connection is read when the relay sits behind a proxy (HAProxy,
 * nginx, a Kubernetes ingress): the proxy appends the address it saw to a header. The header is
 * believed only when the TCP peer is one of `proxies`; a connection straight from anyone else is
 * counted by its own socket address, whatever headers it sends.
 */
export interface TrustedProxy {
  /** The header, e.g. `x-forwarded-for` (HAProxy's `option forwardfor`, nginx's `$proxy_add_x_forwarded_for`). */
  header: string;
  /**
   * Addresses or CIDR ranges of the proxies, e.g. `['10.0.0.0/8']`. Default: loopback only
   * (`127.0.0.0/8`, `::1`).
   */
  proxies?: readonly string[];
  /**
   * How many proxies of yours append to the header: the client's address is the entry this far
   * from the end (entries before it may be anything the client wrote). Default 1.
   */
  hops?: number;
}

/** Which browser pages may open a relay connection (the upgrade's `Origin` header). */
export type OriginPolicy = 'same-origin' | 'any' | readonly string[];

/** Options of {@link attachRelay}: the relay's, plus where, how often, and whom to let in. */
export interface RelayEndpointOptions extends Partial<Omit<RelayOptions, 'catalog'>> {
  /**
   * URL path of the WebSocket endpoint. Default `/ws`. A room may be named in the URL —
   * `/ws/<room>` or `/ws?room=<room>` — so a load balancer can route by room without reading the
   * protocol; the connection's hello must then be for that room.
   */
  path?: string;
  /** Games the relay offers. Default: the game registry. */
  catalog?: RelayCatalog;
  /** How often the relay's clock is advanced, in ms. Default 8 (about twice per 60 Hz tick). */
  updateIntervalMs?: number;
  /**
   * Browser origins allowed to connect. `'same-origin'` (the default): a page served from the
   * host the upgrade is addressed to (the `Origin`'s host equals the `Host` header — so the lab
   * served by the same server, directly or through a proxy that keeps `Host`). A list: exactly
   * those origins, e.g. `['https://play.example.com']`. `'any'`: no check. Requests without an
   * `Origin` (programs, not browsers) are always let through: the check keeps other sites' pages
   * from using a visitor's browser, it is no authentication. A refused upgrade gets 403.
   */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a proxy's header (see {@link TrustedProxy}). Default: none. */
  trustProxy?: TrustedProxy;
  /**
   * Where options not given here are read from (see {@link relayEndpointOptionsFromEnv}), so a
   * container is configured without code. Default `process.env`; pass `{}` to ignore it.
   */
  env?: Readonly<Record<string, string | undefined>>;
}

/** A relay attached to an HTTP server, from {@link attachRelay}. */
export interface RelayEndpoint {
  readonly relay: Relay;
  readonly path: string;
  /**
   * Graceful shutdown (the HTTP server calls it on SIGTERM, before {@link close}): no new rooms,
   * waiting rooms closed, running matches go on for up to `timeoutMs` (default 25 000), then
   * `SHUTDOWN`. Resolves when no room is left. See `Relay.drain`.
   */
  drain(timeoutMs?: number): Promise<void>;
  /** Stop: close every connection (error SHUTDOWN), detach from the server, stop the timer. */
  close(): Promise<void>;
}

/**
 * Options from environment variables (each optional; a bad value throws an Error naming it):
 *
 * - `FIXEDSTEP_ALLOWED_ORIGINS`: `same-origin`, `*` (any), or a comma-separated list of origins;
 * - `FIXEDSTEP_PROXY_HEADER`: the trusted proxy's header, e.g. `x-forwarded-for`;
 * - `FIXEDSTEP_TRUSTED_PROXIES`: comma-separated addresses or CIDR ranges of the proxies
 *   (default loopback);
 * - `FIXEDSTEP_PROXY_HOPS`: how many proxies append to the header (default 1);
 * - `FIXEDSTEP_MAX_CONNECTIONS_PER_ADDRESS`, `FIXEDSTEP_MAX_ROOMS_PER_ADDRESS`,
 *   `FIXEDSTEP_MAX_CONNECTIONS`, `FIXEDSTEP_MAX_ROOMS`: the relay's caps.
 */
export function relayEndpointOptionsFromEnv(
  env: Readonly<Record<string, string | undefined>>,
): Partial<RelayEndpointOptions> {
  const out: Partial<RelayEndpointOptions> = {};
  const origins = env.FIXEDSTEP_ALLOWED_ORIGINS?.trim();
  if (origins) {
    if (origins === 'same-origin') out.allowedOrigins = 'same-origin';
    else if (origins === '*') out.allowedOrigins = 'any';
    else {
      const list = origins.split(',').map((o) => o.trim());
      for (const o of list) {
        if (!isOrigin(o)) {
          throw new Error(
            `FIXEDSTEP_ALLOWED_ORIGINS: "${o}" is not an origin like https://example.com`,
          );
        }
      }
      out.allowedOrigins = list;
    }
  }
  const header = env.FIXEDSTEP_PROXY_HEADER?.trim();
  if (header) {
    if (!/^[A-Za-z0-9-]{1,64}$/.test(header)) {
      throw new Error(`FIXEDSTEP_PROXY_HEADER: "${header}" is not a header name`);
    }
    const proxies = env.FIXEDSTEP_TRUSTED_PROXIES?.split(',')
      .map((p) => p.trim())
      .filter((p) => p !== '');
    const hops = env.FIXEDSTEP_PROXY_HOPS;
    out.trustProxy = {
      header,
      ...(proxies ? { proxies } : {}),
      ...(hops !== undefined ? { hops: envInteger('FIXEDSTEP_PROXY_HOPS', hops, 1, 16) } : {}),
    };
    trustedProxyList(out.trustProxy); // fail early on a bad range
  } else if (env.FIXEDSTEP_TRUSTED_PROXIES || env.FIXEDSTEP_PROXY_HOPS) {
    throw new Error(
      'FIXEDSTEP_TRUSTED_PROXIES and FIXEDSTEP_PROXY_HOPS need FIXEDSTEP_PROXY_HEADER',
    );
  }
  const caps = [
    ['FIXEDSTEP_MAX_CONNECTIONS_PER_ADDRESS', 'maxConnectionsPerAddress'],
    ['FIXEDSTEP_MAX_ROOMS_PER_ADDRESS', 'maxRoomsPerAddress'],
    ['FIXEDSTEP_MAX_CONNECTIONS', 'maxConnections'],
    ['FIXEDSTEP_MAX_ROOMS', 'maxRooms'],
  ] as const;
  for (const [name, key] of caps) {
    const v = env[name];
    if (v !== undefined && v.trim() !== '') out[key] = envInteger(name, v, 1, 1_000_000);
  }
  return out;
}

function envInteger(name: string, value: string, min: number, max: number): number {
  const n = Number(value.trim());
  if (!(Number.isInteger(n) && n >= min && n <= max)) {
    throw new Error(`${name}: "${value}" is not an integer from ${min} to ${max}`);
  }
  return n;
}

function isOrigin(o: string): boolean {
  try {
    const u = new URL(o);
    return (u.protocol === 'http:' || u.protocol === 'https:') && u.origin === o;
  } catch {
    return false;
  }
}

/**
 * The key the relay's per-address caps count by: an IPv4 address as it is (also when written
 * IPv4-mapped, `::ffff:1.2.3.4`), an IPv6 address by its /64 prefix — one subscriber usually
 * holds a whole /64, so counting single IPv6 addresses would cap nothing.
 */
export function addressKey(ip: string): string {
  const mapped = /^::ffff:(\d+\.\d+\.\d+\.\d+)$/i.exec(ip);
  if (mapped) return mapped[1]!;
  if (net.isIPv4(ip)) return ip;
  if (!net.isIPv6(ip)) return ip;
  const groups = expandIPv6(ip);
  return `${groups.slice(0, 4).join(':')}::/64`;
}

/** The eight 16-bit groups of an IPv6 address, in lower-case hex without leading zeros. */
function expandIPv6(ip: string): string[] {
  const zone = ip.indexOf('%');
  const bare = zone >= 0 ? ip.slice(0, zone) : ip;
  const [head = '', tail] = bare.split('::');
  const parse = (part: string): string[] => {
    if (part === '') return [];
    const out: string[] = [];
    for (const g of part.split(':')) {
      if (g.includes('.')) {
        // An embedded IPv4 tail: two groups.
        const b = g.split('.').map(Number);
        out.push(((b[0]! << 8) | b[1]!).toString(16), ((b[2]! << 8) | b[3]!).toString(16));
      } else out.push(parseInt(g, 16).toString(16));
    }
    return out;
  };
  const h = parse(head);
  const t = tail === undefined ? [] : parse(tail);
  const zeros = tail === undefined ? [] : new Array<string>(8 - h.length - t.length).fill('0');
  return [...h, ...zeros, ...t];
}

/** The proxies of `trust` as a block list (throws on an entry that is no address or range). */
export function trustedProxyList(trust: TrustedProxy): net.BlockList {
  const list = new net.BlockList();
  for (const p of trust.proxies ?? ['127.0.0.0/8', '::1']) {
    const [addr = '', bits] = p.split('/');
    const family = net.isIPv4(addr) ? 'ipv4' : net.isIPv6(addr) ? 'ipv6' : undefined;
    if (family === undefined) throw new Error(`trusted proxy "${p}" is not an address or range`);
    if (bits === undefined) list.addAddress(addr, family);
    else {
      const prefix = Number(bits);
      const max = family === 'ipv4' ? 32 : 128;
      if (!(Number.isInteger(prefix) && prefix >= 0 && prefix <= max)) {
        throw new Error(`trusted proxy "${p}": the prefix must be 0 to ${max}`);
      }
      list.addSubnet(addr, prefix, family);
    }
  }
  return list;
}

/**
 * The client address of an upgrade request, or a reason to refuse it (400: a trusted proxy's
 * header that does not end with an address).
 */
export function clientAddress(
  req: http.IncomingMessage,
  trust: TrustedProxy | undefined,
  proxies: net.BlockList | undefined,
): { address: string } | { error: string } {
  const peer = req.socket.remoteAddress ?? 'unknown';
  const plain = /^::ffff:(\d+\.\d+\.\d+\.\d+)$/i.exec(peer)?.[1] ?? peer;
  if (!trust || !proxies) return { address: addressKey(plain) };
  const family = net.isIPv4(plain) ? 'ipv4' : 'ipv6';
  if (!net.isIP(plain) || !proxies.check(plain, family)) return { address: addressKey(plain) };
  const raw = req.headers[trust.header.toLowerCase()];
  const value = Array.isArray(raw) ? raw.join(',') : raw;
  // A trusted peer that sends no header is a local tool, not a client behind the proxy.
  if (value === undefined) return { address: addressKey(plain) };
  const entries = value.split(',').map((e) => e.trim());
  const entry = entries[entries.length - (trust.hops ?? 1)];
  // An IPv6 entry may come bracketed, an IPv4 one with a port.
  const ip = entry
    ?.replace(/^\[(.*)\](?::\d+)?$/, '$1')
    .replace(/^(\d+\.\d+\.\d+\.\d+):\d+$/, '$1');
  if (ip === undefined || !net.isIP(ip)) {
    return { error: `${trust.header} does not end with a client address` };
  }
  return { address: addressKey(ip) };
}

/** Whether an upgrade's `Origin` passes `policy` (see {@link RelayEndpointOptions.allowedOrigins}). */
export function originAllowed(req: http.IncomingMessage, policy: OriginPolicy): boolean {
  const origin = req.headers.origin;
  if (origin === undefined || policy === 'any') return true;
  if (policy === 'same-origin') {
    try {
      return new URL(origin).host === req.headers.host?.toLowerCase();
    } catch {
      return false;
    }
  }
  return policy.includes(origin);
}

/**
 * Attaches the multiplayer relay to `server` at `path` (default `/ws`, and `/ws/<room>`), on the
 * same port as the lab: WebSocket upgrades on that path become relay connections (binary frames,
 * at most one snapshot-sized message — `ws` refuses larger frames before they are buffered);
 * other upgrade paths get a 404 unless another handler is listening. The relay runs on the
 * process's monotonic clock, advanced every `updateIntervalMs`. Upgrades from other sites' pages
 * (see `allowedOrigins`) get 403, a malformed room name in the URL 400; the client address (for
 * the per-address caps) is the socket's, or a trusted proxy's header. Options not given are read
 * from the environment ({@link relayEndpointOptionsFromEnv}).
 */
export function attachRelay(
  server: http.Server,
  options: RelayEndpointOptions = {},
): RelayEndpoint {
  const { env = process.env, ...given } = options;
  const merged: RelayEndpointOptions = { ...relayEndpointOptionsFromEnv(env), ...given };
  const {
    path = '/ws',
    updateIntervalMs = 8,
    allowedOrigins = 'same-origin',
    trustProxy,
    ...relayOptions
  } = merged;
  if (!/^\/[A-Za-z0-9_./-]*$/.test(path) || path.endsWith('/')) {
    throw new RangeError(`attachRelay: path must look like /ws, got "${path}"`);
  }
  const proxies = trustProxy ? trustedProxyList(trustProxy) : undefined;
  const clock = relayOptions.clock ?? performanceClock();
  const relay = createRelay({ ...relayOptions, clock });
  const wss = new WebSocketServer({
    noServer: true,
    maxPayload: relayOptions.limits?.maxMessageBytes ?? DEFAULT_PROTOCOL_LIMITS.maxMessageBytes,
    perMessageDeflate: false,
  });
  const refuse = (socket: Duplex, status: string, reason = '') => {
    socket.write(
      `HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Type: text/plain\r\n` +
        `Content-Length: ${Buffer.byteLength(reason)}\r\n\r\n${reason}`,
    );
    socket.destroy();
  };
  const ownsPath = (pathname: string) => pathname === path || pathname.startsWith(`${path}/`);
  const releasePaths = claimUpgradePaths(server, ownsPath, `${path}/room`);
  const onUpgrade = (req: http.IncomingMessage, socket: Duplex, head: Buffer) => {
    let url: URL;
    try {
      url = new URL(req.url ?? '/', 'http://relay');
    } catch {
      refuse(socket, '400 Bad Request', 'bad URL');
      return;
    }
    let room: string | undefined;
    if (url.pathname === path) {
      room = url.searchParams.get('room') ?? undefined;
    } else if (url.pathname.startsWith(`${path}/`)) {
      room = url.pathname.slice(path.length + 1);
    } else {
      // Another endpoint may own this path; answer only when none does.
      if (shouldRefuseUpgrade(server, ownsPath, url.pathname)) refuse(socket, '404 Not Found');
      return;
    }
    if (room !== undefined && !NAME_PATTERN.test(room)) {
      refuse(socket, '400 Bad Request', 'a room name is 1-32 of A-Z a-z 0-9 _ - .');
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
    wss.handleUpgrade(req, socket, head, (ws) => {
      relay.accept(nodeWebSocketTransport(ws), {
        address: who.address,
        ...(room !== undefined ? { room } : {}),
      });
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
    drain: (timeoutMs) => relay.drain(timeoutMs === undefined ? {} : { timeoutMs }),
    close: () =>
      (closed ??= new Promise<void>((resolve) => {
        clearInterval(timer);
        server.off('upgrade', onUpgrade);
        releasePaths();
        relay.close();
        for (const ws of wss.clients) ws.terminate();
        wss.close(() => {
          resolve();
        });
      })),
  };
}
