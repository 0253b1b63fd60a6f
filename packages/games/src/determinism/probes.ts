/**
 * Function probes: a math function over fixed, seeded inputs (special doubles, random exponents,
 * angles near the branch points), its results' bits traced per tick — the deterministic helpers'
 * scene, and the engine's own Math functions that the determinism suite compares across engines.
 */
import {
  ByteWriter,
  Random,
  dacos,
  dasin,
  datan,
  datan2,
  dcos,
  dexp,
  dhypot,
  dlog,
  dsin,
  dsincos,
  dtan,
  wrapAngle,
} from 'fixedstep';
import { StateLayout } from './state-fields.js';
import type { TraceRun, TraceScene } from './trace.js';

// ----------------------------------------------------------------------------- function probes

/** One function probed over generated inputs. */
export interface FunctionProbe {
  /** How the report names it, e.g. `dsin`. */
  readonly name: string;
  /** Number of arguments. */
  readonly arity: number;
  /** Number of results written by {@link FunctionProbe.apply} (1, or 2 for sincos). */
  readonly results?: number;
  /** Arguments of sample `k` (k counts up from 0 over the whole run). */
  inputs(rng: Random, k: number): readonly number[];
  /** Computes the results of `args` into `out[0 … results − 1]`. */
  apply(args: readonly number[], out: Float64Array): void;
}

/** Options of {@link functionProbeScene}. */
export interface FunctionProbeSceneOptions {
  id: string;
  title: string;
  ticks: number;
  /** Samples of each function per tick. */
  samplesPerTick: number;
  seed: number;
  probes: readonly FunctionProbe[];
  informational?: boolean;
}

/**
 * A "scene" whose state at tick t is the inputs and results of every probe's samples of that
 * tick (canonical f64 bytes): its trace is a hash of every result's bits, never a sum that could
 * hide a difference. The field map names each result, e.g. `dsin(x#1234)`.
 */
export function functionProbeScene(o: FunctionProbeSceneOptions): TraceScene {
  const layout = new StateLayout();
  for (let s = 0; s < o.samplesPerTick; s++) {
    for (const p of o.probes) {
      const args = p.arity === 1 ? ['x'] : p.arity === 2 ? ['y', 'x'] : ['a', 'b', 'c', 'd'];
      for (let i = 0; i < p.arity; i++)
        layout.add('f64', `${p.name}(sample ${s}) argument ${args[i] ?? String(i)}`);
      const results = p.results ?? 1;
      for (let r = 0; r < results; r++) {
        layout.add('f64', `${p.name}(sample ${s})${results > 1 ? `[${r}]` : ''}`);
      }
    }
  }
  const base: TraceScene = {
    id: o.id,
    title: o.title,
    ticks: o.ticks,
    start(): TraceRun {
      const rng = new Random(o.seed);
      const w = new ByteWriter(layout.length);
      const out = new Float64Array(4);
      const counters = o.probes.map(() => 0);
      return {
        next(): Uint8Array {
          w.reset();
          for (let s = 0; s < o.samplesPerTick; s++) {
            for (let i = 0; i < o.probes.length; i++) {
              const p = o.probes[i]!;
              const args = p.inputs(rng, counters[i]!++);
              for (const a of args) w.f64(a);
              out.fill(0);
              p.apply(args, out);
              for (let r = 0; r < (p.results ?? 1); r++) w.f64(out[r]!);
            }
          }
          return w.peek();
        },
      };
    },
    fields: (state) => layout.covering(state.length),
  };
  return o.informational ? { ...base, informational: true } : base;
}

const words = new DataView(new ArrayBuffer(8));

/** A double from its two 32-bit halves, exactly. */
function fromWords(hi: number, lo: number): number {
  words.setUint32(0, hi >>> 0);
  words.setUint32(4, lo >>> 0);
  return words.getFloat64(0);
}

/** A random double of either sign with a binary exponent uniform in [minExp, maxExp] (≥ −1022). */
export function randomDouble(rng: Random, minExp: number, maxExp: number): number {
  const e = minExp + rng.int(maxExp - minExp + 1);
  const sign = rng.nextU32() & 0x80000000;
  const hi = sign | ((e + 1023) << 20) | (rng.nextU32() & 0xfffff);
  return fromWords(hi, rng.nextU32());
}

