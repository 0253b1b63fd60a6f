/**
 * A client session of a relay room: join with hello/welcome, keep the server's clock, receive the
 * confirmed inputs, send the local ones, report state hashes and answer forensics requests — what
 * lockstep, rollback and spectator sessions share; the kinds decide when a tick is stepped.
 * @module
 */
import { fnv1a64 } from '../../det/hash.js';
import type { ButtonInput } from '../../sim/buttons.js';
import type { InputSchema } from '../../sim/input-schema.js';
import type { Simulation } from '../../sim/simulation.js';
import type { Clock } from '../../time/drivers.js';
import { ClockSync } from '../clock-sync.js';
import { InputRing, SnapshotRing } from '../history.js';
import {
  INPUT_DATAGRAM_EVERY,
  DEFAULT_PROTOCOL_LIMITS,
  MAX_DATAGRAM_BYTES,
  REDUNDANT_TICKS,
  RELAY_PROTOCOL,
  decodeMessage,
  encodeMessage,
  type ConfirmedMessage,
  type DesyncMessage,
  type NetMessage,
  type WelcomeMessage,
} from '../relay/messages.js';
import { ProtocolError } from '../wire/error.js';
import type { ErrorMessage } from '../wire/common.js';
import type { Transport } from '../transport.js';
import {
  SessionError,
  type SessionErrorCode,
  type SessionEvent,
  type SessionPhase,
} from './events.js';
import { SessionLife } from './lifecycle.js';
import {
  emptyNetStats,
  resolveGame,
  type NetEvent,
  type NetSessionOptions,
  type NetSessionStats,
} from './relay-options.js';

/** Messages the session has buffered and may resend: never more than this many ticks. */
const MAX_INPUT_WINDOW = DEFAULT_PROTOCOL_LIMITS.maxInputTicks;
/**
 * A session that has sent nothing for this long acks from its message handler, which still runs
 * when frames stop (a background tab): the relay drops members that stay silent.
 */
const KEEPALIVE_MS = 1000;
/**
 * Over datagrams, a relay input ack that has not moved for this long means a tick fell out of the
 * redundancy window unheard: the next message repeats everything from the ack (the relay rewinds
 * its confirmed ticks after the same time).
 */
const ACK_STUCK_MS = 250;
const CONFIRMED_CAPACITY = 4096;
const ISSUED_CAPACITY = 512;

/**
 * The machinery every relay session shares: the hello/welcome handshake, clock sync, the
 * confirmed-input store and acks, sending local inputs with a redundant window, periodic state
 * hashes, and answering the server's forensics requests (snapshots, per-tick hashes).
 *
 * Call {@link frame} once per display frame; it steps as many ticks as are due (at most
 * `maxTicksPerFrame`) and sends what needs sending. Render {@link simulation} with {@link alpha}.
 * How it ends: {@link finished} resolves when the state at `stopAt` is confirmed (or the owner
 * left), and rejects with a {@link SessionError} when the server refuses or drops it, its welcome
 * cannot be built, or its transport closes first — an `error` event says the same.
 */
export abstract class NetSession<I = ButtonInput> {
  readonly stats: NetSessionStats = emptyNetStats();
  /** Desyncs the server reported. */
  readonly desyncs: DesyncMessage[] = [];
  /** Errors the server sent (the first 64), fatal or not. */
  readonly errors: ErrorMessage[] = [];

  protected readonly transport: Transport;
  protected readonly clock: Clock;
  protected readonly options: NetSessionOptions<I>;
  /** The input schema, and its words per player per tick. */
  readonly schema: InputSchema<I>;
  protected readonly words: number;
  private readonly build: (welcome: WelcomeMessage) => Simulation<I>;
  /** One player's words (scratch). */
  private readonly scratch: Uint32Array;
  protected readonly clockSync = new ClockSync();
  protected readonly maxTicksPerFrame: number;
  protected readonly forensicsWindow: number;
  /** The transport is a stream: inputs go once, not in a redundant window. */
  protected readonly reliable: boolean;
  protected readonly stopAt: number;

