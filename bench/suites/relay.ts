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
import {
  BUTTON_WORD,
  BaseTransport,
  ManualClock,
  Random,
  Relay,
  decodeMessage,
  encodeMessage,
  type NetMessage,
  type RelayCatalog,
  type RelayGame,
} from 'fixedstep';
import { formatRatio } from '../lib/format.js';
import { roundOrder, spread, summarize } from '../lib/stats.js';
import { defineSuite } from '../lib/suite.js';

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

const GAME: RelayGame = {
  id: 'bench',
  version: 1,
  tickRate: TICK_HZ,
  minPlayers: 1,
  maxPlayers: 16,
  input: BUTTON_WORD,
  options: () => new Uint8Array(8),
};
const CATALOG: RelayCatalog = () => GAME;

/** A transport end on the relay's side: `push` delivers to the relay, sends go to `sink`. */
class BenchTransport extends BaseTransport {
  constructor(public sink: (bytes: Uint8Array) => void) {
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

function newRelay(clock: ManualClock, seed: number): Relay {
  return new Relay({
    clock,
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
  /** Simulated seconds of play after tick 0. */
  seconds: number;
  oneWayMs: number;
  jitterMs: number;
  seed: number;
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
  serverInputAck: number;
  confirmedEnd: number;
  nextReport: number;
  nextPingAt: number;
  pingId: number;
  buttons: HeldButtons;
}

interface Ev {
  at: number;
  seq: number;
  /** 0 client frame, 1 uplink arrival, 2 relay update, 3 downlink arrival. */
  kind: number;
  client: number;
  bytes: Uint8Array | undefined;
}

/** A binary min-heap of events by (at, seq). */
class EventQueue {
  private readonly heap: Ev[] = [];
  private seq = 0;
  get size(): number {
    return this.heap.length;
  }
  push(at: number, kind: number, client: number, bytes?: Uint8Array): void {
    const h = this.heap;
    h.push({ at, seq: this.seq++, kind, client, bytes });
    let i = h.length - 1;
    while (i > 0) {
      const p = (i - 1) >> 1;
      if (!less(h[i]!, h[p]!)) break;
      [h[i], h[p]] = [h[p]!, h[i]!];
      i = p;
    }
  }
  pop(): Ev {
    const h = this.heap;
    const top = h[0]!;
    const last = h.pop()!;
    if (h.length > 0) {
      h[0] = last;
      let i = 0;
      for (;;) {
        const l = 2 * i + 1;
        const r = l + 1;
        let m = i;
        if (l < h.length && less(h[l]!, h[m]!)) m = l;
        if (r < h.length && less(h[r]!, h[m]!)) m = r;
        if (m === i) break;
        [h[i], h[m]] = [h[m]!, h[i]!];
        i = m;
      }
    }
    return top;
  }
}

function less(a: Ev, b: Ev): boolean {
  return a.at < b.at || (a.at === b.at && a.seq < b.seq);
}

/** Runs the closed-loop match and records what the relay saw. */
export function recordTrace(o: TraceOptions): Trace {
  const rng = new Random(o.seed);
  const clock = new ManualClock(0);
  const relay = newRelay(clock, o.seed);
  const q = new EventQueue();
  const inputDelay = inputDelayTicks(2 * (o.oneWayMs + o.jitterMs));
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

  const clients: Client[] = [];
  for (let r = 0; r < o.rooms; r++) {
    arrival.push(
      Array.from({ length: o.players }, () => new Float64Array(maxTicks + MAX_WINDOW).fill(NaN)),
    );
    nextUnsent.push(0);
    for (let p = 0; p < o.players; p++) {
      const index = clients.length;
      const relayEnd = new BenchTransport(() => undefined);
      const c: Client = {
        index,
        room: r,
        relayEnd,
        roomNumber: -1,
        slot: -1,
        startAt: undefined,
        issueNext: 0,
        issued: new Uint32Array(maxTicks + MAX_WINDOW),
        serverInputAck: 0,
        confirmedEnd: 0,
        nextReport: HASH_EVERY,
        nextPingAt: 0,
        pingId: 0,
        buttons: new HeldButtons(new Random(o.seed * 7919 + index)),
      };
      relayEnd.sink = (b) => {
        onRelaySend(c, b);
        q.push(clock.now() + link(), 3, index, b);
      };
      clients.push(c);
      relay.accept(relayEnd);
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
      q.push(link(), 1, index, hello);
      // Each client's display frames have their own phase within the tick.
      q.push(rng.next() * STEP_MS, 0, index);
    }
  }
  q.push(STEP_MS / 2, 2, -1);

  function onRelaySend(c: Client, b: Uint8Array): void {
    const m = decodeMessage(b);
    if (steadyFrom >= 0 && clock.now() < endAt) sent.push(m);
    if (m.type !== 'confirmed') return;
    const n = m.inputs.length / m.players;
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
    q.push(now + link(), 1, c.index, encodeMessage(m));
  }

  function onClientMessage(c: Client, m: NetMessage): void {
    switch (m.type) {
      case 'welcome':
        c.roomNumber = m.room;
        c.slot = m.slot;
        if (m.startAt !== undefined) c.startAt = m.startAt;
        break;
      case 'start':
        c.startAt = m.startAt;
        break;
      case 'confirmed':
        if (m.tick <= c.confirmedEnd) {
          c.confirmedEnd = Math.max(c.confirmedEnd, m.tick + m.inputs.length / m.players);
        }
        c.serverInputAck = Math.max(c.serverInputAck, m.inputAck);
        break;
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
    const from = Math.max(c.serverInputAck, c.issueNext - MAX_WINDOW);
    if (fresh && from < c.issueNext) {
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
  let end: typeof base;
  /** The timed part starts with the first relay event at or after tick 0's time. */
  const markSteady = (now: number) => {
    if (steadyFrom >= 0 || now < startAt) return;
    steadyFrom = at.length;
    base = { ...relay.stats };
  };
  for (;;) {
    const e = q.pop();
    if (e.at >= endAt) {
      end = { ...relay.stats };
      break;
    }
    clock.set(e.at);
    if (e.kind === 0) {
      const c = clients[e.client]!;
      clientFrame(c, e.at);
      q.push(e.at + STEP_MS, 0, e.client);
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
      q.push(e.at + STEP_MS / 2, 2, -1);
    } else {
      const c = clients[e.client]!;
      onClientMessage(c, decodeMessage(e.bytes!));
      if (startAt === Infinity && c.startAt !== undefined) {
        startAt = c.startAt;
        endAt = startAt + o.seconds * 1000;
      }
    }
  }
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
  const relay = newRelay(clock, trace.options.seed);
  const r: Replay = { relay, clock, ends: [], bytesOut: 0 };
  for (let i = 0; i < trace.connections; i++) {
    const end = new BenchTransport(
      onSend ??
        ((b) => {
          r.bytesOut += b.length;
        }),
    );
    r.ends.push(end);
    relay.accept(end);
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
export function timeRelay(trace: Trace): { ns: number; bytesOut: number } {
  const r = prepareReplay(trace);
  const t0 = process.hrtime.bigint();
  runEvents(r, trace, trace.steadyFrom, trace.at.length);
  const ns = Number(process.hrtime.bigint() - t0);
  return { ns, bytesOut: r.relay.stats.bytesOut };
}

/** Times a bare decode of every delivered message and encode of every sent one, in ns. */
export function timeCodec(trace: Trace): { ns: number; sink: number } {
  const { bytes } = trace;
  let sink = 0;
  const t0 = process.hrtime.bigint();
  for (let i = trace.steadyFrom; i < bytes.length; i++) {
    const b = bytes[i];
    if (b !== undefined) sink += decodeMessage(b).type.length;
  }
  for (const m of trace.sent) sink += encodeMessage(m).length;
  const ns = Number(process.hrtime.bigint() - t0);
  return { ns, sink };
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
    if (updateStart !== 0n && b[1] === 0x05) {
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
  description: 'Relay capacity (players per core at 60 Hz), added latency, bandwidth per player',
  run(ctx) {
    const quick = ctx.quick;
    const players = quick ? 40 : 400;
    const seconds = quick ? 1 : 4;
    const rounds = quick ? 3 : 9;
    const link = { oneWayMs: 25, jitterMs: 5 };
    ctx.note(
      `lockstep at ${TICK_HZ} Hz, ~${players} players per configuration, ${seconds} s simulated; ` +
        `one-way latency ${link.oneWayMs} ms + 0–${link.jitterMs} ms jitter, no loss; held ` +
        `buttons, one change per ~20 ticks; hash every ${HASH_EVERY} ticks, ping every ${PING_MS} ms; ` +
        `update() every half step. Timed: a fresh relay replaying the recorded trace (decode, ` +
        `update, encode, fan-out), ${rounds} interleaved rounds, median.`,
    );

    const capacity: string[][] = [];
    const latency: string[][] = [];
    const bandwidth: string[][] = [];
    const compare: string[][] = [];
    for (const n of [2, 4]) {
      const rooms = Math.max(1, Math.round(players / n));
      const trace = recordTrace({ rooms, players: n, seconds, seed: 0x5eed + n, ...link });
      const p = rooms * n;
      const simS = trace.steadyMs / 1000;
      const check = timeRelay(trace);
      if (trace.dropped > 0 || check.bytesOut !== trace.bytesOutTotal) {
        throw new Error(
          `replay differs from the recording (dropped ${trace.dropped}, bytes ${check.bytesOut} vs ${trace.bytesOutTotal})`,
        );
      }
      timeCodec(trace);
      const samples: number[][] = [[], []];
      for (let round = 0; round < rounds; round++) {
        globalThis.gc?.();
        for (const c of roundOrder(2, round)) {
          samples[c]!.push(c === 0 ? timeCodec(trace).ns : timeRelay(trace).ns);
        }
      }
      const [codec, relay] = summarize(['bare codec', 'relay'], samples, 0);
      const nsPerSimS = relay!.ns.median / simS;
      const ppc = playersPerCore(p, nsPerSimS);
      const msgs = trace.messagesIn + trace.messagesOut;
      capacity.push([
        `${n}`,
        `${rooms} × ${n}`,
        fmt((nsPerSimS / 1e9) * 100, 2) + ' %',
        fmt(nsPerSimS / p / 1000, 1),
        fmt(ppc, 0),
        fmt(ppc / n, 0),
      ]);
      compare.push([
        `${n}`,
        fmt(codec!.ns.median / msgs, 0),
        fmt(relay!.ns.median / msgs, 0),
        `${formatRatio(relay!.ratio!.median)} (${formatRatio(relay!.ratio!.min)}–${formatRatio(relay!.ratio!.max)})`,
      ]);

      const proc = processingLatency(trace);
      const handleP99 = percentile(proc.handle, 99);
      const flushP99 = percentile(proc.flush, 99);
      latency.push([
        `${n}`,
        fmt(handleP99 / 1000, 1),
        fmt(flushP99 / 1000, 1),
        fmt(percentile(trace.delay, 50), 1),
        fmt(percentile(trace.delay, 99), 1),
        fmt(percentile(trace.waitOthers, 99), 1),
        fmt(percentile(trace.waitUpdate, 99), 1),
        `${trace.inputDelay}`,
      ]);

      const upMsgs = trace.messagesIn / p / simS;
      const downMsgs = trace.messagesOut / p / simS;
      const up = trace.bytesIn / p / simS;
      const down = trace.bytesOut / p / simS;
      bandwidth.push([
        `${n}`,
        fmt(upMsgs, 1),
        fmt(up, 0),
        fmt(up + upMsgs * WS_UP_HEADER, 0),
        fmt(downMsgs, 1),
        fmt(down, 0),
        fmt(down + downMsgs * WS_DOWN_HEADER, 0),
        `${trace.filledInputs}`,
      ]);
      const spreadNs = spread(samples[1]!);
      ctx.note(
        `N=${n}: ${rooms} rooms, ${msgs} messages in ${fmt(simS, 2)} s simulated; relay replay ` +
          `${fmt(spreadNs.median / 1e6, 1)} ms (${fmt(spreadNs.min / 1e6, 1)}–${fmt(spreadNs.max / 1e6, 1)}), ` +
          `${trace.closedTicks} ticks closed per room, ${trace.filledInputs} filled inputs, ${trace.dropped} drops`,
      );
    }

    ctx.table(
      'Relay capacity at 60 Hz (one core = relay CPU per real second < 1 s)',
      [
        'N',
        'rooms × players',
        'core at this load',
        'µs per player-second',
        'players/core',
        'rooms/core',
      ],
      capacity,
    );
    ctx.table(
      'Per message: bare decode+encode of the same messages vs the relay (ratio per round)',
      ['N', 'codec ns/msg', 'relay ns/msg', 'relay / codec'],
      compare,
    );
    ctx.table(
      'Latency the server adds: processing (hrtime, µs) and tick-closing design (simulated ms)',
      [
        'N',
        'p99 input handling µs',
        'p99 update→confirmed sent µs',
        'design p50 ms',
        'design p99 ms',
        'p99 wait for others ms',
        'p99 wait for update() ms',
        'input delay ticks',
      ],
      latency,
    );
    ctx.table(
      'Bandwidth per player (payload, and with WebSocket frame headers; no TCP/IP)',
      ['N', 'up msg/s', 'up B/s', 'up B/s +ws', 'down msg/s', 'down B/s', 'down B/s +ws', 'filled'],
      bandwidth,
    );
    ctx.note(
      "Design delay: a tick closes when every player's input is in (or at its deadline, 100 ms " +
        'after its time), then goes out at the next update() (every half step, 8.3 ms). With the ' +
        'input delay the client picks, inputs arrive ahead of their tick, so this delay is hidden ' +
        "from play unless a player is late. Processing latency: p99 of one input message's " +
        "handling, plus p99 of the time from the start of update() to a room's confirmed send " +
        '(rooms earlier in the same update go first); their sum bounds the p99 server processing ' +
        'time. Real-socket run: skipped (time box).',
    );
  },
});
