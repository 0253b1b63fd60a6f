import type { Clock } from '../time/drivers.js';
import { diffSnapshots, type SnapshotDiff } from './forensics.js';
import { InputRing } from './history.js';
import {
  DEFAULT_PROTOCOL_LIMITS,
  ProtocolError,
  TOKEN_BYTES,
  decodeMessage,
  encodeMessage,
  peekMessageType,
  type HelloMessage,
  type LeaveReason,
  type NetErrorCode,
  type NetMessage,
  type ProtocolLimits,
} from './protocol.js';
import type { AnyGameDefinition } from '../sim/game.js';
import type { InputSchema } from '../sim/input-schema.js';
import type { Transport } from './transport.js';

/**
 * What the relay needs to know of a game (it never runs one): a game definition fits. The relay
 * checks every input against the schema, and builds each room's option bytes with `options`.
 */
export interface RelayGame {
  readonly id: string;
  readonly version: number;
  readonly tickRate: number;
  readonly minPlayers: number;
  readonly maxPlayers: number;
  /** What a player's input is: the relay refuses inputs outside it. */
  readonly input: InputSchema<unknown>;
  /** The canonical option bytes of a room (sent to every client). Default: none. */
  options?(players: number, seed: number): Uint8Array;
}

/** A catalog of the given games: unknown ids and other versions are refused with a reason. */
export function relayCatalog(games: readonly (RelayGame | AnyGameDefinition)[]): RelayCatalog {
  return (id, version) => {
    const game = games.find((g) => g.id === id);
    if (game === undefined) {
      return { code: 'UNKNOWN_GAME', message: `no game "${id}" on this server` };
    }
    if (game.version !== version) {
      return {
        code: 'GAME_MISMATCH',
        message: `this server plays ${id} version ${game.version}, not ${version}`,
      };
    }
    return game as RelayGame;
  };
}

/** Finds a game by id and version; a string is the reason it cannot be played. */
export type RelayCatalog = (
  id: string,
  version: number,
) => RelayGame | { code: 'UNKNOWN_GAME' | 'GAME_MISMATCH'; message: string };

/** Per-connection rate limits (token buckets). */
export interface RelayRateLimits {
  /** Sustained messages per second. Default 240 (a client at 144 Hz sends ~150). */
  messagesPerSecond: number;
  /** Message burst. Default 480. */
  messageBurst: number;
  /** Sustained bytes per second. Default 128 KiB. */
  bytesPerSecond: number;
  /** Byte burst (one full snapshot must fit). Default 2 MiB. */
  byteBurst: number;
}

export interface RelayOptions {
  /** The server clock (ms): ticks, deadlines, timeouts. Inject a ManualClock in tests. */
  clock: Clock;
  /** The games rooms may play. */
  catalog: RelayCatalog;
  /**
   * A source of random u32s for seeds and reconnect tokens. Default: `crypto.getRandomValues`.
   * Inject a seeded one in tests.
   */
  randomU32?: () => number;
  /**
   * How long after a tick's start time the relay waits for a connected player's missing input
   * before filling it with the player's last input (held buttons only, see `heldOnly`). Default
   * 100 ms. Everyone else's view of that tick waits this long at most.
   */
  deadlineMs?: number;
  /** Clients report a state hash every this many ticks. Default 30. */
  hashEvery?: number;
  /** Time from "all slots filled" to tick 0, for clocks to sync. Default 500 ms. */
  startDelayMs?: number;
  /** Inputs more than this many ticks ahead of the server clock are refused. Default 180. */
  maxAheadTicks?: number;
  /** Inputs this many ticks older than the newest closed tick count as a violation. Default 256. */
  maxBehindTicks?: number;
  /**
   * Closed ticks kept for late joiners and retransmission. Default 8192 (2 min 16 s at 60 Hz).
   * Each room holds `historyTicks × players × 4` bytes (128 KiB for 4 players).
   */
  historyTicks?: number;
  /** A match ends after this many ticks. Default 216000 (1 h at 60 Hz). */
  maxMatchTicks?: number;
  /** Rooms at once. Default 500. */
  maxRooms?: number;
  /** Connections at once. Default 4000. */
  maxConnections?: number;
  /** Spectators per room. Default 16. */
  maxSpectators?: number;
  /** Violations (tick window, bad hash ticks …) a connection may commit before it is dropped. Default 8. */
  maxStrikes?: number;
  /** A connection must say hello within this time. Default 5000 ms. */
  helloTimeoutMs?: number;
  /** A snapshot donor must answer within this time, else the next member is asked. Default 3000 ms. */
  snapshotTimeoutMs?: number;
  /** Forensics requests (per-tick hashes, snapshots) wait this long for answers. Default 5000 ms. */
  forensicsTimeoutMs?: number;
  /** Hash reports of a tick are compared after this long even if someone has not reported. Default 10000 ms. */
  hashTimeoutMs?: number;
  /** An empty room is removed after this long. Default 30000 ms. */
  emptyRoomTtlMs?: number;
  /** Messages other than snapshots larger than this are refused. Default 4096 bytes. */
  maxSmallMessageBytes?: number;
  rate?: Partial<RelayRateLimits>;
  limits?: Partial<ProtocolLimits>;
  /** Where the relay reports drops, desyncs and room life (default: nowhere). */
  onEvent?: (event: RelayEvent) => void;
}

/** A desync the relay found, with its forensics. */
export interface DesyncRecord {
  room: string;
  /** The periodic report tick where the hashes first disagreed. */
  reportTick: number;
  /** The first tick whose state differs (exact when per-tick hashes pinned it). */
  tick: number;
  exact: boolean;
  /** The sides: hash at `tick` (or `reportTick`), peers, and player slots among them. */
  groups: { hash: bigint; peers: number[]; slots: number[] }[];
  /** Index of the majority group (≥ 3 reporters and more than half), or -1. */
  majority: number;
  /** Each side's representative `save()` bytes at `tick` (empty when not received). */
  snapshots: { peer: number; bytes: Uint8Array }[];
  /** Byte offsets that differ between the first side (the majority, if any) and each other side. */
  diffs: { peer: number; diff: SnapshotDiff }[];
  /** Whether forensics finished (all answers in, or timed out). */
  complete: boolean;
}

