/**
 * The three models measured over real transports by the benchmark (`npm run bench --
 * network-models` writes `data/measured-models.json`, format `fixedstep-measured-models/1`): the
 * loss harness's WebRTC and kernel-TCP links, which a browser page cannot make for itself. Checked
 * field by field before the chapter shows it; a file of another format or with a missing or
 * non-finite number is refused with an Error naming the field.
 */
import recorded from './data/measured-models.json' with { type: 'json' };

export const MEASURED_MODELS_FORMAT = 'fixedstep-measured-models/1';
/** The command that writes `data/measured-models.json`. */
export const MEASURED_MODELS_COMMAND = 'npm run bench -- network-models';

const MODELS = ['statesync', 'lockstep', 'rollback'] as const;

/** One model over one real transport: what player 2 (the impaired player) measured. */
export interface MeasuredRow {
  model: (typeof MODELS)[number];
  upBytesPerSecond: number;
  downBytesPerSecond: number;
  wireUpBytesPerSecond: number;
  wireDownBytesPerSecond: number;
  ownLatencyMs: number;
  otherLatencyMs: number;
  corrections: number;
  largestCorrection: number;
  renderDelayMs: number;
}

export interface MeasuredModels {
  date: string;
  seconds: number;
  results: {
    transport: string;
    link: { latencyMs: number; jitterMs: number; loss: number };
    rows: MeasuredRow[];
  }[];
}

type Obj = Record<string, unknown>;

function obj(v: unknown, where: string): Obj {
  if (typeof v !== 'object' || v === null || Array.isArray(v)) {
    throw new Error(`measured models: ${where} should be an object, got ${JSON.stringify(v)}`);
  }
  return v as Obj;
}

function num(o: Obj, key: string, where: string): number {
  const v = o[key];
  if (typeof v !== 'number' || !Number.isFinite(v)) {
    throw new Error(`measured models: ${where}.${key} should be a finite number, got ${String(v)}`);
  }
  return v;
}

function list(o: Obj, key: string, where: string): unknown[] {
  const v = o[key];
  if (!Array.isArray(v)) throw new Error(`measured models: ${where}.${key} should be a list`);
  return v;
}

/** Checks a report; throws an Error naming the first field that is wrong. */
export function parseMeasuredModels(raw: unknown): MeasuredModels {
  const o = obj(raw, 'the file');
  if (o.format !== MEASURED_MODELS_FORMAT) {
    throw new Error(
      `measured models: format should be ${MEASURED_MODELS_FORMAT}, got ${JSON.stringify(o.format)}`,
    );
  }
  if (typeof o.date !== 'string') throw new Error('measured models: date should be a string');
  return {
    date: o.date,
    seconds: num(o, 'seconds', 'the file'),
    results: list(o, 'results', 'the file').map((r, i) => {
      const where = `results[${i}]`;
      const res = obj(r, where);
      if (typeof res.transport !== 'string') {
        throw new Error(`measured models: ${where}.transport should be a string`);
      }
      const link = obj(res.link, `${where}.link`);
      return {
        transport: res.transport,
        link: {
          latencyMs: num(link, 'latencyMs', `${where}.link`),
          jitterMs: num(link, 'jitterMs', `${where}.link`),
          loss: num(link, 'loss', `${where}.link`),
        },
        rows: list(res, 'rows', where).map((x, j) => {
          const w = `${where}.rows[${j}]`;
          const row = obj(x, w);
          const model = MODELS.find((m) => m === row.model);
          if (model === undefined) {
            throw new Error(
              `measured models: ${w}.model should be a model, got ${String(row.model)}`,
            );
          }
          return {
            model,
            upBytesPerSecond: num(row, 'upBytesPerSecond', w),
            downBytesPerSecond: num(row, 'downBytesPerSecond', w),
            wireUpBytesPerSecond: num(row, 'wireUpBytesPerSecond', w),
            wireDownBytesPerSecond: num(row, 'wireDownBytesPerSecond', w),
            ownLatencyMs: num(row, 'ownLatencyMs', w),
            otherLatencyMs: num(row, 'otherLatencyMs', w),
            corrections: num(row, 'corrections', w),
            largestCorrection: num(row, 'largestCorrection', w),
            renderDelayMs: num(row, 'renderDelayMs', w),
          };
        }),
      };
    }),
  };
}

/** The committed report, checked. */
export function measuredModels(): MeasuredModels {
  return parseMeasuredModels(recorded);
}
