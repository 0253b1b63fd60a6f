/**
 * The room host: connections and rooms by name, with the protections every room kind inherits.
 * @module
 */
import type { Clock } from '../../time/drivers.js';
import type { Transport } from '../transport.js';
import { refusalCode, type LeaveReason, type NetErrorCode } from '../wire/common.js';
import { ProtocolError } from '../wire/error.js';
import type { DecodeOptions, WireProtocol } from '../wire/protocol.js';
import { AddressTally } from './admission.js';
import { HostRoomContext, type HostInternals } from './context.js';
import { FrameHold } from './frames.js';
import { TokenBucket } from './bucket.js';
import { LivenessClock } from './liveness.js';
import {
  HOUSEKEEPING_MS,
  MAX_EARLY_MESSAGES,
  roomHostSettings,
  type RoomHostOptions,
  type RoomHostSettings,
} from './options.js';
import type { Member, MemberInit, Room } from './room.js';
import {
  ADOPTED,
  type ConnectionInfo,
  type HostEvent,
  type HostStats,
  type JoinPlan,
  type RoomContext,
} from './host-types.js';
import { cryptoU32, newToken } from './tokens.js';

/**
 * Connections and rooms by name, with every protection in one place, so each room kind — the
 * relay's, state sync's, signalling's — inherits them: per-address and total caps on connections
 * and rooms (at capacity, rooms where nobody plays make way for a new one, the address holding the
 * most first); a join deadline; token-bucket rates; strikes; liveness judged on the server's
 * responsive time (its own stalls are not its members' silence); seats held for dropped players;
 * waiting, idle and empty rooms closed; drain for a graceful shutdown. Transport-agnostic: the
 * server attaches it to WebSocket connections, tests to simulated links.
 */
export abstract class RoomHost<
  M extends Member,
  R extends Room<M>,
  Msg extends { type: string },
  E extends { type: string } = never,
