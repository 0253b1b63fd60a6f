/**
 * Relay capacity, the latency the server adds, and bandwidth per player, for lockstep at 60 Hz.
 *
 * Two phases, so the timed numbers hold relay work only:
 *
 * 1. **Record.** A closed-loop simulation on a ManualClock: R rooms of N players, each client a
 *    model of a LockstepSession (one input a tick for `serverTick + 1 + inputDelay`, the redundant
 *    window from the relay's input ack, its confirmed ack piggybacked, a hash every 30 ticks, a
 *    ping every 250 ms), seeded one-way latency + jitter both ways, `relay.update()` every half
 *    step as the CLI calls it. Every event the relay sees (a message delivered at time t, an
 *    update at time t) goes into a trace. The design delays (input arrival → the confirmed
 *    message carrying it) are taken here, in simulated time.
 * 2. **Replay.** A fresh relay eats the trace (deterministic: same clock readings, same bytes, a
 *    seeded token source), timed with `process.hrtime.bigint()`: decode, `update()`, encode and
 *    fan-out to transports that only count. Side by side, interleaved by round, with a bare
 *    decode + encode of the same messages as the baseline.
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import net from 'node:net';
import os, { cpus } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import {
  BUTTON_WORD,
  BaseTransport,
  EventScheduler,
  RELAY_PROTOCOL,
  LockstepSession,
  ManualClock,
  Random,
  Relay,
  decodeMessage,
  encodeMessage,
  peekMessageType,
  performanceClock,
  type ConfirmedMessage,
  type NetMessage,
  type GameCatalog,
  type HostedGame,
  type Simulation,
  type Transport,
} from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
// The CLI's Node WebSocket client (the bench runs the sources, like the e2e tests).
import { connectNodeWebSocket } from '../../packages/server/src/relay/client.js';
import { formatRatio } from '../lib/format.js';
import { fixedstepCommand, residentMb } from '../lib/serve.js';
import { roundOrder, spread, summarize } from '../lib/stats.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';

const TICK_HZ = 60;
const STEP_MS = 1000 / TICK_HZ;
const HASH_EVERY = 30;
const PING_MS = 250;
const MAX_WINDOW = 64;
/** WebSocket frame header of a payload < 126 bytes: 2 bytes server → client, 6 (masked) back. */
const WS_DOWN_HEADER = 2;
const WS_UP_HEADER = 6;

// ------------------------------------------------------------------------------ pure helpers

/** Nearest-rank percentile (`p` in 0–100) of a non-empty list. */
export function percentile(values: ArrayLike<number>, p: number): number {
  if (values.length === 0) throw new RangeError('percentile of an empty list');
  const sorted = Float64Array.from(values).sort();
  const rank = Math.ceil((p / 100) * sorted.length);
  return sorted[Math.min(sorted.length, Math.max(1, rank)) - 1]!;
}

/** Players one core serves, given the relay's ns per simulated second for `players` players. */
export function playersPerCore(players: number, nsPerSimSecond: number): number {
  if (!(nsPerSimSecond > 0) || players <= 0) throw new RangeError('need players and a cost');
  return (players * 1e9) / nsPerSimSecond;
}

/** The LockstepSession's automatic input delay: `ceil((rtt + 1.5 step) / step)`. */
export function inputDelayTicks(rttMs: number, stepMs = STEP_MS): number {
  return Math.ceil((rttMs + 1.5 * stepMs) / stepMs);
}

/**
 * Held buttons with occasional changes, as a `ButtonInput`: bits 0–15 held, bits 16–31 "pressed
 * this tick". On average one button toggles every `ticksPerChange` ticks.
 */
export class HeldButtons {
  private held = 0;
  constructor(
    private readonly rng: Random,
    private readonly ticksPerChange = 20,
    private readonly buttons = 8,
  ) {}
  next(): number {
    let pressed = 0;
    if (this.rng.int(this.ticksPerChange) === 0) {
      const bit = 1 << this.rng.int(this.buttons);
      if ((this.held & bit) === 0) pressed = bit;
      this.held ^= bit;
    }
    return (this.held | (pressed << 16)) >>> 0;
  }
}

// ------------------------------------------------------------------------------ the simulation

const GAME: HostedGame = {
  id: 'bench',
  version: 1,
  tickRate: TICK_HZ,
  minPlayers: 1,
  maxPlayers: 16,
  input: BUTTON_WORD,
  options: () => new Uint8Array(8),
};
const CATALOG: GameCatalog = () => GAME;

/**
 * A transport end on the relay's side: `push` delivers to the relay, sends go to `sink`.
 * `reliable`: a WebSocket (the relay streams each tick once) or not (it repeats unacked ticks).
 */
class BenchTransport extends BaseTransport {
  constructor(
    public sink: (bytes: Uint8Array) => void,
    readonly reliable: boolean,
  ) {
    super();
  }
  send(bytes: Uint8Array): void {
    if (this.isOpen) this.sink(bytes);
  }
  push(bytes: Uint8Array): void {
    this.deliver(bytes);
  }
  protected doClose(): void {
    // Nothing to release.
  }
}

/** A seeded u32 source for the relay's tokens (replays must match the recording). */
function seededU32(seed: number): () => number {
  let x = seed >>> 0 || 1;
  return () => {
    x ^= x << 13;
    x ^= x >>> 17;
    x ^= x << 5;
    return x >>> 0;
  };
}

function newRelay(clock: ManualClock, seed: number, sendEvery = 1): Relay {
  return new Relay({
    clock,
    sendEvery,
    catalog: CATALOG,
    randomU32: seededU32(seed),
    hashEvery: HASH_EVERY,
    maxRooms: 4000,
    maxConnections: 16_000,
  });
}

export interface TraceOptions {
  rooms: number;
  players: number;
  /**
   * Over a stream (a WebSocket, protocol 3 on): each input and each confirmed tick is sent once.
   * False: every message repeats the unacknowledged ticks, as protocol 2 did over WebSockets
   * (and the relay still does over lossy links).
   */
  stream: boolean;
  /** Simulated seconds of play after tick 0. */
  seconds: number;
  oneWayMs: number;
  jitterMs: number;
  seed: number;
  /** The relay's network rate, ticks per send (the clients group their inputs alike). Default 1. */
  sendEvery?: number;
}

