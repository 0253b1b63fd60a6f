/**
 * What the loss harness measures on each player's machine — the same code in Node and in the
 * browser page. Times are wall-clock milliseconds (`performance.timeOrigin + performance.now()`),
 * comparable between the two pages of one browser and the peers of one Node process.
 *
 * - **Input-to-screen latency**: for every tick on which a player's input *changed* (a press or a
 *   release — what someone can see), the time from that player's machine sampling it to the first
 *   frame on the other machine whose displayed state was simulated with it, confirmed (a rollback
 *   session may show a correct guess earlier; a new press is never guessed).
 * - **Rollback depth**: a histogram of `onCorrection` depths.
 * - **Stalls**: the session's own count (runs of frames that wanted to step and could not).
 */
import type { Correction, NetSession, Simulation } from 'fixedstep';

/** `PROBE_DEBUG=1` (Node only) logs each stall as it begins. */
const PROBE_DEBUG =
  (globalThis as { process?: { env: Record<string, string | undefined> } }).process?.env
    .PROBE_DEBUG !== undefined;

export function wallNow(): number {
  return performance.timeOrigin + performance.now();
}

/** One player's measurements, as sent back from a page (plain JSON). */
export interface ProbeReport {
  slot: number;
  /** Ticks whose own input changed, and when it was sampled. */
  changes: [tick: number, time: number][];
  /** For each tick t: when this machine first displayed a confirmed state past t (0: never). */
  shownAt: number[];
  /** Rollback depth → count. */
  depths: Record<number, number>;
  stalls: number;
  /** The tick at which each stall began (the first 1000). */
  stallTicks: number[];
  stallFrames: number;
  frames: number;
  rollbacks: number;
  bytesSent: number;
  bytesReceived: number;
  messagesSent: number;
  messagesReceived: number;
  finalHash: string;
  /** Wall time from the first to the last tick of the match, ms. */
  matchMs: number;
  desyncs: number;
}

/** Records one session: wrap its `localInput`, pass `onCorrection`, call `afterFrame` each frame. */
export class Probe {
  private readonly changes: [number, number][] = [];
  private readonly shownAt: number[];
  private readonly depths: Record<number, number> = {};
  private last = '';
  private shownUpTo = 0;
  private startedAt = 0;
  private endedAt = 0;
  private lastStalls = 0;
  readonly lags: number[] = [];
  /** The tick at which each stall began. */
  private readonly stallTicks: number[] = [];

  constructor(
    readonly slot: number,
    private readonly ticks: number,
  ) {
    this.shownAt = new Array<number>(ticks).fill(0);
  }

  /** Wraps a local input function: notes the ticks whose input differs from the one before. */
  input<I>(
    inner: (tick: number, sim: Simulation<I>) => I,
  ): (tick: number, sim: Simulation<I>) => I {
    return (tick, sim) => {
      const v = inner(tick, sim);
      const key = JSON.stringify(v);
      if (key !== this.last) {
        this.last = key;
        this.changes.push([tick, wallNow()]);
      }
      return v;
    };
  }

  readonly onCorrection = (c: Correction): void => {
    this.depths[c.depth] = (this.depths[c.depth] ?? 0) + 1;
  };

  /** After each `session.frame()`. */
  afterFrame(session: NetSession<unknown>): void {
    const now = wallNow();
    const shown = Math.min(session.tick, session.confirmedTick, this.ticks);
    if (this.startedAt === 0 && session.tick > 0) this.startedAt = now;
    if (session.tick > 60 && !session.isFinished)
      this.lags.push(session.serverTick() - session.confirmedTick);
    if (session.stats.stalls > this.lastStalls) {
      this.lastStalls = session.stats.stalls;
      if (this.stallTicks.length < 1000) this.stallTicks.push(session.tick);
      if (PROBE_DEBUG)
        console.log(
          `stall slot ${this.slot} tick ${session.tick} confirmed ${session.confirmedTick} server ${session.serverTick().toFixed(1)} lead ${session.stats.lead} rtt ${session.stats.rtt.toFixed(0)} rttHigh ${session.stats.rttHigh.toFixed(0)}`,
        );
    }
    while (this.shownUpTo < shown) this.shownAt[this.shownUpTo++] = now;
    if (this.endedAt === 0 && session.isFinished) this.endedAt = now;
  }

