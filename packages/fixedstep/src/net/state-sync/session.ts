/**
 * The client side of state sync: a session that receives the world from the server, predicts its
 * own player, and draws everything else between snapshots.
 * @module
 */
import { fnv1a64 } from '../../det/hash.js';
import type { GameDefinition, GameSetup } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import { ClockSync } from '../clock-sync.js';
import { InputRing, SnapshotRing } from '../history.js';
import { ProtocolError } from '../wire/error.js';
import type { ErrorMessage } from '../wire/common.js';
import type { Transport } from '../transport.js';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  decodeStateSyncMessage,
  encodeStateSyncMessage,
  type ResyncReason,
  type StateSnapshotMessage,
  type StateSyncLimits,
  type StateSyncMessage,
  type StateWelcomeMessage,
} from './messages.js';
import { applyDelta } from './delta.js';
import {
  PredictionSmoother,
  LatenessWindow,
  SnapshotTimeline,
  type StateSyncRender,
} from './render.js';

/** Where a state-sync session is. */
export type StateSyncPhase = 'connecting' | 'waiting' | 'running' | 'closed';

/** What a state-sync session tells its owner. */
export type StateSyncEvent =
  | { type: 'welcome'; welcome: StateWelcomeMessage }
  | { type: 'running'; tick: number }
  /** A snapshot could not be used (nothing was applied); a full one was asked for. */
  | { type: 'bad-snapshot'; reason: ResyncReason; message: string; tick: number }
  | { type: 'error'; error: ErrorMessage }
  | { type: 'closed'; reason: string };

/** Options of a {@link StateSyncSession}. */
export interface StateSyncSessionOptions<I, S extends Simulation<I>> {
  /** The pipe to the server. */
  transport: Transport;
  /** The clock frames and probes are measured on (`performanceClock()`; a `ManualClock` in tests). */
  clock: Clock;
  /** Room to join (the first join creates it). */
  room: string;
  /** The game: id, version, input schema, tick rate and how to build it. */
  game: GameDefinition<I, S>;
  /** Play a slot, or watch. Default `'player'`. */
  role?: 'player' | 'spectator';
  /** Player slots, when this session creates the room (default: the game's minimum). */
  players?: number;
  /** The game's seed, when this session creates the room (default: the server picks). */
  seed?: number;
  /** Display name (at most 32 UTF-8 bytes). */
  name?: string;
  /** Reconnect token from an earlier welcome: take that slot back. */
  token?: Uint8Array;
  /**
   * Spectators: the room's invite token (`welcome.invite` of one of its players). The server lets
   * no spectator in without it.
   */
  invite?: Uint8Array;
  /**
   * Builds the client's own copy of the game from the room's setup. Default `game.create(setup)`.
   * It need not be the server's exact code: every snapshot replaces the client's state (the tests
   * give clients a game that drifts on purpose).
   */
  createSimulation?: (setup: GameSetup) => S;
  /**
   * The local player's input for `tick`, called once per tick, in order, just before the client
   * predicts that tick (so it shows at once). `sim` is the predicted state (read it, never step
   * it). Default: the neutral input.
   */
  localInput?: (tick: number, sim: S) => I;
  /** What to draw, for {@link StateSyncSession.render}. Without it the session only predicts. */
  render?: StateSyncRender<S>;
  /**
   * How far behind the server clock other entities are drawn, in ms: `'auto'` (default) takes the
   * snapshot interval plus a high lateness of recent snapshots (one-way delay and jitter), so the
   * snapshot after the drawn moment is nearly always in; it moves gradually, never backwards.
   */
  renderDelay?: number | 'auto';
  /** Half-life of the correction offset, ms (0: corrections show at once). Default 80. */
  smoothingHalfLifeMs?: number;
  /** Called after every reconciliation that moved the own entities (needs `render`). */
  onCorrection?: (correction: StateSyncCorrection) => void;
  /**
   * Ticks to predict ahead of the server clock, so an input reaches the server before its tick is
   * stepped. `'auto'` (default): half a high round trip plus two ticks, one tick at a time every
   * 250 ms, and a tick more whenever the server had to fill one of our inputs.
   */
  lead?: number | 'auto';
  /** Most ticks the prediction may run past the newest snapshot; then it waits. Default 60. */
  maxPrediction?: number;
  /** Most forward ticks per {@link StateSyncSession.frame}. Default 32. */
  maxTicksPerFrame?: number;
  /** Clock probe interval, ms. Default 250 (the first four go 50 ms apart). */
  pingIntervalMs?: number;
  /** Snapshots kept as delta bases. Default 64. */
  baseHistory?: number;
  limits?: Partial<StateSyncLimits>;
  onEvent?: (event: StateSyncEvent) => void;
}