/** What the relay saw: deliveries (`conn` ≥ 0) and updates (`conn` = -1), in order. */
export interface Trace {
  options: TraceOptions;
  connections: number;
  at: Float64Array;
  conn: Int32Array;
  bytes: (Uint8Array | undefined)[];
  /** Index of the first event at or after tick 0's time: the timed part starts here. */
  steadyFrom: number;
  startAt: number;
  /** Simulated ms of the timed part. */
  steadyMs: number;
  /** The messages the relay sent during the timed part (for the bare codec baseline). */
  sent: NetMessage[];
  /** Relay byte counters over the timed part. */
  bytesIn: number;
  bytesOut: number;
  messagesIn: number;
  messagesOut: number;
  bytesOutTotal: number;
  filledInputs: number;
  dropped: number;
  closedTicks: number;
  inputDelay: number;
  /** Per player-tick (simulated ms): arrival of its input → confirmed message sent. */
  delay: Float64Array;
  /** The part of `delay` spent waiting for the room's last input of that tick. */
  waitOthers: Float64Array;
  /** The part spent waiting for the next `update()` after the last input arrived. */
  waitUpdate: Float64Array;
  /**
   * Per player-tick, at the client (simulated ms): its input for the tick sent → the confirmed
   * tick received. The round trip plus the relay's wait for the room's other inputs.
   */
  clientDelay: Float64Array;
}

interface Client {
  index: number;
  room: number;
  relayEnd: BenchTransport;
  roomNumber: number;
  slot: number;
  startAt: number | undefined;
  issueNext: number;
  issued: Uint32Array;
  /** Stream: every issued input before this tick has been sent. */
  sentTo: number;
  /** When it last sent inputs. */
  lastSentAt: number;
  /** When its input for each tick was first sent (NaN: not yet). */
  sentAt: Float64Array;
  serverInputAck: number;
  confirmedEnd: number;
  nextReport: number;
  nextPingAt: number;
  pingId: number;
  buttons: HeldButtons;
}

/** An event of the closed loop. */
interface Ev {
  at: number;
  /** 0 client frame, 1 uplink arrival, 2 relay update, 3 downlink arrival. */
  kind: number;
  client: number;
  bytes: Uint8Array | undefined;
}