/** What the relay reports. */
export type RelayEvent =
  | { type: 'room-created'; room: string; game: string; players: number }
  | { type: 'room-started'; room: string; startAt: number }
  | { type: 'room-removed'; room: string }
  | { type: 'join'; room: string; peer: number; slot: number; late: boolean }
  | { type: 'leave'; room: string; peer: number; reason: LeaveReason }
  | { type: 'drop'; connection: number; code: NetErrorCode; message: string }
  | { type: 'desync'; record: DesyncRecord }
  | { type: 'internal-error'; connection: number; error: unknown };

/** Counters of a relay. */
export interface RelayStats {
  connections: number;
  rooms: number;
  messagesIn: number;
  messagesOut: number;
  bytesIn: number;
  bytesOut: number;
  /** Connections dropped for misbehaviour, by code. */
  dropped: Partial<Record<NetErrorCode, number>>;
  /** Ticks closed with at least one input filled after its deadline. */
  filledInputs: number;
  hashChecks: number;
  desyncs: number;
}

/** A read-only view of a room. */
export interface RoomInfo {
  name: string;
  number: number;
  game: string;
  gameVersion: number;
  players: number;
  seed: number;
  state: 'waiting' | 'running' | 'ended';
  startAt: number | undefined;
  /** Every tick before this one is closed (its inputs final and sent). */
  closedTick: number;
  /** The newest hash report tick on which every reporter agreed. */
  lastAgreedTick: number;
  /** Hash report ticks compared. */
  hashChecks: number;
  members: { peer: number; slot: number; name: string; ack: number }[];
  desyncs: readonly DesyncRecord[];
}

interface Bucket {
  tokens: number;
  bytes: number;
  at: number;
}

interface Slot {
  conn: Conn | undefined;
  token: Uint8Array;
  /** The slot's input words of the newest closed tick. */
  last: Uint32Array;
  pending: InputRing;
  /** Sent at least one input since it (re)joined: the relay waits for it until the deadline. */
  active: boolean;
}

interface Conn {
  id: number;
  transport: Transport;
  state: 'new' | 'joining' | 'member' | 'closed';
  room: Room | undefined;
  peer: number;
  slot: number;
  name: string;
  joinTick: number;
  /** The next confirmed tick it needs. */
  ack: number;
  ackMovedAt: number;
  sentUpTo: number;
  bucket: Bucket;
  strikes: number;
  openedAt: number;
  /**
   * Request ids it may answer (snapshot / hashes). An entry stays after its request timed out —
   * a late answer is ignored, not punished — and only the last 16 are kept.
   */
  owes: Map<number, 'snapshot' | 'hashes'>;
  /** Its welcome, to repeat when a hello is repeated (the first welcome was lost). */
  welcome: Uint8Array | undefined;
  welcomeSentAt: number;
  /** It knows the match has started (it sent an input, or acked a tick past its start). */
  started: boolean;
}

interface JoinRequest {
  conn: Conn;
  donors: Conn[];
  id: number;
  donor: Conn | undefined;
  deadline: number;
}

interface Forensics {
  record: DesyncRecord;
  phase: 'hashes' | 'snapshots' | 'done';
  reps: Conn[];
  groupOf: Map<number, number>;
  from: number;
  requestId: number;
  hashes: Map<number, { from: number; hashes: BigUint64Array }>;
  snaps: Map<number, Uint8Array>;
  deadline: number;
  memberPeers: number[][];
}

class Room {
  readonly slots: Slot[] = [];
  readonly spectators = new Set<Conn>();
  state: 'waiting' | 'running' | 'ended' = 'waiting';
  startAt: number | undefined;
  closedEnd = 0;
  log: InputRing;
  nextSpectatorPeer = 64;
  nextRequestId = 1;
  reports = new Map<number, { at: number; hashes: Map<number, bigint> }>();
  lastAgreed = 0;
  hashChecks = 0;
  desyncs: DesyncRecord[] = [];
  forensics: Forensics | undefined;
  joins: JoinRequest[] = [];
  emptySince: number | undefined;
  readonly tickMs: number;
  /** u32 words per player per tick. */
  readonly words: number;

  constructor(
    readonly name: string,
    readonly number: number,
    readonly game: RelayGame,
    readonly players: number,
    readonly seed: number,
    readonly config: Uint8Array,
    historyTicks: number,
    tokens: () => Uint8Array,
  ) {
    this.tickMs = 1000 / game.tickRate;
    this.words = game.input.words;
    this.log = new InputRing(historyTicks, players * this.words);
    for (let s = 0; s < players; s++) {
      this.slots.push({
        conn: undefined,
        token: tokens(),
        last: new Uint32Array(this.words),
        pending: new InputRing(1024, this.words),
        active: false,
      });
    }
  }

  /** Members that receive the tick stream. */
  *members(): Generator<Conn> {
    for (const s of this.slots) if (s.conn?.state === 'member') yield s.conn;
    for (const c of this.spectators) if (c.state === 'member') yield c;
  }

  get empty(): boolean {
    return this.slots.every((s) => s.conn === undefined) && this.spectators.size === 0;
  }
}

const FATAL = true;

/**
 * The server core: rooms of any game, a tick clock per room, and server-ordered input relay
 * (lockstep on the server: the relay does not run the game). Transport-agnostic — the CLI
 * attaches it to WebSocket connections, tests and the lab to simulated links.
 *
 * The relay closes tick t when every connected, active player's input for t is in, or when its
 * clock passes `startAt + t × step + deadlineMs`: a missing input then becomes the player's last
 * input with held buttons only (a vacant slot's is 0). Closed ticks go to every member, resent
 * until acknowledged. Clients report a hash every `hashEvery` ticks; on disagreement the relay
 * asks one member of each side for per-tick hashes to find the first differing tick, tells
 * everyone, and collects both sides' snapshots of that tick for a byte diff.
 *
 * Call {@link update} at least twice per tick (the CLI does it every half step).
 */
