/**
 * The server side of state sync: a room runs the game at the fixed step, owns the tick clock,
 * applies each player's inputs at the tick they were meant for, and sends every member the world
 * state — delta-coded against the last snapshot that member acknowledged.
 * @module
 */
import { ByteWriter } from '../../det/bytes.js';
import { fnv1a64 } from '../../det/hash.js';
import type { AnyGameDefinition } from '../../sim/game.js';
import { gameSetup } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import { InputRing, SnapshotRing } from '../history.js';
import { ProtocolError, TOKEN_BYTES } from '../protocol.js';
import type { Transport } from '../transport.js';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  decodeStateSyncMessage,
  encodeStateSyncMessage,
  type JoinMessage,
  type StateSyncErrorCode,
  type StateSyncLimits,
  type StateSyncMessage,
} from './codec.js';
import { encodeDelta } from './delta.js';

/**
 * Interest management: the bytes of the world that the member in `slot` (-1: a spectator) may
 * see, in the game's own `save()` format so the client can load them. Return `sim.save()` to show
 * everything; blank what the member must not know (another team's positions behind walls, a hand
 * of cards). Called once per member and snapshot, on the server only; it must not change `sim`.
 */
export type StateSyncView<S> = (sim: S, slot: number) => Uint8Array;

/** Options of a {@link StateSyncRoom}. */
export interface StateSyncRoomOptions<S extends Simulation<unknown> = Simulation<unknown>> {
  /** The game. The room builds it with `create(gameSetup(game, players, seed))`. */
  game: AnyGameDefinition;
  /** The room's name (what clients join). Default `room`. */
  name?: string;
  /**
   * The server clock, in ms: tick t is stepped when it passes `startAt + (t + 1) × step`, `startAt`
   * being the clock when the room was created. Inject a `ManualClock` in tests.
   */
  clock: Clock;
  /** Player slots. Default: the game's minimum. */
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
  /** Interest management (default: everyone sees the whole `save()`). See {@link StateSyncView}. */
  view?: StateSyncView<S>;
  /**
   * Snapshots kept per member as delta bases. An acknowledgement older than that gets a full
   * snapshot. Default 32 (1.6 s at 20 snapshots a second).
   */
  baseHistory?: number;
  /** Inputs more than this many ticks ahead of the room's tick are refused (a strike). Default 120. */
  maxAheadTicks?: number;
  /** Violations a connection may commit before it is dropped. Default 8. */
  maxStrikes?: number;
  /** Sustained messages per second per connection (a token bucket; burst twice as many). Default 240. */
  messagesPerSecond?: number;
  /** At most one full snapshot per member this often after a resync request, in ms. Default 250. */
  resyncIntervalMs?: number;
  /** A member silent for this long is dropped (clients ping every 250 ms). Default 10 000 ms. */
  idleTimeoutMs?: number;
  /**
   * Most ticks one {@link StateSyncRoom.update} steps: after a stall of the process the room
   * catches up this many ticks an update instead of all at once. Default 8.
   */
  maxCatchUpTicks?: number;
  /** Spectators at most. Default 16. */
  maxSpectators?: number;
  /** Random u32s for the seed and reconnect tokens. Default `crypto.getRandomValues`. */
  randomU32?: () => number;
  limits?: Partial<StateSyncLimits>;
  /** Where the room reports joins, leaves and drops (default: nowhere). */
  onEvent?: (event: StateSyncRoomEvent) => void;
}

/** What a room reports. */
export type StateSyncRoomEvent =
  | { type: 'join'; room: string; slot: number; rejoin: boolean }
  | { type: 'leave'; room: string; slot: number; reason: string }
  | { type: 'drop'; room: string; slot: number; code: StateSyncErrorCode; message: string };