/** What a reconciliation changed of the own player's drawn numbers. */
export interface StateSyncCorrection {
  /** The predicted tick it was corrected at, and the snapshot's tick it replayed from. */
  tick: number;
  snapshotTick: number;
  /** The largest change of any own number (game units). */
  size: number;
  /**
   * Whether it was drawn at once (larger than `render.teleport`: a respawn, a teleport) instead
   * of gliding.
   */
  snapped: boolean;
}

/** Counters of a state-sync session. */
export interface StateSyncSessionStats {
  frames: number;
  /** Forward ticks predicted (resimulation not counted). */
  ticks: number;
  /** Snapshots received and applied: whole, delta-coded. */
  fullSnapshots: number;
  deltaSnapshots: number;
  /** Snapshots older than one already applied (reordered on the way): not applied. */
  staleSnapshots: number;
  /** Snapshots refused (damaged, wrong base, unloadable); each asked for a resync. */
  badSnapshots: number;
  /** Reconciliations: a snapshot loaded and the unacknowledged inputs applied again. */
  reconciliations: number;
  /** Ticks resimulated by reconciliations, and the most in one. */
  resimulatedTicks: number;
  maxResimulated: number;
  /** Corrections of the own player's drawn numbers above 1e-9, and the largest (game units). */
  corrections: number;
  maxCorrection: number;
  /** Frames that could not predict further (no snapshot for `maxPrediction` ticks). */
  stallFrames: number;
  /** Frames whose render time was past the newest snapshot (the render delay was too short). */
  starvedFrames: number;
  /** Of our ticks, how many the server stepped without our input (it says so in snapshots). */
  filledInputs: number;
  /** Ticks predicted ahead of the server clock now; render delay now (ms); measured jitter (ms). */
  lead: number;
  renderDelayMs: number;
  jitterMs: number;
  /** Round trip: the smallest and a high one of the window, ms. */
  rtt: number;
  rttHigh: number;
  messagesSent: number;
  messagesReceived: number;
  bytesSent: number;
  bytesReceived: number;
  /** Messages that did not decode. */
  badMessages: number;
}

const ISSUED_CAPACITY = 512;
const MAX_INPUT_WINDOW = DEFAULT_STATE_SYNC_LIMITS.maxInputTicks;

/**
 * A client of a {@link StateSyncRoom} (the talk's model: the server sends the state of the world
 * and the clock). Call {@link frame} once per display frame: it predicts the world from the newest
 * snapshot up to a little ahead of the server clock — the local player's inputs applied at once,
 * others' inputs taken as neutral — and sends the inputs. Each new snapshot is checked (its hash),
 * loaded, and the local inputs after its tick are applied again (reconciliation); a snapshot that
 * cannot be used (damaged, made against a base this client does not have, refused by the game's
 * `load`) changes nothing and asks the server for a full one.
 *
 * Draw with {@link render}: the local player's entities come from the prediction (no input lag;
 * corrections glide, see {@link PredictionSmoother}), everything else is drawn between the two
 * snapshots around `now − renderDelay`.
 *
 * The game need not be deterministic — every snapshot replaces the client's state — and the
 * client sends no state, so it cannot change the world except through its inputs.
 */
export class StateSyncSession<I, S extends Simulation<I>> {
  readonly stats: StateSyncSessionStats = {
    frames: 0,
    ticks: 0,
    fullSnapshots: 0,
    deltaSnapshots: 0,
    staleSnapshots: 0,
    badSnapshots: 0,
    reconciliations: 0,
    resimulatedTicks: 0,
    maxResimulated: 0,
    corrections: 0,
    maxCorrection: 0,
    stallFrames: 0,
    starvedFrames: 0,
    filledInputs: 0,
    lead: 0,
    renderDelayMs: 0,
    jitterMs: 0,
    rtt: 0,
    rttHigh: 0,
    messagesSent: 0,
    messagesReceived: 0,
    bytesSent: 0,
    bytesReceived: 0,
    badMessages: 0,
  };
  /** Errors the server sent (the last 64). */
  readonly errors: ErrorMessage[] = [];

