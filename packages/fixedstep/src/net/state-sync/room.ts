/**
 * The server side of state sync: a room runs the game at the fixed step, owns the tick clock,
 * applies each player's inputs at the tick they were meant for, and sends every member the world
 * state — delta-coded against the last snapshot that member acknowledged. A room of the room core:
 * its seats, invite, caps, rates and liveness are the core's.
 * @module
 */
import type { AnyGameDefinition } from '../../sim/game.js';
import { gameSetup } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import { InputRing, SnapshotRing } from '../history.js';
import { ADOPTED, type RoomContext } from '../room/host-types.js';
import type { RoomHostOptions } from '../room/options.js';
import { Member, Room } from '../room/room.js';
import { newToken } from '../room/tokens.js';
import type { Transport } from '../transport.js';
import type { LeaveReason } from '../wire/common.js';
import { PriorityAccumulator } from './priority.js';
import { SnapshotCoder, WHOLE_VIEW, schemaOf, type SnapshotRound } from './snapshot-coder.js';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  MAX_SLACK,
  STATE_SYNC_PROTOCOL,
  type StateSyncLimits,
  type StateSyncMessage,
} from './messages.js';
import { StateSyncServer } from './server.js';

/**
 * Interest management: the bytes of the world that the member in `slot` (-1: a spectator) may
 * see, in the game's own `save()` format so the client can load them. Return `sim.save()` to show
 * everything; blank what the member must not know (another team's positions behind walls, a hand
 * of cards). Called once per member and snapshot, on the server only; it must not change `sim`.
 */
export type StateSyncView<S> = (sim: S, slot: number) => Uint8Array;

/** Snapshots a second, by default: the tick rate ÷ this is the default `snapshotEvery`. */
export const DEFAULT_SNAPSHOTS_PER_SECOND = 20;
/** Snapshots kept per member as delta bases (1.6 s at 20 a second). */
export const DEFAULT_BASE_HISTORY = 32;
/** Inputs further ahead of the room's tick are a violation (2 s at 60 Hz). */
export const DEFAULT_STATE_MAX_AHEAD_TICKS = 120;
/** At most one full snapshot per member this often after a resync request. */
export const DEFAULT_RESYNC_INTERVAL_MS = 250;
/** Most ticks one update steps: after a stall a room catches up this many ticks an update. */
export const DEFAULT_MAX_CATCH_UP_TICKS = 8;
/** Ticks of inputs a seat keeps ahead of the room. */
const PENDING_TICKS = 256;
/**
 * How many snapshot intervals back the older snapshot of a delta may be: half a session's default
 * history of bases (64), so the client still holds it.
 */
const OLDER_REACH = 32;

/**
 * Options of a {@link StateSyncRoom}. The room core's options (rates, caps, liveness) apply when
 * the room serves connections on its own ({@link StateSyncRoom.accept}); in a
 * {@link StateSyncServer} the server's apply.
 */
export interface StateSyncRoomOptions<
  S extends Simulation<unknown> = Simulation<unknown>,