  protected sim: Simulation<I> | undefined;
  protected welcomeMsg: WelcomeMessage | undefined;
  protected tickMs = 1000 / 60;
  protected players = 0;
  protected slot = -1;
  protected startAt: number | undefined;
  protected startTick = 0;

  /** Confirmed inputs by tick (`players × words` lanes); every tick before `confirmedEnd` is present. */
  protected confirmed = new InputRing(1, 1);
  protected confirmedEnd = 0;
  /** The confirmed words of tick `confirmedEnd - 1` (zeros before the first). */
  protected lastConfirmed = new Uint32Array(0);

  /** This player's input words, issued for ticks `issueFrom … issueNext - 1`. */
  protected issued: InputRing;
  protected issueFrom = 0;
  protected issueNext = 0;
  /** The next tick the server needs an input from us for, and when it last moved. */
  protected serverInputAck = 0;
  private serverInputAckAt = -Infinity;

  /** Snapshots of confirmed (lockstep) or recent (rollback) ticks. */
  protected ring = new SnapshotRing(1);

  /** Phase, events and the `finished` promise. */
  private readonly life: SessionLife<
    WelcomeMessage,
    Exclude<NetEvent, SessionEvent<WelcomeMessage>>
  >;
  private pingId = 0;
  private pingsSent = 0;
  private nextPingAt = -Infinity;
  private newInputs = false;
  private lastInputSendAt = -Infinity;
  /** Reliable transports: every issued input before this tick has been sent. */
  private inputsSentTo = 0;
  private lastSendAt = -Infinity;
  private lastAckSent = -1;
  private lastAckSendAt = -Infinity;
  private nextReport = 0;
  private stalled = false;
  private readonly hello: NetMessage;
  private hidden = false;
  private helloSentAt = -Infinity;
  /** Messages of the frame being run, sent together at its end (one batch frame). */
  private outbox: Uint8Array[] = [];
  private holding = false;
  /** A newly issued input differs from the tick before it: send it at once (datagrams). */
  private changePending = false;
  /** The last send carried a change: send again with the next tick (datagrams). */
  private repeatPending = false;

  constructor(options: NetSessionOptions<I>, role: 'player' | 'spectator') {
    this.options = options;
    this.life = new SessionLife(options.onEvent);
    this.transport = options.transport;
    this.clock = options.clock;
    const { gameId, gameVersion, schema, build } = resolveGame(options);
    this.schema = schema;
    this.build = build;
    this.words = this.schema.words;
    this.scratch = new Uint32Array(this.words);
    this.issued = new InputRing(ISSUED_CAPACITY, this.words);
    this.maxTicksPerFrame = options.maxTicksPerFrame ?? 32;
    if (!(Number.isInteger(this.maxTicksPerFrame) && this.maxTicksPerFrame >= 1)) {
      throw new RangeError(
        `maxTicksPerFrame must be a positive integer, got ${this.maxTicksPerFrame}`,
      );
    }
    this.forensicsWindow = options.forensicsWindow ?? 180;
    this.stopAt = options.stopAt ?? Infinity;
    this.reliable = this.transport.reliable === true;
    this.transport.onMessage((bytes) => {
      this.receive(bytes);
    });
    this.transport.onClose((reason) => {
      this.life.closed(reason);
    });
    const hello: NetMessage = {
      type: 'hello',
      room: options.room,
      role,
      game: gameId,
      gameVersion,
      input: this.schema.id,
      players: options.players ?? 0,
      name: options.name ?? '',
    };
    if (options.seed !== undefined) hello.seed = options.seed;
    const token = role === 'spectator' ? options.invite : options.token;
    if (token !== undefined) hello.token = token;
    if (options.ticket !== undefined) hello.ticket = options.ticket;
    this.hello = hello;
    this.send(hello);
    this.helloSentAt = this.clock.now();
    this.ping(this.clock.now());
  }

