/**
 * What the determinism suite traces: the library's trace catalogue (every scene and game of
 * `@fixedstep/games`), the Rapier scenes (`./rapier.ts`), plus probes of the engines themselves. The browser page and Node import
 * this same module, so every engine runs the very same code.
 */
import type { Random } from 'fixedstep';
import {
  angleInput,
  functionProbeScene,
  randomDouble,
  traceCatalogue,
  type FunctionProbe,
  type TraceScene,
} from '@fixedstep/games';
import { rapierScenes } from './rapier.js';

/** Samples per engine-Math probe: one per tick, so a differing tick is a differing input. */
const MATH_PROBE_TICKS = 1024;

function positive(rng: Random, k: number): number {
  return k % 2 === 0 ? rng.range(0, 50) : Math.abs(randomDouble(rng, -60, 60));
}
function unit(rng: Random, k: number): number {
  return k % 3 === 0 ? rng.range(-1, 1) : rng.range(-0.999, 0.999) * (k % 2 === 0 ? 1 : 0.5);
}
function moderate(rng: Random, k: number): number {
  return k % 2 === 0 ? rng.range(-20, 20) : randomDouble(rng, -30, 9);
}

const unary = (
  name: string,
  f: (x: number) => number,
  input: (rng: Random, k: number) => number,
): FunctionProbe => ({
  name,
  arity: 1,
  inputs: (rng, k) => [input(rng, k)],
  apply: (args, out) => {
    out[0] = f(args[0]!);
  },
});
const binary = (
  name: string,
  f: (a: number, b: number) => number,
  a: (rng: Random, k: number) => number,
  b: (rng: Random, k: number) => number,
): FunctionProbe => ({
  name,
  arity: 2,
  inputs: (rng, k) => [a(rng, k), b(rng, k)],
  apply: (args, out) => {
    out[0] = f(args[0]!, args[1]!);
  },
});

/**
 * The engines' own `Math` functions — the ones a simulation must NOT use. Informational: they are
 * expected to differ between engines (the report counts on how many inputs).
 */
export const ENGINE_MATH_PROBES: readonly FunctionProbe[] = [
  unary('Math.sin', Math.sin, angleInput),
  unary('Math.cos', Math.cos, angleInput),
  unary('Math.tan', Math.tan, angleInput),
  unary('Math.asin', Math.asin, unit),
  unary('Math.acos', Math.acos, unit),
  unary('Math.atan', Math.atan, moderate),
  binary('Math.atan2', Math.atan2, moderate, moderate),
  unary('Math.exp', Math.exp, moderate),
  unary('Math.expm1', Math.expm1, moderate),
  unary('Math.log', Math.log, positive),
  unary('Math.log1p', Math.log1p, positive),
  unary('Math.log2', Math.log2, positive),
  unary('Math.log10', Math.log10, positive),
  binary('Math.pow', Math.pow, positive, moderate),
  binary('x ** y', (x, y) => x ** y, positive, moderate),
  binary('Math.hypot', Math.hypot, moderate, moderate),
  unary('Math.sinh', Math.sinh, moderate),
  unary('Math.cosh', Math.cosh, moderate),
  unary('Math.tanh', Math.tanh, moderate),
  unary('Math.asinh', Math.asinh, moderate),
  unary('Math.acosh', Math.acosh, (rng, k) => 1 + positive(rng, k)),
  unary('Math.atanh', Math.atanh, unit),
  unary('Math.cbrt', Math.cbrt, moderate),
  unary('Math.sqrt', Math.sqrt, positive),
];

function engineMathScenes(): TraceScene[] {
  return ENGINE_MATH_PROBES.map((p) =>
    functionProbeScene({
      id: `engine/${p.name.replace(/ /g, '')}`,
      title: `the engine’s own ${p.name} (a simulation must not use it)`,
      ticks: MATH_PROBE_TICKS,
      samplesPerTick: 1,
      seed: 31,
      probes: [p],
      informational: true,
    }),
  );
}

/**
 * `2 ** k` for every integer k that gives a normal or subnormal double: the replay codec reads
 * varints with `(b & 0x7f) * 2 ** shift`, so integer powers of two must be exact in every engine.
 * Required to match.
 */
function integerPowerScene(): TraceScene {
  return functionProbeScene({
    id: 'engine/integer-powers',
    title: '2 ** k for k = −1074 … 1023 (the replay codec relies on it)',
    ticks: 2098,
    samplesPerTick: 1,
    seed: 1,
    probes: [
      {
        name: '2 ** k',
        arity: 1,
        inputs: (_, k) => [k - 1074],
        apply: (args, out) => {
          out[0] = 2 ** args[0]!;
        },
      },
    ],
  });
}

/**
 * Every scene the suite traces, in a fixed order: the catalogue of `@fixedstep/games`, the Rapier
 * scenes of `@fixedstep/rapier` (async: Rapier's WebAssembly is loaded first), the engine probes.
 */
export async function determinismScenes(): Promise<TraceScene[]> {
  return [
    ...traceCatalogue(),
    ...(await rapierScenes()),
    integerPowerScene(),
    ...engineMathScenes(),
  ];
}