/** Runs the closed-loop match and records what the relay saw. */
export function recordTrace(o: TraceOptions): Trace {
  const rng = new Random(o.seed);
  // The closed loop's events, in time order (ties in the order they were scheduled).
  const scheduler = new EventScheduler(0);
  const clock = scheduler.clock;
  const every = o.sendEvery ?? 1;
  const relay = newRelay(clock, o.seed, every);
  const push = (at: number, kind: number, client: number, bytes?: Uint8Array): void => {
    scheduler.at(at, () => {
      handle({ at, kind, client, bytes });
    });
  };
  // As the LockstepSession picks it: the round trip, and the network rate's grouping both ways.
  const inputDelay = inputDelayTicks(2 * (o.oneWayMs + o.jitterMs)) + 2 * (every - 1);
  const maxTicks = Math.ceil((o.seconds * 1000) / STEP_MS) + inputDelay + 2 * MAX_WINDOW + 64;

  const at: number[] = [];
  const conn: number[] = [];
  const bytes: (Uint8Array | undefined)[] = [];
  const sent: NetMessage[] = [];
  let steadyFrom = -1;
  let startAt = Infinity;
  let endAt = Infinity;
  const link = () => o.oneWayMs + o.jitterMs * rng.next();

  // Per room: first arrival time of each slot's input for each tick; the next tick not yet sent.
  const arrival: Float64Array[][] = [];
  const nextUnsent: number[] = [];
  const delay: number[] = [];
  const waitOthers: number[] = [];
  const waitUpdate: number[] = [];
  const clientDelay: number[] = [];

  const clients: Client[] = [];
  for (let r = 0; r < o.rooms; r++) {
    arrival.push(
      Array.from({ length: o.players }, () => new Float64Array(maxTicks + MAX_WINDOW).fill(NaN)),
    );
    nextUnsent.push(0);
    for (let p = 0; p < o.players; p++) {
      const index = clients.length;
      const relayEnd = new BenchTransport(() => undefined, o.stream);
      const c: Client = {
        index,
        room: r,
        relayEnd,
        roomNumber: -1,
        slot: -1,
        startAt: undefined,
        issueNext: 0,
        issued: new Uint32Array(maxTicks + MAX_WINDOW),
        sentTo: 0,
        lastSentAt: -Infinity,
        sentAt: new Float64Array(maxTicks + MAX_WINDOW).fill(NaN),
        serverInputAck: 0,
        confirmedEnd: 0,
        nextReport: HASH_EVERY,
        nextPingAt: 0,
        pingId: 0,
        buttons: new HeldButtons(new Random(o.seed * 7919 + index)),
      };
      relayEnd.sink = (b) => {
        onRelaySend(c, b);
        push(clock.now() + link(), 3, index, b);
      };
      clients.push(c);
      relay.accept(relayEnd, { address: `client${index}` });
      const hello = encodeMessage({
        type: 'hello',
        room: `r${r}`,
        role: 'player',
        game: GAME.id,
        gameVersion: GAME.version,
        input: GAME.input.id,
        players: o.players,
        seed: r + 1,
        name: `p${index}`,
      });
      push(link(), 1, index, hello);
      // Each client's display frames have their own phase within the tick.
      push(rng.next() * STEP_MS, 0, index);
    }
  }
  push(STEP_MS / 2, 2, -1);

  function onRelaySend(c: Client, frame: Uint8Array): void {
    for (const b of RELAY_PROTOCOL.split(frame)) onRelayMessage(c, b);
  }

  function onRelayMessage(c: Client, b: Uint8Array): void {
    const m = decodeMessage(b);
    if (steadyFrom >= 0 && clock.now() < endAt) sent.push(m);
    if (m.type !== 'confirmed') return;
    const n = m.inputs.length / (m.players * m.words);
    const now = clock.now();
    const arr = arrival[c.room]!;
    for (let t = Math.max(m.tick, nextUnsent[c.room]!); t < m.tick + n; t++) {
      let last = -Infinity;
      for (const a of arr) if (a[t]! > last) last = a[t]!;
      for (const a of arr) {
        const got = a[t]!;
        if (Number.isNaN(got) || now < startAt) continue;
        delay.push(now - got);
        waitOthers.push(last - got);
        waitUpdate.push(now - last);
      }
    }
    nextUnsent[c.room] = Math.max(nextUnsent[c.room]!, m.tick + n);
  }

  function clientSend(c: Client, now: number, m: NetMessage): void {
    push(now + link(), 1, c.index, encodeMessage(m));
  }

  function onClientMessage(c: Client, m: NetMessage, now: number): void {
    switch (m.type) {
      case 'welcome':
        c.roomNumber = m.room;
        c.slot = m.slot;
        if (m.startAt !== undefined) c.startAt = m.startAt;
        break;
      case 'start':
        c.startAt = m.startAt;
        break;
      case 'confirmed': {
        // A stream's XOR-coded message continues exactly where the last one ended.
        const end = m.tick + m.inputs.length / (m.players * m.words);
        if (m.tick <= c.confirmedEnd && !(m.delta && m.tick !== c.confirmedEnd)) {
          for (let t = c.confirmedEnd; t < end; t++) {
            const sent = c.sentAt[t]!;
            if (!Number.isNaN(sent) && now >= startAt) clientDelay.push(now - sent);
          }
          c.confirmedEnd = Math.max(c.confirmedEnd, end);
        }
        c.serverInputAck = Math.max(c.serverInputAck, m.inputAck);
        break;
      }
      default:
        break;
    }
  }

  function clientFrame(c: Client, now: number): void {
    if (c.startAt === undefined) return;
    const serverTick = Math.floor((now - c.startAt) / STEP_MS);
    const target = Math.min(serverTick + 1 + inputDelay, maxTicks - 1);
    let fresh = false;
    while (c.issueNext <= target) {
      c.issued[c.issueNext++] = c.buttons.next();
      fresh = true;
    }
    const from = Math.max(c.serverInputAck, c.issueNext - MAX_WINDOW, o.stream ? c.sentTo : 0);
    // The network rate: inputs go in groups of `every` ticks (or once the first has waited that long).
    const due = c.issueNext - c.sentTo >= every || now - c.lastSentAt >= every * STEP_MS;
    if ((fresh || c.sentTo < c.issueNext) && due && from < c.issueNext) {
      c.lastSentAt = now;
      for (let t = from; t < c.issueNext; t++) if (Number.isNaN(c.sentAt[t]!)) c.sentAt[t] = now;
      c.sentTo = c.issueNext;
      clientSend(c, now, {
        type: 'input',
        room: c.roomNumber,
        player: c.slot,
        ack: c.confirmedEnd,
        tick: from,
        words: 1,
        inputs: c.issued.slice(from, c.issueNext),
      });
    }
    while (c.nextReport <= c.confirmedEnd) {
      const t = c.nextReport;
      c.nextReport += HASH_EVERY;
      const hash = BigInt(t) * 0x9e3779b97f4a7c15n + BigInt(o.seed);
      clientSend(c, now, {
        type: 'hash',
        room: c.roomNumber,
        tick: t,
        hash: BigInt.asUintN(64, hash),
      });
    }
    if (now >= c.nextPingAt) {
      c.nextPingAt = now + PING_MS;
      clientSend(c, now, { type: 'ping', id: c.pingId++, time: now });
    }
  }

  let base = { bytesIn: 0, bytesOut: 0, messagesIn: 0, messagesOut: 0 };
  /** The timed part starts with the first relay event at or after tick 0's time. */
  const markSteady = (now: number) => {
    if (steadyFrom >= 0 || now < startAt) return;
    steadyFrom = at.length;
    base = { ...relay.stats };
  };
  let end: typeof base | undefined;
  /** One event; the first at or after the end of the measured window stops the loop. */
  function handle(e: Ev): void {
    if (end !== undefined) return;
    if (e.at >= endAt) {
      end = { ...relay.stats };
      return;
    }
    if (e.kind === 0) {
      const c = clients[e.client]!;
      clientFrame(c, e.at);
      push(e.at + STEP_MS, 0, e.client);
    } else if (e.kind === 1) {
      const c = clients[e.client]!;
      markSteady(e.at);
      if (steadyFrom >= 0 && c.slot >= 0) {
        // The first input received for a tick is final: note when each arrived.
        const m = decodeMessage(e.bytes!);
        if (m.type === 'input') {
          const a = arrival[c.room]![c.slot]!;
          for (let k = 0; k < m.inputs.length; k++) {
            const t = m.tick + k;
            if (Number.isNaN(a[t]!) && t >= nextUnsent[c.room]!) a[t] = e.at;
          }
        }
      }
      at.push(e.at);
      conn.push(e.client);
      bytes.push(e.bytes);
      c.relayEnd.push(e.bytes!);
    } else if (e.kind === 2) {
      markSteady(e.at);
      at.push(e.at);
      conn.push(-1);
      bytes.push(undefined);
      relay.update(e.at);
      push(e.at + STEP_MS / 2, 2, -1);
    } else {
      const c = clients[e.client]!;
      for (const b of RELAY_PROTOCOL.split(e.bytes!)) onClientMessage(c, decodeMessage(b), e.at);
      if (startAt === Infinity && c.startAt !== undefined) {
        startAt = c.startAt;
        endAt = startAt + o.seconds * 1000;
      }
    }
  }
  scheduler.runUntilDone(() => end !== undefined, Number.MAX_SAFE_INTEGER);
  if (end === undefined) throw new Error('recordTrace: the match never reached its end');
  const rooms = relay.roomList();
  return {
    options: o,
    connections: clients.length,
    at: Float64Array.from(at),
    conn: Int32Array.from(conn),
    bytes,
    steadyFrom,
    startAt,
    steadyMs: endAt - startAt,
    sent,
    bytesIn: end.bytesIn - base.bytesIn,
    bytesOut: end.bytesOut - base.bytesOut,
    messagesIn: end.messagesIn - base.messagesIn,
    messagesOut: end.messagesOut - base.messagesOut,
    bytesOutTotal: relay.stats.bytesOut,
    filledInputs: relay.stats.filledInputs,
    dropped: Object.values(relay.stats.dropped).reduce((a, b) => a + b, 0),
    closedTicks: Math.min(...rooms.map((r) => r.closedTick)),
    inputDelay,
    delay: Float64Array.from(delay),
    waitOthers: Float64Array.from(waitOthers),
    waitUpdate: Float64Array.from(waitUpdate),
    clientDelay: Float64Array.from(clientDelay),
  };
}