  // ---------------------------------------------------------------------------- reading

  /** Where the session is: connecting, waiting (welcomed), running, closed. */
  get phase(): SessionPhase {
    return this.life.phase;
  }

  /**
   * How the session ends; settles once. Resolves at its end: the state at `stopAt` is confirmed
   * here ({@link isFinished}), or its owner called {@link leave}. Rejects with a
   * {@link SessionError} when it fails first: a fatal error from the server (its code —
   * `WRONG_ROOM`, `BAD_TOKEN`, `ROOM_FULL`, `GAME_MISMATCH`, `SHUTDOWN` …), a welcome this
   * client cannot build (`BAD_WELCOME`), or the transport closing (`CLOSED`). The `error` event
   * carries the same error first. Awaiting it is optional: a rejection nobody observes is not
   * reported as unhandled.
   */
  get finished(): Promise<void> {
    return this.life.finished;
  }

  /**
   * Whether {@link finished} has resolved: the session reached `stopAt` with a confirmed state
   * (or its owner left). What a frame loop on simulated time polls.
   */
  get isFinished(): boolean {
    return this.life.isFinished;
  }

  /** The error {@link finished} rejected with, once it has. */
  get failure(): SessionError | undefined {
    return this.life.failure;
  }

  /** The simulation, once welcomed. */
  get simulation(): Simulation<I> | undefined {
    return this.sim;
  }

  /** The simulation's tick (0 before the welcome). */
  get tick(): number {
    return this.sim?.tick ?? 0;
  }

  /** The welcome: slot, peer id, room number, tick rate, reconnect token … */
  get welcome(): WelcomeMessage | undefined {
    return this.welcomeMsg;
  }

  /** The estimated server tick now (fractional; negative before the match starts). */
  serverTick(now = this.clock.now()): number {
    if (this.startAt === undefined) return -Infinity;
    return (this.clockSync.serverTime(now) - this.startAt) / this.tickMs;
  }

  /** Every tick before this one is confirmed (the inputs of every player are final). */
  get confirmedTick(): number {
    return this.confirmedEnd;
  }

  /**
   * The newest tick whose state is final here (all inputs confirmed and simulated with them).
   * Hash reports, snapshots for late joiners and forensics use only such states.
   */
  abstract confirmedStateTick(): number;

  /**
   * The hash (FNV-1a 64 of the `save()` bytes) of the confirmed state at `tick`, while it is
   * kept (the forensics window), else undefined. Equal on every client of a room, or the room
   * has desynced.
   */
  hashAt(tick: number): bigint | undefined {
    if (tick > this.confirmedStateTick()) return undefined;
    const b = this.ring.get(tick);
    return b ? fnv1a64(b) : undefined;
  }

  /** Interpolation factor for the renderer, in [0, 1): how far display time is past `tick`. */
  get alpha(): number {
    const t = this.displayTime(this.clock.now()) - this.tick;
    return t <= 0 ? 0 : t >= 1 ? 0.999 : t;
  }

  // ---------------------------------------------------------------------------- driving

  /**
   * One display frame at `now` (default: the clock): clock sync, issue local inputs, step due
   * ticks (at most `maxTicksPerFrame` forward), send inputs, acks and hashes.
   * @returns ticks stepped forward.
   */
  frame(now = this.clock.now()): number {
    if (this.life.phase === 'closed') return 0;
    // Everything this frame sends — inputs, ack, clock probe, hashes — goes as one frame.
    this.holding = true;
    try {
      return this.runFrame(now);
    } finally {
      this.holding = false;
      this.sendOutbox();
    }
  }