  private readonly options: StateSyncSessionOptions<I, S>;
  private readonly transport: Transport;
  private readonly clock: Clock;
  private readonly game: GameDefinition<I, S>;
  private readonly words: number;
  private readonly limits: StateSyncLimits;
  private readonly clockSync = new ClockSync();
  private readonly lateness = new LatenessWindow(64);
  private readonly maxPrediction: number;
  private readonly maxTicksPerFrame: number;
  private readonly autoLead: boolean;
  private readonly autoDelay: boolean;
  private readonly joinBytes: Uint8Array;

  private phaseValue: StateSyncPhase = 'connecting';
  private welcomeMsg: StateWelcomeMessage | undefined;
  private tickMs = 1000 / 60;
  private sim: S | undefined;
  private scratch: S | undefined;
  /** Verified snapshots by tick: the delta bases. */
  private bases = new SnapshotRing(64);
  private newest = -1;
  private pending: { tick: number; state: Uint8Array } | undefined;
  private appliedOnce = false;

  private readonly issued: InputRing;
  private readonly ownWords: Uint32Array;
  /** The inputs of one predicted step: others neutral, the own one set per tick. */
  private row: I[] = [];
  private neutral!: I;
  private issueFrom = 0;
  private issueNext = 0;
  private serverInputAck = 0;
  private newInputs = false;
  private lastInputSendAt = -Infinity;
  private lastAckSent = -2;
  private lastAckSendAt = -Infinity;

  private pingId = 0;
  private pingsSent = 0;
  private nextPingAt = -Infinity;
  private joinSentAt = -Infinity;
  private leadTicks = -1;
  private lastLeadMove = -Infinity;
  private leadExtra = 0;
  private lastFilled = 0;
  private lastFillAt = -Infinity;
  private delayMs = -1;
  private lastDelayAt = -Infinity;

  // Rendering.
  private readonly renderer: StateSyncRender<S> | undefined;
  private readonly timeline: SnapshotTimeline | undefined;
  private readonly out: Float64Array;
  private readonly scratchValues: Float64Array;
  private predPrev: Float64Array;
  private predCurr: Float64Array;
  private owned: readonly number[] = [];
  private smoother: PredictionSmoother;
  private ownBefore = new Float64Array(0);
  private ownAfter = new Float64Array(0);
  private lastRenderTick = -Infinity;
  private lastRenderAt: number | undefined;
  private renderAlpha = 0;

