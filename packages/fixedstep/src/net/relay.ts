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
   * A source of random u32s for seeds, reconnect and invite tokens. Default:
   * `crypto.getRandomValues`. Inject a seeded one in tests (tokens then become guessable).
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
  /**
   * Connections at once from one client address (see `accept`'s `address`). Default 32: one
   * address cannot take the server's connections, and a household or LAN party still fits.
   */
  maxConnectionsPerAddress?: number;
  /** Rooms that connections from one address created and that still exist. Default 8. */
  maxRoomsPerAddress?: number;
  /** Spectators per room. Default 16. */
  maxSpectators?: number;
  /** Violations (tick window, bad hash ticks …) a connection may commit before it is dropped. Default 8. */
  maxStrikes?: number;
  /** A connection must say hello within this time. Default 5000 ms. */
  helloTimeoutMs?: number;
  /**
   * A member (or a connection joining a room) that has sent nothing — no input, ack, ping or
   * pong — for this long is dropped (`TIMEOUT`) and its slot becomes vacant. Default 10000 ms.
   */
  silenceTimeoutMs?: number;
  /**
   * A member silent for this long is pinged (at most once per this interval); a live client
   * answers with a pong from its message handler, even in a background tab. Default 1000 ms.
   */
  probeAfterMs?: number;
  /**
   * A full room starts only when every player has been heard from within this time: a frozen
   * peer never starts a newcomer's match (it is dropped at `silenceTimeoutMs`, and the room
   * waits for another player). Default 2000 ms.
   */
  startLivenessMs?: number;
  /**
   * A room whose player slots are not all filled within this time after it was created is
   * closed (`TIMEOUT` to its members): waiting rooms cannot be squatted. Default 120000 ms.
   */
  waitingRoomTtlMs?: number;
  /** A snapshot donor must answer within this time, else the next member is asked. Default 3000 ms. */
  snapshotTimeoutMs?: number;
  /** Forensics requests (per-tick hashes, snapshots) wait this long for answers. Default 5000 ms. */
  forensicsTimeoutMs?: number;
  /** Hash reports of a tick are compared after this long even if someone has not reported. Default 10000 ms. */
  hashTimeoutMs?: number;
  /**
   * Desyncs recorded (and diagnosed) per room; later ones are still counted in `stats.desyncs`.
   * Default 64.
   */
  maxDesyncRecords?: number;
  /**
   * Bytes of forensics snapshots a room keeps, all records together; past it a record gets its
   * exact tick but no snapshots. Default 8 MiB.
   */
  maxForensicsBytes?: number;
  /** An empty room is removed after this long. Default 30000 ms. */
  emptyRoomTtlMs?: number;
  /** Messages other than snapshots larger than this are refused. Default 4096 bytes. */
  maxSmallMessageBytes?: number;
  rate?: Partial<RelayRateLimits>;
  limits?: Partial<ProtocolLimits>;
  /** Where the relay reports drops, desyncs and room life (default: nowhere). */
  onEvent?: (event: RelayEvent) => void;
}

/** Where a connection comes from, for {@link Relay.accept}. */
export interface RelayConnectionInfo {
  /**
   * The client's address (its IP, or any key: the per-address caps count connections and rooms by
   * it). Default: one shared key, `"unknown"` — give it whenever you know it.
   */
  address?: string;
  /**
   * The room the connection's URL names (`/ws/<room>`): its hello must be for this room, else it
   * is dropped (`WRONG_ROOM`). Lets a load balancer route by room without reading the protocol.
   */
  room?: string;
  /**
   * Whether the transport delivers every message in order or closes (a WebSocket). Default: the
   * transport's own `reliable`. Over a reliable transport each confirmed tick is sent once,
   * XOR-coded against the tick before it; otherwise every message repeats the unacknowledged ticks.
   */
  reliable?: boolean;
}

