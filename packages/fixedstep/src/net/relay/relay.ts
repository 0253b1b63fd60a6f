/**
 * The relay: rooms of any game, a tick clock per room, server-ordered inputs — lockstep on the
 * server (it never runs the game) — on the room core.
 * @module
 */
import type { Clock } from '../../time/drivers.js';
import { type GameCatalog, type TicketVerifier } from '../room/game-join.js';
import { GameRoomHost } from '../room/game-host.js';
import type { HostEvent, HostStats } from '../room/host-types.js';
import type { RoomHostOptions } from '../room/options.js';
import type { MemberInit } from '../room/room.js';
import type { LeaveReason } from '../wire/common.js';
import type { DesyncRecord } from './forensics.js';
import {
  DEFAULT_PROTOCOL_LIMITS,
  MAX_SEND_EVERY,
  RELAY_PROTOCOL,
  type NetMessage,
  type ProtocolLimits,
} from './messages.js';
import { RelayMember, RelayRoom, type RelayRoomEvents, type RelaySettings } from './room.js';

/** How long after a tick's time a missing input is filled: a late input costs everyone this long. */
export const DEFAULT_DEADLINE_MS = 100;
/** Clients report a state hash every this many ticks (half a second at 60 Hz). */
export const DEFAULT_HASH_EVERY = 30;
/** From "all seats filled" to tick 0, so clocks can sync. */
export const DEFAULT_START_DELAY_MS = 500;
/** Inputs further ahead of the server clock are refused (3 s at 60 Hz). */
export const DEFAULT_MAX_AHEAD_TICKS = 180;
/** Inputs this much older than the newest closed tick are a violation. */
export const DEFAULT_MAX_BEHIND_TICKS = 256;
/** Closed ticks kept for late joiners and retransmission (2 min 16 s at 60 Hz). */
export const DEFAULT_HISTORY_TICKS = 8192;
/** A match ends after this many ticks (1 h at 60 Hz). */
export const DEFAULT_MAX_MATCH_TICKS = 216_000;
/** A full room starts only when every player was heard this recently. */
export const DEFAULT_START_LIVENESS_MS = 2000;
/** A snapshot donor must answer within this, else the next member is asked. */
export const DEFAULT_SNAPSHOT_TIMEOUT_MS = 3000;
/** Forensics requests wait this long for answers. */
export const DEFAULT_FORENSICS_TIMEOUT_MS = 5000;
/** A report tick is compared after this long even if someone has not reported. */
export const DEFAULT_HASH_TIMEOUT_MS = 10_000;
/** Desyncs recorded (and diagnosed) per room. */
export const DEFAULT_MAX_DESYNC_RECORDS = 64;
/** Bytes of forensics snapshots a room keeps, all records together. */
export const DEFAULT_MAX_FORENSICS_BYTES = 8 << 20;