export class Relay {
  readonly stats: RelayStats = {
    connections: 0,
    rooms: 0,
    messagesIn: 0,
    messagesOut: 0,
    bytesIn: 0,
    bytesOut: 0,
    dropped: {},
    filledInputs: 0,
    hashChecks: 0,
    desyncs: 0,
  };

  private readonly clock: Clock;
  private readonly catalog: RelayCatalog;
  private readonly randomU32: () => number;
  private readonly o: Required<
    Omit<RelayOptions, 'clock' | 'catalog' | 'randomU32' | 'rate' | 'limits' | 'onEvent'>
  >;
  private readonly rate: RelayRateLimits;
  private readonly limits: ProtocolLimits;
  private readonly onEvent: ((e: RelayEvent) => void) | undefined;
  private readonly conns = new Map<number, Conn>();
  private readonly rooms = new Map<string, Room>();
  private nextConnId = 1;
  private nextRoomNumber = 1;
  private closedRelay = false;

  constructor(options: RelayOptions) {
    this.clock = options.clock;
    this.catalog = options.catalog;
    this.randomU32 = options.randomU32 ?? cryptoU32;
    this.o = {
      deadlineMs: options.deadlineMs ?? 100,
      hashEvery: options.hashEvery ?? 30,
      startDelayMs: options.startDelayMs ?? 500,
      maxAheadTicks: options.maxAheadTicks ?? 180,
      maxBehindTicks: options.maxBehindTicks ?? 256,
      historyTicks: options.historyTicks ?? 8192,
      maxMatchTicks: options.maxMatchTicks ?? 216_000,
      maxRooms: options.maxRooms ?? 500,
      maxConnections: options.maxConnections ?? 4000,
      maxSpectators: options.maxSpectators ?? 16,
      maxStrikes: options.maxStrikes ?? 8,
      helloTimeoutMs: options.helloTimeoutMs ?? 5000,
      snapshotTimeoutMs: options.snapshotTimeoutMs ?? 3000,
      forensicsTimeoutMs: options.forensicsTimeoutMs ?? 5000,
      hashTimeoutMs: options.hashTimeoutMs ?? 10_000,
      emptyRoomTtlMs: options.emptyRoomTtlMs ?? 30_000,
      maxSmallMessageBytes: options.maxSmallMessageBytes ?? 4096,
    };
    this.rate = {
      messagesPerSecond: 240,
      messageBurst: 480,
      bytesPerSecond: 128 * 1024,
      byteBurst: 2 << 20,
      ...options.rate,
    };
    this.limits = { ...DEFAULT_PROTOCOL_LIMITS, ...options.limits };
    this.onEvent = options.onEvent;
  }

  // ------------------------------------------------------------------------------ public

  /** Take a new connection. Returns its id (used in drop events). */
  accept(transport: Transport): number {
    const now = this.clock.now();
    if (this.closedRelay || this.conns.size >= this.o.maxConnections) {
      transport.send(
        encodeMessage({ type: 'error', code: 'SERVER_FULL', message: 'server full', fatal: true }),
      );
      transport.close('server full');
      return -1;
    }
    const conn: Conn = {
      id: this.nextConnId++,
      transport,
      state: 'new',
      room: undefined,
      peer: -1,
      slot: -1,
      name: '',
      joinTick: 0,
      ack: 0,
      ackMovedAt: now,
      sentUpTo: 0,
      bucket: { tokens: this.rate.messageBurst, bytes: this.rate.byteBurst, at: now },
      strikes: 0,
      openedAt: now,
      owes: new Map(),
      welcome: undefined,
      welcomeSentAt: -Infinity,
      started: false,
    };
    this.conns.set(conn.id, conn);
    this.stats.connections = this.conns.size;
    transport.onMessage((bytes) => {
      try {
        this.onBytes(conn, bytes);
      } catch (error) {
        // A bug must cost one connection, never the server.
        this.emit({ type: 'internal-error', connection: conn.id, error });
        this.drop(conn, 'INTERNAL', 'internal error');
      }
    });
    transport.onClose(() => {
      this.removeConn(conn, 'closed');
    });
    return conn.id;
  }

  /**
   * Advance every room to `now`: close ticks whose inputs are in or whose deadline passed, send
   * confirmed ticks, time out hellos, donors and forensics, remove empty rooms.
   */
  update(now = this.clock.now()): void {
    for (const conn of this.conns.values()) {
      if (conn.state === 'new' && now - conn.openedAt > this.o.helloTimeoutMs) {
        this.drop(conn, 'TIMEOUT', 'no hello in time');
      }
    }
    for (const room of [...this.rooms.values()]) {
      try {
        this.updateRoom(room, now);
      } catch (error) {
        this.emit({ type: 'internal-error', connection: -1, error });
      }
    }
  }

  /** A view of one room. */
  room(name: string): RoomInfo | undefined {
    const r = this.rooms.get(name);
    return r ? this.info(r) : undefined;
  }

  /** Views of all rooms. */
  roomList(): RoomInfo[] {
    return [...this.rooms.values()].map((r) => this.info(r));
  }

  /** Close every connection (error SHUTDOWN) and refuse new ones. */
  close(): void {
    this.closedRelay = true;
    for (const conn of [...this.conns.values()]) {
      this.drop(conn, 'SHUTDOWN', 'server shutting down', false);
    }
  }

  // ------------------------------------------------------------------------------ receiving