  constructor(options: StateSyncSessionOptions<I, S>) {
    this.options = options;
    this.transport = options.transport;
    this.clock = options.clock;
    this.game = options.game;
    this.words = this.game.input.words;
    this.limits = { ...DEFAULT_STATE_SYNC_LIMITS, ...options.limits };
    this.maxPrediction = options.maxPrediction ?? 60;
    this.maxTicksPerFrame = options.maxTicksPerFrame ?? 32;
    for (const [name, v, max] of [
      ['maxPrediction', this.maxPrediction, 600],
      ['maxTicksPerFrame', this.maxTicksPerFrame, 10_000],
    ] as const) {
      if (!(Number.isInteger(v) && v >= 1 && v <= max)) {
        throw new RangeError(
          `StateSyncSession: ${name} must be an integer from 1 to ${max}, got ${String(v)}`,
        );
      }
    }
    this.autoLead = options.lead === undefined || options.lead === 'auto';
    if (typeof options.lead === 'number') {
      if (!(
        Number.isInteger(options.lead) &&
        options.lead >= 0 &&
        options.lead < this.maxPrediction
      )) {
        throw new RangeError(
          `StateSyncSession: lead must be 'auto' or an integer from 0 to maxPrediction - 1, got ${options.lead}`,
        );
      }
      this.leadTicks = options.lead;
    }
    this.autoDelay = options.renderDelay === undefined || options.renderDelay === 'auto';
    if (typeof options.renderDelay === 'number') {
      if (!(Number.isFinite(options.renderDelay) && options.renderDelay >= 0)) {
        throw new RangeError(
          `StateSyncSession: renderDelay must be 'auto' or ms >= 0, got ${options.renderDelay}`,
        );
      }
      this.delayMs = options.renderDelay;
    }
    this.bases = new SnapshotRing(options.baseHistory ?? 64);
    this.issued = new InputRing(ISSUED_CAPACITY, this.words);
    this.ownWords = new Uint32Array(this.words);
    const r = options.render;
    this.renderer = r;
    if (r) {
      if (!(Number.isInteger(r.fields) && r.fields >= 1 && r.fields <= 16)) {
        throw new RangeError(
          `StateSyncSession: render.fields must be an integer from 1 to 16, got ${r.fields}`,
        );
      }
      if (!(Number.isInteger(r.entities) && r.entities >= 0 && r.entities <= 1 << 20)) {
        throw new RangeError(
          `StateSyncSession: render.entities must be an integer from 0 to 2^20, got ${r.entities}`,
        );
      }
      this.timeline = new SnapshotTimeline(r.fields, r.entities, 32);
    }
    const size = r ? r.fields * r.entities : 0;
    this.out = new Float64Array(size);
    this.scratchValues = new Float64Array(size);
    this.predPrev = new Float64Array(size);
    this.predCurr = new Float64Array(size);
    this.smoother = new PredictionSmoother(0);
    this.transport.onMessage((bytes) => {
      this.receive(bytes);
    });
    this.transport.onClose((reason) => {
      this.closed(reason);
    });
    const join: StateSyncMessage = {
      type: 'join',
      room: options.room,
      role: options.role ?? 'player',
      game: this.game.id,
      gameVersion: this.game.version,
      input: this.game.input.id,
      players: options.players ?? 0,
      name: options.name ?? '',
    };
    if (options.seed !== undefined) join.seed = options.seed;
    const token = join.role === 'spectator' ? options.invite : options.token;
    if (token !== undefined) join.token = token;
    this.joinBytes = encodeStateSyncMessage(join);
    const now = this.clock.now();
    this.sendBytes(this.joinBytes);
    this.joinSentAt = now;
    this.ping(now);
  }

  // ---------------------------------------------------------------------------- reading

  get phase(): StateSyncPhase {
    return this.phaseValue;
  }

  /** The welcome (slot, seed, tick rate, snapshot interval, reconnect token …), once here. */
  get welcome(): StateWelcomeMessage | undefined {
    return this.welcomeMsg;
  }

  /** The predicted world (the newest snapshot plus the local inputs since), once running. */
  get simulation(): S | undefined {
    return this.phaseValue === 'running' || this.appliedOnce ? this.sim : undefined;
  }

  /** The predicted tick. */
  get tick(): number {
    return this.sim?.tick ?? 0;
  }

  /** The newest snapshot's tick (-1 before the first). */
  get snapshotTick(): number {
    return this.newest;
  }

  /** The newest verified snapshot's bytes (what the server says the world is), or undefined. */
  get snapshotState(): Uint8Array | undefined {
    return this.newest < 0 ? undefined : this.bases.get(this.newest);
  }

  /**
   * The verified snapshot of `tick`, while it is kept (the last `baseHistory` received), else
   * undefined: the server's world at that tick, as the game's bytes (do not modify).
   */
  snapshotAt(tick: number): Uint8Array | undefined {
    return this.bases.get(tick);
  }

  /** The estimated server tick at `now` (fractional; -Infinity before the welcome). */
  serverTick(now = this.clock.now()): number {
    const w = this.welcomeMsg;
    if (!w) return -Infinity;
    return (this.clockSync.serverTime(now) - w.startAt) / this.tickMs;
  }

  /** The render delay now, ms. */
  get renderDelayMs(): number {
    return Math.max(0, this.delayMs);
  }

  /** The numbers of the last {@link render} (the array it returned; do not modify). */
  get drawn(): Float64Array {
    return this.out;
  }

  /** The fractional tick the last {@link render} drew other entities at. */
  get renderTick(): number {
    return this.lastRenderTick;
  }

