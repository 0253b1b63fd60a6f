/**
 * The quick-match queue: no sockets and no timers — the endpoint joins, accepts, cancels, and
 * sweeps now and then; time comes from an injected clock.
 * @module
 */
import { randomBytes as cryptoRandomBytes, randomInt } from 'node:crypto';
import {
  MATCH_ROOM_PREFIX,
  MAX_MATCH_TIMEOUT_MS,
  type GameCatalog,
  type Clock,
  type MatchQueueRequest,
  type NetErrorCode,
} from 'fixedstep';

/** Bounds of the quick-match queue. */
export interface MatchmakingLimits {
  /** Most players waiting at once, all games together. Default 1000. */
  maxWaiting: number;
  /**
   * Most players waiting at once from one client address (an IPv6 /64), who are never matched with
   * each other. Default 2 (two players of one household).
   */
  maxWaitingPerAddress: number;
  /** Longest wait granted, in ms; a longer request is shortened to it. Default 120 000. */
  maxTimeoutMs: number;
}

/** The defaults of {@link MatchmakingLimits}. */
export const DEFAULT_MATCHMAKING_LIMITS: Readonly<MatchmakingLimits> = Object.freeze({
  maxWaiting: 1000,
  maxWaitingPerAddress: 2,
  maxTimeoutMs: 120_000,
});

/** A proposed match must be accepted by all within this (clients accept at once). */
export const ACCEPT_MS = 3000;
/**
 * A match smaller than its oldest player's largest count forms only once that player has waited
 * this long: players who queue together fill rooms up to the largest count they all accept.
 */
export const FILL_WINDOW_MS = 1000;

/** Options of {@link MatchQueue}. */
export interface MatchQueueOptions {
  /** The clock deadlines are measured on (ms). Inject a `ManualClock` in tests. */
  clock: Clock;
  /** The games that may be queued for (the relay's catalog, so a match can be played there). */
  catalog: GameCatalog;
  /** Bounds; missing fields take {@link DEFAULT_MATCHMAKING_LIMITS}. */
  limits?: Partial<MatchmakingLimits>;
  /** Time to accept a proposed match, ms. Default {@link ACCEPT_MS}. */
  acceptMs?: number;
  /** See {@link FILL_WINDOW_MS}. Default {@link FILL_WINDOW_MS}. */
  fillWindowMs?: number;
  /**
   * `n` random bytes for room names. Default `crypto.randomBytes` (a name is then unguessable).
   */
  randomBytes?: (n: number) => Uint8Array;
  /** A random u32 for a match's seed. Default `crypto.randomInt`. */
  randomU32?: () => number;
  /**
   * Whether players from `address` (a caps key) may be matched with each other. Default
   * {@link isLoopbackKey}: only this machine's own tabs (a developer trying quick match in two
   * tabs); every other address is never matched with itself.
   */
  matchesItself?: (address: string) => boolean;
}

/**
 * Whether caps key `address` is this machine (127.0.0.0/8, or `::1`'s /64). A proxy on loopback
 * must be trusted for its header (see the server's `trustProxy`), or every client looks local.
 */
export function isLoopbackKey(address: string): boolean {
  return address.startsWith('127.') || address === '0:0:0:0::/64';
}

/** One player of a {@link Match}. */
export interface MatchMember<T> {
  /** The ticket number {@link MatchQueue.join} gave it. */
  ticket: number;
  /** What the caller queued with it (e.g. its connection). */
  data: T;
  /** Its seat in the match, 0 to `players` − 1, in the order they queued. */
  order: number;
}

/** Players matched together, each accepted: they should join relay room `room`. */
export interface Match<T> {
  /** A fresh room name: `qm-` and 24 base64url characters (18 random bytes). */
  room: string;
  /** How many players: within every member's range and the game's. */
  players: number;
  game: string;
  gameVersion: number;
  /** The room's seed. */
  seed: number;
  /** The members, by `order`. */
  members: MatchMember<T>[];
}

