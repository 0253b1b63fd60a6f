/**
 * The server side of signalling, on the room core: rooms of one host and up to 15 joiners who
 * bring the room's invite; offers, answers and candidates — and tunnelled game messages when a
 * direct connection failed — forwarded between a joiner and its host with the sender's peer id
 * stamped by the server. Transport-agnostic (`attachSignalling` in `@fixedstep/server` puts it on
 * `/signal/<room>`); it never reads SDP or game bytes beyond their size.
 * @module
 */
import type { Clock } from '../../time/drivers.js';
import { RoomHost } from '../room/host.js';
import type { HostEvent, HostStats, RoomContext } from '../room/host-types.js';
import type { RoomHostOptions } from '../room/options.js';
import { Member, Room, type MemberInit, type SeatRequest } from '../room/room.js';
import { sameToken } from '../room/tokens.js';
import type { LeaveReason, NetErrorCode } from '../wire/common.js';
import {
  DEFAULT_SIGNAL_LIMITS,
  MAX_SIGNAL_PEERS,
  SIGNAL_PROTOCOL,
  type IceServerConfig,
  type SignalLimits,
  type SignalMessage,
} from './signal-messages.js';

/**
 * A host waiting for its joiners keeps its room this long (they may be friends on the way; at
 * capacity a waiting room makes way sooner, as every room kind's does). A room whose peers have
 * connected directly is as quiet — their game goes peer to peer, not through here — so this is
 * also how long a signalling room may go without a signal before it closes (`IDLE`): the peers
 * already connected play on; a later joiner finds no room.
 */
export const SIGNAL_WAITING_TTL_MS = 600_000;

/** Options of a {@link SignallingHub}: the room core's, and the ICE servers to announce. */
export interface SignallingHubOptions extends RoomHostOptions {
  /** The clock of rates and timeouts (ms). */
  clock: Clock;
  /**
   * STUN/TURN servers announced to every host and joiner in `joined` (clients may override them).
   * Default none: peers then connect only where their host addresses reach each other.
   */
  iceServers?: IceServerConfig[];
  limits?: Partial<SignalLimits>;
  /** Rooms made and removed, joins, leaves, drops. */
  onEvent?: (event: HostEvent) => void;
}

/** Counters of a hub. */
export interface SignallingStats extends HostStats {
  /** Tunnelled messages forwarded (the fallback path). */
  tunnelled: number;
}

/** One peer-to-peer room: its host in seat 0, joiners in seats 1 … 15. */
class SignalRoom extends Room<Member> {
  constructor(
    name: string,
    number: number,
    creator: string,
    now: number,
    tokens: () => Uint8Array,
    private readonly ctx: RoomContext<Member, SignalMessage>,
    private readonly hub: { iceServers: IceServerConfig[]; tunnelled(): void },
  ) {
    super(name, number, MAX_SIGNAL_PEERS + 1, creator, now, tokens(), tokens);
  }

  /** Seat 0 for the host that makes the room; any other seat for a joiner with the invite. */
  override seat(m: Member, request: SeatRequest): [NetErrorCode, string] | undefined {
    let slot = 0;
    if (request.slot !== 0) {
      if (request.token === undefined || !sameToken(request.token, this.invite)) {
        return ['BAD_TOKEN', `joining room ${this.name} takes its invite token`];
      }
      slot = this.seats.findIndex((s, i) => i > 0 && s.member === undefined);
      if (slot < 0) return ['ROOM_FULL', `room ${this.name} has ${MAX_SIGNAL_PEERS} peers`];
    }
    this.seats[slot]!.member = m;
    m.slot = slot;
    m.peer = slot;
    return undefined;
  }

  /** A peer who left may join again with the invite: nothing is held for it. */
  override vacate(m: Member, reason: LeaveReason, now: number): void {
    super.vacate(m, reason, now, 0);
  }

  protected replaced(): void {
    // Seats here have no reconnect tokens: nobody is replaced.
  }

  welcome(m: Member): void {
    m.state = 'member';
    this.ctx.send(m, {
      type: 'joined',
      room: this.name,
      peer: m.peer,
      // The host hands the invite to the people it invites; a joiner already has it.
      invite: m.peer === 0 ? this.invite : new Uint8Array(0),
      iceServers: this.hub.iceServers,
    } satisfies SignalMessage);
    if (m.peer !== 0) {
      this.state = 'running';
      const host = this.seats[0]!.member;
      if (host) this.ctx.send(host, { type: 'peer', peer: m.peer } satisfies SignalMessage);
    }
    this.ctx.emit({ type: 'join', room: this.name, peer: m.peer, slot: m.slot, late: false });
  }