  private onBytes(conn: Conn, bytes: Uint8Array): void {
    if (conn.state === 'closed') return;
    const now = this.clock.now();
    this.stats.messagesIn++;
    this.stats.bytesIn += bytes.length;
    if (!this.takeTokens(conn, bytes.length, now)) {
      this.drop(conn, 'RATE_LIMIT', 'too many messages');
      return;
    }
    // Size checks before decoding: only a requested snapshot may be large.
    const kind = peekMessageType(bytes);
    if (bytes.length > this.limits.maxMessageBytes) {
      this.drop(conn, 'TOO_LARGE', `message of ${bytes.length} bytes`);
      return;
    }
    if (kind === 'snapshot') {
      if (![...conn.owes.values()].includes('snapshot')) {
        this.drop(conn, 'UNEXPECTED', 'unrequested snapshot');
        return;
      }
    } else if (bytes.length > this.o.maxSmallMessageBytes) {
      this.drop(conn, 'TOO_LARGE', `message of ${bytes.length} bytes`);
      return;
    }
    let m: NetMessage;
    try {
      m = decodeMessage(bytes, this.limits);
    } catch (error) {
      if (!(error instanceof ProtocolError)) throw error;
      this.drop(conn, 'BAD_MESSAGE', error.message);
      return;
    }
    this.onMessage(conn, m, now);
  }

  private onMessage(conn: Conn, m: NetMessage, now: number): void {
    if (m.type === 'ping') {
      this.send(conn, { type: 'pong', id: m.id, time: m.time, serverTime: now });
      return;
    }
    if (m.type === 'hello') {
      if (conn.state === 'new') {
        this.onHello(conn, m, now);
      } else if (conn.room?.name !== m.room || conn.slot >= 0 !== (m.role === 'player')) {
        this.drop(conn, 'UNEXPECTED', 'hello for another room or role');
      } else if (conn.welcome && now - conn.welcomeSentAt >= 200) {
        // A repeated hello: our welcome was lost.
        this.sendBytes(conn, conn.welcome);
        conn.welcomeSentAt = now;
      }
      return;
    }
    const room = conn.room;
    if (conn.state === 'new' || room === undefined) {
      this.drop(conn, 'NOT_IN_ROOM', `${m.type} before joining a room`);
      return;
    }
    if (!('room' in m) || m.room !== room.number) {
      this.drop(conn, 'WRONG_ROOM', `${m.type} for another room`);
      return;
    }
    switch (m.type) {
      case 'input':
        this.onInput(conn, room, m.player, m.tick, m.words, m.inputs, now);
        this.onAck(conn, room, m.ack, now);
        break;
      case 'ack':
        this.onAck(conn, room, m.ack, now);
        break;
      case 'hash':
        this.onHash(conn, room, m.tick, m.hash, now);
        break;
      case 'leave':
        if (m.peer !== conn.peer) {
          this.drop(conn, 'SPOOFED_PLAYER', 'leave for another peer');
          return;
        }
        this.removeConn(conn, 'left');
        conn.transport.close('left');
        break;
      case 'snapshot':
        this.onSnapshot(conn, room, m.id, m.tick, m.bytes, now);
        break;
      case 'hashes':
        this.onHashes(conn, room, m.id, m.from, m.hashes, now);
        break;
      default:
        this.drop(conn, 'UNEXPECTED', `${m.type} is a server-to-client message`);
    }
  }

  private onHello(conn: Conn, m: HelloMessage, now: number): void {
    const found = this.catalog(m.game, m.gameVersion);
    if ('code' in found) {
      this.drop(conn, found.code, found.message);
      return;
    }
    const game = found;
    if (m.input !== game.input.id) {
      this.drop(
        conn,
        'GAME_MISMATCH',
        `${game.id} takes input schema ${game.input.id}, the client sends ${m.input}`,
      );
      return;
    }
    let room = this.rooms.get(m.room);
    if (room === undefined) {
      if (this.rooms.size >= this.o.maxRooms) {
        this.drop(conn, 'SERVER_FULL', 'too many rooms');
        return;
      }
      const players = m.players === 0 ? game.minPlayers : m.players;
      if (players < game.minPlayers || players > game.maxPlayers) {
        this.drop(
          conn,
          'BAD_HELLO',
          `${game.id} plays ${game.minPlayers} to ${game.maxPlayers} players, not ${players}`,
        );
        return;
      }
      const seed = m.seed ?? this.randomU32() >>> 0;
      room = new Room(
        m.room,
        this.nextRoomNumber++,
        game,
        players,
        seed,
        game.options ? game.options(players, seed) : new Uint8Array(0),
        this.o.historyTicks,
        () => this.token(),
      );
      this.rooms.set(m.room, room);
      this.stats.rooms = this.rooms.size;
      this.emit({ type: 'room-created', room: room.name, game: game.id, players });
    } else if (room.game.id !== game.id || room.game.version !== game.version) {
      this.drop(
        conn,
        'GAME_MISMATCH',
        `room ${room.name} plays ${room.game.id} v${room.game.version}, not ${game.id} v${game.version}`,
      );
      return;
    }
    room.emptySince = undefined;
    conn.name = m.name;
    conn.room = room;

    if (m.role === 'spectator') {
      if (room.spectators.size >= this.o.maxSpectators) {
        this.drop(conn, 'ROOM_FULL', 'no room for another spectator');
        return;
      }
      conn.peer = room.nextSpectatorPeer++;
      conn.slot = -1;
      room.spectators.add(conn);
    } else {
      let slot: number;
      if (m.token !== undefined) {
        slot = room.slots.findIndex((s) => equalBytes(s.token, m.token!));
        if (slot < 0) {
          this.drop(conn, 'BAD_TOKEN', 'no slot of this room has that token');
          return;
        }
        const old = room.slots[slot]!.conn;
        if (old !== undefined && old !== conn) {
          this.drop(old, 'UNEXPECTED', 'replaced by a reconnect', false, 'replaced');
        }
      } else {
        slot = room.slots.findIndex((s) => s.conn === undefined);
        if (slot < 0) {
          this.drop(conn, 'ROOM_FULL', `all ${room.players} player slots are taken`);
          return;
        }
      }
      const s = room.slots[slot]!;
      s.conn = conn;
      s.active = false;
      conn.slot = slot;
      conn.peer = slot;
    }
    conn.state = 'joining';

    if (room.state === 'waiting') {
      this.welcome(conn, room, 0, undefined);
      this.emit({ type: 'join', room: room.name, peer: conn.peer, slot: conn.slot, late: false });
      if (room.slots.every((s) => s.conn?.state === 'member')) this.start(room, now);
      return;
    }
    // Late join or reconnect: a snapshot from a member, then the ticks since.
    const donors = [...room.members()].filter((c) => c !== conn).sort((a, b) => b.ack - a.ack);
    const req: JoinRequest = { conn, donors, id: 0, donor: undefined, deadline: 0 };
    room.joins.push(req);
    this.nextDonor(room, req, now);
  }