> extends RoomHostOptions {
  /** The game. The room builds it with `create(gameSetup(game, players, seed))`. */
  game: AnyGameDefinition;
  /** The room's name (what clients join). Default `room`. */
  name?: string;
  /**
   * The server clock, in ms: tick t is stepped when it passes `startAt + (t + 1) × step`, `startAt`
   * being the clock when the room was created. Inject a `ManualClock` in tests.
   */
  clock: Clock;
  /** Player seats. Default: the game's minimum. */
  players?: number;
  /** The game's seed (u32). Default: from `randomU32`. */
  seed?: number;
  /**
   * A snapshot goes to every member every this many ticks. Default: the tick rate ÷ 20, at least 1
   * (20 snapshots a second). Does not change the simulation, only how often it is seen.
   */
  snapshotEvery?: number;
  /**
   * Delta-code snapshots against each member's acknowledged one. Default true; false sends every
   * snapshot whole (for comparisons: the benchmark's "full" column).
   */
  delta?: boolean;
  /**
   * How snapshots are coded: `'schema'` (the default when the game declares a
   * {@link GameDefinition.stateSchema}) sends the schema's quantised words as bits — and snaps the
   * room's world to them at every snapshot; `'bytes'` sends the game's `save()` bytes (whole, or as
   * XOR runs against the base), the only choice for a game without a schema.
   */
  codec?: 'schema' | 'bytes';
  /**
   * Schema codec: the most payload bytes of one snapshot to one member. A delta that is larger
   * sends only the entities (rows of the schema's largest group) that waited longest — a priority
   * accumulator per member — and the rest as the client predicts them (moved by their rates), so
   * they catch up in later snapshots. E.g. 533 for 32 KB/s at 60 snapshots a second. Default: no
   * budget.
   */
  maxSnapshotBytes?: number;
  /** Interest management (default: everyone sees the whole `save()`). See {@link StateSyncView}. */
  view?: StateSyncView<S>;
  /** Snapshots kept per member as delta bases. Default {@link DEFAULT_BASE_HISTORY}. */
  baseHistory?: number;
  /** Inputs more than this many ticks ahead of the room's tick are refused (a strike). Default 120. */
  maxAheadTicks?: number;
  /** At most one full snapshot per member this often after a resync request, in ms. Default 250. */
  resyncIntervalMs?: number;
  /** Most ticks one update steps. Default {@link DEFAULT_MAX_CATCH_UP_TICKS}. */
  maxCatchUpTicks?: number;
  limits?: Partial<StateSyncLimits>;
  /** Where a room serving on its own reports joins, leaves and drops (default: nowhere). */
  onEvent?: (event: StateSyncRoomEvent) => void;
}

/** What a room reports (a {@link StateSyncServer} reports these among its own). */
export type StateSyncRoomEvent =
  | { type: 'join'; room: string; peer: number; slot: number; late: boolean }
  | { type: 'leave'; room: string; peer: number; reason: LeaveReason }
  | { type: 'drop'; connection: number; code: string; message: string };

/** Where a {@link StateSyncServer} puts a room it makes. */
export interface RoomPlacement {
  /** The server's number for it. */
  number: number;
  /** The address whose join made it. */
  creator: string;
  /** Makes its tokens (invite, reconnect). */
  tokens: () => Uint8Array;
  /** Made from a match ticket. */
  ticketed: boolean;
}

/** Counters of a room. */
export interface StateSyncRoomStats {
  /** Ticks stepped. */
  ticks: number;
  /** Snapshots sent: whole, and delta-coded. */
  fullSnapshots: number;
  deltaSnapshots: number;
  /** Bytes of every snapshot message sent (headers included). */
  snapshotBytes: number;
  /** Player-ticks stepped without that player's input (the missing rule filled them). */
  filledInputs: number;
  /** Inputs that came after their tick was stepped (dropped: the filled value stands). */
  lateInputs: number;
  /** Second, different inputs for a tick already received (dropped: the first is final). */
  conflictingInputs: number;
  /** Resync requests. */
  resyncs: number;
  /** Entity rows left out of snapshots by the byte budget (sent as predicted). */
  deferredRows: number;
  /**
   * Schema codec: the largest |value − sent value| of a quantised number so far, in units of its
   * column's precision (at most 0.5), and the values clamped into their column's range.
   */
  quantisationError: number;
  clampedValues: number;
  /** Connections dropped, by reason (a room serving on its own; in a server, the server's stats). */
  dropped: Partial<Record<string, number>>;
}

/** A state-sync connection: the room core's member and its delta bases. */
export class StateSyncMember extends Member {
  /** Newest snapshot tick the member acknowledged (-1: none). */
  ack = -1;
  /** The acknowledgement before `ack` (-1: none). */
  ackBefore = -1;
  /** The snapshots sent to it, by tick (its delta bases; sized by its room when welcomed). */
  sent = new SnapshotRing(1);
  /** The tick of the last snapshot sent to it (-1: none since it last needed a full one). */
  lastSent = -1;
  /** The one sent before `lastSent` (-1: none since the last full one). */
  sentBefore = -1;
  needsFull = true;
  lastFullAt = -Infinity;
  /** Its rows' priorities under a byte budget. */
  readonly priority = new PriorityAccumulator();
}