/** Options of {@link Relay.drain}. */
export interface RelayDrainOptions {
  /**
   * Running matches may go on this long; then their members are told `SHUTDOWN` and closed.
   * Default 25000 ms (inside Kubernetes' default 30 s grace period).
   */
  timeoutMs?: number;
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
  /** A spectator's state hash differs from the players' agreed one: only that spectator is told. */
  | { type: 'spectator-desync'; room: string; peer: number; tick: number }
  | { type: 'internal-error'; connection: number; error: unknown };

/** Counters of a relay. */
export interface RelayStats {
  connections: number;
  rooms: number;
  /** Rooms waiting for players (refreshed every 250 ms of the relay's clock). */
  waitingRooms: number;
  /** Distinct client addresses connected. */
  addresses: number;
  /** Players and spectators in rooms (refreshed every 250 ms of the relay's clock). */
  members: number;
  messagesIn: number;
  messagesOut: number;
  bytesIn: number;
  bytesOut: number;
  /** Connections dropped for misbehaviour, silence or caps, by code. */
  dropped: Partial<Record<NetErrorCode, number>>;
  /** Ticks closed with at least one input filled after its deadline. */
  filledInputs: number;
  hashChecks: number;
  /** Divergences between players (each split of a group that agreed before). */
  desyncs: number;
  /** Spectators whose hash differed from the players' agreed one (never evidence of a desync). */
  spectatorDesyncs: number;
  /** Liveness pings sent to silent members. */
  probes: number;
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
  /** Server time (ms) the room was created. */
  createdAt: number;
  startAt: number | undefined;
  /** Every tick before this one is closed (its inputs final and sent). */
  closedTick: number;
  /** The newest hash report tick on which every reporting player agreed. */
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
  address: string;
  /** The room its URL names, if any: its hello must be for it. */
  urlRoom: string | undefined;
  reliable: boolean;
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
  /**
   * Reliable transports: the tick after the last row of the previous confirmed message, which it
   * holds (the next message may be XOR-coded against that row); -1 when there is none.
   */
  deltaFrom: number;
  bucket: Bucket;
  strikes: number;
  openedAt: number;
  /** When it last sent anything (liveness). */
  heardAt: number;
  /** When it was last pinged for liveness. */
  probedAt: number;
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

/** A split found by the hash comparison, waiting for its forensics. */
interface Split {
  reportTick: number;
  /** The first tick to compare per-tick hashes from. */
  from: number;
  /** Whether the sides agreed at `from - 1` (the previous compared report). */
  agreedBefore: boolean;
  groups: { hash: bigint; peers: number[] }[];
}

interface Forensics {
  record: DesyncRecord;
  phase: 'hashes' | 'snapshots' | 'done';
  reps: Conn[];
  from: number;
  agreedBefore: boolean;
  requestId: number;
  hashes: Map<number, { from: number; hashes: BigUint64Array }>;
  snaps: Map<number, Uint8Array>;
  deadline: number;
  /** Whether the snapshots are collected (the room's forensics byte budget allows). */
  withSnapshots: boolean;
}

interface Report {
  at: number;
  /** Players' hashes: the evidence. */
  hashes: Map<number, bigint>;
  /** Spectators' hashes: checked against the players' agreed hash only. */
  spectators: Map<number, bigint>;
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
  reports = new Map<number, Report>();
  /** Newest report tick on which every reporting player agreed. */
  lastAgreed = 0;
  /** The previous compared report tick (every group of the partition agreed within there). */
  lastCompared = 0;
  /** Which side each player was on at the last compared report (one label: all agree). */
  partition = new Map<number, number>();
  nextLabel = 1;
  /** The players' agreed hash of recent report ticks, to check spectators' late reports. */
  agreed = new Map<number, bigint>();
  hashChecks = 0;
  desyncs: DesyncRecord[] = [];
  forensics: Forensics | undefined;
  splits: Split[] = [];
  forensicsBytes = 0;
  joins: JoinRequest[] = [];
  emptySince: number | undefined;
  readonly tickMs: number;
  /** u32 words per player per tick. */
  readonly words: number;
  /** The room's invite token: spectators must bring it. */
  readonly invite: Uint8Array;