// ------------------------------------------------------------------------------ replays

interface Replay {
  relay: Relay;
  clock: ManualClock;
  ends: BenchTransport[];
  bytesOut: number;
}

/** A fresh relay fed the trace up to its timed part (handshakes, start). */
function prepareReplay(trace: Trace, onSend?: (bytes: Uint8Array) => void): Replay {
  const clock = new ManualClock(0);
  const relay = newRelay(clock, trace.options.seed, trace.options.sendEvery);
  const r: Replay = { relay, clock, ends: [], bytesOut: 0 };
  for (let i = 0; i < trace.connections; i++) {
    const end = new BenchTransport(
      onSend ??
        ((b) => {
          r.bytesOut += b.length;
        }),
      trace.options.stream,
    );
    r.ends.push(end);
    relay.accept(end, { address: `client${i}` });
  }
  runEvents(r, trace, 0, trace.steadyFrom);
  return r;
}

function runEvents(r: Replay, trace: Trace, from: number, to: number): void {
  const { at, conn, bytes } = trace;
  for (let i = from; i < to; i++) {
    r.clock.set(at[i]!);
    const c = conn[i]!;
    if (c < 0) r.relay.update(at[i]);
    else r.ends[c]!.push(bytes[i]!);
  }
}

/** Times the relay over the trace's timed part, in ns. */
/** CPU time (user + system) of this process so far, in ns. */
function cpuNs(): number {
  const u = process.cpuUsage();
  return (u.user + u.system) * 1000;
}

/**
 * Times the relay over the trace's timed part: wall ns, and CPU ns (user + system of this
 * process: on a machine shared with other jobs, only the relay's own work).
 */
export function timeRelay(trace: Trace): { ns: number; cpuNs: number; bytesOut: number } {
  const r = prepareReplay(trace);
  const c0 = cpuNs();
  const t0 = process.hrtime.bigint();
  runEvents(r, trace, trace.steadyFrom, trace.at.length);
  const ns = Number(process.hrtime.bigint() - t0);
  return { ns, cpuNs: cpuNs() - c0, bytesOut: r.relay.stats.bytesOut };
}

/** Times a bare decode of every delivered message and encode of every sent one, in ns. */
export function timeCodec(trace: Trace): { ns: number; cpuNs: number; sink: number } {
  const { bytes } = trace;
  let sink = 0;
  const c0 = cpuNs();
  const t0 = process.hrtime.bigint();
  for (let i = trace.steadyFrom; i < bytes.length; i++) {
    const b = bytes[i];
    if (b !== undefined) sink += decodeMessage(b).type.length;
  }
  for (const m of trace.sent) sink += encodeMessage(m).length;
  const ns = Number(process.hrtime.bigint() - t0);
  return { ns, cpuNs: cpuNs() - c0, sink };
}

/**
 * Server processing latency (hrtime, no simulated waits): the handling time of each input
 * message, and the time from the start of each `update()` to each confirmed message it sends
 * (the rooms before it in the update queue).
 */
export function processingLatency(trace: Trace): { handle: Float64Array; flush: Float64Array } {
  let updateStart = 0n;
  const flush: number[] = [];
  const r = prepareReplay(trace, (b) => {
    if (updateStart !== 0n && (b[1] === 0x05 || b[1] === RELAY_PROTOCOL.batch)) {
      flush.push(Number(process.hrtime.bigint() - updateStart));
    }
  });
  const handle: number[] = [];
  const { at, conn, bytes } = trace;
  for (let i = trace.steadyFrom; i < at.length; i++) {
    r.clock.set(at[i]!);
    const c = conn[i]!;
    if (c < 0) {
      updateStart = process.hrtime.bigint();
      r.relay.update(at[i]);
      updateStart = 0n;
    } else {
      const b = bytes[i]!;
      const t0 = process.hrtime.bigint();
      r.ends[c]!.push(b);
      if (b[1] === 0x04) handle.push(Number(process.hrtime.bigint() - t0));
    }
  }
  return { handle: Float64Array.from(handle), flush: Float64Array.from(flush) };
}

// ------------------------------------------------------------------------------ the suite

const fmt = (x: number, digits = 1) => x.toFixed(digits);