  private runFrame(now: number): number {
    this.stats.frames++;
    if (now >= this.nextPingAt && !this.hidden) this.ping(now);
    // The handshake survives a lossy link: hello is repeated until welcomed, and a waiting
    // member acks now and then so the server can repeat a lost start.
    if (this.life.phase === 'connecting' && now - this.helloSentAt >= 250) {
      this.send(this.hello);
      this.helloSentAt = now;
    }
    if (this.life.phase === 'waiting') this.flushAck(now);
    if (this.life.phase !== 'running' || this.sim === undefined) return 0;
    const serverTick = this.serverTick(now);
    const n = this.advance(serverTick, now);
    if (n > this.stats.maxTicksInFrame) this.stats.maxTicksInFrame = n;
    this.stats.ticks += n;
    this.flushInputs(now);
    this.reportHashes();
    this.flushAck(now);
    this.stats.rtt = this.clockSync.rtt;
    this.stats.rttHigh = this.clockSync.rttHigh;
    this.checkEnd();
    return n;
  }

  /**
   * Tell the session the page is hidden (or visible again) — `trackVisibility(document, session)`
   * does it. While hidden no clock probes are sent: their answers would be handled late and only
   * inflate the measured round trip. Frames may stop altogether; on return the session catches up
   * at `maxTicksPerFrame` ticks a frame.
   */
  setHidden(hidden: boolean): void {
    this.hidden = hidden;
  }

  /**
   * Leave the room politely and close the transport. The session's end: {@link finished}
   * resolves (unless it failed before).
   */
  leave(): void {
    if (this.life.phase === 'closed') return;
    if (this.welcomeMsg) {
      this.send({
        type: 'leave',
        room: this.welcomeMsg.room,
        peer: this.welcomeMsg.peer,
        reason: 'left',
      });
    }
    this.life.finish();
    this.transport.close('left');
  }

  /** Step due ticks; return how many were stepped forward. */
  protected abstract advance(serverTick: number, now: number): number;

  /** Display time in ticks (for alpha). */
  protected abstract displayTime(now: number): number;

  /** Newly confirmed ticks `[from, to)` (subclasses compare them with predictions). */
  protected onConfirmed?(from: number, to: number, now: number): void;

  /** Count a frame as stalled or not. */
  protected markStall(stalled: boolean): void {
    if (stalled) {
      this.stats.stallFrames++;
      if (!this.stalled) this.stats.stalls++;
    }
    this.stalled = stalled;
  }

  /**
   * Issue local inputs for every tick before `target` (players only). Ticks the server has
   * already closed without us (a hidden tab, a hitch) are skipped: it filled them.
   */
  protected issueUntil(target: number): void {
    if (this.slot < 0 || this.sim === undefined) return;
    if (this.serverInputAck > this.issueNext) this.issueNext = this.serverInputAck;
    const end = Math.min(target, this.stopAt);
    const input = this.options.localInput;
    while (this.issueNext < end) {
      const t = this.issueNext;
      if (input) {
        try {
          this.schema.encode(input(t, this.sim), this.scratch, 0);
        } catch (e) {
          throw new RangeError(`localInput of tick ${t}: ${(e as Error).message}`, { cause: e });
        }
      } else {
        this.scratch.fill(0);
      }
      if (!this.reliable && !this.changePending && this.issued.has(t - 1) && t > this.issueFrom) {
        for (let k = 0; k < this.words; k++) {
          if (this.issued.get(t - 1, k) !== this.scratch[k]) {
            this.changePending = true;
            break;
          }
        }
      }
      this.issued.set(t, this.scratch);
      this.issueNext++;
      this.newInputs = true;
    }
  }

  /**
   * Copy the words this player issued for `tick` into `out[at …]`, if they are still kept;
   * returns whether they were.
   */
  protected issuedInput(tick: number, out: Uint32Array, at: number): boolean {
    if (!(tick >= this.issueFrom && tick < this.issueNext && this.issued.has(tick))) return false;
    this.issued.copy(tick, out, at);
    return true;
  }