/** Counters of a room. */
export interface StateSyncRoomStats {
  /** Ticks stepped. */
  ticks: number;
  /** Snapshots sent: whole, and delta-coded. */
  fullSnapshots: number;
  deltaSnapshots: number;
  /** Bytes of every snapshot message sent (headers included). */
  snapshotBytes: number;
  messagesIn: number;
  messagesOut: number;
  bytesIn: number;
  bytesOut: number;
  /** Player-ticks stepped without that player's input (the missing rule filled them). */
  filledInputs: number;
  /** Inputs that came after their tick was stepped (dropped: the filled value stands). */
  lateInputs: number;
  /** Second, different inputs for a tick already received (dropped: the first is final). */
  conflictingInputs: number;
  /** Resync requests. */
  resyncs: number;
  /** Connections dropped, by reason. */
  dropped: Partial<Record<StateSyncErrorCode, number>>;
}

/** A connection handed to a room (by {@link StateSyncServer} or {@link StateSyncRoom.accept}). */
interface Member {
  transport: Transport;
  slot: number;
  /** Newest snapshot tick the member acknowledged (-1: none). */
  ack: number;
  /** The snapshots sent to it, by tick (its delta bases). */
  sent: SnapshotRing;
  needsFull: boolean;
  lastFullAt: number;
  strikes: number;
  tokens: number;
  tokensAt: number;
  lastHeardAt: number;
  closed: boolean;
}

interface Slot {
  member: Member | undefined;
  token: Uint8Array;
  /** Inputs received for ticks not yet stepped. */
  pending: InputRing;
  /** The words applied at the last stepped tick (the missing rule's "last input"). */
  last: Uint32Array;
  /** Whether it sent an input since it (re)joined: only an active player's input is filled from its last. */
  active: boolean;
  filled: number;
  /** Per tick modulo 256: the tick whose input was filled there (a later arrival is late). */
  filledTicks: Float64Array;
}

/** The checked, defaulted options. */
interface Settings {
  snapshotEvery: number;
  delta: boolean;
  baseHistory: number;
  maxAheadTicks: number;
  maxStrikes: number;
  messagesPerSecond: number;
  resyncIntervalMs: number;
  idleTimeoutMs: number;
  maxCatchUpTicks: number;
  maxSpectators: number;
  limits: StateSyncLimits;
}