/** Inputs every function must survive: signed zeros, infinities, NaN, subnormals, extremes. */
export const SPECIAL_DOUBLES: readonly number[] = Object.freeze([
  0,
  -0,
  Infinity,
  -Infinity,
  NaN,
  Number.MIN_VALUE,
  -Number.MIN_VALUE,
  2.2250738585072014e-308,
  Number.MAX_VALUE,
  -Number.MAX_VALUE,
  1,
  -1,
  0.5,
  Math.PI,
  -Math.PI,
  Math.PI / 2,
  Math.PI / 4,
  1.6e6,
  -1.6e6,
  1e22,
  709.78,
  -745.13,
  1e-300,
]);

/** A mix of everyday, medium, huge, tiny, near-π/2-multiple and special arguments for sample k. */
export function angleInput(rng: Random, k: number): number {
  switch (k % 8) {
    case 0:
    case 1:
    case 2:
      return rng.range(-4, 4);
    case 3:
      return rng.range(-200, 200);
    case 4:
      return randomDouble(rng, -40, 20);
    case 5:
      return randomDouble(rng, 20, 1023);
    case 6: {
      const n = rng.int(20001) - 10000;
      return n * 1.5707963267948966 + rng.range(-1e-9, 1e-9);
    }
    default:
      return SPECIAL_DOUBLES[(k >>> 3) % SPECIAL_DOUBLES.length]!;
  }
}

function generalInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(-10, 10);
    case 1:
      return randomDouble(rng, -1022, 1023);
    case 2:
      return randomDouble(rng, -60, 60);
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

function unitInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
    case 1:
      return rng.range(-1, 1);
    case 2:
      return randomDouble(rng, -60, -1);
    default:
      return k % 8 === 3
        ? rng.range(-1.5, 1.5)
        : SPECIAL_DOUBLES[(k >>> 3) % SPECIAL_DOUBLES.length]!;
  }
}

function expInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(-20, 20);
    case 1:
      return rng.range(-750, 712);
    case 2:
      return randomDouble(rng, -60, -1);
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

function positiveInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(0, 100);
    case 1:
      return Math.abs(randomDouble(rng, -1022, 1023));
    case 2:
      return fromWords(0, rng.nextU32()) + fromWords(rng.int(0x100000), 0); // subnormals
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

/** A probe of a function of one number, its inputs drawn by `input` (sample k of a tick). */
export function unaryProbe(
  name: string,
  f: (x: number) => number,
  input: (rng: Random, k: number) => number,
): FunctionProbe {
  return {
    name,
    arity: 1,
    inputs: (rng, k) => [input(rng, k)],
    apply: (args, out) => {
      out[0] = f(args[0]!);
    },
  };
}

/**
 * A probe of a function of two numbers, drawn by `a` and `b` — by default `a` again, at half the
 * sample index (so the pairs are not all on the diagonal).
 */
export function binaryProbe(
  name: string,
  f: (a: number, b: number) => number,
  a: (rng: Random, k: number) => number,
  b: (rng: Random, k: number) => number = (rng, k) => a(rng, k >>> 1),
): FunctionProbe {
  return {
    name,
    arity: 2,
    inputs: (rng, k) => [a(rng, k), b(rng, k)],
    apply: (args, out) => {
      out[0] = f(args[0]!, args[1]!);
    },
  };
}

/** The deterministic math helpers of `fixedstep` (and the exact `Math.sqrt` they build on). */
export const DET_MATH_PROBES: readonly FunctionProbe[] = Object.freeze([
  unaryProbe('dsin', dsin, angleInput),
  unaryProbe('dcos', dcos, angleInput),
  unaryProbe('dtan', dtan, angleInput),
  {
    name: 'dsincos',
    arity: 1,
    results: 2,
    inputs: (rng, k) => [angleInput(rng, k)],
    apply: (args, out) => {
      dsincos(args[0]!, out, 0);
    },
  },
  unaryProbe('wrapAngle', wrapAngle, angleInput),
  unaryProbe('datan', datan, generalInput),
  binaryProbe('datan2', datan2, generalInput),
  unaryProbe('dasin', dasin, unitInput),
  unaryProbe('dacos', dacos, unitInput),
  unaryProbe('dexp', dexp, expInput),
  unaryProbe('dlog', dlog, positiveInput),
  binaryProbe('dhypot', dhypot, generalInput),
  unaryProbe('Math.sqrt', Math.sqrt, positiveInput),
]);

/** `fixedstep`'s deterministic math over 32 samples of each function per tick. */
export function detMathScene(ticks = 256): TraceScene {
  return functionProbeScene({
    id: 'math/det',
    title: 'deterministic math helpers (dsin … dhypot, Math.sqrt) over fixed inputs',
    ticks,
    samplesPerTick: 32,
    seed: 0x5eed,
    probes: DET_MATH_PROBES,
  });
}
