/**
 * Quick match on the server's HTTP port: a WebSocket on `/match` queues, accepts the proposed match,
 * and gets the relay room and its ticket.
 * @module
 */
import type http from 'node:http';
import type { RawData, WebSocket } from 'ws';
import {
  LivenessClock,
  MATCH_PROTOCOL,
  ProtocolError,
  STALL_TOLERANCE_MS,
  TokenBucket,
  gameCatalog,
  performanceClock,
  refusalCode,
  type AnyGameDefinition,
  type Clock,
  type GameCatalog,
  type MatchClientMessage,
  type MatchServerMessage,
  type NetErrorCode,
} from 'fixedstep';
import { GAMES } from '@fixedstep/games';
import { endpointAdmission, type SurfaceOptions } from '../http/admission.js';
import { WebSocketEndpoint, type UpgradeInfo } from '../http/websocket-endpoint.js';
import { MatchQueue, DEFAULT_MATCHMAKING_LIMITS, type MatchmakingLimits } from './queue.js';
import { MatchTickets } from './tickets.js';

/** How often the queue is swept (proposals formed, deadlines checked), ms. */
export const MATCH_SWEEP_MS = 100;
/** A connection must send its request within this, ms. */
export const MATCH_REQUEST_TIMEOUT_MS = 10_000;
/** A matchmaking client sends a request, an accept and perhaps a cancel: a few messages at most. */
const MATCH_RATE = Object.freeze({
  messagesPerSecond: 5,
  messageBurst: 10,
  bytesPerSecond: 2048,
  byteBurst: 4096,
});

/** Options of {@link attachMatchmaking}. */
export interface MatchmakingEndpointOptions extends SurfaceOptions {
  /** URL path of the WebSocket endpoint. Default `/match`. */
  path?: string;
  /** The games that may be queued for. Default: the game registry (or `catalog`). */
  games?: readonly AnyGameDefinition[];
  /** The relay catalog to check requests against (takes precedence over `games`). */
  catalog?: GameCatalog;
  /** Queue bounds; missing fields take {@link DEFAULT_MATCHMAKING_LIMITS}. */
  limits?: Partial<MatchmakingLimits>;
  /** Time to accept a proposed match, ms (see {@link MatchQueue}). */
  acceptMs?: number;
  /** See {@link MatchQueue}'s fill window. */
  fillWindowMs?: number;
  /**
   * Whether players from one client address may be matched with each other. Default
   * `isLoopbackKey`: this machine's own tabs only, never any other address with itself.
   */
  matchesItself?: (address: string) => boolean;
  /**
   * Signs the tickets of matched players. Default: {@link MatchTickets} with
   * `FIXEDSTEP_MATCH_SECRET` — give the relay the same (`createServer` does).
   */
  tickets?: MatchTickets;
  /** How long a new connection may take to send its request, in ms. Default {@link MATCH_REQUEST_TIMEOUT_MS}. */
  requestTimeoutMs?: number;
  /** The clock waits are measured on. Default the process's monotonic clock. */
  clock?: Clock;
  /**
   * A gap between two sweeps longer than this is the server's own stall: only this much of it
   * counts against the waits (a ready check, a queue deadline), so players whose answers wait
   * unread in a stalled server's sockets are not dropped as no-shows. Default
   * `STALL_TOLERANCE_MS` (1 s), as the room core's liveness; `Infinity` for a manual clock whose
   * jumps are no stalls.
   */
  stallToleranceMs?: number;
  /** Random bytes for room names. Default `crypto.randomBytes`. */
  randomBytes?: (n: number) => Uint8Array;
}

/** One matchmaking connection, as the queue holds it. */
interface Connection {
  send(message: MatchServerMessage): void;
  /** Sends a last message and closes. */
  end(message: MatchServerMessage): void;
}

/** Quick match attached to an HTTP server (see {@link attachMatchmaking}). */
export class MatchEndpoint extends WebSocketEndpoint {
  /** The queue (e.g. its `size` for a dashboard). */
  readonly queue: MatchQueue<Connection>;
  /** The tickets it signs (the relay checks them with {@link MatchTickets.verify}). */
  readonly tickets: MatchTickets;
  private readonly clock: Clock;
  /** The server's responsive time, on which the queue's waits run (see `stallToleranceMs`). */
  private readonly liveness: LivenessClock;
  private readonly responsive: Clock;
  private readonly requestTimeoutMs: number;
  private readonly sweepTimer: ReturnType<typeof setInterval>;
  private open = 0;
  private draining = false;