  report(session: NetSession<unknown>): ProbeReport {
    const s = session.stats;
    const hash = session.hashAt(this.ticks);
    return {
      slot: this.slot,
      changes: this.changes,
      shownAt: this.shownAt,
      depths: this.depths,
      stalls: s.stalls,
      stallTicks: this.stallTicks,
      stallFrames: s.stallFrames,
      frames: s.frames,
      rollbacks: s.rollbacks,
      bytesSent: s.bytesSent,
      bytesReceived: s.bytesReceived,
      messagesSent: s.messagesSent,
      messagesReceived: s.messagesReceived,
      finalHash: hash === undefined ? '' : hash.toString(16).padStart(16, '0'),
      matchMs: this.endedAt > 0 ? this.endedAt - this.startedAt : 0,
      desyncs: session.desyncs.length,
    };
  }
}

/** Nearest-rank percentile of a non-empty list. */
export function percentile(values: readonly number[], p: number): number {
  if (values.length === 0) return NaN;
  const sorted = [...values].sort((a, b) => a - b);
  const rank = Math.ceil((p / 100) * sorted.length);
  return sorted[Math.min(sorted.length, Math.max(1, rank)) - 1]!;
}

/** Input-to-screen latencies (ms) of `from`'s input changes on `to`'s screen. */
export function latencies(from: ProbeReport, to: ProbeReport): number[] {
  const out: number[] = [];
  for (const [tick, time] of from.changes) {
    const shown = to.shownAt[tick];
    if (shown !== undefined && shown > 0) out.push(Math.max(0, shown - time));
  }
  return out;
}

/**
 * What an impairing proxy counted on the wire of one link, each way (up: from the joiner): bytes,
 * packets or segments, and how many of them it dropped.
 */
export interface WireCounts {
  up: number;
  down: number;
  lostUp: number;
  lostDown: number;
  packetsUp: number;
  packetsDown: number;
}

/** One transport's row of the comparison. */
export interface TransportSummary {
  transport: string;
  where: string;
  ticks: number;
  hashesEqual: boolean;
  finalHash: string;
  desyncs: number;
  latencyP50: number;
  latencyP99: number;
  latencySamples: number;
  /** The same per direction: player `from`'s input changes on player `to`'s screen. */
  latencyByDirection?: { from: number; to: number; p50: number; p99: number; n: number }[];
  stalls: number;
  stallFrames: number;
  rollbacks: number;
  maxDepth: number;
  /** Rollback depth → count, both players. */
  depths: Record<number, number>;
  /** Protocol bytes per second each player sent / received (the session's counters). */
  bytesPerSecond: { slot: number; up: number; down: number }[];
  /** Bytes per second on the wire of the impaired link, per direction (proxy counters; UDP payloads incl. TURN/DTLS/SCTP headers, or TCP payload incl. WebSocket framing). */
  wireBytesPerSecond: { up: number; down: number } | undefined;
  /** Datagrams (UDP) or segments (TCP model) per second on the impaired link, per direction. */
  wirePacketsPerSecond?: { up: number; down: number };
  lossSeen: number;
}

export function summarize(
  transport: string,
  where: string,
  ticks: number,
  reports: readonly ProbeReport[],
  wire?: WireCounts,
): TransportSummary {
  const lat: number[] = [];
  const byDirection: NonNullable<TransportSummary['latencyByDirection']> = [];
  for (const a of reports) {
    for (const b of reports) {
      if (a === b) continue;
      const l = latencies(a, b);
      lat.push(...l);
      byDirection.push({
        from: a.slot,
        to: b.slot,
        p50: percentile(l, 50),
        p99: percentile(l, 99),
        n: l.length,
      });
    }
  }
  const depths: Record<number, number> = {};
  let maxDepth = 0;
  for (const r of reports) {
    for (const [d, n] of Object.entries(r.depths)) {
      depths[Number(d)] = (depths[Number(d)] ?? 0) + n;
      maxDepth = Math.max(maxDepth, Number(d));
    }
  }
  const seconds = Math.max(...reports.map((r) => r.matchMs)) / 1000;
  const hashes = reports.map((r) => r.finalHash);
  return {
    transport,
    where,
    ticks,
    hashesEqual: hashes.every((h) => h !== '' && h === hashes[0]),
    finalHash: hashes[0] ?? '',
    desyncs: reports.reduce((n, r) => n + r.desyncs, 0),
    latencyP50: percentile(lat, 50),
    latencyP99: percentile(lat, 99),
    latencySamples: lat.length,
    latencyByDirection: byDirection,
    stalls: reports.reduce((n, r) => n + r.stalls, 0),
    stallFrames: reports.reduce((n, r) => n + r.stallFrames, 0),
    rollbacks: reports.reduce((n, r) => n + r.rollbacks, 0),
    maxDepth,
    depths,
    bytesPerSecond: reports.map((r) => ({
      slot: r.slot,
      up: seconds > 0 ? r.bytesSent / seconds : 0,
      down: seconds > 0 ? r.bytesReceived / seconds : 0,
    })),
    wireBytesPerSecond:
      wire && seconds > 0 ? { up: wire.up / seconds, down: wire.down / seconds } : undefined,
    ...(wire && seconds > 0
      ? {
          wirePacketsPerSecond: {
            up: wire.packetsUp / seconds,
            down: wire.packetsDown / seconds,
          },
        }
      : {}),
    lossSeen:
      wire && wire.packetsUp + wire.packetsDown > 0
        ? (wire.lostUp + wire.lostDown) / (wire.packetsUp + wire.packetsDown)
        : 0,
  };
}

