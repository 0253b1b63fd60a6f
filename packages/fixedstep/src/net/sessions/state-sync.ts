/**
 * A state-sync client: take the world from the server's snapshots (checked against its hash),
 * predict the own player from its inputs and reconcile on every snapshot, draw everything else
 * between snapshots — and send nothing but inputs.
 * @module
 */
import type { GameDefinition, GameSetup } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import { ClockSync, LeadTicks } from '../clock-sync.js';
import { InputRing } from '../history.js';
import { ProtocolError } from '../wire/error.js';
import type { ErrorMessage } from '../wire/common.js';
import type { Transport } from '../transport.js';
import {
  DEFAULT_STATE_SYNC_LIMITS,
  MAX_SLACK,
  decodeStateSyncMessage,
  encodeStateSyncMessage,
  type ResyncReason,
  type StateSnapshotMessage,
  type StateSyncLimits,
  type StateSyncMessage,
  type StateWelcomeMessage,
} from '../state-sync/messages.js';
import { LatenessWindow } from '../state-sync/render.js';
import { SessionError, type SessionEvent, type SessionPhase } from './events.js';
import { SessionLife } from './lifecycle.js';
import { SnapshotBases } from './state-sync-bases.js';
import { NeededLead } from './needed-lead.js';
import { StateSyncDrawing } from './state-sync-drawing.js';
import {
  emptyStateSyncStats,
  type StateSyncEvent,
  type StateSyncSessionOptions,
  type StateSyncSessionStats,
} from './state-sync-options.js';

const ISSUED_CAPACITY = 512;
/** Inputs should reach the server at least this many ticks before their tick is stepped. */
const SLACK_TARGET = 1;
/**
 * Over a stream (TCP) a message lost on the wire holds every message behind it until it is sent
 * again, so each message sent is a chance of a stall: there, inputs go in groups of this many
 * ticks (a changed input at once), and acknowledgements ride on them (else one every 200 ms).
 * 60 → ~24 messages a second at 100 ± 30 ms and 5 % loss; with the lead's 2-minute memory, late
 * inputs over the stream model 0.39 → 0.30 % (worst of 6 seeds 0.60 → 0.50 %), and the lead stays
 * at ~50 ticks where without groups the rarer long stalls pushed it to 56–92 (`npm run bench --
 * state-sync`). The cost: an unchanged input reaches the room up to two ticks later.
 */
const STREAM_INPUT_GROUP = 3;
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
 *
 * How it ends: {@link finished} resolves when its owner leaves or the server closes the room, and
 * rejects with a {@link SessionError} when the server refuses or drops it, its welcome cannot be
 * built, or its transport closes first — an `error` event says the same.
 */
export class StateSyncSession<I, S extends Simulation<I>> {
  readonly stats: StateSyncSessionStats = emptyStateSyncStats();
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

  /** Phase, events and the `finished` promise. */
  private readonly life: SessionLife<
    StateWelcomeMessage,
    Exclude<StateSyncEvent, SessionEvent<StateWelcomeMessage>>
  >;
  private welcomeMsg: StateWelcomeMessage | undefined;
  private tickMs = 1000 / 60;
  private sim: S | undefined;
  private scratch: S | undefined;
  /** Verified snapshots by tick: the delta bases (and what `snapshotAt` returns). */
  private bases = new SnapshotBases(64);
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
  /** The newest input differs from the one before it (sent at once, even over a stream). */
  private changedInput = false;
  private readonly lastWords: Uint32Array;
  /** `issueNext` when inputs were last sent. */
  private sentNext = 0;
  private lastInputSendAt = -Infinity;
  private lastAckSent = -2;
  private lastAckSendAt = -Infinity;

  private pingId = 0;
  private pingsSent = 0;
  private nextPingAt = -Infinity;
  private joinSentAt = -Infinity;
  /**
   * Rises a tick every 50 ms, falls one every 250 ms: a stall longer than any before makes
   * every input late until the lead has caught up with it (at 250 ms a tick, 0.96 % of inputs
   * late in the first two minutes against 0.79 %, `npm run bench -- state-sync`'s stream).
   */
  private readonly lead = new LeadTicks(-1, 50);
  private readonly needs = new NeededLead();
  private lastFilled = 0;
  /** The lowest slack the server reported since the last frame (Infinity: none). */
  private lowSlack = Infinity;
  private delayMs = -1;
  private lastDelayAt = -Infinity;