  /** Decode a row of `players × words` words into one input per player. */
  protected decodeRow(words: Uint32Array, row: I[]): void {
    for (let p = 0; p < this.players; p++) row[p] = this.schema.decode(words, p * this.words);
  }

  /** Save the state at the current tick into the ring (when kept) and return it. */
  protected remember(): Uint8Array | undefined {
    const sim = this.sim!;
    const t = sim.tick;
    if (this.forensicsWindow > 0 || t % this.welcomeMsg!.hashEvery === 0 || t === this.stopAt) {
      const b = sim.save();
      this.ring.put(t, b);
      return b;
    }
    return undefined;
  }

  protected send(m: NetMessage): void {
    if (!this.transport.isOpen) return;
    const bytes = encodeMessage(m);
    this.stats.messagesSent++;
    this.stats.bytesSent += bytes.length;
    this.lastSendAt = this.clock.now();
    if (this.holding) this.outbox.push(bytes);
    else this.transport.send(bytes);
  }

  /**
   * Sends the frame's messages: one batch frame, or several of at most {@link MAX_DATAGRAM_BYTES}
   * over a datagram transport (a larger message goes alone).
   */
  private sendOutbox(): void {
    const out = this.outbox;
    if (out.length === 0) return;
    this.outbox = [];
    if (!this.transport.isOpen) return;
    const limit = this.reliable ? Infinity : MAX_DATAGRAM_BYTES;
    let group: Uint8Array[] = [];
    let size = 2;
    for (const b of out) {
      const grown = size + b.length + 3;
      if (group.length > 0 && grown > limit) {
        this.transport.send(RELAY_PROTOCOL.frame(group));
        group = [];
        size = 2;
      }
      group.push(b);
      size += b.length + 3;
    }
    this.transport.send(RELAY_PROTOCOL.frame(group));
  }

  // ---------------------------------------------------------------------------- receiving

  private receive(frame: Uint8Array): void {
    // A frame is one message, or several (a batch: the server's messages of one flush).
    let messages: Uint8Array[];
    try {
      messages = RELAY_PROTOCOL.split(frame);
    } catch (error) {
      if (!(error instanceof ProtocolError)) throw error;
      this.stats.badMessages++;
      return;
    }
    for (const bytes of messages) this.receiveMessage(bytes);
  }

  private receiveMessage(bytes: Uint8Array): void {
    this.stats.messagesReceived++;
    this.stats.bytesReceived += bytes.length;
    let m: NetMessage;
    try {
      m = decodeMessage(bytes);
    } catch (error) {
      if (!(error instanceof ProtocolError)) throw error;
      this.stats.badMessages++;
      return;
    }
    const now = this.clock.now();
    switch (m.type) {
      case 'welcome':
        this.onWelcome(m);
        break;
      case 'start':
        if (m.room === this.welcomeMsg?.room && this.startAt === undefined) {
          this.startAt = m.startAt;
          this.life.phase = 'running';
          this.life.emit({ type: 'running', tick: this.startTick });
        }
        break;
      case 'pong':
        // The pong echoes our send time; a forged one from the future is ignored by ClockSync.
        if (m.time <= now && now - m.time < 60_000)
          this.clockSync.addSample(m.time, m.serverTime, now);
        break;
      case 'ping':
        // The relay checks that a silent member is alive: answer at once.
        this.send({ type: 'pong', id: m.id, time: m.time, serverTime: now });
        break;
      case 'confirmed':
        this.onConfirmedMessage(m, now);
        break;
      case 'desync':
        if (m.room === this.welcomeMsg?.room) {
          if (this.desyncs.length < 16) this.desyncs.push(m);
          this.life.emit({ type: 'desync', desync: m });
        }
        break;
      case 'error':
        if (this.errors.length < 64) this.errors.push(m);
        this.life.error(SessionError.fromServer(m));
        break;
      case 'leave':
        this.life.emit({ type: 'leave', peer: m.peer, reason: m.reason });
        break;
      case 'snapshot-request':
        this.onSnapshotRequest(m.room, m.id, m.tick);
        break;
      case 'hashes-request':
        this.onHashesRequest(m.room, m.id, m.from, m.count);
        break;
      default:
        // Client-bound traffic only; anything else from the server is ignored.
        this.stats.badMessages++;
    }
    // Frames may have stopped (a background tab) while messages still arrive: stay heard.
    if (this.welcomeMsg && this.life.phase !== 'closed' && now - this.lastSendAt >= KEEPALIVE_MS) {
      this.send({ type: 'ack', room: this.welcomeMsg.room, ack: this.confirmedEnd });
      this.lastAckSent = this.confirmedEnd;
      this.lastAckSendAt = now;
    }
    // Newly confirmed inputs may complete the state at `stopAt` (or a welcome may be at it).
    this.checkEnd();
  }

