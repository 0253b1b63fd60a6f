/**
 * The loss harness's recorded report (`data/loss-harness.json`, format `fixedstep-netem/1`, written
 * by `e2e/netem/report.ts`), checked field by field before the lab charts it: a file of another
 * format or with a missing or non-finite number is refused with an Error naming the field.
 */
import recorded from './data/loss-harness.json' with { type: 'json' };

/** The format string this loader reads. */
export const LOSS_HARNESS_FORMAT = 'fixedstep-netem/1';

/** The command that produced `data/loss-harness.json` (its `browser.json`). */
export const LOSS_HARNESS_COMMAND =
  'npx vitest run --config e2e/vitest.config.ts e2e/netem.e2e.test.ts';

/** One transport's numbers over the whole match (both players). */
export interface TransportRow {
  transport: string;
  ticks: number;
  hashesEqual: boolean;
  desyncs: number;
  /** Input → the other player's screen, ms: median and 99th percentile. */
  latencyP50: number;
  latencyP99: number;
  /** How many inputs the latency percentiles were taken over. */
  latencySamples: number;
  /** Times a player's simulation waited for input, and display frames spent waiting. */
  stalls: number;
  stallFrames: number;
  rollbacks: number;
  /** Deepest rollback, ticks. */
  maxDepth: number;
  /** Rollback depth (ticks) → how many rollbacks went that deep, both players. */
  depths: Map<number, number>;
  /** Protocol bytes per second each player sent (up) and received (down). */
  bytesPerSecond: { slot: number; up: number; down: number }[];
  /** Bytes per second on the impaired link, per direction, if the proxy counted them. */
  wireBytesPerSecond: { up: number; down: number } | undefined;
  /** Fraction of packets or segments the link dropped. */
  lossSeen: number;
}

/** A loss-harness report: the link it ran over and one row per transport. */
export interface LossHarness {
  format: typeof LOSS_HARNESS_FORMAT;
  date: string;
  where: string;
  game: string;
  ticks: number;
  tickRate: number;
  players: number;
  /** One way, ms; loss as a fraction, each way. */
  link: { latencyMs: number; jitterMs: number; loss: number };
  rows: TransportRow[];
}

type Obj = Record<string, unknown>;

function obj(v: unknown, where: string): Obj {
  if (typeof v !== 'object' || v === null || Array.isArray(v)) {
    throw new Error(`loss harness: ${where} should be an object, got ${JSON.stringify(v)}`);
  }
  return v as Obj;
}

function num(o: Obj, key: string, where: string): number {
  const v = o[key];
  if (typeof v !== 'number' || !Number.isFinite(v) || v < 0) {
    throw new Error(
      `loss harness: ${where}.${key} should be a finite number ≥ 0, got ${JSON.stringify(v)}`,
    );
  }
  return v;
}

function str(o: Obj, key: string, where: string): string {
  const v = o[key];
  if (typeof v !== 'string') {
    throw new Error(`loss harness: ${where}.${key} should be a string, got ${JSON.stringify(v)}`);
  }
  return v;
}

function arr(v: unknown, where: string): unknown[] {
  if (!Array.isArray(v)) {
    throw new Error(`loss harness: ${where} should be an array, got ${JSON.stringify(v)}`);
  }
  return v;
}

function row(v: unknown, where: string): TransportRow {
  const o = obj(v, where);
  const depths = new Map<number, number>();
  for (const [k, n] of Object.entries(obj(o.depths, `${where}.depths`))) {
    const depth = Number(k);
    if (!Number.isInteger(depth) || depth < 1) {
      throw new Error(`loss harness: ${where}.depths has a bad depth ${JSON.stringify(k)}`);
    }
    depths.set(depth, num({ n }, 'n', `${where}.depths[${k}]`));
  }
  const wire = o.wireBytesPerSecond;
  const w = wire === undefined ? undefined : obj(wire, `${where}.wireBytesPerSecond`);
  if (typeof o.hashesEqual !== 'boolean') {
    throw new Error(`loss harness: ${where}.hashesEqual should be a boolean`);
  }
  return {
    transport: str(o, 'transport', where),
    ticks: num(o, 'ticks', where),
    hashesEqual: o.hashesEqual,
    desyncs: num(o, 'desyncs', where),
    latencyP50: num(o, 'latencyP50', where),
    latencyP99: num(o, 'latencyP99', where),
    latencySamples: num(o, 'latencySamples', where),
    stalls: num(o, 'stalls', where),
    stallFrames: num(o, 'stallFrames', where),
    rollbacks: num(o, 'rollbacks', where),
    maxDepth: num(o, 'maxDepth', where),
    depths,
    bytesPerSecond: arr(o.bytesPerSecond, `${where}.bytesPerSecond`).map((b, i) => {
      const bo = obj(b, `${where}.bytesPerSecond[${i}]`);
      const at = `${where}.bytesPerSecond[${i}]`;
      return { slot: num(bo, 'slot', at), up: num(bo, 'up', at), down: num(bo, 'down', at) };
    }),
    wireBytesPerSecond: w && {
      up: num(w, 'up', `${where}.wireBytesPerSecond`),
      down: num(w, 'down', `${where}.wireBytesPerSecond`),
    },
    lossSeen: num(o, 'lossSeen', where),
  };
}

/**
 * Checks a parsed report and returns it typed.
 *
 * @throws Error naming the field when `raw` is not a `fixedstep-netem/1` report.
 */
export function parseLossHarness(raw: unknown): LossHarness {
  const o = obj(raw, 'report');
  if (o.format !== LOSS_HARNESS_FORMAT) {
    throw new Error(
      `loss harness: format ${JSON.stringify(o.format)} is not ${LOSS_HARNESS_FORMAT}; ` +
        'this lab reads only that format',
    );
  }
  const link = obj(o.link, 'report.link');
  const rows = arr(o.rows, 'report.rows').map((r, i) => row(r, `report.rows[${i}]`));
  if (rows.length === 0) throw new Error('loss harness: report.rows is empty');
  return {
    format: LOSS_HARNESS_FORMAT,
    date: str(o, 'date', 'report'),
    where: str(o, 'where', 'report'),
    game: str(o, 'game', 'report'),
    ticks: num(o, 'ticks', 'report'),
    tickRate: num(o, 'tickRate', 'report'),
    players: num(o, 'players', 'report'),
    link: {
      latencyMs: num(link, 'latencyMs', 'report.link'),
      jitterMs: num(link, 'jitterMs', 'report.link'),
      loss: num(link, 'loss', 'report.link'),
    },
    rows,
  };
}

/** The committed report, checked once when first asked for. */
let cached: LossHarness | undefined;
export function lossHarness(): LossHarness {
  cached ??= parseLossHarness(recorded);
  return cached;
}