  /** The last {@link render}'s blend between the previous and the current predicted tick. */
  get alpha(): number {
    return this.renderAlpha;
  }

  /** The own player's correction offset now (largest number; 0 without corrections). */
  get correctionOffset(): number {
    return this.smoother.magnitude;
  }

  /** The entities this client predicts (its player's), from `render.owned`. */
  get ownedEntities(): readonly number[] {
    return this.owned;
  }

  // ---------------------------------------------------------------------------- driving

  /**
   * One display frame at `now`: clock probes, apply the newest snapshot (reconcile), predict up to
   * `serverTick + lead` (at most `maxTicksPerFrame` ticks), send inputs and acknowledgements.
   * @returns ticks predicted forward.
   */
  frame(now = this.clock.now()): number {
    if (this.phaseValue === 'closed') return 0;
    this.stats.frames++;
    if (now >= this.nextPingAt) this.ping(now);
    if (this.phaseValue === 'connecting' && now - this.joinSentAt >= 250) {
      this.sendBytes(this.joinBytes);
      this.joinSentAt = now;
    }
    this.stats.rtt = this.clockSync.rtt;
    this.stats.rttHigh = this.clockSync.rttHigh;
    if (this.sim === undefined || this.welcomeMsg === undefined) return 0;
    if (this.pending) this.reconcile();
    if (!this.appliedOnce) {
      this.flushAck(now);
      return 0;
    }
    this.adaptDelay(now);
    let n = 0;
    // Without a clock estimate the server tick is unknown: hold the snapshot until the first pong.
    if (this.welcomeMsg.slot >= 0 && this.clockSync.ready) {
      this.adaptLead(now);
      const server = this.serverTick(now);
      const target = Math.min(
        Math.floor(server) + this.leadTicks,
        this.newest + this.maxPrediction,
      );
      while (this.sim.tick < target && n < this.maxTicksPerFrame) {
        this.stepPredicted(true);
        n++;
      }
      if (this.sim.tick < Math.floor(server) + this.leadTicks && this.sim.tick >= target) {
        this.stats.stallFrames++;
      }
      this.stats.ticks += n;
      this.flushInputs(now);
    }
    this.flushAck(now);
    return n;
  }

  /**
   * What to draw at `now` (requires `render`): every entity's numbers, the others' blended between
   * the snapshots around `now − renderDelay`, the own ones from the prediction (blended between
   * the last two predicted ticks) plus the decaying correction offset. The array is reused.
   */
  render(now = this.clock.now()): Float64Array {
    const r = this.renderer;
    const w = this.welcomeMsg;
    if (!r || !this.timeline || !w || !this.appliedOnce) return this.out;
    const server = this.serverTick(now);
    let tick = server - this.renderDelayMs / this.tickMs;
    if (tick < this.lastRenderTick) tick = this.lastRenderTick;
    this.lastRenderTick = tick;
    const how = this.timeline.sample(tick, this.out, r.teleport ?? Infinity);
    if (how === 'after') this.stats.starvedFrames++;
    if (this.lastRenderAt !== undefined) this.smoother.decay(now - this.lastRenderAt);
    this.lastRenderAt = now;
    if (w.slot >= 0 && this.sim) {
      const display = server + this.leadTicks;
      const a = display - this.sim.tick;
      const alpha = a <= 0 ? 0 : a >= 1 ? 1 : a;
      // The state at sim.tick is drawn at display time sim.tick + 1: blend prev → curr.
      this.renderAlpha = alpha;
      const f = r.fields;
      let k = 0;
      for (const e of this.owned) {
        for (let j = 0; j < f; j++) {
          const i = e * f + j;
          const p = this.predPrev[i]!;
          const c = this.predCurr[i]!;
          this.out[i] = p + (c - p) * alpha + this.smoother.offset[k++]!;
        }
      }
    }
    return this.out;
  }

  /** Leave the room politely and close the transport. */
  leave(): void {
    if (this.phaseValue === 'closed') return;
    this.send({ type: 'leave' });
    this.transport.close('left');
  }

  // ---------------------------------------------------------------------------- prediction

