import { randomBytes as cryptoRandomBytes } from 'node:crypto';
import {
  MAX_MATCH_TIMEOUT_MS,
  type Clock,
  type MatchErrorCode,
  type MatchQueueRequest,
  type RelayCatalog,
} from 'fixedstep';

/** Bounds of the quick-match queue. */
export interface MatchmakingLimits {
  /** Most players waiting at once, all games together. Default 1000. */
  maxWaiting: number;
  /** Most players waiting at once from one client address (an IPv6 /64). Default 4. */
  maxWaitingPerAddress: number;
  /** Longest wait granted, in ms; a longer request is shortened to it. Default 120 000. */
  maxTimeoutMs: number;
}

/** The defaults of {@link MatchmakingLimits}. */
export const DEFAULT_MATCHMAKING_LIMITS: Readonly<MatchmakingLimits> = Object.freeze({
  maxWaiting: 1000,
  maxWaitingPerAddress: 4,
  maxTimeoutMs: 120_000,
});

/** Options of {@link MatchQueue}. */
export interface MatchQueueOptions {
  /** The clock deadlines are measured on (ms). Inject a `ManualClock` in tests. */
  clock: Clock;
  /** The games that may be queued for (the relay's catalog, so a match can be played there). */
  catalog: RelayCatalog;
  /** Bounds; missing fields take {@link DEFAULT_MATCHMAKING_LIMITS}. */
  limits?: Partial<MatchmakingLimits>;
  /**
   * `n` random bytes for room names. Default `crypto.randomBytes` (a name is then unguessable:
   * knowing it is what lets a player into the match's room).
   */
  randomBytes?: (n: number) => Uint8Array;
}

/** One player of a {@link Match}. */
export interface MatchMember<T> {
  /** The ticket {@link MatchQueue.join} gave it. */
  ticket: number;
  /** What the caller queued with it (e.g. its connection). */
  data: T;
  /** Its place in the match, 0 to `players` − 1, in the order they queued. */
  order: number;
}

/** Players matched together: they are out of the queue, and should join relay room `room`. */
export interface Match<T> {
  /** A fresh room name: `qm-` and 24 base64url characters (18 random bytes). */
  room: string;
  /** How many players: within every member's range and the game's. */
  players: number;
  /** The game's id. */
  game: string;
  /** The game's version. */
  gameVersion: number;
  /** The members, by `order`. */
  members: MatchMember<T>[];
}

/** What {@link MatchQueue.join} answers. */
export type JoinResult<T> =
  | {
      ok: true;
      /** The player's ticket (to {@link MatchQueue.cancel} it). */
      ticket: number;
      /** The wait granted, in ms (the request's, at most `maxTimeoutMs`). */
      timeoutMs: number;
      /** The match this join completed, if it did (the new player is among its members). */
      match?: Match<T>;
    }
  | {
      ok: false;
      /** Why, as the `error` message's code. */
      code: MatchErrorCode;
      /** Why, in words naming the value or cap. */
      message: string;
    };

interface Entry<T> {
  ticket: number;
  key: string;
  address: string;
  minPlayers: number;
  maxPlayers: number;
  deadline: number;
  data: T;
}

/**
 * The quick-match queue: players wait by game, version and input schema, each with a range of
 * player counts and a deadline. No sockets and no timers: the caller joins, cancels, and calls
 * {@link expire} now and then; time comes from the injected clock.
 *
 * Matching: a match forms the moment a join makes one possible — among the players waiting for
 * the same game, version and input schema, with the new player in it (the queue held no possible
 * match before, so any new one contains the newcomer). Of the counts in the newcomer's range, the
 * largest that enough waiting players accept is taken, and of those players the longest-waiting.
 * So two players of 2–4 are matched as two at once; a player who needs 3 waits for a third.
 */
export class MatchQueue<T> {
  private readonly clock: Clock;
  private readonly catalog: RelayCatalog;
  private readonly limits: MatchmakingLimits;
  private readonly randomBytes: (n: number) => Uint8Array;
  private readonly buckets = new Map<string, Entry<T>[]>();
  private readonly byTicket = new Map<number, Entry<T>>();
  private readonly perAddress = new Map<string, number>();
  private nextTicket = 1;

  /** A queue over `options.catalog`'s games, on `options.clock`. */
  constructor(options: MatchQueueOptions) {
    this.clock = options.clock;
    this.catalog = options.catalog;
    this.limits = { ...DEFAULT_MATCHMAKING_LIMITS, ...options.limits };
    for (const [key, value] of Object.entries(this.limits)) {
      if (!Number.isInteger(value) || value < 1) {
        throw new RangeError(`matchmaking limit ${key} must be a positive integer, got ${value}`);
      }
    }
    this.randomBytes = options.randomBytes ?? ((n) => cryptoRandomBytes(n));
  }

  /** Players waiting, all games together. */
  get size(): number {
    return this.byTicket.size;
  }

  /** Players waiting from client address `address`. */
  waitingFrom(address: string): number {
    return this.perAddress.get(address) ?? 0;
  }