  constructor(
    readonly name: string,
    readonly number: number,
    readonly game: RelayGame,
    readonly players: number,
    readonly seed: number,
    readonly config: Uint8Array,
    readonly creator: string,
    readonly createdAt: number,
    historyTicks: number,
    tokens: () => Uint8Array,
  ) {
    this.tickMs = 1000 / game.tickRate;
    this.words = game.input.words;
    this.log = new InputRing(historyTicks, players * this.words);
    this.invite = tokens();
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

  /** Player members. */
  *playerMembers(): Generator<Conn> {
    for (const s of this.slots) if (s.conn?.state === 'member') yield s.conn;
  }

  /** Every connection in the room, joining or member. */
  *conns(): Generator<Conn> {
    for (const s of this.slots) if (s.conn !== undefined) yield s.conn;
    yield* this.spectators;
  }

  get empty(): boolean {
    return this.slots.every((s) => s.conn === undefined) && this.spectators.size === 0;
  }

  get hasPlayers(): boolean {
    return this.slots.some((s) => s.conn !== undefined);
  }
}

const FATAL = true;
/** How often silence is checked (ms of relay clock). */
const LIVENESS_CHECK_MS = 250;

/**
 * The server core: rooms of any game, a tick clock per room, and server-ordered input relay
 * (lockstep on the server: the relay does not run the game). Transport-agnostic — the CLI
 * attaches it to WebSocket connections, tests and the lab to simulated links.
 *
 * The relay closes tick t when every connected, active player's input for t is in, or when its
 * clock passes `startAt + t × step + deadlineMs`: a missing input then becomes the player's last
 * input with held buttons only (a vacant slot's is 0). Closed ticks go to every member — over a
 * reliable transport once each, otherwise resent until acknowledged. Players report a hash every
 * `hashEvery` ticks; whenever players who agreed before disagree, the relay asks one member of each
 * side for per-tick hashes to find the first differing tick, tells everyone, and collects the
 * sides' snapshots of that tick for a byte diff. Spectators' hashes are never evidence.
 *
 * Strangers cannot hold it hostage: silent members are pinged and then dropped, waiting rooms
 * expire, a full room starts only with live players, connections and rooms are capped per client
 * address and in total, and spectators need the room's invite token.
 *
 * Call {@link update} at least twice per tick (the CLI does it every half step).
 */
export class Relay {
  readonly stats: RelayStats = {
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
    filledInputs: 0,
    hashChecks: 0,
    desyncs: 0,
    spectatorDesyncs: 0,
    probes: 0,
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
  private readonly connsByAddress = new Map<string, number>();
  private readonly roomsByAddress = new Map<string, number>();
  private rowScratch = new Uint32Array(16);
  private nextConnId = 1;
  private nextRoomNumber = 1;
  private nextProbeId = 1;
  private lastLivenessCheck = -Infinity;
  private closedRelay = false;
  private drainState: { deadline: number; resolve: () => void; done: Promise<void> } | undefined;

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
      maxConnectionsPerAddress: options.maxConnectionsPerAddress ?? 32,
      maxRoomsPerAddress: options.maxRoomsPerAddress ?? 8,
      maxSpectators: options.maxSpectators ?? 16,
      maxStrikes: options.maxStrikes ?? 8,
      helloTimeoutMs: options.helloTimeoutMs ?? 5000,
      silenceTimeoutMs: options.silenceTimeoutMs ?? 10_000,
      probeAfterMs: options.probeAfterMs ?? 1000,
      startLivenessMs: options.startLivenessMs ?? 2000,
      waitingRoomTtlMs: options.waitingRoomTtlMs ?? 120_000,
      snapshotTimeoutMs: options.snapshotTimeoutMs ?? 3000,
      forensicsTimeoutMs: options.forensicsTimeoutMs ?? 5000,
      hashTimeoutMs: options.hashTimeoutMs ?? 10_000,
      maxDesyncRecords: options.maxDesyncRecords ?? 64,
      maxForensicsBytes: options.maxForensicsBytes ?? 8 << 20,
      emptyRoomTtlMs: options.emptyRoomTtlMs ?? 30_000,
      maxSmallMessageBytes: options.maxSmallMessageBytes ?? 4096,
    };
    for (const [k, v] of Object.entries(this.o)) {
      if (!(typeof v === 'number' && v >= 0 && !Number.isNaN(v))) {
        throw new RangeError(`Relay: ${k} must be a number >= 0, got ${String(v)}`);
      }
    }
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