  private onWelcome(w: WelcomeMessage): void {
    if (this.welcomeMsg) return;
    this.welcomeMsg = w;
    this.players = w.players;
    this.slot = w.slot;
    this.tickMs = 1000 / w.tickRate;
    let sim: Simulation<I>;
    try {
      sim = this.build(w);
      // The relay cannot check a snapshot (it does not run the game): a member may have sent a
      // broken one. Refuse it here; a wrong but loadable one shows up as a desync.
      if (w.snapshot) sim.load(w.snapshot);
    } catch (error) {
      this.fail('BAD_WELCOME', `cannot build the game from the welcome: ${String(error)}`);
      return;
    }
    if (sim.tick !== w.startTick) {
      this.fail('BAD_WELCOME', `snapshot is at tick ${sim.tick}, the welcome says ${w.startTick}`);
      return;
    }
    this.sim = sim;
    this.startTick = w.startTick;
    this.confirmed = new InputRing(CONFIRMED_CAPACITY, w.players * this.words);
    this.confirmedEnd = w.startTick;
    this.lastConfirmed = new Uint32Array(w.players * this.words);
    this.issueFrom = Math.max(w.inputFrom, w.startTick);
    this.issueNext = this.issueFrom;
    this.inputsSentTo = this.issueFrom;
    this.serverInputAck = this.issueFrom;
    this.ring = new SnapshotRing(this.ringCapacity());
    this.ring.put(sim.tick, w.snapshot ?? sim.save());
    this.nextReport = (Math.floor(w.startTick / w.hashEvery) + 1) * w.hashEvery;
    this.life.phase = 'waiting';
    this.life.emit({ type: 'welcome', welcome: w });
    if (w.startAt !== undefined) {
      this.startAt = w.startAt;
      this.life.phase = 'running';
      this.life.emit({ type: 'running', tick: w.startTick });
    }
  }

  /** Snapshot ring size. */
  protected ringCapacity(): number {
    return Math.max(2, this.forensicsWindow + 1);
  }