/** Options of a {@link Relay}: the room core's, and the relay's own. */
export interface RelayOptions extends RoomHostOptions {
  /** The server clock (ms): ticks, deadlines, timeouts. Inject a ManualClock in tests. */
  clock: Clock;
  /** The games rooms may play. */
  catalog: GameCatalog;
  /** Checks quick-match tickets (from the server's matchmaker). Default: tickets are refused. */
  tickets?: TicketVerifier;
  /**
   * How long after a tick's start time the relay waits for a connected player's missing input
   * before filling it with the player's last input (held buttons only). Default
   * {@link DEFAULT_DEADLINE_MS}. Everyone else's view of that tick waits this long at most.
   */
  deadlineMs?: number;
  /** Clients report a state hash every this many ticks. Default {@link DEFAULT_HASH_EVERY}. */
  hashEvery?: number;
  /**
   * The network rate, as ticks per send (1 to {@link MAX_SEND_EVERY}): confirmed ticks go out in
   * groups of this many, and the welcome asks players to send their inputs in groups of this
   * many. Fewer, larger WebSocket frames — 60 Hz play at `sendEvery: 3` sends 20 frames a second
   * each way instead of 60 — for up to `sendEvery − 1` ticks more latency each way (which the
   * sessions' input delay and playout buffer take in). Default 1. Does not change what is played.
   */
  sendEvery?: number;
  /** Time from "all seats filled" to tick 0. Default {@link DEFAULT_START_DELAY_MS}. */
  startDelayMs?: number;
  /** Inputs more than this many ticks ahead of the server clock are refused. Default {@link DEFAULT_MAX_AHEAD_TICKS}. */
  maxAheadTicks?: number;
  /** Inputs this many ticks older than the newest closed tick are a violation. Default {@link DEFAULT_MAX_BEHIND_TICKS}. */
  maxBehindTicks?: number;
  /**
   * Closed ticks kept for late joiners and retransmission. Default {@link DEFAULT_HISTORY_TICKS}.
   * Each room holds `historyTicks × players × words × 4` bytes (128 KiB for 4 players of one word).
   */
  historyTicks?: number;
  /** A match ends after this many ticks. Default {@link DEFAULT_MAX_MATCH_TICKS}. */
  maxMatchTicks?: number;
  /**
   * A full room starts only when every player has been heard from within this time: a frozen peer
   * never starts a newcomer's match. Default {@link DEFAULT_START_LIVENESS_MS}.
   */
  startLivenessMs?: number;
  /** A snapshot donor must answer within this time. Default {@link DEFAULT_SNAPSHOT_TIMEOUT_MS}. */
  snapshotTimeoutMs?: number;
  /** Forensics requests wait this long. Default {@link DEFAULT_FORENSICS_TIMEOUT_MS}. */
  forensicsTimeoutMs?: number;
  /** A report tick is compared after this long. Default {@link DEFAULT_HASH_TIMEOUT_MS}. */
  hashTimeoutMs?: number;
  /** Desyncs recorded per room (later ones are still counted). Default {@link DEFAULT_MAX_DESYNC_RECORDS}. */
  maxDesyncRecords?: number;
  /** Forensics snapshot bytes a room keeps. Default {@link DEFAULT_MAX_FORENSICS_BYTES}. */
  maxForensicsBytes?: number;
  limits?: Partial<ProtocolLimits>;
  /** Where the relay reports drops, desyncs and room life (default: nowhere). */
  onEvent?: (event: RelayEvent) => void;
}

/** Options of {@link Relay.drain}. */
export interface RelayDrainOptions {
  /** Running matches may go on this long; then their members are told `SHUTDOWN`. Default 25 000 ms. */
  timeoutMs?: number;
}

/** What the relay reports. */
export type RelayEvent =
  | HostEvent
  | { type: 'room-started'; room: string; startAt: number }
  | { type: 'desync'; record: DesyncRecord }
  /** A spectator's state hash differs from the players' agreed one: only that spectator is told. */
  | { type: 'spectator-desync'; room: string; peer: number; tick: number };

/** Counters of a relay. */
export interface RelayStats extends HostStats {
  /** Ticks closed with at least one input filled after its deadline. */
  filledInputs: number;
  hashChecks: number;
  /** Divergences between players (each split of a group that agreed before). */
  desyncs: number;
  /** Spectators whose hash differed from the players' agreed one (never evidence of a desync). */
  spectatorDesyncs: number;
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

/**
 * The relay. Every protection is the room core's ({@link RoomHost}): caps per address and in
 * total (at capacity, idle rooms make way), join deadlines, rates, liveness on the server's
 * responsive time, seats held for dropped players, invites for spectators, quick-match tickets.
 * See {@link RelayRoom} for a match's tick clock and {@link DesyncDetector} for its forensics.
 *
 * Call {@link update} at least twice per tick (the server does it every half step).
 */
export class Relay extends GameRoomHost<RelayMember, RelayRoom, NetMessage, RelayEvent> {
  declare readonly stats: RelayStats;
  private readonly catalog: GameCatalog;
  private readonly tickets: TicketVerifier | undefined;
  private readonly relay: RelaySettings;
  private readonly roomEvents: RelayRoomEvents;