  /**
   * Take a new connection. `info` says where it comes from (its address, for the per-address
   * caps; the room its URL names). Returns its id (used in drop events), or -1 when it was
   * refused (`SERVER_FULL`: the relay is closed, or the global or per-address cap is reached).
   */
  accept(transport: Transport, info: RelayConnectionInfo = {}): number {
    const now = this.clock.now();
    const address = info.address ?? 'unknown';
    const refuse = (message: string): number => {
      this.stats.dropped.SERVER_FULL = (this.stats.dropped.SERVER_FULL ?? 0) + 1;
      this.emit({ type: 'drop', connection: -1, code: 'SERVER_FULL', message });
      transport.send(encodeMessage({ type: 'error', code: 'SERVER_FULL', message, fatal: true }));
      transport.close(`SERVER_FULL: ${message}`);
      return -1;
    };
    if (this.closedRelay) return refuse('server shut down');
    if (this.conns.size >= this.o.maxConnections) return refuse('too many connections');
    if ((this.connsByAddress.get(address) ?? 0) >= this.o.maxConnectionsPerAddress) {
      return refuse(`too many connections from one address (${this.o.maxConnectionsPerAddress})`);
    }
    const conn: Conn = {
      id: this.nextConnId++,
      transport,
      address,
      urlRoom: info.room,
      reliable: info.reliable ?? transport.reliable === true,
      state: 'new',
      room: undefined,
      peer: -1,
      slot: -1,
      name: '',
      joinTick: 0,
      ack: 0,
      ackMovedAt: now,
      sentUpTo: 0,
      deltaFrom: -1,
      bucket: { tokens: this.rate.messageBurst, bytes: this.rate.byteBurst, at: now },
      strikes: 0,
      openedAt: now,
      heardAt: now,
      probedAt: now,
      owes: new Map(),
      welcome: undefined,
      welcomeSentAt: -Infinity,
      started: false,
    };
    this.conns.set(conn.id, conn);
    bump(this.connsByAddress, address, 1);
    this.stats.connections = this.conns.size;
    this.stats.addresses = this.connsByAddress.size;
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
   * confirmed ticks, probe and drop silent connections, expire waiting rooms, time out donors and
   * forensics, remove empty rooms, and move a drain along.
   */
  update(now = this.clock.now()): void {
    const housekeeping = now - this.lastLivenessCheck >= LIVENESS_CHECK_MS;
    if (housekeeping) {
      this.lastLivenessCheck = now;
      this.checkLiveness(now);
    }
    for (const room of [...this.rooms.values()]) {
      try {
        this.updateRoom(room, now);
      } catch (error) {
        this.emit({ type: 'internal-error', connection: -1, error });
      }
    }
    if (housekeeping) this.countRooms();
    const d = this.drainState;
    if (d) {
      if (now >= d.deadline) {
        for (const room of [...this.rooms.values()])
          this.closeRoom(room, 'SHUTDOWN', 'server shutting down');
      }
      if (this.rooms.size === 0) d.resolve();
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

  /**
   * The invite token of a room (what its players get in their welcome), for the server's owner:
   * e.g. to hand a spectator link to an audience. A secret: anyone with it may watch the room.
   */
  invite(name: string): Uint8Array | undefined {
    return this.rooms.get(name)?.invite.slice();
  }

  /** Whether {@link drain} was called: no new rooms are created. */
  get draining(): boolean {
    return this.drainState !== undefined;
  }

  /**
   * Graceful shutdown: from now on no room is created (a hello that would create one gets a fatal
   * `SHUTDOWN`: the client should try another server); waiting rooms are closed at once
   * (`SHUTDOWN` to their members); running matches go on — reconnects and invited spectators
   * still join them — until their players have all left, or until `timeoutMs` has passed, when
   * their members are told `SHUTDOWN` and closed. Resolves when no room is left. {@link update}
   * must keep being called (the CLI's timer does).
   */
  drain(options: RelayDrainOptions = {}): Promise<void> {
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

  /** Close every connection (error SHUTDOWN) and refuse new ones. */
  close(): void {
    this.closedRelay = true;
    for (const conn of [...this.conns.values()]) {
      this.drop(conn, 'SHUTDOWN', 'server shutting down', false);
    }
    for (const room of [...this.rooms.values()]) this.removeRoom(room);
    this.drainState?.resolve();
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
    conn.heardAt = now;
    this.onMessage(conn, m, now);
  }

  private onMessage(conn: Conn, m: NetMessage, now: number): void {
    if (m.type === 'ping') {
      this.send(conn, { type: 'pong', id: m.id, time: m.time, serverTime: now });
      return;
    }
    if (m.type === 'pong') return; // The answer to a liveness probe: being heard is all.
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
      this.drop(
        conn,
        'room' in m ? 'WRONG_ROOM' : 'UNEXPECTED',
        'room' in m ? `${m.type} for another room` : `${m.type} is a server-to-client message`,
      );
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
    if (conn.urlRoom !== undefined && conn.urlRoom !== m.room) {
      this.drop(conn, 'WRONG_ROOM', `this connection is for room ${conn.urlRoom}, not ${m.room}`);
      return;
    }
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
      if (m.role === 'spectator') {
        this.drop(conn, 'BAD_HELLO', `no room ${m.room} to watch`);
        return;
      }
      if (this.drainState) {
        this.drop(conn, 'SHUTDOWN', 'server draining: no new rooms here', false);
        return;
      }
      if (this.rooms.size >= this.o.maxRooms) {
        this.drop(conn, 'SERVER_FULL', 'too many rooms');
        return;
      }
      if ((this.roomsByAddress.get(conn.address) ?? 0) >= this.o.maxRoomsPerAddress) {
        this.drop(
          conn,
          'SERVER_FULL',
          `too many rooms from one address (${this.o.maxRoomsPerAddress})`,
        );
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
        conn.address,
        now,
        this.o.historyTicks,
        () => this.token(),
      );
      this.rooms.set(m.room, room);
      bump(this.roomsByAddress, conn.address, 1);
      this.countRooms();
      this.emit({ type: 'room-created', room: room.name, game: game.id, players });
    } else if (room.game.id !== game.id || room.game.version !== game.version) {
      this.drop(
        conn,
        'GAME_MISMATCH',
        `room ${room.name} plays ${room.game.id} v${room.game.version}, not ${game.id} v${game.version}`,
      );
      return;
    }

    if (m.role === 'spectator') {
      if (m.token === undefined || !equalBytes(m.token, room.invite)) {
        this.drop(conn, 'BAD_TOKEN', `watching room ${room.name} takes its invite token`);
        return;
      }
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
      // A (re)joining player's state comes from a donor: it is on the donor's side of any split.
      room.partition.delete(slot);
    }
    room.emptySince = undefined;
    conn.name = m.name;
    conn.room = room;
    conn.state = 'joining';

    if (room.state === 'waiting') {
      this.welcome(conn, room, 0, undefined);
      this.emit({ type: 'join', room: room.name, peer: conn.peer, slot: conn.slot, late: false });
      this.tryStart(room, now);
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
    conn.deltaFrom = -1;
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
      invite: slot ? room.invite : new Uint8Array(0),
    };
    if (room.startAt !== undefined) m.startAt = room.startAt;
    if (snapshot !== undefined) m.snapshot = snapshot;
    conn.welcome = encodeMessage(m);
    conn.welcomeSentAt = this.clock.now();
    conn.started = room.startAt !== undefined;
    this.sendBytes(conn, conn.welcome);
  }

  /** Start a full waiting room, if every player in it has been heard from lately. */
  private tryStart(room: Room, now: number): void {
    if (room.state !== 'waiting') return;
    for (const s of room.slots) {
      const c = s.conn;
      if (c?.state !== 'member' || now - c.heardAt > this.o.startLivenessMs) return;
    }
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
    if (conn.slot < 0) {
      // A spectator's hash is checked against the players' agreement, never counted as evidence.
      const agreed = room.agreed.get(tick);
      if (agreed !== undefined) {
        this.checkSpectator(conn, room, tick, hash, agreed);
        return;
      }
      const r = tick > room.lastCompared ? this.report(room, tick, now) : undefined;
      r?.spectators.set(conn.peer, hash);
      return;
    }
    if (tick <= room.lastCompared) return;
    const r = this.report(room, tick, now);
    if (r === undefined) return;
    r.hashes.set(conn.peer, hash);
    this.checkReports(room, now);
  }

  private report(room: Room, tick: number, now: number): Report | undefined {
    let r = room.reports.get(tick);
    if (r === undefined) {
      if (room.reports.size >= 64) return undefined;
      r = { at: now, hashes: new Map(), spectators: new Map() };
      room.reports.set(tick, r);
    }
    return r;
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
      if (room.forensicsBytes + bytes.length <= this.o.maxForensicsBytes) {
        room.forensicsBytes += bytes.length;
        f.snaps.set(conn.peer, bytes);
      } else {
        f.snaps.set(conn.peer, new Uint8Array(0));
      }
      if (f.snaps.size === f.reps.length) this.finishForensics(room, f, now);
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

  // ------------------------------------------------------------------------------ liveness

  private checkLiveness(now: number): void {
    for (const conn of this.conns.values()) {
      if (conn.state === 'new') {
        if (now - conn.openedAt > this.o.helloTimeoutMs) {
          this.drop(conn, 'TIMEOUT', 'no hello in time');
        }
        continue;
      }
      const silent = now - conn.heardAt;
      if (silent >= this.o.silenceTimeoutMs) {
        this.drop(conn, 'TIMEOUT', `silent for ${Math.round(silent / 1000)} s`, FATAL, 'timeout');
      } else if (silent >= this.o.probeAfterMs && now - conn.probedAt >= this.o.probeAfterMs) {
        conn.probedAt = now;
        this.stats.probes++;
        this.send(conn, { type: 'ping', id: this.nextProbeId++ >>> 0, time: now });
      }
    }
  }

  // ------------------------------------------------------------------------------ the tick clock

  private updateJoins(room: Room, now: number): void {
    for (const req of [...room.joins]) {
      if (req.conn.state !== 'joining') room.joins = room.joins.filter((j) => j !== req);
      else if (now >= req.deadline) this.nextDonor(room, req, now);
    }
  }

  private updateRoom(room: Room, now: number): void {
    if (room.joins.length > 0) this.updateJoins(room, now);
    if (room.state === 'waiting') {
      if (now - room.createdAt >= this.o.waitingRoomTtlMs) {
        this.closeRoom(
          room,
          'TIMEOUT',
          `no match: the room waited ${Math.round(this.o.waitingRoomTtlMs / 1000)} s for players`,
        );
        return;
      }
      if (room.slots.every((s) => s.conn !== undefined)) this.tryStart(room, now);
    }
    if (room.state === 'running') this.closeTicks(room, now);
    this.flush(room, now);
    if (room.reports.size > 0) this.checkReports(room, now);
    const f = room.forensics;
    if (f && f.phase !== 'done' && now >= f.deadline) {
      if (f.phase === 'hashes') this.pinDesync(room, f, now);
      else this.finishForensics(room, f, now);
    }
    if (this.drainState && !room.hasPlayers) {
      this.closeRoom(room, 'SHUTDOWN', 'server shutting down');
      return;
    }
    if (room.empty) {
      room.emptySince ??= now;
      if (room.state === 'waiting' || now - room.emptySince >= this.o.emptyRoomTtlMs) {
        this.removeRoom(room);
      }
    }
  }

  /** Tell every connection of the room `code` (fatal), close them, and remove the room. */
  private closeRoom(room: Room, code: NetErrorCode, message: string): void {
    for (const c of [...room.conns()]) {
      this.drop(c, code, message, code !== 'SHUTDOWN', code === 'TIMEOUT' ? 'timeout' : 'closed');
    }
    this.removeRoom(room);
  }

  private removeRoom(room: Room): void {
    if (this.rooms.get(room.name) !== room) return;
    this.rooms.delete(room.name);
    bump(this.roomsByAddress, room.creator, -1);
    this.countRooms();
    this.emit({ type: 'room-removed', room: room.name });
  }

  private countRooms(): void {
    this.stats.rooms = this.rooms.size;
    let waiting = 0;
    let members = 0;
    for (const r of this.rooms.values()) {
      if (r.state === 'waiting') waiting++;
      for (const s of r.slots) if (s.conn?.state === 'member') members++;
      for (const c of r.spectators) if (c.state === 'member') members++;
    }
    this.stats.waitingRooms = waiting;
    this.stats.members = members;
  }

  private closeTicks(room: Room, now: number): void {
    const startAt = room.startAt!;
    const w = room.words;
    const row = this.closingRow(room.players * w);
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

  /** A scratch row of at least `lanes` words for {@link closeTicks} (which copies it into the log). */
  private closingRow(lanes: number): Uint32Array {
    if (this.rowScratch.length < lanes) this.rowScratch = new Uint32Array(lanes);
    return this.rowScratch;
  }

  /**
   * Send each member the closed ticks it lacks. Over a reliable transport each tick goes once,
   * XOR-coded against the tick before it (a held button costs one byte a player, and the header
   * six); otherwise every message repeats every unacknowledged tick, so a lost one costs nothing
   * but the next. Either way a member whose ack stops moving is rewound to its ack.
   */
  private flush(room: Room, now: number): void {
    // Loops rather than room.members(): this runs for every room twice a tick, and a generator
    // costs more than the usual work here (nothing to send).
    for (const s of room.slots) if (s.conn?.state === 'member') this.flushMember(room, s.conn, now);
    for (const c of room.spectators) if (c.state === 'member') this.flushMember(room, c, now);
  }

  private flushMember(room: Room, c: Conn, now: number): void {
    const newest = room.closedEnd;
    const maxTicks = this.limits.maxConfirmedTicks;
    const oldest = Math.max(0, newest - room.log.capacity + 1);
    const lanes = room.players * room.words;
    if (c.ack < oldest) {
      // Fell out of the history: it cannot catch up from here.
      this.drop(c, 'NO_SNAPSHOT', 'too far behind the room');
      return;
    }
    if (c.sentUpTo < c.ack) c.sentUpTo = c.ack;
    const rewind = c.ack < c.sentUpTo && now - c.ackMovedAt > (c.reliable ? 1000 : 250);
    if (!(newest > c.sentUpTo || rewind)) return;
    // Small gap: every message carries every unacknowledged tick (loss costs nothing).
    // Large gap (a late joiner catching up): stream onwards; go back to the ack on a timeout.
    let from = rewind || (!c.reliable && newest - c.ack <= maxTicks) ? c.ack : c.sentUpTo;
    if (rewind) {
      c.ackMovedAt = now;
      c.deltaFrom = -1;
    }
    const inputAck = this.inputAck(room, c);
    for (let k = 0; k < 8 && from < newest; k++) {
      const n = Math.min(maxTicks, newest - from);
      const inputs = new Uint32Array(n * lanes);
      for (let i = 0; i < n; i++) room.log.copy(from + i, inputs, i * lanes);
      const delta = c.reliable && from > 0 && c.deltaFrom === from;
      if (delta) {
        // XOR every row with tick from − 1's (which it holds): unchanged inputs become zeros.
        for (let p = 0; p < lanes; p++) {
          const base = room.log.get(from - 1, p);
          for (let i = 0; i < n; i++) inputs[i * lanes + p] = (inputs[i * lanes + p]! ^ base) >>> 0;
        }
      }
      this.send(c, {
        type: 'confirmed',
        inputAck: c.slot < 0 ? from + n : Math.max(inputAck, from + n),
        tick: from,
        players: room.players,
        words: room.words,
        inputs,
        delta,
      });
      from += n;
      if (c.reliable) c.deltaFrom = from;
    }
    c.sentUpTo = Math.max(c.sentUpTo, from);
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

  /**
   * Compare the players' reports of each tick once every player member that joined before it has
   * reported (or it timed out). Players who agreed at the previous comparison and now disagree
   * are a new desync — every one is diagnosed, not only the room's first — while a divergence
   * that persists (the same sides as before) is not reported again. Sides that agree again merge.
   */
  private checkReports(room: Room, now: number): void {
    const ticks = [...room.reports.keys()].sort((a, b) => a - b);
    for (const tick of ticks) {
      const r = room.reports.get(tick)!;
      let all = true;
      for (const c of room.playerMembers()) {
        if (c.joinTick >= tick) continue;
        if (!r.hashes.has(c.peer)) all = false;
      }
      const timedOut = now - r.at >= this.o.hashTimeoutMs || room.reports.size > 48;
      if (!(all || timedOut)) continue;
      room.reports.delete(tick);
      if (r.hashes.size === 0) continue;
      room.hashChecks++;
      this.stats.hashChecks++;
      const groups = groupByHash(r.hashes);
      const previous = room.lastCompared;
      room.lastCompared = tick;
      if (groups.length === 1) {
        room.lastAgreed = tick;
        const agreed = groups[0]!.hash;
        room.agreed.set(tick, agreed);
        if (room.agreed.size > 16) room.agreed.delete(room.agreed.keys().next().value!);
        for (const [peer, hash] of r.spectators) {
          const c = [...room.spectators].find((x) => x.peer === peer);
          if (c) this.checkSpectator(c, room, tick, hash, agreed);
        }
      }
      this.repartition(room, tick, previous, groups, now);
    }
  }

  /** Compare the new grouping with the previous one: splits are desyncs; relabel every player. */
  private repartition(
    room: Room,
    tick: number,
    previous: number,
    groups: { hash: bigint; peers: number[] }[],
    now: number,
  ): void {
    // A player without a side yet (the first report, a newcomer) is on the most common side.
    const counts = new Map<number, number>();
    for (const l of room.partition.values()) counts.set(l, (counts.get(l) ?? 0) + 1);
    let common = 0;
    let best = -1;
    for (const [l, n] of counts) {
      if (n > best || (n === best && l < common)) {
        best = n;
        common = l;
      }
    }
    const labelOf = (peer: number) => room.partition.get(peer) ?? common;
    // For each old side: the new groups its players went to.
    const sides = new Map<number, Map<number, number[]>>();
    groups.forEach((g, gi) => {
      for (const p of g.peers) {
        const l = labelOf(p);
        let m = sides.get(l);
        if (!m) sides.set(l, (m = new Map<number, number[]>()));
        let list = m.get(gi);
        if (!list) m.set(gi, (list = []));
        list.push(p);
      }
    });
    const newLabel = groups.map(() => room.nextLabel++);
    const oldToNew = new Map<number, number>();
    for (const [l, m] of sides) {
      if (m.size === 1) {
        oldToNew.set(l, newLabel[m.keys().next().value!]!);
        continue;
      }
      // A split: players who agreed at `previous` disagree now.
      const split = [...m.entries()].map(([gi, peers]) => ({ hash: groups[gi]!.hash, peers }));
      split.sort((a, b) => b.peers.length - a.peers.length || a.peers[0]! - b.peers[0]!);
      this.stats.desyncs++;
      if (
        room.desyncs.length + room.splits.length + (room.forensics ? 1 : 0) <
        this.o.maxDesyncRecords
      ) {
        const from = Math.max(previous + 1, tick - this.limits.maxHashes + 1);
        room.splits.push({
          reportTick: tick,
          from,
          agreedBefore: from === previous + 1,
          groups: split,
        });
      }
    }
    // Players who did not report keep their side if it did not split.
    for (const [peer, l] of [...room.partition]) {
      const next = oldToNew.get(l);
      if (next !== undefined) room.partition.set(peer, next);
    }
    groups.forEach((g, gi) => {
      for (const p of g.peers) room.partition.set(p, newLabel[gi]!);
    });
    if (room.forensics === undefined) this.nextForensics(room, now);
  }

  private checkSpectator(c: Conn, room: Room, tick: number, hash: bigint, agreed: bigint): void {
    if (hash === agreed) return;
    this.stats.spectatorDesyncs++;
    const players = [...room.playerMembers()].map((p) => p.peer);
    this.send(c, {
      type: 'desync',
      room: room.number,
      tick,
      exact: false,
      reportTick: tick,
      majority: 0,
      groups: [
        { hash: agreed, peers: players },
        { hash, peers: [c.peer] },
      ],
    });
    this.emit({ type: 'spectator-desync', room: room.name, peer: c.peer, tick });
  }

  private nextForensics(room: Room, now: number): void {
    const split = room.splits.shift();
    if (split) this.beginForensics(room, split, now);
  }

  private beginForensics(room: Room, split: Split, now: number): void {
    const byPeer = new Map<number, Conn>();
    for (const c of room.playerMembers()) byPeer.set(c.peer, c);
    const reps: Conn[] = [];
    for (const g of split.groups) {
      const rep = g.peers.map((p) => byPeer.get(p)).find((c) => c !== undefined);
      if (rep) reps.push(rep);
    }
    const total = split.groups.reduce((n, g) => n + g.peers.length, 0);
    const record: DesyncRecord = {
      room: room.name,
      reportTick: split.reportTick,
      tick: split.reportTick,
      exact: false,
      groups: split.groups.map((g) => ({
        hash: g.hash,
        peers: g.peers,
        slots: g.peers.filter((p) => p < 64),
      })),
      majority: majorityOf(split.groups, total),
      snapshots: [],
      diffs: [],
      complete: false,
    };
    const f: Forensics = {
      record,
      phase: 'hashes',
      reps,
      from: split.from,
      agreedBefore: split.agreedBefore,
      requestId: room.nextRequestId++,
      hashes: new Map(),
      snaps: new Map(),
      deadline: now + this.o.forensicsTimeoutMs,
      withSnapshots: room.forensicsBytes < this.o.maxForensicsBytes,
    };
    room.forensics = f;
    room.desyncs.push(record);
    for (const c of reps) {
      this.owe(c, f.requestId, 'hashes');
      this.send(c, {
        type: 'hashes-request',
        room: room.number,
        id: f.requestId,
        from: split.from,
        count: split.reportTick - split.from + 1,
      });
    }
    if (reps.length === 0) this.pinDesync(room, f, now);
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
      // Exact when the sides agree just before (or it is the first tick they were compared from).
      const before = peers.map((p) => hashAt(p, first - 1));
      rec.exact =
        (first === f.from && f.agreedBefore) ||
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
    if (!f.withSnapshots) {
      this.finishForensics(room, f, now);
      return;
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

  private finishForensics(room: Room, f: Forensics, now: number): void {
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
    this.nextForensics(room, now);
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
    bump(this.connsByAddress, conn.address, -1);
    this.stats.connections = this.conns.size;
    this.stats.addresses = this.connsByAddress.size;
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
      createdAt: r.createdAt,
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

function bump(counts: Map<string, number>, key: string, by: number): void {
  const n = (counts.get(key) ?? 0) + by;
  if (n <= 0) counts.delete(key);
  else counts.set(key, n);
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