/** A match proposed to its players (the ready check). */
export interface Proposal<T> {
  id: number;
  players: number;
  /** Server time by which every member must accept. */
  deadline: number;
  members: MatchMember<T>[];
}

/** What {@link MatchQueue.join} answers. */
export type JoinResult =
  | { ok: true; ticket: number; timeoutMs: number }
  | { ok: false; code: NetErrorCode; message: string };

/** What a sweep did: proposals to announce, players to tell. */
export interface SweepResult<T> {
  /** New proposals: tell each member `found`. */
  proposed: Proposal<T>[];
  /** Players back in the queue, in their old place (another did not accept): tell them `queued`. */
  requeued: MatchMember<T>[];
  /** Players who did not accept in time: dropped (`NO_SHOW`). */
  noShows: MatchMember<T>[];
  /** Players whose wait ended without a match (`no-match`). */
  expired: MatchMember<T>[];
}

interface Entry<T> {
  ticket: number;
  key: string;
  game: string;
  gameVersion: number;
  address: string;
  minPlayers: number;
  maxPlayers: number;
  /** When it joined: its place in the queue, kept when a proposal falls through. */
  since: number;
  deadline: number;
  data: T;
  proposal: ProposalState<T> | undefined;
  accepted: boolean;
}

interface ProposalState<T> {
  id: number;
  players: number;
  deadline: number;
  entries: Entry<T>[];
}

/**
 * The quick-match queue. Players wait by game, version and input schema, each with a range of
 * player counts and a deadline; one address holds at most `maxWaitingPerAddress` of them, never in
 * one match. Every {@link sweep} forms matches among the waiting players, oldest first: for the
 * oldest, the largest count it accepts that enough others (from other addresses) accept too —
 * smaller only after it has waited `fillWindowMs` — and proposes them (a ready check): each must
 * {@link accept} within `acceptMs`. When all have, the match is made (a fresh room, its seed);
 * a player who did not is dropped, and the others go back to the queue in their old place.
 */
export class MatchQueue<T> {
  private readonly clock: Clock;
  private readonly catalog: GameCatalog;
  private readonly limits: MatchmakingLimits;
  private readonly acceptMs: number;
  private readonly fillWindowMs: number;
  private readonly randomBytes: (n: number) => Uint8Array;
  private readonly randomU32: () => number;
  private readonly matchesItself: (address: string) => boolean;
  private readonly entries = new Map<number, Entry<T>>();
  private readonly perAddress = new Map<string, number>();
  private nextTicket = 1;
  private nextProposal = 1;

  constructor(options: MatchQueueOptions) {
    this.clock = options.clock;
    this.catalog = options.catalog;
    this.limits = { ...DEFAULT_MATCHMAKING_LIMITS, ...options.limits };
    for (const [key, value] of Object.entries(this.limits)) {
      if (!Number.isInteger(value) || value < 1) {
        throw new RangeError(`matchmaking limit ${key} must be a positive integer, got ${value}`);
      }
    }
    this.acceptMs = options.acceptMs ?? ACCEPT_MS;
    this.fillWindowMs = options.fillWindowMs ?? FILL_WINDOW_MS;
    this.randomBytes = options.randomBytes ?? ((n) => cryptoRandomBytes(n));
    this.randomU32 = options.randomU32 ?? (() => randomInt(0, 2 ** 32 - 1));
    this.matchesItself = options.matchesItself ?? isLoopbackKey;
  }

  /** Players queued (waiting or in a proposal), all games together. */
  get size(): number {
    return this.entries.size;
  }

  /** How long ticket `ticket` may still wait, ms (0: not queued, or its wait is over). */
  waitLeft(ticket: number): number {
    const e = this.entries.get(ticket);
    return e === undefined ? 0 : Math.max(0, Math.round(e.deadline - this.clock.now()));
  }