interface SeatInputs {
  /** Inputs received for ticks not yet stepped. */
  pending: InputRing;
  /** The words applied at the last stepped tick (the missing rule's "last input"). */
  last: Uint32Array;
  /** Whether it sent an input since it (re)joined: only an active player's input is filled from its last. */
  active: boolean;
  filled: number;
  /** Of the filled ticks, the inputs that came later. */
  late: number;
  /** The fewest ticks an input arrived ahead of its tick since the last snapshot ({@link MAX_SLACK}: none). */
  slack: number;
  /** Per tick modulo {@link PENDING_TICKS}: the tick whose input was filled there (a later arrival is late). */
  filledTicks: Float64Array;
}

/** The checked, defaulted room settings. */
interface Settings {
  snapshotEvery: number;
  delta: boolean;
  baseHistory: number;
  maxAheadTicks: number;
  resyncIntervalMs: number;
  maxCatchUpTicks: number;
  limits: StateSyncLimits;
}

function positiveInt(name: string, v: number, max: number): number {
  if (!(Number.isInteger(v) && v >= 1 && v <= max)) {
    throw new RangeError(
      `StateSyncRoom: ${name} must be an integer from 1 to ${max}, got ${String(v)}`,
    );
  }
  return v;
}

/**
 * One state-sync room: the authority. It runs the game — built from the game definition, the seed
 * and the players — at the fixed step on the server clock. Clients send only inputs; the room
 * checks them against the input schema (a client cannot send what its controller could not),
 * against its seat (nor for another player), and against the tick window (nor many ticks ahead),
 * and keeps the first input of each tick. Tick t is stepped at `startAt + (t + 1) × step` with the
 * inputs that are in; a missing input follows the relay's rule — a connected player's last input,
 * held buttons only, axes kept; a vacant seat's is 0 — and one that comes later is dropped.
 *
 * Every `snapshotEvery` ticks each member gets the state — what {@link StateSyncRoomOptions.view}
 * lets it see — as the game's canonical bytes, delta-coded against the newest snapshot it
 * acknowledged (whole on join, when its acknowledgement is older than `baseHistory` snapshots, or
 * after it asked to resync), with the state's hash and the server time. Nothing a client sends is
 * ever state, so a client that lies about the world changes nothing. The game need not be
 * deterministic: clients correct their prediction from every snapshot.
 *
 * In a {@link StateSyncServer} the server drives it; on its own, {@link accept} connections and
 * call {@link update} every few ms (on an `EventScheduler` in tests).
 */
export class StateSyncRoom<
  S extends Simulation<unknown> = Simulation<unknown>,