> {
  readonly stats: HostStats = {
    connections: 0,
    rooms: 0,
    waitingRooms: 0,
    addresses: 0,
    members: 0,
    messagesIn: 0,
    messagesOut: 0,
    bytesIn: 0,
    bytesOut: 0,
    dropped: {},
    probes: 0,
    evictions: 0,
    idleRooms: 0,
    stalledMs: 0,
  };
  readonly clock: Clock;
  protected readonly settings: RoomHostSettings;
  protected readonly liveness: LivenessClock;
  protected readonly rooms = new Map<string, R>();
  // Connections whose token names a seat still in use, waiting for its old connection's answer.
  private readonly claims = new Map<M, { room: R; plan: JoinPlan<R>; since: number; holder: M }>();
  private readonly random: () => number;
  private readonly members = new Map<number, M>();
  private readonly connectionTally: AddressTally;
  private readonly roomTally: AddressTally;
  private readonly answersPings: boolean;
  private readonly probes: boolean;
  private nextMemberId = 1;
  private nextRoomNumber = 1;
  private nextProbeId = 1;
  private lastHousekeeping = -Infinity;
  private closedHost = false;
  private drainState: { deadline: number; resolve: () => void; done: Promise<void> } | undefined;
  // One frame a member a flush (an update, one client message's handling).
  private readonly frames: FrameHold<M>;
  /** What rooms get to act on the host. */
  protected readonly context: RoomContext<M, Msg>;

  constructor(
    /** The name in option errors, e.g. `Relay`. */
    who: string,
    clock: Clock,
    options: RoomHostOptions,
    /** The protocol its connections speak. */
    protected readonly protocol: WireProtocol<Msg, object>,
    private readonly onEvent: ((e: HostEvent | E) => void) | undefined,
  ) {
    this.clock = clock;
    this.settings = roomHostSettings(who, options);
    this.random = options.randomU32 ?? cryptoU32;
    this.liveness = new LivenessClock(this.settings.stallToleranceMs);
    this.connectionTally = new AddressTally(
      'connections',
      this.settings.maxConnectionsPerAddress,
      this.settings.maxConnections,
    );
    this.roomTally = new AddressTally(
      'rooms',
      this.settings.maxRoomsPerAddress,
      this.settings.maxRooms,
    );
    this.frames = new FrameHold(protocol);
    this.answersPings = protocol.types.includes('pong');
    this.probes = protocol.types.includes('ping') && protocol.sender('ping') === 'both';
    // The host's protected parts, as its context calls them (see `context.ts`).
    this.context = new HostRoomContext(
      this as unknown as HostInternals<M, Msg>,
      this.settings,
      clock,
    );
  }

  // ------------------------------------------------------------------------------ public

  /**
   * Take a new connection. `info` says where it comes from (its address, for the per-address caps;
   * the room its URL names). Returns its id (in drop events), or -1 when it was refused
   * (`SERVER_FULL`, `ADDRESS_LIMIT`, or `SHUTDOWN` once closed).
   */
  accept(transport: Transport, info: ConnectionInfo = {}): number {
    const now = this.clock.now();
    const address = info.address ?? 'unknown';
    const refusal: [NetErrorCode, string] | undefined = this.closedHost
      ? ['SHUTDOWN', 'server shut down']
      : this.connectionTally.refusal(address);
    if (refusal !== undefined) {
      const [code, message] = refusal;
      this.count(code);
      this.emit({ type: 'drop', connection: -1, code, message });
      transport.send(this.protocol.encode(this.error(code, message, true)));
      transport.close(`${code}: ${message}`);
      return -1;
    }
    const live = this.liveness.at(now);
    const bucket = new TokenBucket(this.settings.rate, now);
    const m = this.createMember(
      {
        id: this.nextMemberId++,
        transport,
        address,
        urlRoom: info.room,
        bucket,
        openedAt: now,
        heardAt: live,
        reliable: info.reliable ?? transport.reliable === true,
      },
      info,
    );
    this.members.set(m.id, m);
    this.connectionTally.add(address);
    this.countConnections();
    transport.onMessage((bytes) => {
      try {
        this.frames.hold();
        try {
          this.onBytes(m, bytes);
        } finally {
          this.frames.release();
        }
      } catch (error) {
        // A bug must cost one connection, never the server.
        this.emit({ type: 'internal-error', connection: m.id, error });
        this.drop(m, 'INTERNAL', 'internal error');
      }
    });
    transport.onClose(() => {
      this.removeMember(m, 'closed');
    });
    return m.id;
  }

  /**
   * Advance to `now`: liveness (probe, then drop silent members), join deadlines, waiting, idle
   * and empty rooms, every room's own work (ticks, sends), and a drain's progress. Call it every
   * few milliseconds (the server does, every 8 ms).
   */
  update(now = this.clock.now()): void {
    this.frames.hold();
    try {
      this.advance(now);
    } finally {
      this.frames.release();
    }
  }

  private advance(now: number): void {
    this.liveness.update(now);
    this.stats.stalledMs = this.liveness.stalledMs;
    const housekeeping = now - this.lastHousekeeping >= HOUSEKEEPING_MS;
    if (this.claims.size > 0) this.settleClaims(now);
    if (housekeeping) {
      this.lastHousekeeping = now;
      this.checkLiveness(now);
      this.checkRooms(now);
    }
    // A room closed meanwhile leaves the map; a Map's iteration takes that in its stride.
    for (const room of this.rooms.values()) {
      try {
        room.advance(now);
      } catch (error) {
        this.roomFailed(room, error);
        continue;
      }
      // Draining: a room whose players have all gone is done.
      if (this.drainState && !room.hasPlayers && room.creator !== ADOPTED) {
        this.closeRoom(room, 'SHUTDOWN', 'server shutting down');
      }
    }
    if (housekeeping) this.countRooms();
    const d = this.drainState;
    if (d) {
      if (now >= d.deadline) {
        for (const room of [...this.rooms.values()]) {
          this.closeRoom(room, 'SHUTDOWN', 'server shutting down');
        }
      }
      if (this.rooms.size === 0) d.resolve();
    }
  }

  /**
   * A heartbeat of the stage in front of this host — what reads the clients' sockets and hands it
   * their bytes, such as the main thread of a server whose rooms run in a worker thread. Send one
   * every 100 ms or so (well within `stallToleranceMs`) once you send any: the host's responsive
   * time then also stops while that stage is stalled, so its members' silence meanwhile — their
   * messages waiting, unread, in its sockets — is not held against them.
   */
  heartbeat(now = this.clock.now()): void {
    this.liveness.upstream(now);
  }

  /** Whether {@link drain} was called: no new rooms are made. */
  get draining(): boolean {
    return this.drainState !== undefined;
  }

  /**
   * Graceful shutdown: from now on no room is made (a join that would make one gets `SHUTDOWN`:
   * the client should try another server); waiting rooms are closed at once; running rooms go on —
   * reconnects and invited spectators still join them — until their players have all left, or
   * until `timeoutMs` (default 25 000, inside Kubernetes' 30 s grace period) has passed, when their
   * members are told `SHUTDOWN`. Resolves when no room is left. {@link update} must keep running.
   */
  drain(options: { timeoutMs?: number } = {}): Promise<void> {
    if (this.drainState) return this.drainState.done;
    const timeoutMs = options.timeoutMs ?? 25_000;
    if (!(timeoutMs >= 0)) throw new RangeError(`drain: timeoutMs must be >= 0, got ${timeoutMs}`);
    let resolve!: () => void;
    const done = new Promise<void>((r) => (resolve = r));
    this.drainState = { deadline: this.clock.now() + timeoutMs, resolve, done };
    for (const room of [...this.rooms.values()]) {
      if (room.state === 'waiting') this.closeRoom(room, 'SHUTDOWN', 'server shutting down');
    }
    this.countRooms();
    if (this.rooms.size === 0) resolve();
    return done;
  }

  /** Close every connection (`SHUTDOWN`) and refuse new ones. */
  close(): void {
    this.closedHost = true;
    for (const m of [...this.members.values()]) {
      this.drop(m, 'SHUTDOWN', 'server shutting down', 'closed', false);
    }
    for (const room of [...this.rooms.values()]) this.removeRoom(room);
    this.drainState?.resolve();
  }

  /**
   * The invite token of a room (what its players get in their welcome), for the server's owner:
   * e.g. to hand a spectator link to an audience. A secret: anyone with it may watch the room.
   */
  invite(name: string): Uint8Array | undefined {
    return this.rooms.get(name)?.invite.slice();
  }

  /**
   * Serves a room made elsewhere (a room serving on its own): registered under its name, not
   * counted against any address.
   */
  protected adopt(room: R): void {
    this.rooms.set(room.name, room);
    this.countRooms();
  }

  /** The names of the rooms, in creation order. */
  roomNames(): string[] {
    return [...this.rooms.keys()];
  }

  // ------------------------------------------------------------------------------ for subclasses

  /** Makes the member object of a new connection (`info`: what its server said of it). */
  protected abstract createMember(init: MemberInit, info: ConnectionInfo): M;

  /**
   * A message from a connection that has no room yet: a join is handled (typically through
   * {@link join}) and true returned; anything else returns false (counted, and ignored up to
   * {@link MAX_EARLY_MESSAGES}: messages may overtake the join on an unordered link).
   */
  protected abstract onJoinMessage(m: M, message: Msg, now: number): boolean;

  /** The decode limits of the protocol (default: the protocol's own). Asked once. */
  protected decodeLimits(): object | undefined {
    return undefined;
  }

  // What every client message is decoded with: made once (every message of a match needs it).
  private clientDecode: DecodeOptions<object> | undefined;
  private decodeOptions(): DecodeOptions<object> {
    if (this.clientDecode === undefined) {
      const limits = this.decodeLimits();
      this.clientDecode = { from: 'client', ...(limits ? { limits } : {}) };
    }
    return this.clientDecode;
  }

  /**
   * Seats `m` in the room `plan` names — made first if it does not exist and admission allows
   * (never while draining; at capacity, an idle or long-waiting room of the address holding the
   * most makes way) — and welcomes it. A refusal drops the connection with its code.
   */
  protected join(m: M, plan: JoinPlan<R>, now: number): R | undefined {
    if (m.urlRoom !== undefined && m.urlRoom !== plan.room) {
      this.drop(m, 'WRONG_ROOM', `this connection is for room ${m.urlRoom}, not ${plan.room}`);
      return undefined;
    }
    let room = this.rooms.get(plan.room);
    if (room === undefined) {
      if (plan.role === 'spectator') {
        this.drop(m, 'BAD_HELLO', `no room ${plan.room} to watch`);
        return undefined;
      }
      const refusal = plan.mayCreate ?? this.admitRoom(m.address, now);
      if (refusal !== undefined) {
        this.drop(m, refusal[0], refusal[1], 'dropped', refusal[0] !== 'SHUTDOWN');
        return undefined;
      }
      const made = plan.create(this.nextRoomNumber++, () => newToken(this.context.randomU32));
      if (Array.isArray(made)) {
        this.drop(m, made[0], made[1]);
        return undefined;
      }
      room = made;
      this.rooms.set(room.name, room);
      this.roomTally.add(room.creator);
      this.countRooms();
      plan.created?.(room);
    } else {
      const wrong = plan.fits?.(room);
      if (wrong !== undefined) {
        this.drop(m, wrong[0], wrong[1]);
        return undefined;
      }
    }
    // A token for a seat whose connection was heard lately: the seat's owner reconnecting from a
    // new network (the old connection not dead yet), or someone who stole the token. Ask the old
    // connection; if it answers, it keeps its seat (see settleClaims).
    const holder =
      plan.token !== undefined && plan.role === 'player' ? room.holderOf(plan.token) : undefined;
    const live = this.liveness.at(now);
    if (
      holder !== undefined &&
      holder !== m &&
      live - holder.heardAt < 2 * this.settings.probeAfterMs
    ) {
      m.state = 'claiming';
      this.claims.set(m, { room, plan, since: live, holder });
      this.probe(holder, now);
      return undefined;
    }
    return this.seatIn(room, m, plan, now);
  }

  /** Seats `m` in `room` per `plan` and welcomes it; a refusal drops the connection. */
  private seatIn(room: R, m: M, plan: JoinPlan<R>, now: number): R | undefined {
    const refusal = room.seat(m, plan, now, { maxSpectators: this.settings.maxSpectators });
    if (refusal !== undefined) {
      this.drop(m, refusal[0], refusal[1]);
      return undefined;
    }
    room.emptySince = undefined;
    m.room = room;
    m.state = 'joining';
    room.welcome(m, now);
    return room;
  }

  /**
   * Decides the seats claimed by token (see `join`): the old connection answered since the claim
   * — a live player: the claimant is refused (`ROOM_FULL`); it closed, or stayed silent for a
   * probe interval — gone: the claimant takes the seat and the old one is replaced.
   */
  private settleClaims(now: number): void {
    const live = this.liveness.at(now);
    for (const [m, c] of this.claims) {
      if (m.state !== 'claiming') {
        this.claims.delete(m);
      } else if (this.rooms.get(c.room.name) !== c.room) {
        this.claims.delete(m);
        this.drop(m, 'NO_ROOM', `room ${c.room.name} has ended`);
      } else if (c.holder.state !== 'closed' && c.holder.heardAt > c.since) {
        this.claims.delete(m);
        this.drop(
          m,
          'ROOM_FULL',
          `seat ${c.holder.slot} is in use: its player is connected and answers (a reconnect takes ` +
            'the seat once that connection has closed or gone quiet)',
        );
      } else if (c.holder.state === 'closed' || live - c.since >= this.settings.probeAfterMs) {
        this.claims.delete(m);
        m.state = 'new';
        this.seatIn(c.room, m, c.plan, now);
      }
    }
  }

  /** Encodes and sends `message`. */
  protected send(m: M, message: Msg): void {
    this.sendBytes(m, this.protocol.encode(message));
  }

  protected sendBytes(m: M, bytes: Uint8Array): void {
    if (!m.transport.isOpen) return;
    this.stats.messagesOut++;
    this.stats.bytesOut += bytes.length;
    if (!this.frames.add(m, bytes)) m.transport.send(bytes);
  }

  /** Sends what is held for `m` now, as one frame (see `FrameHold`). */
  protected sendFrame(m: M): void {
    this.frames.send(m);
  }

  /** Sends a fatal error and closes; `count` false for shutdowns and replacements. */
  protected drop(
    m: M,
    code: NetErrorCode,
    message: string,
    reason: LeaveReason = 'dropped',
    count = true,
  ): void {
    if (m.state === 'closed') return;
    if (count) {
      this.count(code);
      this.emit({ type: 'drop', connection: m.id, code, message });
    }
    this.send(m, this.error(code, message, true));
    this.removeMember(m, reason);
    this.sendFrame(m);
    m.transport.close(`${code}: ${message}`);
  }

  /** A violation: the first is told (not fatal), more than `maxStrikes` drop the connection. */
  protected strike(m: M, code: NetErrorCode, message: string): void {
    m.strikes++;
    if (m.strikes > this.settings.maxStrikes) {
      this.drop(m, code, `${message} (too many violations)`);
    } else if (m.strikes === 1) {
      this.send(m, this.error(code, message, false));
    }
  }

  protected emit(e: HostEvent | E): void {
    this.onEvent?.(e);
  }

  /** A room's own work threw: close it (`INTERNAL`), keep serving the others. */
  protected roomFailed(room: R, error: unknown): void {
    this.emit({ type: 'internal-error', connection: -1, error });
    this.closeRoom(
      room,
      'INTERNAL',
      `the room stopped: ${error instanceof Error ? error.message : String(error)}`,
    );
  }

  /** Tell every connection of the room `code` (fatal), close them, and remove the room. */
  protected closeRoom(room: R, code: NetErrorCode, message: string): void {
    room.closing = true;
    if (code !== 'SHUTDOWN') this.emit({ type: 'room-closed', room: room.name, code, message });
    for (const c of [...room.connections()]) {
      this.drop(c, code, message, code === 'TIMEOUT' ? 'timeout' : 'closed', code !== 'SHUTDOWN');
    }
    this.removeRoom(room);
  }

  // ------------------------------------------------------------------------------ inside

  private error(code: NetErrorCode, message: string, fatal: boolean): Msg {
    return { type: 'error', code, fatal, message } as unknown as Msg;
  }

  private count(code: NetErrorCode): void {
    this.stats.dropped[code] = (this.stats.dropped[code] ?? 0) + 1;
  }

  private onBytes(m: M, bytes: Uint8Array): void {
    if (m.state === 'closed') return;
    const now = this.clock.now();
    this.stats.messagesIn++;
    this.stats.bytesIn += bytes.length;
    if (!m.bucket.take(bytes.length, now)) {
      const r = this.settings.rate;
      this.drop(
        m,
        'RATE_LIMIT',
        `more than ${r.messagesPerSecond} messages (or ${r.bytesPerSecond} bytes) a second`,
      );
      return;
    }
    // A client may send a batch frame too (a protocol that has them): several messages of one
    // frame — over a datagram transport, one packet instead of several.
    let parts: Uint8Array[];
    try {
      parts = this.protocol.split(bytes);
    } catch (error) {
      if (!(error instanceof ProtocolError)) throw error;
      this.drop(m, refusalCode(error, bytes, this.protocol.header), error.message);
      return;
    }
    for (const part of parts) {
      this.onMessageBytes(m, part, now);
      // A message may have closed it (a refusal, a leave): the rest of the frame is not read.
      if (isClosed(m)) return;
    }
  }

  private onMessageBytes(m: M, bytes: Uint8Array, now: number): void {
    if (isClosed(m)) return;
    let message: Msg;
    try {
      message = this.protocol.decode(bytes, this.decodeOptions());
    } catch (error) {
      if (!(error instanceof ProtocolError)) throw error;
      this.drop(m, refusalCode(error, bytes, this.protocol.header), error.message);
      return;
    }
    m.heardAt = this.liveness.at(now);
    if (message.type === 'ping') {
      if (this.answersPings) {
        const ping = message as unknown as { id: number; time: number };
        this.send(m, {
          type: 'pong',
          id: ping.id,
          time: ping.time,
          serverTime: now,
        } as unknown as Msg);
      }
      return;
    }
    // The answer to a liveness probe: being heard is all.
    if (message.type === 'pong') return;
    const room = this.roomOf(m);
    if (m.state === 'new' || room === undefined) {
      if (this.onJoinMessage(m, message, now)) return;
      if (++m.early > MAX_EARLY_MESSAGES) {
        this.drop(m, 'NOT_IN_ROOM', `${m.early} messages before joining a room`);
      }
      return;
    }
    room.onMessage(m, message, now);
  }

  /** The room `m` is seated in, if any. */
  protected roomOf(m: M): R | undefined {
    return m.room as R | undefined;
  }

  /** Takes `m` out of the host and its room; its seat is held if its connection was lost. */
  protected removeMember(m: M, reason: LeaveReason): void {
    if (m.state === 'closed') return;
    const seated = m.state !== 'new';
    m.state = 'closed';
    this.members.delete(m.id);
    this.connectionTally.remove(m.address);
    this.countConnections();
    const room = this.roomOf(m);
    if (room === undefined || !seated) return;
    const now = this.clock.now();
    room.vacate(m, reason, now, this.settings.seatHoldMs);
    room.onLeave(m, reason, now);
    if (room.empty) room.emptySince ??= now;
  }

  /** Why a new room from `address` cannot be made, after making way at capacity if it can. */
  private admitRoom(address: string, now: number): [NetErrorCode, string] | undefined {
    if (this.drainState) return ['SHUTDOWN', 'server draining: no new rooms here'];
    const refusal = this.roomTally.refusal(address);
    if (refusal?.[0] !== 'SERVER_FULL') return refusal;
    const victim = this.evictable(now);
    if (victim === undefined) return refusal;
    this.stats.evictions++;
    this.closeRoom(victim, 'IDLE', 'the room was closed to make way: nobody was playing in it');
    return undefined;
  }

  /**
   * The room to close at capacity: one nobody has played in for `idleGraceMs`, or still waiting
   * after `waitingGraceMs`, or empty — of the address holding the most rooms, the idlest first.
   */
  private evictable(now: number): R | undefined {
    const s = this.settings;
    let best: R | undefined;
    let bestKey = -Infinity;
    for (const room of this.rooms.values()) {
      if (room.creator === ADOPTED) continue;
      const idle =
        room.empty ||
        (room.state === 'running' && now - room.lastPlayAt >= s.idleGraceMs) ||
        (room.state === 'waiting' && now - room.createdAt >= s.waitingGraceMs);
      if (!idle) continue;
      // The address holding the most rooms first, then the room idle longest.
      const key = this.roomTally.of(room.creator) * 1e12 + (now - room.lastPlayAt);
      if (key > bestKey) {
        bestKey = key;
        best = room;
      }
    }
    return best;
  }

  /** Pings `m` (a protocol whose server pings): a live client answers at once. */
  private probe(m: M, now: number): void {
    if (!this.probes) return;
    m.probedAt = this.liveness.at(now);
    this.stats.probes++;
    this.send(m, { type: 'ping', id: this.nextProbeId++ >>> 0, time: now } as unknown as Msg);
  }

  private checkLiveness(now: number): void {
    const s = this.settings;
    const live = this.liveness.at(now);
    for (const m of [...this.members.values()]) {
      const silent = live - m.heardAt;
      if (m.state === 'new') {
        if (live - m.acceptedAt > s.helloTimeoutMs) this.drop(m, 'TIMEOUT', 'no join in time');
        continue;
      }
      if (silent >= s.silenceTimeoutMs) {
        this.drop(m, 'TIMEOUT', `silent for ${Math.round(silent / 1000)} s`, 'timeout');
      } else if (silent >= s.probeAfterMs && live - m.probedAt >= s.probeAfterMs) {
        this.probe(m, now);
      }
    }
  }

  /** Waiting rooms that never filled, rooms nobody plays in, empty rooms, drained rooms. */
  private checkRooms(now: number): void {
    const s = this.settings;
    for (const room of [...this.rooms.values()]) {
      // A room serving on its own lives as long as its host.
      if (room.creator === ADOPTED) continue;
      if (room.state === 'waiting' && now - room.createdAt >= s.waitingRoomTtlMs) {
        this.closeRoom(
          room,
          'TIMEOUT',
          `no match: the room waited ${Math.round(s.waitingRoomTtlMs / 1000)} s for players`,
        );
      } else if (
        room.state === 'running' &&
        room.hasPlayers &&
        now - room.lastPlayAt >= s.idleRoomTtlMs
      ) {
        this.stats.idleRooms++;
        this.closeRoom(
          room,
          'IDLE',
          `nobody played for ${Math.round(s.idleRoomTtlMs / 1000)} s: the room is closed`,
        );
      } else if (room.empty) {
        room.emptySince ??= now;
        // A seat still held for a dropped player keeps the room for that player's reconnect.
        const held = room.seats.some((seat) => seat.heldUntil > now);
        if (room.state === 'waiting' || (now - room.emptySince >= s.emptyRoomTtlMs && !held)) {
          this.removeRoom(room);
        }
      }
    }
  }

  private removeRoom(room: R): void {
    if (this.rooms.get(room.name) !== room) return;
    this.rooms.delete(room.name);
    if (room.creator !== ADOPTED) this.roomTally.remove(room.creator);
    this.countRooms();
    this.emit({ type: 'room-removed', room: room.name });
  }

  private countConnections(): void {
    this.stats.connections = this.members.size;
    this.stats.addresses = this.connectionTally.addresses;
  }

  private countRooms(): void {
    this.stats.rooms = this.rooms.size;
    let waiting = 0;
    let members = 0;
    for (const r of this.rooms.values()) {
      if (r.state === 'waiting') waiting++;
      members += r.countMembers();
    }
    this.stats.waitingRooms = waiting;
    this.stats.members = members;
  }
}

/** Whether a member's connection is closed (read afresh: a handler may have closed it). */
function isClosed(m: Member): boolean {
  return m.state === 'closed';
}