export default defineSuite({
  name: 'relay',
  description:
    'Relay capacity (players per core at 60 Hz), added latency, bandwidth per player; 3 processes behind HAProxy',
  async run(ctx) {
    const quick = ctx.quick;
    const players = quick ? 40 : 400;
    const seconds = quick ? 1 : 4;
    const rounds = quick ? 3 : 9;
    const link = { oneWayMs: 25, jitterMs: 5 };
    ctx.note(
      `lockstep at ${TICK_HZ} Hz, ~${players} players per configuration, ${seconds} s simulated; ` +
        `one-way latency ${link.oneWayMs} ms + 0–${link.jitterMs} ms jitter, no loss; held ` +
        `buttons, one change per ~20 ticks; hash every ${HASH_EVERY} ticks, ping every ${PING_MS} ms; ` +
        `update() every half step. Two ways to send over a WebSocket: "stream" (protocol 3 on: each ` +
        `input and each confirmed tick once, XOR-coded against the tick before) and "redundant" ` +
        `(every message repeats the unacknowledged ticks, as protocol 2 did; the relay still ` +
        `does it over lossy links). Timed: a fresh relay replaying the recorded trace (decode, ` +
        `update, encode, fan-out), ${rounds} interleaved rounds, median of the process's CPU time ` +
        `(user + system), so other jobs on the machine do not count.`,
    );

    const modes = [
      { name: 'stream', stream: true },
      { name: 'redundant', stream: false },
    ] as const;
    const capacity: string[][] = [];
    const latency: string[][] = [];
    const bandwidth: string[][] = [];
    const compare: string[][] = [];
    for (const n of [2, 4]) {
      const rooms = Math.max(1, Math.round(players / n));
      const traces = modes.map((m) =>
        recordTrace({ rooms, players: n, seconds, seed: 0x5eed + n, stream: m.stream, ...link }),
      );
      const p = rooms * n;
      for (const trace of traces) {
        const check = timeRelay(trace);
        if (trace.dropped > 0 || check.bytesOut !== trace.bytesOutTotal) {
          throw new Error(
            `replay differs from the recording (dropped ${trace.dropped}, bytes ${check.bytesOut} vs ${trace.bytesOutTotal})`,
          );
        }
        timeCodec(trace);
      }
      // Candidates: the bare codec of the stream's messages, then the relay in each mode.
      const samples: number[][] = [[], [], []];
      for (let round = 0; round < rounds; round++) {
        globalThis.gc?.();
        for (const c of roundOrder(3, round)) {
          samples[c]!.push(c === 0 ? timeCodec(traces[0]!).cpuNs : timeRelay(traces[c - 1]!).cpuNs);
        }
      }
      const summary = summarize(['bare codec', 'stream', 'redundant'], samples, 0);
      modes.forEach((mode, k) => {
        const trace = traces[k]!;
        const simS = trace.steadyMs / 1000;
        const relay = summary[k + 1]!;
        const nsPerSimS = relay.ns.median / simS;
        const ppc = playersPerCore(p, nsPerSimS);
        const msgs = trace.messagesIn + trace.messagesOut;
        capacity.push([
          `${n}`,
          mode.name,
          `${rooms} × ${n}`,
          fmt((nsPerSimS / 1e9) * 100, 2) + ' %',
          fmt(nsPerSimS / p / 1000, 1),
          fmt(ppc, 0),
          fmt(ppc / n, 0),
        ]);
        if (k === 0) {
          compare.push([
            `${n}`,
            fmt(summary[0]!.ns.median / msgs, 0),
            fmt(relay.ns.median / msgs, 0),
            `${formatRatio(relay.ratio!.median)} (${formatRatio(relay.ratio!.min)}–${formatRatio(relay.ratio!.max)})`,
          ]);
        }
        const proc = processingLatency(trace);
        latency.push([
          `${n}`,
          mode.name,
          fmt(percentile(proc.handle, 99) / 1000, 1),
          fmt(percentile(proc.flush, 99) / 1000, 1),
          fmt(percentile(trace.delay, 50), 1),
          fmt(percentile(trace.delay, 99), 1),
          fmt(percentile(trace.clientDelay, 50), 1),
          fmt(percentile(trace.clientDelay, 99), 1),
          `${trace.inputDelay}`,
        ]);
        const upMsgs = trace.messagesIn / p / simS;
        const downMsgs = trace.messagesOut / p / simS;
        const up = trace.bytesIn / p / simS;
        const down = trace.bytesOut / p / simS;
        bandwidth.push([
          `${n}`,
          mode.name,
          fmt(upMsgs, 1),
          fmt(up, 0),
          fmt(up + upMsgs * WS_UP_HEADER, 0),
          fmt(downMsgs, 1),
          fmt(down, 0),
          fmt(down + downMsgs * WS_DOWN_HEADER, 0),
          `${trace.filledInputs}`,
        ]);
        const spreadNs = spread(samples[k + 1]!);
        ctx.note(
          `N=${n} ${mode.name}: ${rooms} rooms, ${msgs} messages in ${fmt(simS, 2)} s simulated; relay replay ` +
            `${fmt(spreadNs.median / 1e6, 1)} ms (${fmt(spreadNs.min / 1e6, 1)}–${fmt(spreadNs.max / 1e6, 1)}), ` +
            `${trace.closedTicks} ticks closed per room, ${trace.filledInputs} filled inputs, ${trace.dropped} drops`,
        );
      });
    }

    ctx.table(
      'Relay capacity at 60 Hz (one core = relay CPU per real second < 1 s)',
      [
        'N',
        'sending',
        'rooms × players',
        'core at this load',
        'µs per player-second',
        'players/core',
        'rooms/core',
      ],
      capacity,
    );
    ctx.table(
      'Per message (stream): bare decode+encode of the same messages vs the relay (ratio per round)',
      ['N', 'codec ns/msg', 'relay ns/msg', 'relay / codec'],
      compare,
    );
    ctx.table(
      'Latency: server processing (hrtime, µs), tick closing at the relay and input → confirmed at the client (simulated ms)',
      [
        'N',
        'sending',
        'p99 input handling µs',
        'p99 update→confirmed sent µs',
        'relay p50 ms',
        'relay p99 ms',
        'client p50 ms',
        'client p99 ms',
        'input delay ticks',
      ],
      latency,
    );
    ctx.table(
      'Bandwidth per player (payload, and with WebSocket frame headers; no TCP/IP)',
      [
        'N',
        'sending',
        'up msg/s',
        'up B/s',
        'up B/s +ws',
        'down msg/s',
        'down B/s',
        'down B/s +ws',
        'filled',
      ],
      bandwidth,
    );
    ctx.note(
      "Relay delay: a player's input arrives → the confirmed message carrying it leaves (a tick " +
        "closes when every player's input is in, or at its deadline 100 ms after its time, and " +
        'goes out at the next update(), every half step). Client delay: the client sends its ' +
        'input → receives it confirmed: the round trip plus the wait for the other inputs. With ' +
        'the input delay the client picks, inputs arrive ahead of their tick, so these delays are ' +
        'hidden from play unless a player is late. Processing latency: p99 of one input ' +
        "message's handling, plus p99 of the time from the start of update() to a room's " +
        'confirmed send (rooms earlier in the same update go first).',
    );

    await socketSection(ctx);
    await balancerSection(ctx);
  },
});

// ------------------------------------------------------------------------------ behind HAProxy

const ROOT = fileURLToPath(new URL('../../', import.meta.url));