  /** Step the predicted world one tick: the own input issued for it (issuing it when `issue`), others neutral. */
  private stepPredicted(issue: boolean): void {
    const sim = this.sim!;
    const slot = this.welcomeMsg!.slot;
    const t = sim.tick;
    if (issue && slot >= 0 && t >= this.issueNext) this.issue(t, sim);
    const row = this.row;
    if (slot >= 0) {
      if (this.issued.has(t)) {
        this.issued.copy(t, this.ownWords);
        row[slot] = this.game.input.decode(this.ownWords, 0);
      } else {
        row[slot] = this.neutral;
      }
    }
    const r = this.renderer;
    if (r) {
      const swap = this.predPrev;
      this.predPrev = this.predCurr;
      this.predCurr = swap;
    }
    sim.step(row);
    if (r) r.read(sim, this.predCurr);
  }

  private issue(t: number, sim: S): void {
    const words = this.ownWords;
    words.fill(0);
    const input = this.options.localInput;
    if (input) {
      try {
        this.game.input.encode(input(t, sim), words, 0);
      } catch (e) {
        throw new RangeError(`localInput of tick ${t}: ${(e as Error).message}`, { cause: e });
      }
    }
    this.issued.set(t, words);
    this.issueNext = t + 1;
    this.newInputs = true;
  }

  /** Load the newest snapshot and apply the own inputs after it again, up to the predicted tick. */
  private reconcile(): void {
    const p = this.pending!;
    this.pending = undefined;
    const sim = this.sim!;
    const r = this.renderer;
    const predicted = sim.tick;
    const had = this.appliedOnce;
    if (r && had) {
      for (let k = 0; k < this.ownBefore.length; k++)
        this.ownBefore[k] = this.predCurr[this.ownIndex(k)]!;
    }
    sim.load(p.state);
    this.appliedOnce = true;
    if (this.phaseValue === 'waiting') {
      this.phaseValue = 'running';
      this.emit({ type: 'running', tick: p.tick });
    }
    if (r) {
      r.read(sim, this.predCurr);
      this.predPrev.set(this.predCurr);
    }
    if (this.welcomeMsg!.slot < 0) return;
    if (this.issueNext < p.tick) this.issueNext = p.tick;
    if (predicted <= p.tick || !had) return;
    const depth = predicted - p.tick;
    for (let t = p.tick; t < predicted; t++) this.stepPredicted(false);
    this.stats.reconciliations++;
    this.stats.resimulatedTicks += depth;
    if (depth > this.stats.maxResimulated) this.stats.maxResimulated = depth;
    if (r && this.owned.length > 0) {
      for (let k = 0; k < this.ownAfter.length; k++)
        this.ownAfter[k] = this.predCurr[this.ownIndex(k)]!;
      const size = this.smoother.correct(this.ownBefore, this.ownAfter);
      if (size > 1e-9) {
        this.stats.corrections++;
        if (size > this.stats.maxCorrection) this.stats.maxCorrection = size;
        this.options.onCorrection?.({
          tick: predicted,
          snapshotTick: p.tick,
          size,
          snapped: !(size <= (r.teleport ?? Infinity)),
        });
      }
    }
  }

  /** The index in a render array of the k-th owned number. */
  private ownIndex(k: number): number {
    const f = this.renderer!.fields;
    return this.owned[Math.floor(k / f)]! * f + (k % f);
  }

  // ---------------------------------------------------------------------------- adapting

  private adaptLead(now: number): void {
    if (this.autoLead) {
      if (this.stats.filledInputs > this.lastFilled) {
        // The server stepped a tick without our input: it came too late. Run a tick further ahead.
        this.lastFilled = this.stats.filledInputs;
        if (now - this.lastFillAt > 100) this.leadExtra = Math.min(10, this.leadExtra + 1);
        this.lastFillAt = now;
      } else if (this.leadExtra > 0 && now - this.lastFillAt > 5000) {
        this.leadExtra--;
        this.lastFillAt = now;
      }
      const want = Math.max(
        1,
        Math.min(
          this.maxPrediction - 1,
          Math.ceil(this.clockSync.rttHigh / 2 / this.tickMs) + 2 + this.leadExtra,
        ),
      );
      if (this.leadTicks < 0) {
        this.leadTicks = want;
        this.lastLeadMove = now;
      } else if (want !== this.leadTicks && now - this.lastLeadMove >= 250) {
        this.leadTicks += want > this.leadTicks ? 1 : -1;
        this.lastLeadMove = now;
      }
    }
    this.stats.lead = this.leadTicks;
  }