  /**
   * Queues a player from `address` (the caps' key) with `data` for the caller. Refuses, with a
   * code and a message naming the value, a request that is malformed (it may come straight from
   * the network), for an unknown game or another version or input schema, with a range outside
   * the game's, or over a cap. When this join completes a match, the match's players (this one
   * included) have left the queue and are in `match`.
   */
  join(request: MatchQueueRequest, address: string, data: T): JoinResult<T> {
    const fail = (code: MatchErrorCode, message: string): JoinResult<T> => ({
      ok: false,
      code,
      message,
    });
    const { game: id, gameVersion, input, minPlayers, maxPlayers, timeoutMs } = request;
    if (typeof id !== 'string' || typeof input !== 'string' || !Number.isInteger(gameVersion)) {
      return fail('BAD_MESSAGE', 'a request names a game, its version and its input schema');
    }
    if (!Number.isInteger(minPlayers) || !Number.isInteger(maxPlayers) || minPlayers > maxPlayers) {
      return fail(
        'BAD_PLAYERS',
        `minPlayers ${minPlayers} and maxPlayers ${maxPlayers} are not a range of player counts`,
      );
    }
    if (!Number.isInteger(timeoutMs) || timeoutMs < 1 || timeoutMs > MAX_MATCH_TIMEOUT_MS) {
      return fail(
        'BAD_MESSAGE',
        `timeoutMs must be 1 to ${MAX_MATCH_TIMEOUT_MS}, got ${timeoutMs}`,
      );
    }
    const game = this.catalog(id, gameVersion);
    if ('code' in game) return fail(game.code, game.message);
    if (game.input.id !== input) {
      return fail(
        'GAME_MISMATCH',
        `this server plays ${id} with input schema ${game.input.id}, not ${input}`,
      );
    }
    if (minPlayers < game.minPlayers || maxPlayers > game.maxPlayers) {
      return fail(
        'BAD_PLAYERS',
        `${id} is played by ${game.minPlayers} to ${game.maxPlayers} players, not ${minPlayers} to ${maxPlayers}`,
      );
    }
    if (this.byTicket.size >= this.limits.maxWaiting) {
      return fail('QUEUE_FULL', `the queue is full (${this.limits.maxWaiting} waiting)`);
    }
    if (this.waitingFrom(address) >= this.limits.maxWaitingPerAddress) {
      return fail(
        'TOO_MANY_FROM_ADDRESS',
        `at most ${this.limits.maxWaitingPerAddress} players wait from one address`,
      );
    }
    const granted = Math.min(timeoutMs, this.limits.maxTimeoutMs);
    const entry: Entry<T> = {
      ticket: this.nextTicket++,
      key: `${id}\n${gameVersion}\n${input}`,
      address,
      minPlayers,
      maxPlayers,
      deadline: this.clock.now() + granted,
      data,
    };
    const bucket = this.buckets.get(entry.key) ?? [];
    const others = this.pick(bucket, entry);
    if (others !== undefined) {
      const members = [...others, entry];
      for (const m of others) this.remove(m);
      return {
        ok: true,
        ticket: entry.ticket,
        timeoutMs: granted,
        match: {
          room: this.roomName(),
          players: members.length,
          game: id,
          gameVersion,
          members: members.map((m, order) => ({ ticket: m.ticket, data: m.data, order })),
        },
      };
    }
    bucket.push(entry);
    this.buckets.set(entry.key, bucket);
    this.byTicket.set(entry.ticket, entry);
    this.perAddress.set(address, this.waitingFrom(address) + 1);
    return { ok: true, ticket: entry.ticket, timeoutMs: granted };
  }

  /** Takes a waiting player out (cancelled, or its connection closed). False if not waiting. */
  cancel(ticket: number): boolean {
    const entry = this.byTicket.get(ticket);
    if (entry === undefined) return false;
    this.remove(entry);
    return true;
  }

  /** Takes out and returns the players whose wait has ended (deadline ≤ the clock's now). */
  expire(): MatchMember<T>[] {
    const now = this.clock.now();
    const out: MatchMember<T>[] = [];
    for (const entry of [...this.byTicket.values()]) {
      if (entry.deadline <= now) {
        this.remove(entry);
        out.push({ ticket: entry.ticket, data: entry.data, order: 0 });
      }
    }
    return out;
  }

  /** Empties the queue, returning everyone who was waiting (e.g. to tell them on shutdown). */
  clear(): T[] {
    const all = [...this.byTicket.values()].map((e) => e.data);
    this.buckets.clear();
    this.byTicket.clear();
    this.perAddress.clear();
    return all;
  }

  /** The waiting players to match with `entry`, oldest first, or undefined if none fit. */
  private pick(bucket: readonly Entry<T>[], entry: Entry<T>): Entry<T>[] | undefined {
    for (let n = entry.maxPlayers; n >= entry.minPlayers; n--) {
      if (n === 1) return [];
      const fits = bucket.filter((e) => e.minPlayers <= n && n <= e.maxPlayers);
      if (fits.length >= n - 1) return fits.slice(0, n - 1);
    }
    return undefined;
  }

  private remove(entry: Entry<T>): void {
    this.byTicket.delete(entry.ticket);
    const bucket = this.buckets.get(entry.key);
    if (bucket) {
      const i = bucket.indexOf(entry);
      if (i >= 0) bucket.splice(i, 1);
      if (bucket.length === 0) this.buckets.delete(entry.key);
    }
    const left = this.waitingFrom(entry.address) - 1;
    if (left > 0) this.perAddress.set(entry.address, left);
    else this.perAddress.delete(entry.address);
  }

  private roomName(): string {
    return `qm-${Buffer.from(this.randomBytes(18)).toString('base64url')}`;
  }
}