  private onConfirmedMessage(m: ConfirmedMessage, now: number): void {
    if (m.players !== this.players || m.words !== this.words || this.sim === undefined) return;
    // Until the start time is known nothing is acked: the server sees that and repeats the start.
    if (this.life.phase !== 'running') return;
    if (m.delta) {
      // XOR-coded against tick − 1: only a continuation of what we hold can be read. Otherwise
      // wait: our ack stops moving, and the relay resends from it uncoded.
      if (m.tick !== this.confirmedEnd || m.tick === 0) return;
      const lanes = m.players * m.words;
      const base = this.lastConfirmed;
      for (let i = 0; i < m.inputs.length; i++) {
        m.inputs[i] = (m.inputs[i]! ^ base[i % lanes]!) >>> 0;
      }
    }
    if (m.inputAck > this.serverInputAck) {
      this.serverInputAck = m.inputAck;
      this.serverInputAckAt = now;
    }
    const lanes = m.players * m.words;
    const n = m.inputs.length / lanes;
    const keepFrom = this.keepInputsFrom();
    const before = this.confirmedEnd;
    for (let k = 0; k < n; k++) {
      const t = m.tick + k;
      if (t < this.confirmedEnd || this.confirmed.has(t)) continue;
      // Never overwrite a tick still needed.
      if (t >= keepFrom + this.confirmed.capacity) break;
      this.confirmed.set(t, m.inputs, k * lanes);
    }
    while (this.confirmed.has(this.confirmedEnd)) this.confirmedEnd++;
    if (this.confirmedEnd > before) {
      this.confirmed.copy(this.confirmedEnd - 1, this.lastConfirmed);
      if (this.slot >= 0) {
        const at = this.slot * this.words;
        for (let t = before; t < this.confirmedEnd; t++) {
          if (!this.issuedInput(t, this.scratch, 0)) continue;
          for (let k = 0; k < this.words; k++) {
            if (this.scratch[k] !== this.confirmed.get(t, at + k)) {
              this.stats.replacedInputs++;
              break;
            }
          }
        }
      }
      this.onConfirmed?.(before, this.confirmedEnd, now);
    }
  }

  /** The oldest tick whose confirmed inputs may still be read. */
  protected keepInputsFrom(): number {
    return this.sim?.tick ?? 0;
  }

  private onSnapshotRequest(room: number, id: number, tick: number): void {
    const w = this.welcomeMsg;
    if (room !== w?.room || !this.sim) return;
    const latest = this.confirmedStateTick();
    const t = tick < 0 ? latest : tick;
    let bytes = t <= latest ? this.ring.get(t) : undefined;
    if (bytes === undefined && t === this.sim.tick && t <= latest) bytes = this.sim.save();
    this.send({ type: 'snapshot', room, id, tick: t, bytes: bytes ?? new Uint8Array(0) });
  }

  private onHashesRequest(room: number, id: number, from: number, count: number): void {
    if (room !== this.welcomeMsg?.room) return;
    const last = Math.min(from + count - 1, this.confirmedStateTick());
    let start = from;
    while (start <= last && !this.ring.has(start)) start++;
    const out: bigint[] = [];
    for (let t = start; t <= last; t++) {
      const b = this.ring.get(t);
      if (!b) break;
      out.push(fnv1a64(b));
    }
    this.send({ type: 'hashes', room, id, from: start, hashes: BigUint64Array.from(out) });
  }

  // ---------------------------------------------------------------------------- sending

  private ping(now: number): void {
    this.send({ type: 'ping', id: this.pingId++, time: now });
    this.pingsSent++;
    this.nextPingAt = now + (this.pingsSent < 4 ? 50 : (this.options.pingIntervalMs ?? 250));
  }

  private flushInputs(now: number): void {
    if (this.slot < 0 || this.welcomeMsg === undefined) return;
    if (this.reliable ? this.flushStreamInputs(now) : this.flushDatagramInputs(now)) {
      this.newInputs = false;
      this.lastInputSendAt = now;
      this.lastAckSent = this.confirmedEnd;
      this.lastAckSendAt = now;
    }
  }

  /**
   * Over a stream each input goes once, new ones in groups of the room's network rate
   * (`sendEvery` ticks).
   */
  private flushStreamInputs(now: number): boolean {
    const from = Math.max(
      this.serverInputAck,
      this.issueNext - MAX_INPUT_WINDOW,
      this.issueFrom,
      this.inputsSentTo,
    );
    if (from >= this.issueNext) return false;
    if (!this.newInputs && now - this.lastInputSendAt < 50) return false;
    const every = this.welcomeMsg!.sendEvery;
    if (this.newInputs && every > 1 && this.issueNext - this.inputsSentTo < every) {
      if (now - this.lastInputSendAt < every * this.tickMs) return false;
    }
    this.sendInputs(from);
    return true;
  }