/** User + system CPU seconds of a process so far (Linux /proc), or NaN. */
function cpuSeconds(pid: number): number {
  try {
    const stat = readFileSync(`/proc/${pid}/stat`, 'utf8');
    // Fields after the command name (which may hold spaces): utime is the 14th, stime the 15th.
    const f = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
    return (Number(f[11]) + Number(f[12])) / 100;
  } catch {
    return Number.NaN;
  }
}

async function waitFor<T>(what: string, f: () => T | Promise<T>, ms = 60_000): Promise<T> {
  const end = performance.now() + ms;
  for (;;) {
    const v = await f();
    if (v) return v;
    if (performance.now() > end) throw new Error(`bench: timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** Waits (up to 60 s) until process `pid` uses under 3 % of a core over a second. */
async function waitQuiet(pid: number): Promise<void> {
  const end = performance.now() + 60_000;
  while (performance.now() < end) {
    const before = cpuSeconds(pid);
    await new Promise((r) => setTimeout(r, 1000));
    if (!(cpuSeconds(pid) - before >= 0.03)) return;
  }
}

function freePort(): Promise<number> {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const port = (s.address() as net.AddressInfo).port;
      s.close(() => {
        resolve(port);
      });
    });
  });
}

/** A counter: the cheapest simulation that still has a state, a save and a hash. */
class Counter implements Simulation {
  tick = 0;
  private acc = 0;
  step(inputs: readonly unknown[]): void {
    for (const i of inputs) this.acc = (Math.imul(this.acc, 31) + (i as number)) | 0;
    this.tick++;
  }
  save(): Uint8Array {
    const b = new Uint8Array(8);
    const v = new DataView(b.buffer);
    v.setUint32(0, this.tick, true);
    v.setInt32(4, this.acc, true);
    return b;
  }
  load(bytes: Uint8Array): void {
    const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.tick = v.getUint32(0, true);
    this.acc = v.getInt32(4, true);
  }
  hash(): bigint {
    return BigInt(this.tick) * 0x9e3779b1n + BigInt(this.acc >>> 0);
  }
}

export interface BalancedRun {
  processes: number;
  players: number;
  seconds: number;
  relayCpu: number[];
  haproxyCpu: number;
  generatorCpu: number;
  clientDelay: Float64Array;
  lateInputs: number;
  inputs: number;
  agree: boolean;
  /** WebSocket frames per player per second, up (to the relay) and down, while measuring. */
  framesUp: number;
  framesDown: number;
  /** Each relay process's resident memory at the end of the measurement, and its peak, MB. */
  relayRss: { now: number; peak: number }[];
}

/**
 * `players` lockstep players (rooms of 2, a trivial client-side game, held buttons) through
 * HAProxy with deploy/haproxy/haproxy.cfg to `processes` `fixedstep serve` processes (1: all three
 * server lines point at the same process), for `seconds` of real time after every room started.
 */
export async function runBalanced(
  haproxy: string | undefined,
  processes: number,
  players: number,
  seconds: number,
  sendEvery = 1,
): Promise<BalancedRun> {
  const dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-bench-'));
  const children: ChildProcess[] = [];
  const sessions: LockstepSession<unknown>[] = [];
  let timer: ReturnType<typeof setInterval> | undefined;
  try {
    await writeFile(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
    const relays = await Promise.all(
      Array.from({ length: processes }, async (_, index) => {
        const child = spawn(
          process.execPath,
          [...fixedstepCommand().args, 'serve'].concat([
            '--port',
            '0',
            '--root',
            dir,
            '--data',
            // A data folder belongs to one process (it is locked).
            path.join(dir, `data-${index}`),
          ]),
          {
            cwd: ROOT,
            env: {
              ...process.env,
              // HAProxy passes each client's address on; the caps per address stay as deployed.
              ...(haproxy !== undefined ? { FIXEDSTEP_PROXY_HEADER: 'x-forwarded-for' } : {}),
              FIXEDSTEP_SEND_EVERY: String(sendEvery),
            },
            stdio: ['ignore', 'pipe', 'inherit'],
          },
        );
        children.push(child);
        let out = '';
        child.stdout.on('data', (b: Buffer) => (out += b.toString()));
        const port = Number(await waitFor('a relay', () => /localhost:(\d+)\//.exec(out)?.[1]));
        // Ready (its store open) before HAProxy counts it up: PGlite's start holds the event loop.
        await waitFor('a ready relay', async () => {
          try {
            return (await fetch(`http://127.0.0.1:${port}/readyz`)).ok;
          } catch {
            return false;
          }
        });
        // Quiet before it is measured: a new server's worker threads (the verification pool,
        // state sync) load and compile their games for a while after it is ready, and that is not
        // the relay's work.
        await waitQuiet(child.pid!);
        return { pid: child.pid!, port };
      }),
    );
    // Without HAProxy: the players connect to the one relay directly.
    let lbPort = relays[0]!.port;
    let lbPid: number | undefined;
    if (haproxy !== undefined) {
      lbPort = await freePort();
      const statsPort = await freePort();
      const extra = path.join(dir, 'stats.cfg');
      await writeFile(
        extra,
        `frontend bench_stats\n  bind 127.0.0.1:${statsPort}\n` +
          `  http-request return status 200 content-type text/plain lf-string "%[nbsrv(relays_by_room)]"\n`,
      );
      const server = (i: number) => `127.0.0.1:${relays[i % processes]!.port}`;
      const lb = spawn(
        haproxy,
        ['-db', '-f', path.join(ROOT, 'deploy/haproxy/haproxy.cfg'), '-f', extra],
        {
          env: {
            PATH: process.env.PATH ?? '',
            FIXEDSTEP_BIND: `127.0.0.1:${lbPort}`,
            FIXEDSTEP_RELAY1: server(0),
            FIXEDSTEP_RELAY2: server(1),
            FIXEDSTEP_RELAY3: server(2),
          },
          stdio: 'ignore',
        },
      );
      children.push(lb);
      await waitFor('HAProxy', async () => {
        try {
          return (await (await fetch(`http://127.0.0.1:${statsPort}/`)).text()) === '3';
        } catch {
          return false;
        }
      });
      lbPid = lb.pid;
    }
    const clock = performanceClock();
    const delays: number[] = [];
    let measuring = false;
    let framesUp = 0;
    let framesDown = 0;
    for (let i = 0; i < players; i++) {
      const room = `bench-${i >> 1}`;
      // Every player from an address of its own (127/8 is all this machine's), as on the internet.
      const t = await connectNodeWebSocket(`ws://127.0.0.1:${lbPort}/ws/${room}`, {
        localAddress: `127.1.${i >> 7}.${(i & 127) + 1}`,
      });
      const issuedAt = new Float64Array(1 << 16).fill(Number.NaN);
      let slot = -1;
      let confirmedEnd = 0;
      // Watch the confirmed stream: when each of this player's inputs comes back confirmed.
      const observed: Transport = {
        reliable: true,
        send: (b) => {
          if (measuring) framesUp++;
          t.send(b);
        },
        onMessage: (h) => {
          t.onMessage((b) => {
            if (measuring) framesDown++;
            for (const part of measuring && slot >= 0 ? RELAY_PROTOCOL.split(b) : []) {
              if (peekMessageType(part) !== 'confirmed') continue;
              const m = decodeMessage(part) as ConfirmedMessage;
              const end = m.tick + m.inputs.length / (m.players * m.words);
              const now = clock.now();
              for (let k = Math.max(m.tick, confirmedEnd); k < end; k++) {
                const at = issuedAt[k & 0xffff]!;
                if (!Number.isNaN(at)) delays.push(now - at);
              }
              confirmedEnd = Math.max(confirmedEnd, end);
            }
            h(b);
          });
        },
        onClose: (h) => {
          t.onClose(h);
        },
        close: (r) => {
          t.close(r);
        },
        get isOpen() {
          return t.isOpen;
        },
      };
      const buttons = new HeldButtons(new Random(i + 1), 20, 4);
      sessions.push(
        new LockstepSession({
          transport: observed,
          clock,
          room,
          game: ctfGame,
          players: 2,
          seed: 1,
          createSimulation: (w) => {
            slot = w.slot;
            return new Counter();
          },
          localInput: (tick) => {
            issuedAt[tick & 0xffff] = clock.now();
            return buttons.next();
          },
        }),
      );
    }
    timer = setInterval(() => {
      for (const s of sessions) s.frame();
    }, 1000 / TICK_HZ);
    await waitFor('every room to start', () => sessions.every((s) => s.phase === 'running'));
    // Settle for a second (input delay, jitter buffers), then measure.
    await new Promise((r) => setTimeout(r, 1000));
    const late0 = sessions.reduce((a, s) => a + s.stats.replacedInputs, 0);
    const ticks0 = sessions.reduce((a, s) => a + s.tick, 0);
    const cpu0 = relays.map((r) => cpuSeconds(r.pid));
    const lb0 = lbPid === undefined ? 0 : cpuSeconds(lbPid);
    const gen0 = process.cpuUsage();
    const t0 = performance.now();
    measuring = true;
    await new Promise((r) => setTimeout(r, seconds * 1000));
    measuring = false;
    const wall = (performance.now() - t0) / 1000;
    const gen = process.cpuUsage(gen0);
    const run: BalancedRun = {
      processes,
      players,
      seconds: wall,
      relayCpu: relays.map((r, i) => (cpuSeconds(r.pid) - cpu0[i]!) / wall),
      haproxyCpu: lbPid === undefined ? 0 : (cpuSeconds(lbPid) - lb0) / wall,
      generatorCpu: (gen.user + gen.system) / 1e6 / wall,
      clientDelay: Float64Array.from(delays),
      lateInputs: sessions.reduce((a, s) => a + s.stats.replacedInputs, 0) - late0,
      inputs: sessions.reduce((a, s) => a + s.tick, 0) - ticks0,
      agree: true,
      framesUp: framesUp / players / wall,
      framesDown: framesDown / players / wall,
      relayRss: relays.map((r) => residentMb(r.pid)),
    };
    // Both players of each room on one state at a tick they both have.
    for (let i = 0; i + 1 < sessions.length; i += 2) {
      const a = sessions[i]!;
      const b = sessions[i + 1]!;
      const t = Math.min(a.confirmedStateTick(), b.confirmedStateTick()) - 1;
      if (a.hashAt(t) !== b.hashAt(t)) run.agree = false;
    }
    return run;
  } finally {
    if (timer) clearInterval(timer);
    for (const s of sessions) s.leave();
    for (const c of children) if (c.exitCode === null && c.signalCode === null) c.kill('SIGKILL');
    await rm(dir, { recursive: true, force: true });
  }
}