  onMessage(m: Member, message: { type: string }, now: number): void {
    const msg = message as SignalMessage;
    if (msg.type !== 'signal' && msg.type !== 'data') {
      this.ctx.drop(m, 'UNEXPECTED', `a ${msg.type} in a room`);
      return;
    }
    // The host speaks to any joiner, a joiner to the host only.
    const target =
      m.peer === 0
        ? this.seats[msg.peer]?.member
        : msg.peer === 0
          ? this.seats[0]!.member
          : undefined;
    if (target === undefined || target === m) {
      if (msg.type === 'signal') {
        this.ctx.send(m, {
          type: 'error',
          code: 'NO_PEER',
          fatal: false,
          message: `no peer ${msg.peer} in room ${this.name}`,
        } satisfies SignalMessage);
      }
      return;
    }
    if (msg.type === 'data') this.hub.tunnelled();
    this.lastPlayAt = now;
    this.ctx.send(target, { ...msg, peer: m.peer });
  }

  onLeave(m: Member, reason: LeaveReason): void {
    this.ctx.emit({ type: 'leave', room: this.name, peer: m.peer, reason });
    if (m.peer === 0 && !this.closing) {
      // The host is gone: its joiners are told, and the room closes.
      for (const p of this.connections())
        this.ctx.send(p, { type: 'leave', peer: 0 } satisfies SignalMessage);
      this.ctx.closeRoom(this, 'NO_ROOM', `the host of room ${this.name} left`);
      return;
    }
    const host = this.seats[0]!.member;
    if (host) this.ctx.send(host, { type: 'leave', peer: m.peer } satisfies SignalMessage);
  }

  advance(): void {
    // Nothing runs in a signalling room between messages.
  }
}

/**
 * Signalling rooms by name, with every protection of the room core: a join deadline, caps per
 * address and in total (1 000 hosts from one address get `ADDRESS_LIMIT` after the eighth), rates,
 * liveness (quiet members are pinged; a `SignalClient` answers), the invite for joiners, waiting
 * and idle rooms closed — and at capacity, rooms where nothing has been said make way first.
 */
export class SignallingHub extends RoomHost<Member, SignalRoom, SignalMessage> {
  declare readonly stats: SignallingStats;
  /** The ICE servers announced to clients. */
  readonly iceServers: readonly IceServerConfig[];
  private readonly limits: SignalLimits;

  constructor(options: SignallingHubOptions) {
    super(
      'SignallingHub',
      options.clock,
      {
        waitingRoomTtlMs: SIGNAL_WAITING_TTL_MS,
        idleRoomTtlMs: SIGNAL_WAITING_TTL_MS,
        ...options,
        rate: {
          // A host tunnelling for 15 peers at 60 Hz sends ~900 messages a second.
          messagesPerSecond: 1200,
          messageBurst: 2400,
          bytesPerSecond: 512 * 1024,
          byteBurst: 4 << 20,
          ...options.rate,
        },
      },
      SIGNAL_PROTOCOL,
      options.onEvent,
    );
    this.stats.tunnelled = 0;
    this.iceServers = options.iceServers ?? [];
    this.limits = { ...DEFAULT_SIGNAL_LIMITS, ...options.limits };
    // Refuse a bad configuration here, not at the first client.
    SIGNAL_PROTOCOL.encode({
      type: 'joined',
      room: 'x',
      peer: 0,
      invite: new Uint8Array(0),
      iceServers: [...this.iceServers],
    });
  }

  /** The rooms: name, and the peer ids present (0 is the host). */
  roomList(): { room: string; peers: number[] }[] {
    return [...this.rooms.values()].map((r) => ({
      room: r.name,
      peers: [...r.connections()].map((m) => m.peer).sort((a, b) => a - b),
    }));
  }

  protected override decodeLimits(): object {
    return this.limits;
  }

  protected createMember(init: MemberInit): Member {
    return new Member(init);
  }

  protected onJoinMessage(m: Member, message: SignalMessage, now: number): boolean {
    if (message.type !== 'host' && message.type !== 'join') return false;
    if (m.state !== 'new') return true;
    const name = message.room;
    if (message.type === 'join') {
      if (!this.rooms.has(name)) {
        if (m.urlRoom !== undefined && m.urlRoom !== name) {
          this.drop(m, 'WRONG_ROOM', `this connection is for room ${m.urlRoom}, not ${name}`);
        } else {
          this.drop(m, 'NO_ROOM', `no room ${name} (its host has not arrived or has left)`);
        }
        return true;
      }
      this.join(
        m,
        { room: name, role: 'player', token: message.invite, create: () => ['NO_ROOM', name] },
        now,
      );
      return true;
    }
    const hub = {
      iceServers: [...this.iceServers],
      tunnelled: () => {
        this.stats.tunnelled++;
      },
    };
    this.join(
      m,
      {
        room: name,
        role: 'player',
        slot: 0,
        create: (number, tokens) =>
          new SignalRoom(name, number, m.address, now, tokens, this.context, hub),
        fits: (room) => ['ROOM_TAKEN', `room ${room.name} already has a host`],
        created: (room) => {
          this.emit({ type: 'room-created', room: room.name, game: 'signalling', players: 1 });
        },
      },
      now,
    );
    return true;
  }
}
