/**
 * Admission: who may open a WebSocket to any of the server's surfaces (`/ws`, `/state`, `/signal`,
 * `/match`) — in one place, so a new surface inherits it. A browser page of another site is
 * refused (the `Origin`); the client's address is its socket's, or a trusted proxy's header; one
 * address holds at most its share of the sockets of every surface together.
 * @module
 */
import type http from 'node:http';
import net from 'node:net';
import { AddressTally } from 'fixedstep';
import { RateLimiter } from './rate-limit.js';

/**
 * Where the client address of a connection is read when the server sits behind a proxy (HAProxy,
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

/**
 * Which browser pages may open a WebSocket (the upgrade's `Origin` header). `'same-origin'` (the
 * default everywhere): a page served from the host the upgrade is addressed to (the `Origin`'s
 * host equals the `Host` header — the lab served by the same server, directly or through a proxy
 * that keeps `Host`). A list: exactly those origins, e.g. `['https://play.example.com']`. `'any'`:
 * no check. Requests without an `Origin` (programs, not browsers) are always let through: the check
 * keeps other sites' pages from using a visitor's browser, it is no authentication.
 */
export type OriginPolicy = 'same-origin' | 'any' | readonly string[];

/** The default origin policy of every surface. */
export const DEFAULT_ORIGIN_POLICY: OriginPolicy = 'same-origin';

/** WebSockets at once from one address, all surfaces together: a household or a LAN party fits. */
export const MAX_SOCKETS_PER_ADDRESS = 64;
/** WebSockets at once, all surfaces together. */
export const MAX_SOCKETS = 10_000;
/**
 * New WebSockets a minute from one address, all surfaces together: a player's tabs and reconnects
 * fit many times over, and an address remaking its rooms to keep them younger than the room core's
 * grace (8 rooms, 5 s: 96 a minute) cannot.
 */
export const MAX_SOCKETS_PER_MINUTE = 60;

/**
 * The key the per-address caps count by: an IPv4 address as it is (also when written IPv4-mapped,
 * `::ffff:1.2.3.4`), an IPv6 address by its /64 prefix — one subscriber usually holds a whole /64,
 * so counting single IPv6 addresses would cap nothing.
 */