/**
 * The headline: players per core of one relay process, its players connected over real WebSockets
 * (on 127.0.0.1, straight to it), at each network rate.
 */
async function socketSection(ctx: SuiteContext): Promise<void> {
  const title = 'Relay capacity through real WebSockets: one process, rooms of 2 at 60 Hz';
  if (ctx.quick) {
    ctx.note(`${title}: not in --quick (npm run bench -- relay runs it).`);
    return;
  }
  // As many players as the load generator (one thread, in this process) drives at close to a
  // frame a tick each way on a 2-core machine: 200 cost ~2,000 µs of relay CPU a player-second, 500
  // ~1,400 (the relay's wake-ups serve more sockets each as its load grows); at 1,000 the generator
  // falls to ~18 frames a second a player — a bundling that would flatter the relay.
  const players = 500;
  const seconds = 10;
  const rates = [1, 2, 3, 4];
  const rounds = 2;
  // Interleaved rounds; each run's relay CPU per player-second of play at 60 Hz (the ticks the
  // sessions played, so a load generator that falls behind does not flatter the relay).
  const runs: BalancedRun[][] = rates.map(() => []);
  for (let round = 0; round < rounds; round++) {
    for (const i of roundOrder(rates.length, round)) {
      runs[i]!.push(await runBalanced(undefined, 1, players, seconds, rates[i]));
    }
  }
  const perPlayer = (r: BalancedRun) => r.relayCpu[0]! / (r.inputs / TICK_HZ / r.seconds);
  const rows = rates.map((every, i) => {
    const rs = runs[i]!;
    const cost = spread(rs.map(perPlayer));
    const r = rs[0]!;
    const delays = Float64Array.from(rs.flatMap((x) => [...x.clientDelay]));
    const mean = (f: (x: BalancedRun) => number) => rs.reduce((a, x) => a + f(x), 0) / rs.length;
    return [
      `${every} (${fmt(TICK_HZ / every, 0)} Hz)`,
      `${r.players}`,
      fmt(
        mean((x) => x.inputs / x.players / x.seconds),
        1,
      ),
      `${fmt(
        mean((x) => x.framesUp),
        1,
      )} / ${fmt(
        mean((x) => x.framesDown),
        1,
      )}`,
      `${fmt(mean((x) => x.relayCpu[0]!) * 100, 1)} %`,
      `${fmt(cost.median * 1e6, 0)} (${fmt(cost.min * 1e6, 0)}–${fmt(cost.max * 1e6, 0)})`,
      `${fmt(1 / cost.median, 0)} (${fmt(1 / cost.max, 0)}–${fmt(1 / cost.min, 0)})`,
      `${fmt(mean((x) => x.generatorCpu) * 100, 1)} %`,
      fmt(Math.max(...rs.map((x) => x.relayRss[0]!.peak)), 0),
      `${fmt(percentile(delays, 50), 1)} / ${fmt(percentile(delays, 99), 1)}`,
      `${fmt(
        (100 * rs.reduce((a, x) => a + x.lateInputs, 0)) /
          Math.max(
            1,
            rs.reduce((a, x) => a + x.inputs, 0),
          ),
        2,
      )} %${rs.every((x) => x.agree) ? '' : ' DISAGREE'}`,
    ];
  });
  ctx.table(
    title,
    [
      'sendEvery (network rate)',
      'players',
      'ticks/s played',
      'frames/s up / down',
      'relay CPU',
      'µs CPU per player-second',
      'players per core',
      'load generator CPU',
      'relay RSS peak MB',
      'input → confirmed p50 / p99 ms',
      'late inputs',
    ],
    rows,
  );
  ctx.note(
    `${players} players (LockstepSessions with a trivial game, in this process: the load ` +
      `generator) in rooms of 2 for ${seconds} s after every room started, ${rounds} interleaved ` +
      `rounds (median, range), each player from a loopback ` +
      `address of its own, connected straight to one \`fixedstep serve\` (${fixedstepCommand().how}, ` +
      `FIXEDSTEP_SEND_EVERY set); relay CPU from /proc, user + system (system time is about ` +
      `half of it: on loopback the kernel's TCP work for both ends of each packet the relay ` +
      `sends is charged to the relay). ` +
      `µs CPU per player-second = relay CPU / (ticks the sessions played / 60 / s), so a load ` +
      `generator that falls behind does not flatter it; players per core = its inverse. Frames: ` +
      `WebSocket frames per player per second, to the relay and from it. The relay sends one WebSocket frame a connection a ` +
      `flush (protocol 5's batch frame when it has several messages); sendEvery groups confirmed ` +
      `ticks and the players' inputs, fewer frames each way, for the latency in the input → ` +
      `confirmed column (the client's send to its receipt of the tick confirmed, over loopback). ` +
      `${cpus().length} cores shared by the relay, the load generator and anything else (load ` +
      `average ${os.loadavg()[0]!.toFixed(1)}).`,
  );
}