> extends Room<StateSyncMember> {
  readonly game: AnyGameDefinition;
  readonly seed: number;
  /** Server time (ms) of tick 0. */
  readonly startAt: number;
  /** Milliseconds per tick. */
  readonly tickMs: number;
  readonly stats: StateSyncRoomStats = {
    ticks: 0,
    fullSnapshots: 0,
    deltaSnapshots: 0,
    snapshotBytes: 0,
    filledInputs: 0,
    lateInputs: 0,
    conflictingInputs: 0,
    resyncs: 0,
    deferredRows: 0,
    quantisationError: 0,
    clampedValues: 0,
    dropped: {},
  };

  private readonly sim: S;
  private readonly options: StateSyncRoomOptions<S>;
  private readonly settings: Settings;
  private readonly words: number;
  private readonly inputs: SeatInputs[] = [];
  private readonly config: Uint8Array;
  private readonly row: unknown[];
  private readonly rowWords: Uint32Array;
  private readonly coder: SnapshotCoder;
  /** The schema has columns that extrapolate: deltas name an older snapshot too. */
  private readonly extrapolates: boolean;
  private ctx: RoomContext<StateSyncMember, StateSyncMessage> | undefined;
  /** The host of a room serving on its own (made at its first connection). */
  private standalone: StateSyncServer | undefined;

  /**
   * @param placement — where a {@link StateSyncServer} puts it (its number, who made it, its
   * tokens); without one the room serves connections on its own ({@link accept}).
   */
  constructor(options: StateSyncRoomOptions<S>, placement?: RoomPlacement) {
    const game = options.game;
    const random = randomOf(options);
    const players = options.players ?? game.minPlayers;
    const now = options.clock.now();
    const tokens = placement?.tokens ?? (() => newToken(random));
    super(
      options.name ?? 'room',
      placement?.number ?? 1,
      players,
      placement?.creator ?? ADOPTED,
      now,
      tokens(),
      tokens,
      placement?.ticketed ?? false,
    );
    this.options = options;
    this.game = game;
    this.seed = options.seed ?? random();
    const setup = gameSetup(game, players, this.seed);
    this.config = setup.options;
    this.sim = game.create(setup) as S;
    this.tickMs = 1000 / game.tickRate;
    this.words = game.input.words;
    const limits = { ...DEFAULT_STATE_SYNC_LIMITS, ...options.limits };
    this.settings = {
      snapshotEvery: positiveInt(
        'snapshotEvery',
        options.snapshotEvery ??
          Math.max(1, Math.round(game.tickRate / DEFAULT_SNAPSHOTS_PER_SECOND)),
        1 << 16,
      ),
      delta: options.delta ?? true,
      baseHistory: positiveInt('baseHistory', options.baseHistory ?? DEFAULT_BASE_HISTORY, 4096),
      maxAheadTicks: positiveInt(
        'maxAheadTicks',
        options.maxAheadTicks ?? DEFAULT_STATE_MAX_AHEAD_TICKS,
        240,
      ),
      resyncIntervalMs: options.resyncIntervalMs ?? DEFAULT_RESYNC_INTERVAL_MS,
      maxCatchUpTicks: positiveInt(
        'maxCatchUpTicks',
        options.maxCatchUpTicks ?? DEFAULT_MAX_CATCH_UP_TICKS,
        10_000,
      ),
      limits,
    };
    this.coder = new SnapshotCoder(
      schemaOf(game, options.codec),
      game.tickRate,
      options.maxSnapshotBytes === undefined
        ? Infinity
        : positiveInt('maxSnapshotBytes', options.maxSnapshotBytes, 1 << 30),
      this.stats,
    );
    this.extrapolates = this.coder.extrapolates;
    if (this.words > limits.maxInputWords) {
      throw new RangeError(
        `StateSyncRoom: ${game.id} inputs have ${this.words} words, at most ${limits.maxInputWords}`,
      );
    }
    for (let p = 0; p < players; p++) {
      this.inputs.push({
        pending: new InputRing(PENDING_TICKS, this.words),
        last: new Uint32Array(this.words),
        active: false,
        filled: 0,
        late: 0,
        slack: MAX_SLACK,
        filledTicks: new Float64Array(PENDING_TICKS).fill(-1),
      });
    }
    this.row = new Array<unknown>(players);
    this.rowWords = new Uint32Array(players * this.words);
    this.startAt = now;
    // The world runs from the start: there is nothing to wait for.
    this.state = 'running';
  }

  // ---------------------------------------------------------------------------- reading

  /** The authoritative world (read it; never step it). */
  get simulation(): S {
    return this.sim;
  }

  /** Ticks stepped. */
  get tick(): number {
    return this.sim.tick;
  }

  /** Snapshot interval, ticks. */
  get snapshotEvery(): number {
    return this.settings.snapshotEvery;
  }

  /** Connected members: players and spectators. */
  get memberCount(): number {
    return [...this.connections()].length;
  }

  /** Which player seats have a connected member. */
  occupied(): boolean[] {
    return this.seats.map((s) => s.member !== undefined);
  }

  // ---------------------------------------------------------------------------- on its own

  /**
   * Take a connection whose first message will be a join for this room (a room serving on its
   * own, in tests and the lab: the room core's protections apply as in a server).
   */
  accept(transport: Transport, info: { address?: string } = {}): void {
    this.serveAlone().accept(transport, { room: this.name, ...info });
  }

  /**
   * Advance to server time `now` (default: the clock): step every tick that is due — at most
   * `maxCatchUpTicks` — and send the snapshots of snapshot ticks (and, serving on its own, the
   * room core's housekeeping).
   * @returns ticks stepped.
   */
  update(now = this.options.clock.now()): number {
    const before = this.stats.ticks;
    if (this.standalone !== undefined) this.standalone.update(now);
    else this.advance(now);
    return this.stats.ticks - before;
  }

  /** Close every connection (`SHUTDOWN`); the room stops. */
  close(): void {
    this.standalone?.close();
    this.state = 'ended';
  }

  private serveAlone(): StateSyncServer {
    if (this.standalone === undefined) {
      if (this.ctx !== undefined) throw new Error(`StateSyncRoom ${this.name} belongs to a server`);
      const host = StateSyncServer.serving(
        this as unknown as StateSyncRoom,
        this.options as StateSyncRoomOptions,
      );
      this.standalone = host;
      // Its drops are this room's.
      this.stats.dropped = host.stats.dropped;
    }
    return this.standalone;
  }

  /** Puts the room in its server's hands; called once, by the server that made or adopted it. */
  attach(ctx: RoomContext<StateSyncMember, StateSyncMessage>): void {
    this.ctx = ctx;
  }

  // ---------------------------------------------------------------------------- the room core

  protected replaced(old: StateSyncMember): void {
    this.ctx!.drop(old, 'UNEXPECTED', 'replaced by a reconnect', 'replaced');
  }

  welcome(m: StateSyncMember, now: number): void {
    m.state = 'member';
    m.sent = new SnapshotRing(this.settings.baseHistory);
    if (m.slot >= 0) this.inputs[m.slot]!.active = false;
    this.sendWelcome(m);
    this.ctx!.emit({
      type: 'join',
      room: this.name,
      peer: m.peer,
      slot: m.slot,
      late: this.stats.ticks > 0,
    });
    // The first snapshot goes at once: the client can draw the world before the next snapshot tick.
    const round = this.coder.newRound();
    this.coder.snap(this.sim, round, this.options.view === undefined);
    this.snapshotTo(m, this.viewFor(m.slot, round), now, round);
  }

  onLeave(m: StateSyncMember, reason: LeaveReason): void {
    if (m.slot >= 0 && this.seats[m.slot]?.member === undefined)
      this.inputs[m.slot]!.active = false;
    this.ctx!.emit({ type: 'leave', room: this.name, peer: m.peer, reason });
  }

  advance(now: number): void {
    if (this.state === 'ended') return;
    let n = 0;
    while (
      now >= this.startAt + (this.sim.tick + 1) * this.tickMs &&
      n < this.settings.maxCatchUpTicks
    ) {
      this.stepOne();
      n++;
      if (this.sim.tick % this.settings.snapshotEvery === 0) this.snapshotAll(now);
    }
  }

  private sendWelcome(m: StateSyncMember): void {
    const seat = m.slot >= 0 ? this.seats[m.slot] : undefined;
    const welcome: StateSyncMessage = {
      type: 'welcome',
      slot: m.slot,
      players: this.players,
      seed: this.seed,
      tickRate: this.game.tickRate,
      snapshotEvery: this.settings.snapshotEvery,
      startAt: this.startAt,
      inputFrom: this.sim.tick,
      config: this.config,
      token: seat ? seat.token : new Uint8Array(0),
      invite: seat ? this.invite : new Uint8Array(0),
    };
    this.ctx!.send(m, welcome);
  }

  private stepOne(): void {
    const t = this.sim.tick;
    const w = this.words;
    const schema = this.game.input;
    const words = this.rowWords;
    for (let p = 0; p < this.players; p++) {
      const s = this.inputs[p]!;
      const seated = this.seats[p]!.member !== undefined;
      if (s.pending.has(t)) {
        s.pending.copy(t, words, p * w);
        s.pending.clear(t);
      } else if (seated && s.active) {
        schema.missing(s.last, 0, words, p * w);
        s.filled++;
        s.filledTicks[t % PENDING_TICKS] = t;
        this.stats.filledInputs++;
      } else if (seated) {
        schema.missing(s.last, 0, words, p * w);
      } else {
        words.fill(0, p * w, (p + 1) * w);
      }
      for (let k = 0; k < w; k++) s.last[k] = words[p * w + k]!;
      this.row[p] = schema.decode(words, p * w);
    }
    this.sim.step(this.row);
    this.stats.ticks++;
  }

  // ---------------------------------------------------------------------------- snapshots

  private viewFor(slot: number, round: SnapshotRound): Uint8Array {
    const view = this.options.view;
    const key = view ? slot : WHOLE_VIEW;
    let bytes = round.views.get(key);
    if (bytes === undefined) {
      bytes = view ? view(this.sim, slot) : this.sim.save();
      if (bytes.length > this.settings.limits.maxStateBytes) {
        throw new RangeError(
          `StateSyncRoom: a state of ${bytes.length} bytes is above maxStateBytes`,
        );
      }
      round.views.set(key, bytes);
    }
    return bytes;
  }

  private snapshotAll(now: number): void {
    // Nobody to send to: nothing to quantise (the world runs on unsnapped until someone joins).
    if (this.members().next().done === true) return;
    const round = this.coder.newRound();
    this.coder.snap(this.sim, round, this.options.view === undefined);
    for (const m of this.members()) this.snapshotTo(m, this.viewFor(m.slot, round), now, round);
  }

  private snapshotTo(
    m: StateSyncMember,
    view: Uint8Array,
    now: number,
    round: SnapshotRound,
  ): void {
    const tick = this.sim.tick;
    let baseTick = -1;
    let olderTick = -1;
    if (m.needsFull) {
      if (now - m.lastFullAt < this.settings.resyncIntervalMs) return;
    } else if (this.settings.delta) {
      // Over a reliable transport (a WebSocket) what was sent arrives, in order: the last snapshot
      // is the client's base as soon as it is sent — a delta over one snapshot interval, not a
      // round trip's worth (Colyseus patches the same way). Otherwise the acknowledged one.
      const base = m.reliable ? m.lastSent : m.ack;
      if (base >= 0 && base < tick && m.sent.get(base)) {
        baseTick = base;
        // Columns that extrapolate need one more the client holds: the one sent (or acknowledged)
        // before, while it is young enough to be in the client's history.
        const older = m.reliable ? m.sentBefore : m.ackBefore;
        if (
          this.extrapolates &&
          older >= 0 &&
          older < base &&
          tick - older <= OLDER_REACH * this.settings.snapshotEvery &&
          m.sent.get(older)
        ) {
          olderTick = older;
        }
      }
    }
    const coded = this.coder.code(m, view, tick, baseTick, olderTick, round);
    m.sent.put(tick, coded.state);
    m.sentBefore = baseTick >= 0 ? m.lastSent : -1;
    m.lastSent = tick;
    const seat = m.slot >= 0 ? this.inputs[m.slot] : undefined;
    const bytes = STATE_SYNC_PROTOCOL.encode({
      type: 'snapshot',
      tick,
      base: baseTick,
      older: olderTick,
      sendDelayUs: Math.max(0, Math.round((now - (this.startAt + tick * this.tickMs)) * 1000)),
      inputAck: seat ? this.inputAck(seat) : tick,
      filled: seat?.filled ?? 0,
      late: seat?.late ?? 0,
      slack: seat ? Math.max(-MAX_SLACK, Math.min(MAX_SLACK, seat.slack)) : MAX_SLACK,
      codec: this.coder.schema ? 'schema' : 'bytes',
      size: coded.state.length,
      hash: coded.hash,
      payload: coded.payload,
    });
    this.ctx!.sendBytes(m, bytes);
    if (seat) seat.slack = MAX_SLACK;
    this.stats.snapshotBytes += bytes.length;
    if (baseTick >= 0) {
      this.stats.deltaSnapshots++;
    } else {
      this.stats.fullSnapshots++;
      m.needsFull = false;
      m.lastFullAt = now;
    }
  }

  /** The first tick from the room's tick on whose input from a seat has not come. */
  private inputAck(seat: SeatInputs): number {
    let t = this.sim.tick;
    while (seat.pending.has(t)) t++;
    return t;
  }

  // ---------------------------------------------------------------------------- receiving

  onMessage(m: StateSyncMember, message: { type: string }): void {
    const msg = message as StateSyncMessage;
    switch (msg.type) {
      case 'join':
        // A repeated join (its welcome was lost): welcome again, with a full snapshot.
        if (msg.room !== this.name || m.slot >= 0 !== (msg.role === 'player')) {
          this.ctx!.drop(m, 'UNEXPECTED', 'join for another room or role');
          return;
        }
        this.sendWelcome(m);
        m.needsFull = true;
        break;
      case 'input':
        this.onInput(m, msg.player, msg.tick, msg.words, msg.inputs);
        this.onAck(m, msg.ack);
        break;
      case 'ack':
        this.onAck(m, msg.ack);
        break;
      case 'resync':
        this.stats.resyncs++;
        m.needsFull = true;
        m.ack = -1;
        m.ackBefore = -1;
        break;
      case 'leave':
        this.ctx!.leave(m);
        break;
      default:
        // The host decodes client messages only; nothing else reaches here.
        this.ctx!.drop(m, 'UNEXPECTED', `a ${msg.type} message from a client`);
    }
  }

  private onInput(
    m: StateSyncMember,
    player: number,
    tick: number,
    words: number,
    inputs: Uint32Array,
  ): void {
    if (m.slot < 0) {
      this.ctx!.drop(m, 'SPOOFED_PLAYER', 'a spectator sent inputs');
      return;
    }
    if (player !== m.slot) {
      this.ctx!.drop(m, 'SPOOFED_PLAYER', `inputs for player ${player} from player ${m.slot}`);
      return;
    }
    if (words !== this.words) {
      this.ctx!.drop(
        m,
        'BAD_INPUT',
        `inputs of ${words} words, ${this.game.id} takes ${this.words}`,
      );
      return;
    }
    const ticks = inputs.length / words;
    const schema = this.game.input;
    for (let k = 0; k < ticks; k++) {
      const problem = schema.problem(inputs, k * words);
      if (problem !== undefined) {
        this.ctx!.drop(m, 'BAD_INPUT', `input of tick ${tick + k}: ${problem}`);
        return;
      }
    }
    const now = this.sim.tick;
    const last = tick + ticks - 1;
    if (last > now + this.settings.maxAheadTicks) {
      this.ctx!.strike(m, 'TICK_WINDOW', `inputs for tick ${last}, the room is at ${now}`);
      return;
    }
    const s = this.inputs[m.slot]!;
    for (let k = 0; k < ticks; k++) {
      const t = tick + k;
      if (t < now) {
        // The relay's rule: a tick is stepped once; an input that comes later is dropped. Count it
        // once, if that tick was filled without it (the redundant window resends ticks that made it).
        if (s.filledTicks[t % PENDING_TICKS] === t) {
          s.filledTicks[t % PENDING_TICKS] = -1;
          this.stats.lateInputs++;
          s.late++;
          if (t - now < s.slack) s.slack = t - now;
        }
        continue;
      }
      if (s.pending.has(t)) {
        for (let i = 0; i < words; i++) {
          if (s.pending.get(t, i) !== inputs[k * words + i]) {
            this.stats.conflictingInputs++;
            break;
          }
        }
        continue;
      }
      s.pending.set(t, inputs, k * words);
      // A first arrival: how early it came (0: in time for the next step, just).
      if (t - now < s.slack) s.slack = t - now;
    }
    s.active = true;
    // A player who sends inputs plays: the room is not idle.
    this.lastPlayAt = this.options.clock.now();
  }

  private onAck(m: StateSyncMember, ack: number): void {
    if (ack > this.sim.tick) {
      this.ctx!.strike(m, 'TICK_WINDOW', `ack of tick ${ack}, the room is at ${this.sim.tick}`);
      return;
    }
    if (ack > m.ack) {
      m.ackBefore = m.ack;
      m.ack = ack;
    }
  }
}

/** What one snapshot tick computes once and shares among members: views, hashes, deltas. */
function randomOf(options: { randomU32?: () => number }): () => number {
  return options.randomU32 ?? (() => crypto.getRandomValues(new Uint32Array(1))[0]!);
}