  /** Players queued from client address `address`. */
  waitingFrom(address: string): number {
    return this.perAddress.get(address) ?? 0;
  }

  /**
   * Queues a player from `address` (the caps' key) with `data` for the caller. Refuses, with a code
   * and a message naming the value, a request for an unknown game or another version or input
   * schema, with a range outside the game's, or over a cap.
   */
  join(request: MatchQueueRequest, address: string, data: T): JoinResult {
    const { game: id, gameVersion, input, minPlayers, maxPlayers, timeoutMs } = request;
    const game = this.catalog(id, gameVersion);
    if ('code' in game) return { ok: false, code: game.code, message: game.message };
    if (game.input.id !== input) {
      return {
        ok: false,
        code: 'GAME_MISMATCH',
        message: `this server plays ${id} with input schema ${game.input.id}, not ${input}`,
      };
    }
    if (minPlayers < game.minPlayers || maxPlayers > game.maxPlayers) {
      return {
        ok: false,
        code: 'BAD_PLAYERS',
        message: `${id} is played by ${game.minPlayers} to ${game.maxPlayers} players, not ${minPlayers} to ${maxPlayers}`,
      };
    }
    if (this.entries.size >= this.limits.maxWaiting) {
      return {
        ok: false,
        code: 'QUEUE_FULL',
        message: `the queue is full (${this.limits.maxWaiting} waiting)`,
      };
    }
    if (this.waitingFrom(address) >= this.limits.maxWaitingPerAddress) {
      return {
        ok: false,
        code: 'ADDRESS_LIMIT',
        message: `at most ${this.limits.maxWaitingPerAddress} players wait from one address`,
      };
    }
    const granted = Math.min(timeoutMs, this.limits.maxTimeoutMs, MAX_MATCH_TIMEOUT_MS);
    const now = this.clock.now();
    const entry: Entry<T> = {
      ticket: this.nextTicket++,
      key: `${id}\n${gameVersion}\n${input}`,
      game: id,
      gameVersion,
      address,
      minPlayers,
      maxPlayers,
      since: now,
      deadline: now + granted,
      data,
      proposal: undefined,
      accepted: false,
    };
    this.entries.set(entry.ticket, entry);
    this.perAddress.set(address, this.waitingFrom(address) + 1);
    return { ok: true, ticket: entry.ticket, timeoutMs: granted };
  }

  /**
   * The player of `ticket` accepts its proposed match. When it was the last to, the match is made
   * and returned (its players have left the queue).
   */
  accept(ticket: number): Match<T> | undefined {
    const e = this.entries.get(ticket);
    const p = e?.proposal;
    if (e === undefined || p === undefined) return undefined;
    e.accepted = true;
    if (!p.entries.every((x) => x.accepted)) return undefined;
    for (const x of p.entries) this.remove(x);
    const first = p.entries[0]!;
    return {
      room: `${MATCH_ROOM_PREFIX}${Buffer.from(this.randomBytes(18)).toString('base64url')}`,
      players: p.players,
      game: first.game,
      gameVersion: first.gameVersion,
      seed: this.randomU32() >>> 0,
      members: p.entries.map((x, order) => ({ ticket: x.ticket, data: x.data, order })),
    };
  }

  /**
   * Takes a player out (cancelled, or its connection closed). A proposal it was in falls through:
   * the others are back in the queue. Returns those others (to tell them `queued`).
   */
  cancel(ticket: number): MatchMember<T>[] {
    const e = this.entries.get(ticket);
    if (e === undefined) return [];
    const back = e.proposal ? this.dissolve(e.proposal, [e]) : [];
    this.remove(e);
    return back;
  }