function defaultRandomU32(): number {
  return crypto.getRandomValues(new Uint32Array(1))[0]!;
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
 * against its slot (nor for another player), and against the tick window (nor many ticks ahead),
 * and keeps the first input of each tick. Tick t is stepped at `startAt + (t + 1) × step` with the
 * inputs that are in; a missing input follows the relay's rule — a connected player's last input,
 * held buttons only, axes kept; a vacant slot's is 0 — and one that comes later is dropped.
 *
 * Every `snapshotEvery` ticks each member gets the state — what {@link StateSyncRoomOptions.view}
 * lets it see — as the game's canonical bytes, delta-coded against the newest snapshot it
 * acknowledged (whole on join, when its acknowledgement is older than `baseHistory` snapshots, or
 * after it asked to resync), with the state's hash and the server time. Nothing a client sends is
 * ever state, so a client that lies about the world changes nothing.
 *
 * Drive it with {@link update} (every few ms on a server; on an `EventScheduler` in tests). The
 * game need not be deterministic: clients correct their prediction from every snapshot.
 */
export class StateSyncRoom<S extends Simulation<unknown> = Simulation<unknown>> {
  readonly name: string;
  readonly game: AnyGameDefinition;
  readonly players: number;
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
    messagesIn: 0,
    messagesOut: 0,
    bytesIn: 0,
    bytesOut: 0,
    filledInputs: 0,
    lateInputs: 0,
    conflictingInputs: 0,
    resyncs: 0,
    dropped: {},
  };

  private readonly sim: S;
  private readonly clock: Clock;
  private readonly options: StateSyncRoomOptions<S>;
  private readonly settings: Settings;
  private readonly words: number;
  private readonly slots: Slot[] = [];
  private readonly spectators: Member[] = [];
  private readonly randomU32: () => number;
  private readonly config: Uint8Array;
  private readonly row: unknown[];
  private readonly rowWords: Uint32Array;
  private readonly writer = new ByteWriter(4096);
  private closedRoom = false;
  private emptySince: number;

  constructor(options: StateSyncRoomOptions<S>) {
    const game = options.game;
    this.options = options;
    this.game = game;
    this.clock = options.clock;
    this.name = options.name ?? 'room';
    this.randomU32 = options.randomU32 ?? defaultRandomU32;
    this.players = options.players ?? game.minPlayers;
    this.seed = options.seed ?? this.randomU32();
    const setup = gameSetup(game, this.players, this.seed);
    this.config = setup.options;
    this.sim = game.create(setup) as S;
    this.tickMs = 1000 / game.tickRate;
    this.words = game.input.words;
    const limits = { ...DEFAULT_STATE_SYNC_LIMITS, ...options.limits };
    this.settings = {
      snapshotEvery: positiveInt(
        'snapshotEvery',
        options.snapshotEvery ?? Math.max(1, Math.round(game.tickRate / 20)),
        1 << 16,
      ),
      delta: options.delta ?? true,
      baseHistory: positiveInt('baseHistory', options.baseHistory ?? 32, 4096),
      maxAheadTicks: positiveInt('maxAheadTicks', options.maxAheadTicks ?? 120, 240),
      maxStrikes: positiveInt('maxStrikes', options.maxStrikes ?? 8, 1000),
      messagesPerSecond: positiveInt(
        'messagesPerSecond',
        options.messagesPerSecond ?? 240,
        100_000,
      ),
      resyncIntervalMs: options.resyncIntervalMs ?? 250,
      idleTimeoutMs: options.idleTimeoutMs ?? 10_000,
      maxCatchUpTicks: positiveInt('maxCatchUpTicks', options.maxCatchUpTicks ?? 8, 10_000),
      maxSpectators: options.maxSpectators ?? 16,
      limits,
    };
    if (this.words > limits.maxInputWords) {
      throw new RangeError(
        `StateSyncRoom: ${game.id} inputs have ${this.words} words, at most ${limits.maxInputWords}`,
      );
    }
    for (let p = 0; p < this.players; p++) {
      this.slots.push({
        member: undefined,
        token: new Uint8Array(0),
        pending: new InputRing(256, this.words),
        last: new Uint32Array(this.words),
        active: false,
        filled: 0,
        filledTicks: new Float64Array(256).fill(-1),
      });
    }
    this.row = new Array<unknown>(this.players);
    this.rowWords = new Uint32Array(this.players * this.words);
    this.startAt = this.clock.now();
    this.emptySince = this.startAt;
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
    return this.slots.filter((s) => s.member !== undefined).length + this.spectators.length;
  }

  /** Since when the room has had no member (server ms), or undefined while it has one. */
  get emptySinceMs(): number | undefined {
    return this.memberCount === 0 ? this.emptySince : undefined;
  }

  /** Which player slots have a connected member. */
  occupied(): boolean[] {
    return this.slots.map((s) => s.member !== undefined);
  }

  /** Whether the room takes a join for this game, version and input schema (else the reason). */
  accepts(join: JoinMessage): { code: StateSyncErrorCode; message: string } | undefined {
    if (join.game !== this.game.id || join.gameVersion !== this.game.version) {
      return {
        code: 'GAME_MISMATCH',
        message: `room ${this.name} plays ${this.game.id} version ${this.game.version}, not ${join.game} version ${join.gameVersion}`,
      };
    }
    if (join.input !== this.game.input.id) {
      return {
        code: 'GAME_MISMATCH',
        message: `room ${this.name} reads inputs of schema ${this.game.input.id}, not ${join.input}`,
      };
    }
    return undefined;
  }

  // ---------------------------------------------------------------------------- connections

  /**
   * Take a connection whose first message will be a join for this room (a standalone room, in
   * tests and the lab). A {@link StateSyncServer} hands over joined connections with {@link join}.
   */
  accept(transport: Transport): void {
    waitForJoin(transport, this.settings.limits, this.clock, (join) => {
      if (join.room !== this.name) {
        refuse(transport, 'WRONG_ROOM', `this is room ${this.name}, not ${join.room}`);
        return;
      }
      const wrong = this.accepts(join);
      if (wrong) refuse(transport, wrong.code, wrong.message);
      else this.join(transport, join);
    });
  }

  /**
   * Seat a connection that sent `join` (already checked with {@link accepts}): a free player
   * slot, its own slot back with a reconnect token, or a spectator seat; it gets a welcome and a
   * full snapshot at once. Takes over the transport's message handler. Refuses with `ROOM_FULL`
   * or `BAD_TOKEN` (closing the transport).
   */
  join(transport: Transport, join: JoinMessage): void {
    if (this.closedRoom) {
      refuse(transport, 'SHUTDOWN', 'the room is closed');
      return;
    }
    const now = this.clock.now();
    let slot = -1;
    let rejoin = false;
    if (join.role === 'player') {
      if (join.token !== undefined) {
        slot = this.slots.findIndex((s) => s.token.length > 0 && equalBytes(s.token, join.token!));
        if (slot < 0) {
          refuse(transport, 'BAD_TOKEN', 'no slot of this room has that token');
          return;
        }
        rejoin = true;
        const old = this.slots[slot]!.member;
        if (old) this.remove(old, 'replaced');
      } else {
        slot = this.slots.findIndex((s) => s.member === undefined);
        if (slot < 0) {
          refuse(transport, 'ROOM_FULL', `all ${this.players} player slots are taken`);
          return;
        }
      }
    } else if (this.spectators.length >= this.settings.maxSpectators) {
      refuse(transport, 'ROOM_FULL', `${this.settings.maxSpectators} spectators already`);
      return;
    }
    const member: Member = {
      transport,
      slot,
      ack: -1,
      sent: new SnapshotRing(this.settings.baseHistory),
      needsFull: true,
      lastFullAt: -Infinity,
      strikes: 0,
      tokens: 2 * this.settings.messagesPerSecond,
      tokensAt: now,
      lastHeardAt: now,
      closed: false,
    };
    let token: Uint8Array = new Uint8Array(0);
    if (slot >= 0) {
      const s = this.slots[slot]!;
      if (!rejoin) {
        s.token = new Uint8Array(TOKEN_BYTES);
        const view = new DataView(s.token.buffer);
        for (let i = 0; i < TOKEN_BYTES; i += 4) view.setUint32(i, this.randomU32());
      }
      token = s.token;
      s.member = member;
      s.active = false;
    } else {
      this.spectators.push(member);
    }
    transport.onMessage((bytes) => {
      this.receive(member, bytes);
    });
    transport.onClose(() => {
      this.remove(member, 'closed');
    });
    this.send(member, {
      type: 'welcome',
      slot,
      players: this.players,
      seed: this.seed,
      tickRate: this.game.tickRate,
      snapshotEvery: this.settings.snapshotEvery,
      startAt: this.startAt,
      inputFrom: this.sim.tick,
      config: this.config,
      token,
    });
    this.options.onEvent?.({ type: 'join', room: this.name, slot, rejoin });
    // The first snapshot goes at once: the client can draw the world before the next snapshot tick.
    const round = newRound();
    this.snapshotTo(member, this.viewFor(slot, round), now, round);
  }

  /** Close every connection (error `code`, default `SHUTDOWN`); the room stops. */
  close(code: StateSyncErrorCode = 'SHUTDOWN', message = 'the server is shutting down'): void {
    if (this.closedRoom) return;
    this.closedRoom = true;
    for (const m of this.members()) this.drop(m, code, message);
  }

  // ---------------------------------------------------------------------------- the clock

  /**
   * Advance to server time `now` (default: the clock): step every tick that is due — at most
   * `maxCatchUpTicks` — and send the snapshots of snapshot ticks; drop members silent for
   * `idleTimeoutMs`.
   * @returns ticks stepped.
   */
  update(now = this.clock.now()): number {
    if (this.closedRoom) return 0;
    let n = 0;
    while (
      now >= this.startAt + (this.sim.tick + 1) * this.tickMs &&
      n < this.settings.maxCatchUpTicks
    ) {
      this.stepOne();
      n++;
      if (this.sim.tick % this.settings.snapshotEvery === 0) this.snapshotAll(now);
    }
    for (const m of this.members()) {
      if (now - m.lastHeardAt > this.settings.idleTimeoutMs)
        this.drop(m, 'TIMEOUT', 'no message for too long');
    }
    if (this.memberCount > 0) this.emptySince = now;
    return n;
  }

  private stepOne(): void {
    const t = this.sim.tick;
    const w = this.words;
    const schema = this.game.input;
    const words = this.rowWords;
    for (let p = 0; p < this.players; p++) {
      const s = this.slots[p]!;
      if (s.pending.has(t)) {
        s.pending.copy(t, words, p * w);
        s.pending.clear(t);
      } else if (s.member !== undefined && s.active) {
        schema.missing(s.last, 0, words, p * w);
        s.filled++;
        s.filledTicks[t % 256] = t;
        this.stats.filledInputs++;
      } else if (s.member !== undefined) {
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
    const key = view ? slot : -2;
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
    const round = newRound();
    for (const m of this.members()) this.snapshotTo(m, this.viewFor(m.slot, round), now, round);
  }

  private snapshotTo(m: Member, state: Uint8Array, now: number, round: SnapshotRound): void {
    const tick = this.sim.tick;
    let base: Uint8Array | undefined;
    let baseTick = -1;
    if (m.needsFull) {
      if (now - m.lastFullAt < this.settings.resyncIntervalMs) return;
    } else if (this.settings.delta && m.ack >= 0 && m.ack < tick) {
      base = m.sent.get(m.ack);
      if (base) baseTick = m.ack;
    }
    m.sent.put(tick, state);
    // Members that see the same bytes and acknowledged the same base share the work.
    let hash = round.hashes.get(state);
    if (hash === undefined) {
      hash = fnv1a64(state);
      round.hashes.set(state, hash);
    }
    let payload = state;
    if (base) {
      let byBase = round.deltas.get(state);
      if (byBase === undefined) {
        byBase = new Map();
        round.deltas.set(state, byBase);
      }
      let delta = byBase.get(base);
      if (delta === undefined) {
        encodeDelta(base, state, this.writer.reset());
        delta = this.writer.finish();
        byBase.set(base, delta);
      }
      payload = delta;
    }
    const slot = m.slot >= 0 ? this.slots[m.slot] : undefined;
    const bytes = this.send(m, {
      type: 'snapshot',
      tick,
      base: baseTick,
      sendDelayUs: Math.max(0, Math.round((now - (this.startAt + tick * this.tickMs)) * 1000)),
      inputAck: slot ? this.inputAck(slot) : tick,
      filled: slot?.filled ?? 0,
      size: state.length,
      hash,
      payload,
    });
    this.stats.snapshotBytes += bytes;
    if (base) {
      this.stats.deltaSnapshots++;
    } else {
      this.stats.fullSnapshots++;
      m.needsFull = false;
      m.lastFullAt = now;
    }
  }

  /** The first tick from the room's tick on whose input from `slot` has not come. */
  private inputAck(slot: Slot): number {
    let t = this.sim.tick;
    while (slot.pending.has(t)) t++;
    return t;
  }

  // ---------------------------------------------------------------------------- receiving

  private receive(m: Member, bytes: Uint8Array): void {
    if (m.closed) return;
    const now = this.clock.now();
    this.stats.messagesIn++;
    this.stats.bytesIn += bytes.length;
    m.lastHeardAt = now;
    const rate = this.settings.messagesPerSecond;
    m.tokens = Math.min(2 * rate, m.tokens + ((now - m.tokensAt) * rate) / 1000);
    m.tokensAt = now;
    if (m.tokens < 1) {
      this.drop(m, 'RATE_LIMIT', `more than ${rate} messages a second`);
      return;
    }
    m.tokens--;
    let msg: StateSyncMessage;
    try {
      msg = decodeStateSyncMessage(bytes, this.settings.limits);
    } catch (e) {
      if (!(e instanceof ProtocolError)) throw e;
      this.drop(m, e.code === 'TOO_LARGE' ? 'TOO_LARGE' : 'BAD_MESSAGE', e.message);
      return;
    }
    switch (msg.type) {
      case 'join':
        // A repeated join (its welcome was lost): welcome again, with a full snapshot.
        this.send(m, {
          type: 'welcome',
          slot: m.slot,
          players: this.players,
          seed: this.seed,
          tickRate: this.game.tickRate,
          snapshotEvery: this.settings.snapshotEvery,
          startAt: this.startAt,
          inputFrom: this.sim.tick,
          config: this.config,
          token: m.slot >= 0 ? this.slots[m.slot]!.token : new Uint8Array(0),
        });
        m.needsFull = true;
        break;
      case 'input':
        this.onInput(m, msg.player, msg.tick, msg.words, msg.inputs);
        this.onAck(m, msg.ack);
        break;
      case 'ack':
        this.onAck(m, msg.ack);
        break;
      case 'ping':
        this.send(m, { type: 'pong', id: msg.id, time: msg.time, serverTime: now });
        break;
      case 'resync':
        this.stats.resyncs++;
        m.needsFull = true;
        m.ack = -1;
        break;
      case 'leave':
        this.remove(m, 'left');
        m.transport.close('left');
        break;
      default:
        // Server-bound traffic only: a client that sends a snapshot or a welcome is not playing by
        // the rules (and a state it claims would change nothing anyway).
        this.drop(m, 'BAD_MESSAGE', `a ${msg.type} message from a client`);
    }
  }

  private onInput(
    m: Member,
    player: number,
    tick: number,
    words: number,
    inputs: Uint32Array,
  ): void {
    if (m.slot < 0) {
      this.drop(m, 'SPOOFED_PLAYER', 'a spectator sent inputs');
      return;
    }
    if (player !== m.slot) {
      this.drop(m, 'SPOOFED_PLAYER', `inputs for player ${player} from player ${m.slot}`);
      return;
    }
    if (words !== this.words) {
      this.drop(m, 'BAD_INPUT', `inputs of ${words} words, ${this.game.id} takes ${this.words}`);
      return;
    }
    const ticks = inputs.length / words;
    const schema = this.game.input;
    for (let k = 0; k < ticks; k++) {
      const problem = schema.problem(inputs, k * words);
      if (problem !== undefined) {
        this.drop(m, 'BAD_INPUT', `input of tick ${tick + k}: ${problem}`);
        return;
      }
    }
    const now = this.sim.tick;
    const last = tick + ticks - 1;
    if (last > now + this.settings.maxAheadTicks) {
      this.strike(m, 'TICK_WINDOW', `inputs for tick ${last}, the room is at ${now}`);
      return;
    }
    const s = this.slots[m.slot]!;
    for (let k = 0; k < ticks; k++) {
      const t = tick + k;
      if (t < now) {
        // The relay's rule: a tick is stepped once; an input that comes later is dropped. Count it
        // once, if that tick was filled without it (the redundant window resends ticks that made it).
        if (s.filledTicks[t % 256] === t) {
          s.filledTicks[t % 256] = -1;
          this.stats.lateInputs++;
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
    }
    s.active = true;
  }

  private onAck(m: Member, ack: number): void {
    if (ack > this.sim.tick) {
      this.strike(m, 'TICK_WINDOW', `ack of tick ${ack}, the room is at ${this.sim.tick}`);
      return;
    }
    if (ack > m.ack) m.ack = ack;
  }

  // ---------------------------------------------------------------------------- sending

  private send(m: Member, msg: StateSyncMessage): number {
    if (m.closed || !m.transport.isOpen) return 0;
    const bytes = encodeStateSyncMessage(msg);
    this.stats.messagesOut++;
    this.stats.bytesOut += bytes.length;
    m.transport.send(bytes);
    return bytes.length;
  }

  private strike(m: Member, code: StateSyncErrorCode, message: string): void {
    m.strikes++;
    if (m.strikes > this.settings.maxStrikes)
      this.drop(m, code, `${message} (too many violations)`);
    else if (m.strikes === 1) this.send(m, { type: 'error', code, fatal: false, message });
  }

  private drop(m: Member, code: StateSyncErrorCode, message: string): void {
    if (m.closed) return;
    this.send(m, { type: 'error', code, fatal: true, message });
    this.stats.dropped[code] = (this.stats.dropped[code] ?? 0) + 1;
    this.options.onEvent?.({ type: 'drop', room: this.name, slot: m.slot, code, message });
    this.remove(m, 'dropped');
    m.transport.close(`${code}: ${message}`);
  }

  private remove(m: Member, reason: string): void {
    if (m.closed) return;
    m.closed = true;
    if (m.slot >= 0) {
      const s = this.slots[m.slot]!;
      if (s.member === m) {
        s.member = undefined;
        s.active = false;
      }
    } else {
      const i = this.spectators.indexOf(m);
      if (i >= 0) this.spectators.splice(i, 1);
    }
    if (reason === 'replaced') m.transport.close('replaced');
    this.options.onEvent?.({ type: 'leave', room: this.name, slot: m.slot, reason });
  }

  private *members(): Generator<Member> {
    for (const s of this.slots) if (s.member) yield s.member;
    yield* [...this.spectators];
  }
}

/** What one snapshot tick computes once and shares among members: views, hashes, deltas. */
interface SnapshotRound {
  views: Map<number, Uint8Array>;
  hashes: Map<Uint8Array, bigint>;
  /** By state, then by base: the delta's bytes. */
  deltas: Map<Uint8Array, Map<Uint8Array, Uint8Array>>;
}

function newRound(): SnapshotRound {
  return { views: new Map(), hashes: new Map(), deltas: new Map() };
}

function equalBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

/** Messages other than a join a connection may send before its join (pings, early inputs). */
const MAX_BEFORE_JOIN = 32;

/**
 * Read a new connection until its join and hand that to `onJoin` (once). Pings are answered with
 * the server time (so the client's clock sync starts at once); other messages that overtook the
 * join on the way are ignored, up to {@link MAX_BEFORE_JOIN}; bytes that do not decode, or too many
 * messages before the join, are refused.
 */
export function waitForJoin(
  transport: Transport,
  limits: Readonly<StateSyncLimits>,
  clock: Clock,
  onJoin: (join: JoinMessage) => void,
): void {
  let done = false;
  let before = 0;
  transport.onMessage((bytes) => {
    if (done) return;
    let m: StateSyncMessage;
    try {
      m = decodeStateSyncMessage(bytes, limits);
    } catch (e) {
      if (!(e instanceof ProtocolError)) throw e;
      done = true;
      refuse(transport, 'BAD_MESSAGE', e.message);
      return;
    }
    if (m.type === 'join') {
      done = true;
      onJoin(m);
      return;
    }
    if (++before > MAX_BEFORE_JOIN) {
      done = true;
      refuse(transport, 'NOT_JOINED', `${before} messages before a join`);
      return;
    }
    if (m.type === 'ping' && transport.isOpen) {
      transport.send(
        encodeStateSyncMessage({ type: 'pong', id: m.id, time: m.time, serverTime: clock.now() }),
      );
    }
  });
}

/** Answer a connection that is not (yet) in a room with a fatal error, and close it. */
export function refuse(transport: Transport, code: StateSyncErrorCode, message: string): void {
  if (transport.isOpen)
    transport.send(encodeStateSyncMessage({ type: 'error', code, fatal: true, message }));
  transport.close(`${code}: ${message}`);
}