  private nextDonor(room: Room, req: JoinRequest, now: number): void {
    const donor = req.donors.shift();
    if (donor?.state !== 'member') {
      if (donor !== undefined) {
        this.nextDonor(room, req, now);
        return;
      }
      room.joins = room.joins.filter((j) => j !== req);
      // No member can help: replay from tick 0 if the history still holds it.
      if (room.closedEnd <= room.log.capacity) {
        this.welcome(req.conn, room, 0, undefined);
        this.emit({
          type: 'join',
          room: room.name,
          peer: req.conn.peer,
          slot: req.conn.slot,
          late: true,
        });
      } else {
        this.drop(req.conn, 'NO_SNAPSHOT', 'no member could send a snapshot');
      }
      return;
    }
    req.donor = donor;
    req.id = room.nextRequestId++;
    req.deadline = now + this.o.snapshotTimeoutMs;
    this.owe(donor, req.id, 'snapshot');
    this.send(donor, { type: 'snapshot-request', room: room.number, id: req.id, tick: -1 });
  }

  private welcome(conn: Conn, room: Room, tick: number, snapshot: Uint8Array | undefined): void {
    conn.state = 'member';
    conn.joinTick = tick;
    conn.ack = tick;
    conn.sentUpTo = tick;
    conn.ackMovedAt = this.clock.now();
    const slot = conn.slot >= 0 ? room.slots[conn.slot] : undefined;
    const m: NetMessage = {
      type: 'welcome',
      room: room.number,
      peer: conn.peer,
      slot: conn.slot,
      players: room.players,
      seed: room.seed,
      tickRate: room.game.tickRate,
      hashEvery: this.o.hashEvery,
      deadlineMs: this.o.deadlineMs,
      inputFrom: room.state === 'waiting' ? 0 : room.closedEnd,
      startTick: tick,
      config: room.config,
      token: slot ? slot.token : new Uint8Array(0),
    };
    if (room.startAt !== undefined) m.startAt = room.startAt;
    if (snapshot !== undefined) m.snapshot = snapshot;
    conn.welcome = encodeMessage(m);
    conn.welcomeSentAt = this.clock.now();
    conn.started = room.startAt !== undefined;
    this.sendBytes(conn, conn.welcome);
  }

  private start(room: Room, now: number): void {
    room.state = 'running';
    room.startAt = now + this.o.startDelayMs;
    for (const s of room.slots) s.active = true;
    for (const c of room.members())
      this.send(c, { type: 'start', room: room.number, startAt: room.startAt });
    this.emit({ type: 'room-started', room: room.name, startAt: room.startAt });
  }

  private onInput(
    conn: Conn,
    room: Room,
    player: number,
    tick: number,
    words: number,
    inputs: Uint32Array,
    now: number,
  ): void {
    if (conn.slot < 0 || conn.state !== 'member') {
      this.drop(conn, 'SPOOFED_PLAYER', 'a spectator sent inputs');
      return;
    }
    if (player !== conn.slot) {
      this.drop(conn, 'SPOOFED_PLAYER', `inputs for player ${player} from player ${conn.slot}`);
      return;
    }
    if (words !== room.words) {
      this.drop(conn, 'BAD_INPUT', `inputs of ${words} words, ${room.game.id} takes ${room.words}`);
      return;
    }
    const ticks = inputs.length / words;
    for (let k = 0; k < ticks; k++) {
      const problem = room.game.input.problem(inputs, k * words);
      if (problem !== undefined) {
        this.drop(conn, 'BAD_INPUT', `input of tick ${tick + k}: ${problem}`);
        return;
      }
    }
    const last = tick + ticks - 1;
    const clockTick =
      room.startAt === undefined ? 0 : Math.max(0, Math.floor((now - room.startAt) / room.tickMs));
    if (last > clockTick + this.o.maxAheadTicks) {
      this.strike(conn, 'TICK_WINDOW', `inputs for tick ${last}, the server is at ${clockTick}`);
      return;
    }
    if (last < room.closedEnd - this.o.maxBehindTicks) {
      this.strike(conn, 'TICK_WINDOW', `inputs for tick ${last}, long closed`);
      return;
    }
    const s = room.slots[conn.slot]!;
    for (let k = 0; k < ticks; k++) {
      const t = tick + k;
      if (t < room.closedEnd || t >= room.closedEnd + s.pending.capacity || s.pending.has(t))
        continue;
      s.pending.set(t, inputs, k * words);
    }
    s.active = true;
    conn.started = true;
  }

  private onAck(conn: Conn, room: Room, ack: number, now: number): void {
    if (ack > room.closedEnd) {
      this.strike(conn, 'TICK_WINDOW', `ack of tick ${ack}, only ${room.closedEnd} closed`);
      return;
    }
    if (ack > conn.ack) {
      conn.ack = ack;
      conn.ackMovedAt = now;
    }
    if (!conn.started && room.startAt !== undefined) {
      if (ack > conn.joinTick) {
        conn.started = true;
      } else if (now - conn.welcomeSentAt >= 200) {
        // Still waiting: the start was lost.
        this.send(conn, { type: 'start', room: room.number, startAt: room.startAt });
        conn.welcomeSentAt = now;
      }
    }
  }