  /**
   * Expires waits and proposals past their deadline, then forms new proposals among the waiting
   * players (see the class comment). Call it now and then (the endpoint does, every 100 ms).
   */
  sweep(): SweepResult<T> {
    const now = this.clock.now();
    const out: SweepResult<T> = { proposed: [], requeued: [], noShows: [], expired: [] };
    const proposals = new Set<ProposalState<T>>();
    for (const e of this.entries.values()) if (e.proposal) proposals.add(e.proposal);
    for (const p of proposals) {
      if (now < p.deadline) continue;
      const late = p.entries.filter((x) => !x.accepted);
      out.requeued.push(...this.dissolve(p, late));
      for (const x of late) {
        this.remove(x);
        out.noShows.push(member(x, 0));
      }
    }
    for (const e of [...this.entries.values()]) {
      if (e.proposal === undefined && e.deadline <= now) {
        this.remove(e);
        out.expired.push(member(e, 0));
      }
    }
    const waiting = [...this.entries.values()]
      .filter((e) => e.proposal === undefined)
      .sort((a, b) => a.since - b.since || a.ticket - b.ticket);
    const taken = new Set<Entry<T>>();
    for (const oldest of waiting) {
      if (taken.has(oldest)) continue;
      const others = this.pick(oldest, waiting, taken, now);
      if (others === undefined) continue;
      const entries = [oldest, ...others];
      const p: ProposalState<T> = {
        id: this.nextProposal++,
        players: entries.length,
        deadline: now + this.acceptMs,
        entries,
      };
      for (const x of entries) {
        taken.add(x);
        x.proposal = p;
        x.accepted = false;
      }
      out.proposed.push({
        id: p.id,
        players: p.players,
        deadline: p.deadline,
        members: entries.map((x, order) => member(x, order)),
      });
    }
    return out;
  }

  /** Empties the queue, returning everyone who was in it (e.g. to tell them on shutdown). */
  clear(): T[] {
    const all = [...this.entries.values()].map((e) => e.data);
    this.entries.clear();
    this.perAddress.clear();
    return all;
  }

  /**
   * The players to propose with `oldest`: for the largest count it accepts that enough waiting
   * players of its game — each from an address of its own — accept too, the longest-waiting of
   * them; a smaller count only once `oldest` has waited the fill window. Undefined: not yet.
   */
  private pick(
    oldest: Entry<T>,
    waiting: Entry<T>[],
    taken: Set<Entry<T>>,
    now: number,
  ): Entry<T>[] | undefined {
    for (let n = oldest.maxPlayers; n >= oldest.minPlayers; n--) {
      const chosen: Entry<T>[] = [];
      const addresses = new Set([oldest.address]);
      for (const e of waiting) {
        if (chosen.length === n - 1) break;
        if (e === oldest || taken.has(e) || e.key !== oldest.key) continue;
        if (addresses.has(e.address) && !this.matchesItself(e.address)) continue;
        if (e.minPlayers > n || n > e.maxPlayers) continue;
        chosen.push(e);
        addresses.add(e.address);
      }
      if (chosen.length < n - 1) continue;
      if (n < oldest.maxPlayers && now - oldest.since < this.fillWindowMs) return undefined;
      return chosen;
    }
    return undefined;
  }

  /** Ends a proposal: everyone in it but `leaving` is back in the queue, in its old place. */
  private dissolve(p: ProposalState<T>, leaving: Entry<T>[]): MatchMember<T>[] {
    const back: MatchMember<T>[] = [];
    for (const x of p.entries) {
      x.proposal = undefined;
      x.accepted = false;
      if (!leaving.includes(x)) back.push(member(x, 0));
    }
    return back;
  }

  private remove(e: Entry<T>): void {
    if (!this.entries.delete(e.ticket)) return;
    const left = this.waitingFrom(e.address) - 1;
    if (left > 0) this.perAddress.set(e.address, left);
    else this.perAddress.delete(e.address);
  }
}

function member<T>(e: Entry<T>, order: number): MatchMember<T> {
  return { ticket: e.ticket, data: e.data, order };
}
