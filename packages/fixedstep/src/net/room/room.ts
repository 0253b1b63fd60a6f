/**
 * The room core: a connection ({@link Member}) and a room of player seats and spectators
 * ({@link Room}) — what the relay's rooms, state sync's rooms and signalling's rooms all are.
 * @module
 */
import type { Transport } from '../transport.js';
import type { LeaveReason, NetErrorCode } from '../wire/common.js';
import type { TokenBucket } from './bucket.js';
import { sameToken } from './tokens.js';

/** Where a connection is: before its join, being seated (a late joiner's snapshot), in, gone. */
/**
 * Where a connection is: `new` (no join yet), `claiming` (its token names a seat whose connection
 * still looks live: the host asks that one first), `joining`, `member`, `closed`.
 */
export type MemberState = 'new' | 'claiming' | 'joining' | 'member' | 'closed';

/** What the host knows of a new connection when it makes its {@link Member}. */
export interface MemberInit {
  /** The host's id for it (in drop events). */
  id: number;
  transport: Transport;
  /** Its client address: the key of the per-address caps. */
  address: string;
  /** The room its URL names, if any: its join must be for it. */
  urlRoom: string | undefined;
  /** Its message-rate bucket. */
  bucket: TokenBucket;
  /** Server time it connected (ms). */
  openedAt: number;
  /** When it connected, on the host's responsive clock (liveness and its join deadline). */
  heardAt: number;
  /** Its transport delivers every message in order or closes (see `ConnectionInfo.reliable`). */
  reliable: boolean;
}

/** One connection to a host, and its place in a room once it has one. */
export class Member {
  state: MemberState = 'new';
  /** Its player seat, or -1 (a spectator, or not seated). */
  slot = -1;
  /** Its id in the room: the seat for players, 64 and up for spectators; -1 before. */
  peer = -1;
  /** Display name from its join. */
  name = '';
  /** Violations so far (see the host's `maxStrikes`). */
  strikes = 0;
  /** When it last sent anything, on the host's responsive clock (liveness). */
  heardAt: number;
  /** When it was last pinged for liveness, on the responsive clock. */
  probedAt: number;
  /** Messages before its join (pings, inputs that overtook it) — bounded. */
  early = 0;
  /** Messages held for one frame at the end of the host's flush (see `RoomHost`). */
  outgoing: Uint8Array[] = [];
  /** Its room, once seated. */
  room: Room<Member> | undefined;
  /** When it connected, on the host's responsive clock (its join deadline counts from here). */
  readonly acceptedAt: number;
  /** The host's id for it (in drop events). */
  readonly id: number;
  readonly transport: Transport;
  /** Its client address: the key of the per-address caps. */
  readonly address: string;
  /** The room its URL names, if any: its join must be for it. */
  readonly urlRoom: string | undefined;
  readonly bucket: TokenBucket;
  /** Server time it connected (ms). */
  readonly openedAt: number;
  /**
   * Its transport delivers every message in order or closes (a WebSocket): what was sent to it
   * arrives, so nothing needs repeating and what it holds is known without its acknowledgement.
   */
  readonly reliable: boolean;

  constructor(init: MemberInit) {
    this.id = init.id;
    this.transport = init.transport;
    this.address = init.address;
    this.urlRoom = init.urlRoom;
    this.bucket = init.bucket;
    this.openedAt = init.openedAt;
    this.reliable = init.reliable;
    this.heardAt = init.heardAt;
    this.probedAt = init.heardAt;
    this.acceptedAt = init.heardAt;
  }
}

/** A player seat. */
export interface Seat<M extends Member> {
  member: M | undefined;
  /** Its reconnect token: whoever brings it takes the seat back. */
  token: Uint8Array;
  /**
   * After its player dropped (a lost connection, not a leave), the seat is held for that player
   * until this server time: only its token may take it (never a stranger) — 0 when not held.
   */
  heldUntil: number;
}

/** What a join asks of a room. */
export interface SeatRequest {
  role: 'player' | 'spectator';
  /** A player's reconnect token, a spectator's (or a signalling joiner's) invite. */
  token?: Uint8Array;
  /** The seat a match ticket names. */
  slot?: number;
}

/** The first spectator's peer id (players' peer ids are their seats). */
export const FIRST_SPECTATOR_PEER = 64;

/**
 * A room: player seats with reconnect tokens held for their players, spectators who need the
 * invite, and what the host needs to judge it — when it was made and by whom, whether anyone plays
 * in it. Each kind (the relay's, state sync's, signalling's) extends it with what happens inside.
 */
export abstract class Room<M extends Member> {
  readonly seats: Seat<M>[] = [];
  readonly spectators = new Set<M>();
  state: 'waiting' | 'running' | 'ended' = 'waiting';
  /** Its host is closing it: every member is being told why (one reason for all of them). */
  closing = false;
  /** Since when the room has had no member (server ms), or undefined. */
  emptySince: number | undefined;
  /** When a player last played in it (an input, a signal — not a keep-alive), server ms. */
  lastPlayAt: number;
  private nextSpectatorPeer = FIRST_SPECTATOR_PEER;