  private onHash(conn: Conn, room: Room, tick: number, hash: bigint, now: number): void {
    if (conn.state !== 'member') return;
    if (tick % this.o.hashEvery !== 0 || tick > room.closedEnd || tick <= conn.joinTick) {
      this.strike(conn, 'TICK_WINDOW', `hash for tick ${tick}`);
      return;
    }
    if (tick <= room.lastAgreed || room.desyncs.length > 0) return;
    let r = room.reports.get(tick);
    if (r === undefined) {
      if (room.reports.size >= 64) return;
      r = { at: now, hashes: new Map() };
      room.reports.set(tick, r);
    }
    r.hashes.set(conn.peer, hash);
    this.checkReports(room, now);
  }

  private onSnapshot(
    conn: Conn,
    room: Room,
    id: number,
    tick: number,
    bytes: Uint8Array,
    now: number,
  ): void {
    if (conn.owes.get(id) !== 'snapshot') {
      this.drop(conn, 'UNEXPECTED', 'unrequested snapshot');
      return;
    }
    conn.owes.delete(id);
    const req = room.joins.find((j) => j.id === id && j.donor === conn);
    if (req) {
      const oldest = Math.max(0, room.closedEnd - room.log.capacity + 1);
      if (
        bytes.length === 0 ||
        tick > room.closedEnd ||
        tick < oldest ||
        req.conn.state !== 'joining'
      ) {
        if (req.conn.state === 'joining') this.nextDonor(room, req, now);
        return;
      }
      room.joins = room.joins.filter((j) => j !== req);
      this.welcome(req.conn, room, tick, bytes);
      this.emit({
        type: 'join',
        room: room.name,
        peer: req.conn.peer,
        slot: req.conn.slot,
        late: true,
      });
      return;
    }
    const f = room.forensics;
    if (
      f?.phase === 'snapshots' &&
      id === f.requestId &&
      f.reps.includes(conn) &&
      tick === f.record.tick
    ) {
      f.snaps.set(conn.peer, bytes);
      if (f.snaps.size === f.reps.length) this.finishForensics(room, f);
    }
  }

  private onHashes(
    conn: Conn,
    room: Room,
    id: number,
    from: number,
    hashes: BigUint64Array,
    now: number,
  ): void {
    if (conn.owes.get(id) !== 'hashes') {
      this.strike(conn, 'UNEXPECTED', 'unrequested hashes');
      return;
    }
    conn.owes.delete(id);
    const f = room.forensics;
    if (f?.phase === 'hashes' && id === f.requestId && f.reps.includes(conn)) {
      f.hashes.set(conn.peer, { from, hashes });
      if (f.hashes.size === f.reps.length) this.pinDesync(room, f, now);
    }
  }

  // ------------------------------------------------------------------------------ the tick clock

  private updateRoom(room: Room, now: number): void {
    for (const req of [...room.joins]) {
      if (req.conn.state !== 'joining') room.joins = room.joins.filter((j) => j !== req);
      else if (now >= req.deadline) this.nextDonor(room, req, now);
    }
    if (room.state === 'running') this.closeTicks(room, now);
    this.flush(room, now);
    if (room.reports.size > 0) this.checkReports(room, now);
    const f = room.forensics;
    if (f && f.phase !== 'done' && now >= f.deadline) {
      if (f.phase === 'hashes') this.pinDesync(room, f, now);
      else this.finishForensics(room, f);
    }
    if (room.empty) {
      room.emptySince ??= now;
      if (room.state === 'waiting' || now - room.emptySince >= this.o.emptyRoomTtlMs) {
        this.rooms.delete(room.name);
        this.stats.rooms = this.rooms.size;
        this.emit({ type: 'room-removed', room: room.name });
      }
    }
  }

  private closeTicks(room: Room, now: number): void {
    const startAt = room.startAt!;
    const w = room.words;
    const row = new Uint32Array(room.players * w);
    for (let guard = 0; guard < 4096 && room.closedEnd < this.o.maxMatchTicks; guard++) {
      const t = room.closedEnd;
      const tickStart = startAt + t * room.tickMs;
      let required = 0;
      let missing = 0;
      for (const s of room.slots) {
        if (s.conn?.state === 'member' && s.active) {
          required++;
          if (!s.pending.has(t)) missing++;
        }
      }
      // Early (before its time) only when every required input is in; never without any input.
      if (
        missing > 0 ? now < tickStart + this.o.deadlineMs : required === 0 ? now < tickStart : false
      )
        break;
      let filled = false;
      for (let p = 0; p < room.players; p++) {
        const s = room.slots[p]!;
        if (s.pending.has(t)) {
          s.pending.copy(t, row, p * w);
          s.pending.clear(t);
        } else if (s.conn) {
          // The game's rule for a missing input: held buttons only, axes kept.
          room.game.input.missing(s.last, 0, row, p * w);
          if (s.conn.state === 'member' && s.active) filled = true;
        } else {
          row.fill(0, p * w, (p + 1) * w);
        }
        for (let k = 0; k < w; k++) s.last[k] = row[p * w + k]!;
      }
      if (filled) this.stats.filledInputs++;
      room.log.set(t, row);
      room.closedEnd++;
    }
    if (room.closedEnd >= this.o.maxMatchTicks) room.state = 'ended';
  }

  private flush(room: Room, now: number): void {
    const newest = room.closedEnd;
    const maxTicks = this.limits.maxConfirmedTicks;
    const oldest = Math.max(0, newest - room.log.capacity + 1);
    for (const c of room.members()) {
      if (c.ack < oldest) {
        // Fell out of the history: it cannot catch up from here.
        this.drop(c, 'NO_SNAPSHOT', 'too far behind the room');
        continue;
      }
      if (c.sentUpTo < c.ack) c.sentUpTo = c.ack;
      const rewind = c.ack < c.sentUpTo && now - c.ackMovedAt > 250;
      if (!(newest > c.sentUpTo || rewind)) continue;
      // Small gap: every message carries every unacknowledged tick (loss costs nothing).
      // Large gap (a late joiner catching up): stream onwards; go back to the ack on a timeout.
      let from = newest - c.ack <= maxTicks || rewind ? c.ack : c.sentUpTo;
      if (rewind) c.ackMovedAt = now;
      const inputAck = this.inputAck(room, c);
      const lanes = room.players * room.words;
      for (let k = 0; k < 8 && from < newest; k++) {
        const n = Math.min(maxTicks, newest - from);
        const inputs = new Uint32Array(n * lanes);
        for (let i = 0; i < n; i++) room.log.copy(from + i, inputs, i * lanes);
        this.send(c, {
          type: 'confirmed',
          room: room.number,
          inputAck,
          tick: from,
          players: room.players,
          words: room.words,
          inputs,
        });
        from += n;
      }
      c.sentUpTo = Math.max(c.sentUpTo, from);
    }
  }