  private adaptDelay(now: number): void {
    const w = this.welcomeMsg!;
    this.stats.jitterMs = this.lateness.jitter;
    if (!this.autoDelay) {
      this.stats.renderDelayMs = this.delayMs;
      return;
    }
    const target = w.snapshotEvery * this.tickMs + Math.max(0, this.lateness.high) + 1;
    if (this.delayMs < 0) {
      this.delayMs = target;
    } else {
      // Move gradually: at most 10 % of the frame's time, so drawn time never jumps.
      const dt = Math.max(0, Math.min(100, now - this.lastDelayAt));
      const step = 0.1 * dt;
      this.delayMs += Math.max(-step, Math.min(step, target - this.delayMs));
    }
    this.lastDelayAt = now;
    this.stats.renderDelayMs = this.delayMs;
  }

  // ---------------------------------------------------------------------------- receiving

  private receive(bytes: Uint8Array): void {
    this.stats.messagesReceived++;
    this.stats.bytesReceived += bytes.length;
    let m: StateSyncMessage;
    try {
      m = decodeStateSyncMessage(bytes, this.limits);
    } catch (e) {
      if (!(e instanceof ProtocolError)) throw e;
      this.stats.badMessages++;
      return;
    }
    const now = this.clock.now();
    switch (m.type) {
      case 'welcome':
        this.onWelcome(m);
        break;
      case 'snapshot':
        this.onSnapshot(m, now);
        break;
      case 'pong':
        if (m.time <= now && now - m.time < 60_000)
          this.clockSync.addSample(m.time, m.serverTime, now);
        break;
      case 'error':
        if (this.errors.length >= 64) this.errors.shift();
        this.errors.push(m);
        this.emit({ type: 'error', error: m });
        break;
      default:
        this.stats.badMessages++;
    }
  }

  private onWelcome(w: StateWelcomeMessage): void {
    if (this.welcomeMsg) return;
    if (w.tickRate !== this.game.tickRate) {
      this.transport.close(
        `the room ticks at ${w.tickRate} Hz, ${this.game.id} at ${this.game.tickRate}`,
      );
      return;
    }
    const setup: GameSetup = Object.freeze({ seed: w.seed, players: w.players, options: w.config });
    const create = this.options.createSimulation ?? ((s: GameSetup) => this.game.create(s));
    try {
      this.sim = create(setup);
      this.scratch = create(setup);
    } catch (e) {
      this.transport.close(`cannot build the game from the welcome: ${String(e)}`);
      return;
    }
    this.welcomeMsg = w;
    this.tickMs = 1000 / w.tickRate;
    this.neutral = this.game.input.neutral();
    this.row = Array.from({ length: w.players }, () => this.neutral);
    this.issueFrom = w.inputFrom;
    this.issueNext = w.inputFrom;
    this.serverInputAck = w.inputFrom;
    const r = this.renderer;
    if (r) {
      const owned = w.slot < 0 ? [] : (r.owned?.(w.slot) ?? [w.slot]);
      for (const e of owned) {
        if (!(Number.isInteger(e) && e >= 0 && e < r.entities)) {
          throw new RangeError(
            `render.owned(${w.slot}) names entity ${e}, not one of 0–${r.entities - 1}`,
          );
        }
      }
      this.owned = owned;
      const n = owned.length * r.fields;
      this.ownBefore = new Float64Array(n);
      this.ownAfter = new Float64Array(n);
      this.smoother = new PredictionSmoother(
        n,
        this.options.smoothingHalfLifeMs ?? 80,
        r.teleport ?? Infinity,
      );
    }
    this.phaseValue = 'waiting';
    this.emit({ type: 'welcome', welcome: w });
  }