  /**
   * Over datagrams: new ticks in groups of {@link INPUT_DATAGRAM_EVERY} (or the room's `sendEvery`,
   * if larger), a changed input at once (and again with the next tick when groups are longer than
   * two ticks); each message repeats at most
   * {@link REDUNDANT_TICKS} ticks that were sent before and are not acknowledged. When nothing new
   * is issued (a stall), the whole unacknowledged window is resent every group's time.
   */
  private flushDatagramInputs(now: number): boolean {
    const pace = Math.max(this.welcomeMsg!.sendEvery, INPUT_DATAGRAM_EVERY);
    const oldest = Math.max(this.serverInputAck, this.issueNext - MAX_INPUT_WINDOW, this.issueFrom);
    if (oldest >= this.issueNext) return false;
    let from = oldest;
    // The relay's ack stopped moving: a tick fell out of the window unheard, resend from the ack.
    const stuck = now - this.serverInputAckAt >= ACK_STUCK_MS;
    if (this.newInputs) {
      const due =
        this.changePending ||
        this.repeatPending ||
        this.issueNext - this.inputsSentTo >= pace ||
        now - this.lastInputSendAt >= pace * this.tickMs;
      if (!due) return false;
      if (!stuck) {
        from = Math.max(oldest, Math.min(this.inputsSentTo, this.issueNext) - REDUNDANT_TICKS);
      }
    } else if (now - this.lastInputSendAt < Math.max(50, pace * this.tickMs)) {
      return false;
    }
    this.repeatPending = this.changePending && pace > 2;
    this.changePending = false;
    this.sendInputs(from);
    return true;
  }

  private sendInputs(from: number): void {
    this.inputsSentTo = this.issueNext;
    const w = this.words;
    const inputs = new Uint32Array((this.issueNext - from) * w);
    for (let t = from; t < this.issueNext; t++) this.issued.copy(t, inputs, (t - from) * w);
    this.send({
      type: 'input',
      room: this.welcomeMsg!.room,
      player: this.slot,
      ack: this.confirmedEnd,
      tick: from,
      words: w,
      inputs,
    });
  }

  private flushAck(now: number): void {
    const w = this.welcomeMsg;
    if (!w) return;
    if (this.confirmedEnd === this.lastAckSent && now - this.lastAckSendAt < 200) return;
    // A playing player's ack rides on its inputs; at a network rate below the tick rate, it does
    // not go alone in between (that would be a frame per confirmed group again).
    if (
      (w.sendEvery > 1 || !this.reliable) &&
      this.slot >= 0 &&
      this.life.phase === 'running' &&
      now - this.lastAckSendAt < 200
    ) {
      return;
    }
    this.send({ type: 'ack', room: w.room, ack: this.confirmedEnd });
    this.lastAckSent = this.confirmedEnd;
    this.lastAckSendAt = now;
  }

  private reportHashes(): void {
    const w = this.welcomeMsg!;
    const upTo = this.confirmedStateTick();
    while (this.nextReport <= upTo) {
      const t = this.nextReport;
      this.nextReport += w.hashEvery;
      const b = this.ring.get(t);
      if (!b) continue;
      this.send({ type: 'hash', room: w.room, tick: t, hash: fnv1a64(b) });
      this.stats.hashesReported++;
    }
  }

  /** The session's end: the state at `stopAt` is confirmed here. */
  private checkEnd(): void {
    if (this.life.settled || this.sim === undefined) return;
    if (this.sim.tick >= this.stopAt && this.confirmedStateTick() >= this.stopAt)
      this.life.finish();
  }

  /** A local failure: the `error` event, `finished` rejects, and the transport closes. */
  private fail(code: SessionErrorCode, message: string): void {
    this.life.error(new SessionError(code, message));
    this.transport.close(message);
  }
}