  /** The next tick the relay needs an input from `c` for. */
  private inputAck(room: Room, c: Conn): number {
    if (c.slot < 0) return 0;
    const s = room.slots[c.slot]!;
    let t = room.closedEnd;
    while (s.pending.has(t) && t < room.closedEnd + s.pending.capacity) t++;
    return t;
  }

  // ------------------------------------------------------------------------------ desync forensics

  private checkReports(room: Room, now: number): void {
    const ticks = [...room.reports.keys()].sort((a, b) => a - b);
    for (const tick of ticks) {
      const r = room.reports.get(tick)!;
      let all = true;
      for (const c of room.members()) {
        if (c.joinTick >= tick) continue;
        if (!r.hashes.has(c.peer)) all = false;
      }
      const timedOut = now - r.at >= this.o.hashTimeoutMs || room.reports.size > 48;
      if (!(all || timedOut)) continue;
      room.reports.delete(tick);
      room.hashChecks++;
      this.stats.hashChecks++;
      const groups = groupByHash(r.hashes);
      if (groups.length === 1) {
        if (tick > room.lastAgreed) room.lastAgreed = tick;
        continue;
      }
      if (room.desyncs.length === 0 && room.forensics === undefined)
        this.beginForensics(room, tick, groups, now);
      room.reports.clear();
      return;
    }
  }

  private beginForensics(
    room: Room,
    reportTick: number,
    groups: { hash: bigint; peers: number[] }[],
    now: number,
  ): void {
    const byPeer = new Map<number, Conn>();
    for (const c of room.members()) byPeer.set(c.peer, c);
    const reps: Conn[] = [];
    const groupOf = new Map<number, number>();
    groups.forEach((g, i) => {
      for (const p of g.peers) groupOf.set(p, i);
      const rep = g.peers.map((p) => byPeer.get(p)).find((c) => c !== undefined);
      if (rep) reps.push(rep);
    });
    const total = groups.reduce((n, g) => n + g.peers.length, 0);
    const record: DesyncRecord = {
      room: room.name,
      reportTick,
      tick: reportTick,
      exact: false,
      groups: groups.map((g) => ({
        hash: g.hash,
        peers: g.peers,
        slots: g.peers.filter((p) => p < 64),
      })),
      majority: majorityOf(groups, total),
      snapshots: [],
      diffs: [],
      complete: false,
    };
    const from = Math.max(room.lastAgreed + 1, reportTick - this.limits.maxHashes + 1);
    const f: Forensics = {
      record,
      phase: 'hashes',
      reps,
      groupOf,
      from,
      requestId: room.nextRequestId++,
      hashes: new Map(),
      snaps: new Map(),
      deadline: now + this.o.forensicsTimeoutMs,
      memberPeers: groups.map((g) => g.peers),
    };
    room.forensics = f;
    room.desyncs.push(record);
    this.stats.desyncs++;
    for (const c of reps) {
      this.owe(c, f.requestId, 'hashes');
      this.send(c, {
        type: 'hashes-request',
        room: room.number,
        id: f.requestId,
        from,
        count: reportTick - from + 1,
      });
    }
  }

  /** Per-tick hashes are in (or timed out): find the first differing tick and tell everyone. */
  private pinDesync(room: Room, f: Forensics, now: number): void {
    const rec = f.record;
    const hashAt = (peer: number, t: number): bigint | undefined => {
      const h = f.hashes.get(peer);
      if (!h || t < h.from || t >= h.from + h.hashes.length) return undefined;
      return h.hashes[t - h.from];
    };
    const peers = f.reps.map((c) => c.peer);
    let first = -1;
    for (let t = f.from; t <= rec.reportTick && first < 0; t++) {
      const seen = peers.map((p) => hashAt(p, t)).filter((h) => h !== undefined);
      if (seen.length >= 2 && seen.some((h) => h !== seen[0])) first = t;
    }
    if (first >= 0) {
      rec.tick = first;
      // Exact when every side's hashes reach back to the last agreed tick, or agree just before.
      const before = peers.map((p) => hashAt(p, first - 1));
      rec.exact =
        first === room.lastAgreed + 1 ||
        (before.every((h) => h !== undefined) && before.every((h) => h === before[0]));
      // Regroup the representatives by their hash at the first differing tick.
      rec.groups = rec.groups.map((g, i) => {
        const rep = f.reps[i];
        const h = rep ? hashAt(rep.peer, first) : undefined;
        return { ...g, hash: h ?? g.hash };
      });
    }
    for (const c of room.members()) {
      this.send(c, {
        type: 'desync',
        room: room.number,
        tick: rec.tick,
        exact: rec.exact,
        reportTick: rec.reportTick,
        majority: rec.majority,
        groups: rec.groups.map((g) => ({ hash: g.hash, peers: g.peers })),
      });
    }
    f.phase = 'snapshots';
    f.requestId = room.nextRequestId++;
    f.deadline = now + this.o.forensicsTimeoutMs;
    for (const c of f.reps) {
      if (c.state !== 'member') continue;
      this.owe(c, f.requestId, 'snapshot');
      this.send(c, {
        type: 'snapshot-request',
        room: room.number,
        id: f.requestId,
        tick: rec.tick,
      });
    }
  }