  constructor(server: http.Server, options: MatchmakingEndpointOptions = {}) {
    super(server, {
      path: options.path ?? '/match',
      rooms: 'none',
      maxPayload: MATCH_PROTOCOL.largest('client'),
      protocol: MATCH_PROTOCOL,
      admission: endpointAdmission(options, options.env ?? process.env),
    });
    this.clock = options.clock ?? performanceClock();
    const clock = this.clock;
    const liveness = new LivenessClock(options.stallToleranceMs ?? STALL_TOLERANCE_MS);
    this.liveness = liveness;
    this.responsive = { now: () => liveness.at(clock.now()) };
    this.requestTimeoutMs = options.requestTimeoutMs ?? MATCH_REQUEST_TIMEOUT_MS;
    this.tickets = options.tickets ?? new MatchTickets();
    this.queue = new MatchQueue<Connection>({
      clock: this.responsive,
      catalog: options.catalog ?? gameCatalog(options.games ?? GAMES),
      limits: { ...DEFAULT_MATCHMAKING_LIMITS, ...options.limits },
      ...(options.acceptMs !== undefined ? { acceptMs: options.acceptMs } : {}),
      ...(options.fillWindowMs !== undefined ? { fillWindowMs: options.fillWindowMs } : {}),
      ...(options.matchesItself ? { matchesItself: options.matchesItself } : {}),
      ...(options.randomBytes ? { randomBytes: options.randomBytes } : {}),
    });
    this.sweepTimer = setInterval(() => {
      this.sweep();
    }, MATCH_SWEEP_MS);
    this.sweepTimer.unref();
  }

  /** Counters: the time the server's sweeps stalled (not counted against any wait), ms. */
  readonly stats = { stalledMs: 0 };

  /** Open matchmaking connections (waiting or not yet sent their request). */
  get connections(): number {
    return this.open;
  }

  private sweep(): void {
    this.liveness.update(this.clock.now());
    this.stats.stalledMs = this.liveness.stalledMs;
    const s = this.queue.sweep();
    for (const m of s.expired) m.data.end({ type: 'no-match' });
    for (const m of s.noShows) {
      m.data.end({
        type: 'error',
        code: 'NO_SHOW',
        fatal: true,
        message: 'the match was not accepted in time',
      });
    }
    this.requeue(s.requeued);
    for (const p of s.proposed) {
      const acceptMs = Math.max(1, Math.round(p.deadline - this.responsive.now()));
      for (const m of p.members) m.data.send({ type: 'found', players: p.players, acceptMs });
    }
  }