/** Rollback depth buckets for the table: 0 (none), 1–2, 3–5, 6–10, 11–20, 21+. */
export function depthBuckets(depths: Record<number, number>): string {
  const buckets: [string, number, number][] = [
    ['1–2', 1, 2],
    ['3–5', 3, 5],
    ['6–10', 6, 10],
    ['11–20', 11, 20],
    ['21+', 21, Infinity],
  ];
  return buckets
    .map(([label, lo, hi]) => {
      let n = 0;
      for (const [d, c] of Object.entries(depths)) if (Number(d) >= lo && Number(d) <= hi) n += c;
      return `${label}: ${n}`;
    })
    .join(', ');
}

/** The comparison as a markdown table. */
export function comparisonTable(rows: readonly TransportSummary[]): string {
  const fmt = (v: number, d = 0) => (Number.isFinite(v) ? v.toFixed(d) : '–');
  const lines = [
    '| | ' + rows.map((r) => `${r.transport} (${r.where})`).join(' | ') + ' |',
    '|---|' + rows.map(() => '---').join('|') + '|',
  ];
  const row = (label: string, f: (r: TransportSummary) => string) =>
    lines.push(`| ${label} | ${rows.map(f).join(' | ')} |`);
  row(
    'ticks, final hashes',
    (r) => `${r.ticks}, ${r.hashesEqual ? 'equal' : 'DIFFERENT'} (${r.finalHash})`,
  );
  row(
    'input-to-screen p50 / p99 (ms)',
    (r) => `${fmt(r.latencyP50)} / ${fmt(r.latencyP99)} (n = ${r.latencySamples})`,
  );
  row('… per direction, P→P: p50 / p99', (r) =>
    (r.latencyByDirection ?? [])
      .map((d) => `P${d.from + 1}→P${d.to + 1} ${fmt(d.p50)} / ${fmt(d.p99)}`)
      .join('; '),
  );
  row('stalls (stalled frames)', (r) => `${r.stalls} (${r.stallFrames})`);
  row('rollbacks, deepest', (r) => `${r.rollbacks}, ${r.maxDepth}`);
  row('rollback depths', (r) => depthBuckets(r.depths));
  row('protocol B/s per player, up / down', (r) =>
    r.bytesPerSecond.map((b) => `P${b.slot + 1} ${fmt(b.up)} / ${fmt(b.down)}`).join('; '),
  );
  row('wire B/s of the impaired link, up / down', (r) =>
    r.wireBytesPerSecond
      ? `${fmt(r.wireBytesPerSecond.up)} / ${fmt(r.wireBytesPerSecond.down)}`
      : '–',
  );
  row('wire packets/s of the impaired link, up / down', (r) =>
    r.wirePacketsPerSecond
      ? `${fmt(r.wirePacketsPerSecond.up)} / ${fmt(r.wirePacketsPerSecond.down)}`
      : '–',
  );
  row('packets lost (UDP) or retransmitted (TCP model)', (r) => `${fmt(r.lossSeen * 100, 1)} %`);
  row('desyncs', (r) => String(r.desyncs));
  return lines.join('\n');
}