  private finishForensics(room: Room, f: Forensics): void {
    const rec = f.record;
    rec.snapshots = f.reps.map((c) => ({
      peer: c.peer,
      bytes: f.snaps.get(c.peer) ?? new Uint8Array(0),
    }));
    const baseIndex = rec.majority >= 0 ? rec.majority : 0;
    const base = rec.snapshots[baseIndex];
    if (base && base.bytes.length > 0) {
      rec.diffs = rec.snapshots
        .filter((s, i) => i !== baseIndex && s.bytes.length > 0)
        .map((s) => ({ peer: s.peer, diff: diffSnapshots(base.bytes, s.bytes) }));
    }
    rec.complete = true;
    f.phase = 'done';
    room.forensics = undefined;
    this.emit({ type: 'desync', record: rec });
  }

  // ------------------------------------------------------------------------------ connections

  private owe(conn: Conn, id: number, kind: 'snapshot' | 'hashes'): void {
    conn.owes.set(id, kind);
    if (conn.owes.size > 16) conn.owes.delete(conn.owes.keys().next().value!);
  }

  private strike(conn: Conn, code: NetErrorCode, message: string): void {
    conn.strikes++;
    if (conn.strikes > this.o.maxStrikes) {
      this.drop(conn, code, `${message} (too many violations)`);
    } else if (conn.strikes === 1) {
      this.send(conn, { type: 'error', code, message, fatal: false });
    }
  }

  /** Send a fatal error and close; `count` false for shutdowns and replacements. */
  private drop(
    conn: Conn,
    code: NetErrorCode,
    message: string,
    count = FATAL,
    reason: LeaveReason = 'dropped',
  ): void {
    if (conn.state === 'closed') return;
    if (count) {
      this.stats.dropped[code] = (this.stats.dropped[code] ?? 0) + 1;
      this.emit({ type: 'drop', connection: conn.id, code, message });
    }
    this.send(conn, { type: 'error', code, message, fatal: true });
    this.removeConn(conn, reason);
    conn.transport.close(`${code}: ${message}`);
  }

  private removeConn(conn: Conn, reason: LeaveReason): void {
    if (conn.state === 'closed') return;
    const wasMember = conn.state === 'member';
    conn.state = 'closed';
    this.conns.delete(conn.id);
    this.stats.connections = this.conns.size;
    const room = conn.room;
    if (!room) return;
    if (conn.slot >= 0) {
      const s = room.slots[conn.slot]!;
      if (s.conn === conn) {
        s.conn = undefined;
        s.active = false;
        s.last.fill(0);
        for (let t = room.closedEnd; t < room.closedEnd + s.pending.capacity; t++)
          s.pending.clear(t);
      }
    } else {
      room.spectators.delete(conn);
    }
    const now = this.clock.now();
    for (const req of [...room.joins]) {
      if (req.conn === conn) room.joins = room.joins.filter((j) => j !== req);
      else if (req.donor === conn) this.nextDonor(room, req, now);
    }
    if (wasMember) {
      for (const c of room.members())
        this.send(c, { type: 'leave', room: room.number, peer: conn.peer, reason });
      this.emit({ type: 'leave', room: room.name, peer: conn.peer, reason });
    }
  }

  private send(conn: Conn, m: NetMessage): void {
    this.sendBytes(conn, encodeMessage(m));
  }

  private sendBytes(conn: Conn, bytes: Uint8Array): void {
    if (!conn.transport.isOpen) return;
    this.stats.messagesOut++;
    this.stats.bytesOut += bytes.length;
    conn.transport.send(bytes);
  }

  private takeTokens(conn: Conn, bytes: number, now: number): boolean {
    const b = conn.bucket;
    const dt = Math.max(0, now - b.at) / 1000;
    b.at = now;
    b.tokens = Math.min(this.rate.messageBurst, b.tokens + dt * this.rate.messagesPerSecond);
    b.bytes = Math.min(this.rate.byteBurst, b.bytes + dt * this.rate.bytesPerSecond);
    b.tokens -= 1;
    b.bytes -= bytes;
    return b.tokens >= 0 && b.bytes >= 0;
  }

  private token(): Uint8Array {
    const t = new Uint8Array(TOKEN_BYTES);
    const v = new DataView(t.buffer);
    for (let i = 0; i < TOKEN_BYTES; i += 4) v.setUint32(i, this.randomU32() >>> 0);
    return t;
  }

  private info(r: Room): RoomInfo {
    return {
      name: r.name,
      number: r.number,
      game: r.game.id,
      gameVersion: r.game.version,
      players: r.players,
      seed: r.seed,
      state: r.state,
      startAt: r.startAt,
      closedTick: r.closedEnd,
      lastAgreedTick: r.lastAgreed,
      hashChecks: r.hashChecks,
      members: [...r.members()].map((c) => ({
        peer: c.peer,
        slot: c.slot,
        name: c.name,
        ack: c.ack,
      })),
      desyncs: r.desyncs,
    };
  }

  private emit(e: RelayEvent): void {
    this.onEvent?.(e);
  }
}

function groupByHash(hashes: Map<number, bigint>): { hash: bigint; peers: number[] }[] {
  const groups: { hash: bigint; peers: number[] }[] = [];
  const peers = [...hashes.keys()].sort((a, b) => a - b);
  for (const p of peers) {
    const h = hashes.get(p)!;
    const g = groups.find((x) => x.hash === h);
    if (g) g.peers.push(p);
    else groups.push({ hash: h, peers: [p] });
  }
  // Largest side first.
  return groups.sort((a, b) => b.peers.length - a.peers.length || a.peers[0]! - b.peers[0]!);
}

function majorityOf(groups: { peers: number[] }[], total: number): number {
  if (total < 3) return -1;
  const i = groups.findIndex((g) => g.peers.length * 2 > total);
  return i;
}

function equalBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  let d = 0;
  for (let i = 0; i < a.length; i++) d |= a[i]! ^ b[i]!;
  return d === 0;
}

function cryptoU32(): number {
  const a = new Uint32Array(1);
  globalThis.crypto.getRandomValues(a);
  return a[0]!;
}