  constructor(
    readonly name: string,
    /** The host's number for it (the relay's messages carry it). */
    readonly number: number,
    /** Player seats. */
    readonly players: number,
    /** The address that made it (counted against that address's rooms). */
    readonly creator: string,
    /** Server time it was made (ms). */
    readonly createdAt: number,
    /** The invite token: spectators (or signalling's joiners) must bring it. */
    readonly invite: Uint8Array,
    tokens: () => Uint8Array,
    /** Made from a match ticket: its players come with tickets or reconnect tokens only. */
    readonly ticketed = false,
  ) {
    this.lastPlayAt = createdAt;
    for (let s = 0; s < players; s++) {
      this.seats.push({ member: undefined, token: tokens(), heldUntil: 0 });
    }
  }

  /** Player members (seated, welcomed). */
  *playerMembers(): Generator<M> {
    for (const s of this.seats) if (s.member?.state === 'member') yield s.member;
  }

  /** Members that receive the room's traffic: players, then spectators. */
  *members(): Generator<M> {
    yield* this.playerMembers();
    for (const c of this.spectators) if (c.state === 'member') yield c;
  }

  /** How many {@link members} there are. */
  countMembers(): number {
    let n = 0;
    for (const s of this.seats) if (s.member?.state === 'member') n++;
    for (const c of this.spectators) if (c.state === 'member') n++;
    return n;
  }

  /** Every connection in the room, joining or member. */
  *connections(): Generator<M> {
    for (const s of this.seats) if (s.member !== undefined) yield s.member;
    yield* this.spectators;
  }

  get empty(): boolean {
    return this.seats.every((s) => s.member === undefined) && this.spectators.size === 0;
  }

  /** The connection in the seat `token` opens, if any. */
  holderOf(token: Uint8Array): M | undefined {
    return this.seats.find((s) => sameToken(s.token, token))?.member;
  }

  get hasPlayers(): boolean {
    return this.seats.some((s) => s.member !== undefined);
  }

  /**
   * Finds `m` a place for `request`: a spectator seat with the invite; a player's own seat back
   * with its token (replacing a connection still in it: the host first makes sure that one is
   * gone, see `RoomHost`); the seat a ticket names; or the first seat neither taken nor held.
   * Returns why not, or undefined when seated (`m.slot`, `m.peer`).
   */
  seat(
    m: M,
    request: SeatRequest,
    now: number,
    limits: { maxSpectators: number },
  ): [NetErrorCode, string] | undefined {
    if (request.role === 'spectator') {
      if (request.token === undefined || !sameToken(request.token, this.invite)) {
        return ['BAD_TOKEN', `watching room ${this.name} takes its invite token`];
      }
      if (this.spectators.size >= limits.maxSpectators) {
        return ['ROOM_FULL', `${limits.maxSpectators} spectators already`];
      }
      m.slot = -1;
      m.peer = this.nextSpectatorPeer++;
      this.spectators.add(m);
      return undefined;
    }
    let slot: number;
    if (request.token !== undefined) {
      slot = this.seats.findIndex((s) => sameToken(s.token, request.token!));
      if (slot < 0) return ['BAD_TOKEN', 'no seat of this room has that token'];
    } else if (request.slot !== undefined) {
      slot = request.slot;
      const s = this.seats[slot];
      if (s === undefined) return ['BAD_TOKEN', `the ticket's seat ${slot} is not in this room`];
      // The ticket is the seat's secret: its holder may take it whenever it is empty.
      if (s.member !== undefined) return ['ROOM_FULL', `seat ${slot} is taken`];
    } else {
      if (this.ticketed) return ['BAD_TOKEN', `room ${this.name} seats players with tickets only`];
      slot = this.seats.findIndex((s) => s.member === undefined && s.heldUntil <= now);
      if (slot < 0) {
        const held = this.seats.some((s) => s.member === undefined);
        return [
          'ROOM_FULL',
          held
            ? `every free seat of room ${this.name} is held for the player who left it`
            : `all ${this.players} player seats are taken`,
        ];
      }
    }
    const s = this.seats[slot]!;
    const old = s.member;
    s.member = m;
    s.heldUntil = 0;
    m.slot = slot;
    m.peer = slot;
    if (old !== undefined && old !== m) this.replaced(old);
    return undefined;
  }

  /**
   * Frees `m`'s place. Once the match runs, a player's seat is held for `holdMs` when its
   * connection was lost (closed, timed out): a stranger cannot take it before its owner is back.
   * (Before the start nothing is lost: the seat is free for the next player at once.)
   */
  vacate(m: M, reason: LeaveReason, now: number, holdMs: number): void {
    if (m.slot >= 0) {
      const s = this.seats[m.slot];
      if (s?.member === m) {
        s.member = undefined;
        const lost = reason === 'closed' || reason === 'timeout';
        s.heldUntil = lost && this.state === 'running' ? now + holdMs : 0;
      }
    } else {
      this.spectators.delete(m);
    }
  }

  /** A connection was replaced in its seat by its player's reconnect: the host closes it. */
  protected abstract replaced(old: M): void;

  /** Welcome a member just seated (send what it needs; a late joiner may wait for a snapshot). */
  abstract welcome(m: M, now: number): void;

  /** One of its member's messages (its join and pings are the host's). */
  abstract onMessage(m: M, message: { type: string }, now: number): void;

  /** A member left (after {@link vacate}): tell the others, forget its state. */
  abstract onLeave(m: M, reason: LeaveReason, now: number): void;

  /** Advance to server time `now`: ticks, sends, timeouts of the room's own. */
  abstract advance(now: number): void;
}