  private onSnapshot(m: StateSnapshotMessage, now: number): void {
    const w = this.welcomeMsg;
    const scratch = this.scratch;
    if (!w || !scratch) return;
    if (m.inputAck > this.serverInputAck) this.serverInputAck = m.inputAck;
    if (m.filled > this.stats.filledInputs) this.stats.filledInputs = m.filled;
    if (m.tick <= this.newest) {
      this.stats.staleSnapshots++;
      return;
    }
    let state: Uint8Array;
    if (m.base < 0) {
      state = m.payload;
    } else {
      const base = this.bases.get(m.base);
      if (base === undefined) {
        this.badSnapshot(m, 'no-base', `no snapshot of tick ${m.base} here to apply a delta to`);
        return;
      }
      try {
        state = applyDelta(base, m.payload, m.size);
      } catch (e) {
        if (!(e instanceof ProtocolError)) throw e;
        this.badSnapshot(m, 'bad-delta', e.message);
        return;
      }
    }
    if (fnv1a64(state) !== m.hash) {
      this.badSnapshot(
        m,
        'hash-mismatch',
        `the state rebuilt for tick ${m.tick} does not have the server's hash (a damaged delta, or the wrong base)`,
      );
      return;
    }
    try {
      scratch.load(state);
    } catch (e) {
      this.badSnapshot(
        m,
        'unloadable',
        `the game refused the state: ${e instanceof Error ? e.message : String(e)}`,
      );
      return;
    }
    if (scratch.tick !== m.tick) {
      this.badSnapshot(
        m,
        'unloadable',
        `the state is at tick ${scratch.tick}, the snapshot says ${m.tick}`,
      );
      return;
    }
    this.bases.put(m.tick, state);
    this.newest = m.tick;
    this.pending = { tick: m.tick, state };
    if (m.base < 0) this.stats.fullSnapshots++;
    else this.stats.deltaSnapshots++;
    if (this.renderer && this.timeline) {
      this.renderer.read(scratch, this.scratchValues);
      this.timeline.push(m.tick, this.scratchValues);
    }
    this.lateness.add(this.clockSync.serverTime(now) - (w.startAt + m.tick * this.tickMs));
  }

  private badSnapshot(m: StateSnapshotMessage, reason: ResyncReason, message: string): void {
    this.stats.badSnapshots++;
    this.send({ type: 'resync', reason });
    this.emit({ type: 'bad-snapshot', reason, message, tick: m.tick });
  }

  // ---------------------------------------------------------------------------- sending

  private ping(now: number): void {
    this.send({ type: 'ping', id: this.pingId++, time: now });
    this.pingsSent++;
    this.nextPingAt = now + (this.pingsSent < 4 ? 50 : (this.options.pingIntervalMs ?? 250));
  }

  private flushInputs(now: number): void {
    const w = this.welcomeMsg!;
    const from = Math.max(this.serverInputAck, this.issueNext - MAX_INPUT_WINDOW, this.issueFrom);
    if (from >= this.issueNext) return;
    if (!this.newInputs && now - this.lastInputSendAt < 50) return;
    const words = this.words;
    const inputs = new Uint32Array((this.issueNext - from) * words);
    for (let t = from; t < this.issueNext; t++) {
      if (this.issued.has(t)) this.issued.copy(t, inputs, (t - from) * words);
    }
    this.send({ type: 'input', player: w.slot, ack: this.newest, tick: from, words, inputs });
    this.newInputs = false;
    this.lastInputSendAt = now;
    this.lastAckSent = this.newest;
    this.lastAckSendAt = now;
  }

  private flushAck(now: number): void {
    if (this.newest < 0) return;
    if (this.newest === this.lastAckSent && now - this.lastAckSendAt < 200) return;
    this.send({ type: 'ack', ack: this.newest });
    this.lastAckSent = this.newest;
    this.lastAckSendAt = now;
  }

  private send(m: StateSyncMessage): void {
    this.sendBytes(encodeStateSyncMessage(m));
  }

  private sendBytes(bytes: Uint8Array): void {
    if (!this.transport.isOpen) return;
    this.stats.messagesSent++;
    this.stats.bytesSent += bytes.length;
    this.transport.send(bytes);
  }

  private closed(reason: string): void {
    if (this.phaseValue === 'closed') return;
    this.phaseValue = 'closed';
    this.emit({ type: 'closed', reason });
  }

  private emit(e: StateSyncEvent): void {
    this.options.onEvent?.(e);
  }
}