  /** What to draw: the snapshots' numbers, the prediction's, the corrections' offsets. */
  private readonly drawing: StateSyncDrawing<S>;

  constructor(options: StateSyncSessionOptions<I, S>) {
    this.options = options;
    this.life = new SessionLife(options.onEvent);
    this.transport = options.transport;
    this.clock = options.clock;
    this.game = options.game;
    this.words = this.game.input.words;
    this.limits = { ...DEFAULT_STATE_SYNC_LIMITS, ...options.limits };
    this.maxPrediction = options.maxPrediction ?? 120;
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
      this.lead.ticks = options.lead;
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
    this.bases = new SnapshotBases(options.baseHistory ?? 64);
    this.issued = new InputRing(ISSUED_CAPACITY, this.words);
    this.lastWords = new Uint32Array(this.words);
    this.ownWords = new Uint32Array(this.words);
    this.drawing = new StateSyncDrawing(options.render);
    this.transport.onMessage((bytes) => {
      this.receive(bytes);
    });
    this.transport.onClose((reason) => {
      this.life.closed(reason);
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

  /** Where the session is: connecting, waiting (welcomed, no snapshot yet), running, closed. */
  get phase(): SessionPhase {
    return this.life.phase;
  }

  /**
   * How the session ends; settles once. State sync has no last tick: it resolves when the
   * session's owner calls {@link leave}, or when the server closes the room after welcoming it
   * (a fatal `SHUTDOWN`: `StateSyncRoom.close()`, a server that shuts down or drains) — the room's
   * end. Rejects with a {@link SessionError} when it fails first: any other fatal error from the
   * server (its code — `WRONG_ROOM`, `BAD_TOKEN`, `ROOM_FULL`, `GAME_MISMATCH` …; a `SHUTDOWN`
   * before the welcome is a refusal too), a welcome this client cannot build (`BAD_WELCOME`), or
   * the transport closing (`CLOSED`). The `error` event carries the same error first. Awaiting it
   * is optional: a rejection nobody observes is not reported as unhandled.
   */
  get finished(): Promise<void> {
    return this.life.finished;
  }

  /** Whether {@link finished} has resolved (the owner left, or the server ended the room). */
  get isFinished(): boolean {
    return this.life.isFinished;
  }

  /** The error {@link finished} rejected with, once it has. */
  get failure(): SessionError | undefined {
    return this.life.failure;
  }

  /** The welcome (slot, seed, tick rate, snapshot interval, reconnect token …), once here. */
  get welcome(): StateWelcomeMessage | undefined {
    return this.welcomeMsg;
  }

  /** The predicted world (the newest snapshot plus the local inputs since), once running. */
  get simulation(): S | undefined {
    return this.life.phase === 'running' || this.appliedOnce ? this.sim : undefined;
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
    return this.newest < 0 ? undefined : this.bases.state(this.newest);
  }

  /**
   * The verified snapshot of `tick`, while it is kept (the last `baseHistory` received), else
   * undefined: the server's world at that tick, as the game's bytes (do not modify).
   */
  snapshotAt(tick: number): Uint8Array | undefined {
    return this.bases.state(tick);
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
    return this.drawing.out;
  }

  /** The fractional tick the last {@link render} drew other entities at. */
  get renderTick(): number {
    return this.drawing.renderTick;
  }

  /** The last {@link render}'s blend between the previous and the current predicted tick. */
  get alpha(): number {
    return this.drawing.alpha;
  }

  /** The own player's correction offset now (largest number; 0 without corrections). */
  get correctionOffset(): number {
    return this.drawing.correctionOffset;
  }

  /** The entities this client predicts (its player's), from `render.owned`. */
  get ownedEntities(): readonly number[] {
    return this.drawing.owned;
  }

  // ---------------------------------------------------------------------------- driving

  /**
   * One display frame at `now`: clock probes, apply the newest snapshot (reconcile), predict up to
   * `serverTick + lead` (at most `maxTicksPerFrame` ticks), send inputs and acknowledgements.
   * @returns ticks predicted forward.
   */
  frame(now = this.clock.now()): number {
    if (this.life.phase === 'closed') return 0;
    this.stats.frames++;
    if (now >= this.nextPingAt) this.ping(now);
    if (this.life.phase === 'connecting' && now - this.joinSentAt >= 250) {
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
        Math.floor(server) + this.lead.ticks,
        this.newest + this.maxPrediction,
      );
      while (this.sim.tick < target && n < this.maxTicksPerFrame) {
        this.stepPredicted(true);
        n++;
      }
      if (this.sim.tick < Math.floor(server) + this.lead.ticks && this.sim.tick >= target) {
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
    const d = this.drawing;
    const w = this.welcomeMsg;
    if (!d.enabled || !w || !this.appliedOnce) return d.out;
    const server = this.serverTick(now);
    const own = w.slot >= 0 && this.sim ? server + this.lead.ticks - this.sim.tick : undefined;
    if (d.draw(server - this.renderDelayMs / this.tickMs, own, now)) this.stats.starvedFrames++;
    return d.out;
  }

  /**
   * Leave the room politely and close the transport. The session's end: {@link finished}
   * resolves (unless it failed before).
   */
  leave(): void {
    if (this.life.phase === 'closed') return;
    this.send({ type: 'leave' });
    this.life.finish();
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
    this.drawing.beforeStep();
    sim.step(row);
    this.drawing.afterStep(sim);
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
    for (let i = 0; i < words.length; i++) {
      if (words[i] !== this.lastWords[i]) {
        this.changedInput = true;
        this.lastWords.set(words);
        break;
      }
    }
    this.issueNext = t + 1;
    this.stats.issuedInputs++;
    this.newInputs = true;
  }

  /** Load the newest snapshot and apply the own inputs after it again, up to the predicted tick. */
  private reconcile(): void {
    const p = this.pending!;
    this.pending = undefined;
    const sim = this.sim!;
    const d = this.drawing;
    const predicted = sim.tick;
    const had = this.appliedOnce;
    if (had) d.beforeReconcile();
    sim.load(p.state);
    this.appliedOnce = true;
    if (this.life.phase === 'waiting') {
      this.life.phase = 'running';
      this.life.emit({ type: 'running', tick: p.tick });
    }
    d.loaded(sim);
    if (this.welcomeMsg!.slot < 0) return;
    if (this.issueNext < p.tick) this.issueNext = p.tick;
    if (predicted <= p.tick || !had) return;
    const depth = predicted - p.tick;
    for (let t = p.tick; t < predicted; t++) this.stepPredicted(false);
    this.stats.reconciliations++;
    this.stats.resimulatedTicks += depth;
    if (depth > this.stats.maxResimulated) this.stats.maxResimulated = depth;
    const size = d.afterReconcile();
    if (size > 1e-9) {
      this.stats.corrections++;
      if (size > this.stats.maxCorrection) this.stats.maxCorrection = size;
      this.options.onCorrection?.({
        tick: predicted,
        snapshotTick: p.tick,
        size,
        snapped: d.snaps(size),
      });
    }
  }

  // ---------------------------------------------------------------------------- adapting

  private adaptLead(now: number): void {
    if (this.autoLead) {
      const low = this.lowSlack;
      this.lowSlack = Infinity;
      const filled = this.stats.filledInputs > this.lastFilled;
      this.lastFilled = this.stats.filledInputs;
      // What the inputs' delays ask for (see NeededLead); an input filled without a slack
      // reported (lost on datagrams, never came) asks for a tick more than the lead now.
      if (low !== Infinity) this.needs.note(now, this.lead.ticks - low + SLACK_TARGET);
      else if (filled) this.needs.note(now, this.lead.ticks + 1);
      const want = Math.max(
        1,
        Math.min(
          this.maxPrediction - 1,
          Math.max(Math.ceil(this.clockSync.rttHigh / 2 / this.tickMs) + 2, this.needs.value(now)),
        ),
      );
      this.lead.follow(want, now);
    }
    this.stats.lead = this.lead.ticks;
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
        // The server closing the room this session plays in is how a state-sync room ends.
        if (m.fatal && m.code === 'SHUTDOWN' && this.welcomeMsg !== undefined) this.life.finish();
        this.life.error(SessionError.fromServer(m));
        break;
      default:
        this.stats.badMessages++;
    }
  }

  private onWelcome(w: StateWelcomeMessage): void {
    if (this.welcomeMsg) return;
    if (w.tickRate !== this.game.tickRate) {
      this.fail(`the room ticks at ${w.tickRate} Hz, ${this.game.id} at ${this.game.tickRate}`);
      return;
    }
    const setup: GameSetup = Object.freeze({ seed: w.seed, players: w.players, options: w.config });
    const create = this.options.createSimulation ?? ((s: GameSetup) => this.game.create(s));
    try {
      this.sim = create(setup);
      this.scratch = create(setup);
    } catch (e) {
      this.fail(`cannot build the game from the welcome: ${String(e)}`);
      return;
    }
    this.welcomeMsg = w;
    this.tickMs = 1000 / w.tickRate;
    this.neutral = this.game.input.neutral();
    this.row = Array.from({ length: w.players }, () => this.neutral);
    this.issueFrom = w.inputFrom;
    this.issueNext = w.inputFrom;
    this.serverInputAck = w.inputFrom;
    this.drawing.welcome(w.slot, this.options.smoothingHalfLifeMs ?? 80);
    this.life.phase = 'waiting';
    this.life.emit({ type: 'welcome', welcome: w });
  }

  private onSnapshot(m: StateSnapshotMessage, now: number): void {
    const w = this.welcomeMsg;
    const scratch = this.scratch;
    if (!w || !scratch) return;
    if (m.inputAck > this.serverInputAck) this.serverInputAck = m.inputAck;
    if (m.filled > this.stats.filledInputs) this.stats.filledInputs = m.filled;
    if (m.late > this.stats.lateInputs) {
      this.stats.lateInputs = m.late;
      this.life.emit({ type: 'late-inputs', late: m.late, tick: m.tick });
    }
    if (m.slack < MAX_SLACK) {
      this.stats.slack = m.slack;
      if (m.slack < this.lowSlack) this.lowSlack = m.slack;
    }
    if (m.tick <= this.newest) {
      this.stats.staleSnapshots++;
      return;
    }
    const schema = this.game.stateSchema;
    if (m.codec === 'schema' && schema === undefined) {
      this.fail(
        `the room sends schema-coded snapshots and ${this.game.id} here has no stateSchema`,
      );
      return;
    }
    const rebuilt = this.bases.rebuild(m, schema, w.tickRate, () => this.sim!.save());
    if (!rebuilt.ok) {
      this.badSnapshot(m, rebuilt.reason, rebuilt.message);
      return;
    }
    const { state, words } = rebuilt;
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
    this.bases.put(m.tick, state, words);
    this.newest = m.tick;
    this.pending = { tick: m.tick, state };
    if (m.base < 0) this.stats.fullSnapshots++;
    else this.stats.deltaSnapshots++;
    this.drawing.snapshot(m.tick, scratch);
    this.lateness.add(this.clockSync.serverTime(now) - (w.startAt + m.tick * this.tickMs));
  }

  private badSnapshot(m: StateSnapshotMessage, reason: ResyncReason, message: string): void {
    this.stats.badSnapshots++;
    this.send({ type: 'resync', reason });
    this.life.emit({ type: 'bad-snapshot', reason, message, tick: m.tick });
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
    if (
      this.transport.reliable &&
      !this.changedInput &&
      this.issueNext - this.sentNext < STREAM_INPUT_GROUP &&
      now - this.lastInputSendAt < 50
    ) {
      return;
    }
    const words = this.words;
    const inputs = new Uint32Array((this.issueNext - from) * words);
    for (let t = from; t < this.issueNext; t++) {
      if (this.issued.has(t)) this.issued.copy(t, inputs, (t - from) * words);
    }
    this.send({ type: 'input', player: w.slot, ack: this.newest, tick: from, words, inputs });
    this.newInputs = false;
    this.changedInput = false;
    this.sentNext = this.issueNext;
    this.lastInputSendAt = now;
    this.lastAckSent = this.newest;
    this.lastAckSendAt = now;
  }

  private flushAck(now: number): void {
    if (this.newest < 0) return;
    if (this.newest === this.lastAckSent && now - this.lastAckSendAt < 200) return;
    // Over a stream the room deltas against the snapshot it sent before, not the acknowledged one.
    if (this.transport.reliable && now - this.lastAckSendAt < 200) return;
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

  /** A welcome this client cannot use: the `error` event, `finished` rejects, the transport closes. */
  private fail(message: string): void {
    this.life.error(new SessionError('BAD_WELCOME', message));
    this.transport.close(message);
  }
}