  constructor(options: RelayOptions) {
    super('Relay', options.clock, options, RELAY_PROTOCOL, options.onEvent);
    Object.assign(this.stats, { filledInputs: 0, hashChecks: 0, desyncs: 0, spectatorDesyncs: 0 });
    this.catalog = options.catalog;
    this.tickets = options.tickets;
    this.relay = {
      deadlineMs: options.deadlineMs ?? DEFAULT_DEADLINE_MS,
      hashEvery: options.hashEvery ?? DEFAULT_HASH_EVERY,
      sendEvery: options.sendEvery ?? 1,
      startDelayMs: options.startDelayMs ?? DEFAULT_START_DELAY_MS,
      maxAheadTicks: options.maxAheadTicks ?? DEFAULT_MAX_AHEAD_TICKS,
      maxBehindTicks: options.maxBehindTicks ?? DEFAULT_MAX_BEHIND_TICKS,
      historyTicks: options.historyTicks ?? DEFAULT_HISTORY_TICKS,
      maxMatchTicks: options.maxMatchTicks ?? DEFAULT_MAX_MATCH_TICKS,
      startLivenessMs: options.startLivenessMs ?? DEFAULT_START_LIVENESS_MS,
      snapshotTimeoutMs: options.snapshotTimeoutMs ?? DEFAULT_SNAPSHOT_TIMEOUT_MS,
      forensicsTimeoutMs: options.forensicsTimeoutMs ?? DEFAULT_FORENSICS_TIMEOUT_MS,
      hashTimeoutMs: options.hashTimeoutMs ?? DEFAULT_HASH_TIMEOUT_MS,
      maxDesyncRecords: options.maxDesyncRecords ?? DEFAULT_MAX_DESYNC_RECORDS,
      maxForensicsBytes: options.maxForensicsBytes ?? DEFAULT_MAX_FORENSICS_BYTES,
      limits: { ...DEFAULT_PROTOCOL_LIMITS, ...options.limits },
    };
    const every = this.relay.sendEvery;
    if (!(Number.isInteger(every) && every >= 1 && every <= MAX_SEND_EVERY)) {
      throw new RangeError(
        `Relay: sendEvery must be an integer from 1 to ${MAX_SEND_EVERY}, got ${every}`,
      );
    }
    for (const [k, v] of Object.entries(this.relay)) {
      if (typeof v === 'number' && !(v >= 0)) {
        throw new RangeError(`Relay: ${k} must be a number >= 0, got ${String(v)}`);
      }
    }
    const stats = this.stats;
    this.roomEvents = {
      join: (room, m, late) => {
        this.emit({ type: 'join', room: room.name, peer: m.peer, slot: m.slot, late });
      },
      leave: (room, m, reason: LeaveReason) => {
        this.emit({ type: 'leave', room: room.name, peer: m.peer, reason });
      },
      started: (room) => {
        this.emit({ type: 'room-started', room: room.name, startAt: room.startAt! });
      },
      desync: (_room, record) => {
        this.emit({ type: 'desync', record });
      },
      spectatorDesync: (room, m, tick) => {
        this.emit({ type: 'spectator-desync', room: room.name, peer: m.peer, tick });
      },
      filled: () => {
        stats.filledInputs++;
      },
      hashCheck: () => {
        stats.hashChecks++;
      },
      split: () => {
        stats.desyncs++;
      },
      spectatorSplit: () => {
        stats.spectatorDesyncs++;
      },
    };
  }

  /** A view of one room. */
  room(name: string): RoomInfo | undefined {
    const r = this.rooms.get(name);
    return r ? info(r) : undefined;
  }

  /** Views of all rooms. */
  roomList(): RoomInfo[] {
    return [...this.rooms.values()].map(info);
  }

  override drain(options: RelayDrainOptions = {}): Promise<void> {
    return super.drain(options);
  }

  protected override decodeLimits(): object {
    return this.relay.limits;
  }

  protected createMember(init: MemberInit): RelayMember {
    return new RelayMember(init);
  }

  protected onJoinMessage(m: RelayMember, message: NetMessage, now: number): boolean {
    if (message.type !== 'hello') return false;
    return this.joinGame(
      m,
      message,
      {
        catalog: this.catalog,
        tickets: this.tickets,
        make: (setup, number, tokens) =>
          new RelayRoom(
            message.room,
            number,
            setup.game,
            setup.players,
            setup.seed,
            setup.game.options ? setup.game.options(setup.players, setup.seed) : new Uint8Array(0),
            m.address,
            now,
            tokens(),
            tokens,
            setup.ticketed,
            this.context,
            this.relay,
            this.roomEvents,
          ),
      },
      now,
    );
  }
}

function info(r: RelayRoom): RoomInfo {
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
    lastAgreedTick: r.desyncs.lastAgreed,
    hashChecks: r.desyncs.hashChecks,
    members: [...r.members()].map((c) => ({
      peer: c.peer,
      slot: c.slot,
      name: c.name,
      ack: c.ack,
    })),
    desyncs: r.desyncs.records,
  };
}