export function addressKey(ip: string): string {
  const mapped = /^::ffff:(\d+\.\d+\.\d+\.\d+)$/i.exec(ip);
  if (mapped) return mapped[1]!;
  if (!net.isIPv6(ip)) return ip;
  return `${expandIPv6(ip).slice(0, 4).join(':')}::/64`;
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
 * The client address of a request (an upgrade, a highscore submission), or a reason to refuse it
 * (400: a trusted proxy's header that does not end with an address).
 */
export function clientAddress(
  req: http.IncomingMessage,
  trust: TrustedProxy | undefined,
  proxies: net.BlockList | undefined = trust && trustedProxyList(trust),
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

/** A trusted proxy given as its header's name alone: the proxy on loopback. */
export function trustedProxy(trust: string | TrustedProxy | undefined): TrustedProxy | undefined {
  return typeof trust === 'string' ? { header: trust } : trust;
}

/**
 * The client address of an HTTP request, for rate limits: as {@link clientAddress}, and when a
 * trusted proxy's header holds no address, the socket's own.
 */
export function requestAddress(
  req: http.IncomingMessage,
  trust: string | TrustedProxy | undefined,
): string {
  const who = clientAddress(req, trustedProxy(trust));
  return 'address' in who ? who.address : addressKey(req.socket.remoteAddress ?? 'unknown');
}

/** Whether a request's `Origin` passes `policy` (see {@link OriginPolicy}). */
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
 * An {@link OriginPolicy} written as text (an environment variable, a command-line option):
 * `same-origin`, `any` (or `*`), or comma-separated origins like `https://game.example`. Throws an
 * Error naming `what` for anything else.
 */
export function parseOriginPolicy(text: string, what: string): OriginPolicy {
  const t = text.trim();
  if (t === 'same-origin') return 'same-origin';
  if (t === 'any' || t === '*') return 'any';
  const list = t.split(',').map((o) => o.trim());
  for (const o of list) {
    if (!isOrigin(o)) {
      throw new Error(
        `${what}: "${o}" is not an origin like https://game.example (or same-origin, or any)`,
      );
    }
  }
  return list;
}

/** Options of {@link Admission}. */
export interface AdmissionOptions {
  /** Browser origins allowed to open a WebSocket. Default {@link DEFAULT_ORIGIN_POLICY}. */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a proxy's header (see {@link TrustedProxy}). Default: none. */
  trustProxy?: TrustedProxy;
  /** WebSockets at once from one address, every surface together. Default {@link MAX_SOCKETS_PER_ADDRESS}. */
  maxSocketsPerAddress?: number;
  /** WebSockets at once, every surface together. Default {@link MAX_SOCKETS}. */
  maxSockets?: number;
  /** New WebSockets a minute from one address. Default {@link MAX_SOCKETS_PER_MINUTE}. */
  maxSocketsPerMinute?: number;
  /** The clock of the per-minute count (tests). Default `Date.now`. */
  now?: () => number;
}

/** An admitted upgrade: the client's address, and the release of its place once it closes. */
export interface Admitted {
  address: string;
  /** Frees the socket's place (call once, when the socket closes; later calls do nothing). */
  readonly release: () => void;
}

/** A refused upgrade: the HTTP status line and why. */
export interface Refused {
  status: string;
  reason: string;
}

/** The admission of every WebSocket surface of a server (see the module's comment). */
export class Admission {
  readonly allowedOrigins: OriginPolicy;
  readonly trustProxy: TrustedProxy | undefined;
  private readonly proxies: net.BlockList | undefined;
  private readonly sockets: AddressTally;
  private readonly opens: RateLimiter;
  /** Connections closed at once by {@link watch}: their address held its share. */
  refusedConnections = 0;

  constructor(options: AdmissionOptions = {}) {
    this.allowedOrigins = options.allowedOrigins ?? DEFAULT_ORIGIN_POLICY;
    this.trustProxy = options.trustProxy;
    this.proxies = options.trustProxy ? trustedProxyList(options.trustProxy) : undefined;
    this.sockets = new AddressTally(
      'sockets',
      options.maxSocketsPerAddress ?? MAX_SOCKETS_PER_ADDRESS,
      options.maxSockets ?? MAX_SOCKETS,
    );
    this.opens = new RateLimiter(
      options.maxSocketsPerMinute ?? MAX_SOCKETS_PER_MINUTE,
      60_000,
      options.now ?? Date.now,
    );
  }

  /** Open WebSockets, every surface together. */
  get open(): number {
    return this.sockets.total;
  }

  /**
   * Holds the TCP connections to `server` from one address to `perAddress` at once, from the moment
   * they connect — before any request is read, so half-sent requests (a slow handshake that never
   * finishes its headers) count too: a connection over the share is closed at once. A trusted
   * proxy's connections are not counted (every client behind it shares its address). Returns a
   * function that stops watching.
   */
  watch(server: net.Server, perAddress: number): () => void {
    if (!(Number.isInteger(perAddress) && perAddress >= 1)) {
      throw new RangeError(`connections per address must be an integer >= 1, got ${perAddress}`);
    }
    const tally = new AddressTally('connections', perAddress, Infinity);
    const onConnection = (socket: net.Socket) => {
      const peer = socket.remoteAddress;
      if (peer === undefined) return;
      const plain = /^::ffff:(\d+\.\d+\.\d+\.\d+)$/i.exec(peer)?.[1] ?? peer;
      if (this.proxies?.check(plain, net.isIPv4(plain) ? 'ipv4' : 'ipv6') === true) return;
      const key = addressKey(plain);
      if (tally.refusal(key) !== undefined) {
        this.refusedConnections++;
        socket.destroy();
        return;
      }
      tally.add(key);
      socket.once('close', () => {
        tally.remove(key);
      });
    };
    // Before the HTTP server's own listener: a connection over the share is never parsed.
    server.prependListener('connection', onConnection);
    return () => {
      server.off('connection', onConnection);
    };
  }

  /** The client address of a request (for the HTTP API's rate limits too), or why it is refused. */
  address(req: http.IncomingMessage): { address: string } | { error: string } {
    return clientAddress(req, this.trustProxy, this.proxies);
  }

  /**
   * Admits a WebSocket upgrade, or says why not: another site's page (403), a proxy header without
   * an address (400), this address's share taken or its new connections a minute used up (429),
   * the server's sockets taken (503).
   */
  admit(req: http.IncomingMessage): Admitted | Refused {
    if (!originAllowed(req, this.allowedOrigins)) {
      return { status: '403 Forbidden', reason: 'origin not allowed' };
    }
    const who = this.address(req);
    if ('error' in who) return { status: '400 Bad Request', reason: who.error };
    const refusal = this.sockets.refusal(who.address);
    if (refusal !== undefined) {
      return refusal[0] === 'ADDRESS_LIMIT'
        ? { status: '429 Too Many Requests', reason: refusal[1] }
        : { status: '503 Service Unavailable', reason: refusal[1] };
    }
    const wait = this.opens.check(who.address);
    if (wait > 0) {
      return {
        status: '429 Too Many Requests',
        reason: `${this.opens.limit} new connections a minute from one address: try again in ${wait} s`,
      };
    }
    this.opens.charge(who.address);
    this.sockets.add(who.address);
    let held = true;
    return {
      address: who.address,
      release: () => {
        if (!held) return;
        held = false;
        this.sockets.remove(who.address);
      },
    };
  }
}

/** How an endpoint attached on its own is admitted, when not given the server's admission. */
export interface EndpointAdmissionOptions {
  /** The server's admission, shared by every surface (`createServer` gives each its one). */
  admission?: Admission;
  /** Browser origins allowed to connect. Default `'same-origin'` (or `FIXEDSTEP_ALLOWED_ORIGINS`). */
  allowedOrigins?: OriginPolicy;
  /** Read the client address from a proxy's header. Default: none (or `FIXEDSTEP_PROXY_HEADER`). */
  trustProxy?: TrustedProxy;
}

/** What every surface's options (`attachRelay`, `attachStateSync` …) share: who is let in. */
export interface SurfaceOptions extends EndpointAdmissionOptions {
  /**
   * Where settings not given here are read from (`FIXEDSTEP_*`: origins, proxy, and for the room
   * hosts the room core's caps), so a container is configured without code. Default
   * `process.env`; pass `{}` to ignore it.
   */
  env?: Readonly<Record<string, string | undefined>>;
}

/**
 * The admission of an endpoint — the same rule on every surface: the server's when given, else one
 * of its own from `options`, then the environment (`FIXEDSTEP_ALLOWED_ORIGINS`,
 * `FIXEDSTEP_PROXY_*`, `FIXEDSTEP_MAX_SOCKETS_PER_ADDRESS`), then the defaults.
 */
export function endpointAdmission(
  options: EndpointAdmissionOptions,
  env: Readonly<Record<string, string | undefined>>,
): Admission {
  return (
    options.admission ??
    new Admission({
      ...admissionOptionsFromEnv(env),
      ...(options.allowedOrigins !== undefined ? { allowedOrigins: options.allowedOrigins } : {}),
      ...(options.trustProxy !== undefined ? { trustProxy: options.trustProxy } : {}),
    })
  );
}

/** Origin and proxy settings from environment variables (a bad value throws an Error naming it). */
export function admissionOptionsFromEnv(
  env: Readonly<Record<string, string | undefined>>,
): Partial<AdmissionOptions> {
  const out: Partial<AdmissionOptions> = {};
  const origins = env.FIXEDSTEP_ALLOWED_ORIGINS?.trim();
  if (origins) out.allowedOrigins = parseOriginPolicy(origins, 'FIXEDSTEP_ALLOWED_ORIGINS');
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
  const perAddress = env.FIXEDSTEP_MAX_SOCKETS_PER_ADDRESS;
  if (perAddress !== undefined && perAddress.trim() !== '') {
    out.maxSocketsPerAddress = envInteger(
      'FIXEDSTEP_MAX_SOCKETS_PER_ADDRESS',
      perAddress,
      1,
      1_000_000,
    );
  }
  const perMinute = env.FIXEDSTEP_MAX_SOCKETS_PER_MINUTE;
  if (perMinute !== undefined && perMinute.trim() !== '') {
    out.maxSocketsPerMinute = envInteger(
      'FIXEDSTEP_MAX_SOCKETS_PER_MINUTE',
      perMinute,
      1,
      1_000_000,
    );
  }
  return out;
}

/**
 * The room core's caps from environment variables, for every room host (relay, state sync,
 * signalling): `FIXEDSTEP_MAX_CONNECTIONS_PER_ADDRESS`, `FIXEDSTEP_MAX_ROOMS_PER_ADDRESS`,
 * `FIXEDSTEP_MAX_CONNECTIONS`, `FIXEDSTEP_MAX_ROOMS`.
 */
export function roomCapsFromEnv(
  env: Readonly<Record<string, string | undefined>>,
): Partial<
  Record<'maxConnectionsPerAddress' | 'maxRoomsPerAddress' | 'maxConnections' | 'maxRooms', number>
> {
  const out: Partial<
    Record<
      'maxConnectionsPerAddress' | 'maxRoomsPerAddress' | 'maxConnections' | 'maxRooms',
      number
    >
  > = {};
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

/** An integer environment variable within a range, or an Error naming it. */
export function envInteger(name: string, value: string, min: number, max: number): number {
  const n = Number(value.trim());
  if (!(Number.isInteger(n) && n >= min && n <= max)) {
    throw new Error(`${name}: "${value}" is not an integer from ${min} to ${max}`);
  }
  return n;
}

/** Whether `o` is an origin like `https://example.com`. */
export function isOrigin(o: string): boolean {
  try {
    const u = new URL(o);
    return (u.protocol === 'http:' || u.protocol === 'https:') && u.origin === o;
  } catch {
    return false;
  }
}