async function balancerSection(ctx: SuiteContext): Promise<void> {
  const title = 'Behind HAProxy: 1 relay process vs 3 (real sockets on 127.0.0.1)';
  if (ctx.quick) {
    ctx.note(`${title}: not in --quick (npm run bench -- relay runs it).`);
    return;
  }
  const haproxy = ['/usr/sbin/haproxy', '/usr/local/sbin/haproxy'].find((p) => existsSync(p));
  if (haproxy === undefined) {
    ctx.note(`${title}: skipped, no haproxy (Debian: apt-get install haproxy).`);
    return;
  }
  const players = 200;
  const seconds = 8;
  const runs: BalancedRun[] = [];
  for (const processes of [1, 3])
    runs.push(await runBalanced(haproxy, processes, players, seconds));
  const perCore = runs.map((r) => r.players / r.relayCpu.reduce((a, b) => a + b, 0));
  ctx.table(
    title,
    [
      'relays',
      'players',
      'relay CPU (each, % of a core)',
      'HAProxy CPU',
      'load generator CPU',
      'client p50 / p99 ms',
      'late inputs',
      'players per relay core',
      'projected players at 60 Hz',
    ],
    runs.map((r, i) => [
      `${r.processes}`,
      `${r.players}`,
      r.relayCpu.map((c) => `${fmt(c * 100, 1)} %`).join(', '),
      `${fmt(r.haproxyCpu * 100, 1)} %`,
      `${fmt(r.generatorCpu * 100, 1)} %`,
      `${fmt(percentile(r.clientDelay, 50), 1)} / ${fmt(percentile(r.clientDelay, 99), 1)}`,
      `${fmt((100 * r.lateInputs) / Math.max(1, r.inputs), 2)} %${r.agree ? '' : ' DISAGREE'}`,
      fmt(perCore[i]!, 0),
      fmt(perCore[i]! * r.processes, 0),
    ]),
  );
  const cores = cpus().length;
  const ratio = (perCore[1]! * 3) / perCore[0]!;
  ctx.note(
    `${players} players in rooms of 2 for ${seconds} s after every room started; the clients are ` +
      `LockstepSessions with a trivial game in this process (the load generator), each from a ` +
      `loopback address of its own (127.1.x.y), under the per-address caps as deployed. Players per relay ` +
      `core = players / relay CPU (all relays together); projected = that × relays, i.e. with a ` +
      `core per relay. 3 relays vs 1: ${fmt(ratio, 2)}× (goal ≥ 2.7× with a core per relay). This ` +
      `machine has ${cores} cores shared by the relays, HAProxy, the load generator and anything ` +
      `else running (load average ${os.loadavg()[0]!.toFixed(1)}), so the 3 relays here cannot ` +
      `together get more than ${cores} cores: the projection, not a measured 3-core run.`,
  );
}
