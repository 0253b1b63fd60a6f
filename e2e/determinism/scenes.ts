/**
 * What the determinism suite traces: the library's trace catalogue (every scene and game of
 * `@fixedstep/games`), the Rapier scenes (`./rapier.ts`), plus probes of the engines themselves. The browser page and Node import
 * this same module, so every engine runs the very same code.
 */
import type { Random } from 'fixedstep';
import {
  angleInput,
  binaryProbe,
  functionProbeScene,
  randomDouble,
  traceCatalogue,
  unaryProbe,
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

/**
 * The engines' own `Math` functions — the ones a simulation must NOT use. Informational: they are
 * expected to differ between engines (the report counts on how many inputs).
 */
export const ENGINE_MATH_PROBES: readonly FunctionProbe[] = [
  unaryProbe('Math.sin', Math.sin, angleInput),
  unaryProbe('Math.cos', Math.cos, angleInput),
  unaryProbe('Math.tan', Math.tan, angleInput),
  unaryProbe('Math.asin', Math.asin, unit),
  unaryProbe('Math.acos', Math.acos, unit),
  unaryProbe('Math.atan', Math.atan, moderate),
  binaryProbe('Math.atan2', Math.atan2, moderate, moderate),
  unaryProbe('Math.exp', Math.exp, moderate),
  unaryProbe('Math.expm1', Math.expm1, moderate),
  unaryProbe('Math.log', Math.log, positive),
  unaryProbe('Math.log1p', Math.log1p, positive),
  unaryProbe('Math.log2', Math.log2, positive),
  unaryProbe('Math.log10', Math.log10, positive),
  binaryProbe('Math.pow', Math.pow, positive, moderate),
  binaryProbe('x ** y', (x, y) => x ** y, positive, moderate),
  binaryProbe('Math.hypot', Math.hypot, moderate, moderate),
  unaryProbe('Math.sinh', Math.sinh, moderate),
  unaryProbe('Math.cosh', Math.cosh, moderate),
  unaryProbe('Math.tanh', Math.tanh, moderate),
  unaryProbe('Math.asinh', Math.asinh, moderate),
  unaryProbe('Math.acosh', Math.acosh, (rng, k) => 1 + positive(rng, k)),
  unaryProbe('Math.atanh', Math.atanh, unit),
  unaryProbe('Math.cbrt', Math.cbrt, moderate),
  unaryProbe('Math.sqrt', Math.sqrt, positive),
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