  protected connected(ws: WebSocket, info: UpgradeInfo): void {
    this.open++;
    const bucket = new TokenBucket(MATCH_RATE, this.clock.now());
    let ticket: number | undefined;
    let done = false;
    const connection: Connection = {
      send(message) {
        if (!done) ws.send(MATCH_PROTOCOL.encode(message));
      },
      end(message) {
        if (done) return;
        connection.send(message);
        done = true;
        clearTimeout(timer);
        ws.close(1000);
      },
    };
    const fail = (code: NetErrorCode, message: string) => {
      connection.end({ type: 'error', code, fatal: true, message });
    };
    // The request deadline runs on the responsive time too: a request that waited, unread, through
    // a stall of the server is not late.
    const openedAt = this.responsive.now();
    let timer: ReturnType<typeof setTimeout>;
    const arm = (ms: number) => {
      timer = setTimeout(() => {
        const left = this.requestTimeoutMs - (this.responsive.now() - openedAt);
        if (left > 0) arm(left);
        else fail('TIMEOUT', `no request within ${this.requestTimeoutMs} ms`);
      }, ms);
      timer.unref();
    };
    arm(this.requestTimeoutMs);
    ws.on('message', (data: RawData, isBinary: boolean) => {
      // A text frame was refused by the endpoint (the base class).
      if (done || !isBinary) return;
      const bytes = Array.isArray(data) ? Buffer.concat(data) : Buffer.from(data as Buffer);
      if (!bucket.take(bytes.length, this.clock.now())) {
        fail('RATE_LIMIT', 'too many messages');
        return;
      }
      let m: MatchClientMessage;
      try {
        m = MATCH_PROTOCOL.decode(bytes, { from: 'client' }) as MatchClientMessage;
      } catch (error) {
        if (!(error instanceof ProtocolError)) throw error;
        fail(refusalCode(error, bytes, MATCH_PROTOCOL.header), error.message);
        return;
      }
      if (m.type === 'cancel') {
        if (ticket !== undefined) this.requeue(this.queue.cancel(ticket));
        connection.end({ type: 'cancelled' });
      } else if (m.type === 'accept') {
        if (ticket === undefined) fail('UNEXPECTED', 'accept before a request');
        else this.accept(ticket);
      } else if (ticket !== undefined) {
        this.requeue(this.queue.cancel(ticket));
        fail('UNEXPECTED', 'one queue request per connection');
      } else if (this.draining) {
        fail('SHUTDOWN', 'this server is shutting down: queue again (another server takes it)');
      } else {
        const result = this.queue.join(m, info.address, connection);
        if (!result.ok) {
          fail(result.code, result.message);
          return;
        }
        ticket = result.ticket;
        clearTimeout(timer);
        connection.send({ type: 'queued', timeoutMs: result.timeoutMs });
      }
    });
    ws.on('close', () => {
      clearTimeout(timer);
      if (!done && ticket !== undefined) this.requeue(this.queue.cancel(ticket));
      done = true;
      this.open--;
    });
    ws.on('error', () => undefined);
  }

  /** The proposal of `ticket` is accepted by it; when by all, each member gets its ticket. */
  private accept(ticket: number): void {
    const match = this.queue.accept(ticket);
    if (match === undefined) return;
    for (const member of match.members) {
      member.data.end({
        type: 'matched',
        room: match.room,
        players: match.players,
        order: member.order,
        seed: match.seed,
        ticket: this.tickets.issue({
          room: match.room,
          game: match.game,
          gameVersion: match.gameVersion,
          players: match.players,
          seed: match.seed,
          slot: member.order,
        }),
      });
    }
  }

  /** Players whose proposal fell through are back in the queue: tell them, with the wait left. */
  private requeue(members: { ticket: number; data: Connection }[]): void {
    for (const m of members) {
      m.data.send({ type: 'queued', timeoutMs: this.queue.waitLeft(m.ticket) });
    }
  }

  /** Tell every waiting client `SHUTDOWN`. */
  /**
   * Drain before a shutdown: new requests get `SHUTDOWN` (the balancer sends the next ones to
   * another server: readiness is false meanwhile); players already waiting are matched as usual
   * until they are all gone or `timeoutMs` has passed. Call {@link close} after.
   */
  drain(timeoutMs = 25_000): Promise<void> {
    this.draining = true;
    const deadline = this.clock.now() + timeoutMs;
    return new Promise((resolve) => {
      const check = setInterval(() => {
        if (this.queue.size > 0 && this.clock.now() < deadline) return;
        clearInterval(check);
        resolve();
      }, MATCH_SWEEP_MS);
    });
  }

  protected stop(): void {
    clearInterval(this.sweepTimer);
    for (const c of this.queue.clear()) {
      c.end({
        type: 'error',
        code: 'SHUTDOWN',
        fatal: true,
        message: 'the server is shutting down',
      });
    }
  }
}

/**
 * Attaches the quick-match queue to `server` at `path` (default `/match`), beside the relay's
 * `/ws`: a client sends one `queue` request (see `quickMatch` in fixedstep), is told `queued`,
 * then `found` (a ready check: it must `accept` in time), and at last `matched` — the room, its
 * seed and this player's ticket — or `no-match`, `cancelled`, an `error`; then the server closes
 * the connection. Closing it first cancels. Admitted as every surface is; per connection a
 * small rate; one address holds at most `maxWaitingPerAddress` tickets, never matched together.
 */
export function attachMatchmaking(
  server: http.Server,
  options: MatchmakingEndpointOptions = {},
): MatchEndpoint {
  return new MatchEndpoint(server, options);
}
