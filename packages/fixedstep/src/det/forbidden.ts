/**
 * The one list of ambient functions that make a simulation non-deterministic: clocks, unseeded
 * randomness, and the `Math` functions whose last bit differs between JavaScript engines.
 *
 * Two things read it and nothing else defines it: the runtime determinism guard (det/guard.ts)
 * traps every entry while a step runs, and the ESLint rule for simulation code
 * (`eslint.config.js`, `no-restricted-properties`) bans every entry in the source. A test checks
 * that the guard traps each one.
 *
 * Plain data with no imports, so the lint configuration can load it too.
 * @module
 */

/** Why a function is forbidden in simulation code. */
export type ForbiddenKind = 'math' | 'random' | 'clock';

/** One forbidden function: `object.property`, why, and what to use instead. */
export interface ForbiddenFunction {
  /** The global object it lives on: `Math`, `Date`, `performance` or `crypto`. */
  readonly object: 'Math' | 'Date' | 'performance' | 'crypto';
  /** The function's property name, e.g. `sin`. */
  readonly property: string;
  readonly kind: ForbiddenKind;
  /** What to do instead: said by the guard's error and by the lint message. */
  readonly advice: string;
}

const RANDOM = 'use a seeded Random kept in the simulation state';
const CLOCK = 'simulation code never reads a clock; time is tick × step';

function math(property: string, use?: string): ForbiddenFunction {
  return {
    object: 'Math',
    property,
    kind: 'math',
    advice:
      use === undefined
        ? `engines differ in the last bit of Math.${property}; build it from + - * /, Math.sqrt and the fixedstep det helpers`
        : `engines differ in the last bit of Math.${property}; use ${use} from fixedstep`,
  };
}

/** Every forbidden function. `Math.sqrt` and the exact `Math` functions (floor, abs, min …) are allowed: IEEE 754 fixes their results. */
export const FORBIDDEN_FUNCTIONS: readonly ForbiddenFunction[] = Object.freeze([
  { object: 'Math', property: 'random', kind: 'random', advice: RANDOM },
  math('sin', 'dsin'),
  math('cos', 'dcos'),
  math('tan', 'dtan'),
  math('asin', 'dasin'),
  math('acos', 'dacos'),
  math('atan', 'datan'),
  math('atan2', 'datan2'),
  math('exp', 'dexp'),
  math('expm1'),
  math('log', 'dlog'),
  math('log1p'),
  math('log2'),
  math('log10'),
  math('pow', 'dexp and dlog, or repeated multiplication'),
  math('hypot', 'dhypot'),
  math('sinh'),
  math('cosh'),
  math('tanh'),
  math('asinh'),
  math('acosh'),
  math('atanh'),
  math('cbrt'),
  { object: 'Date', property: 'now', kind: 'clock', advice: CLOCK },
  { object: 'performance', property: 'now', kind: 'clock', advice: CLOCK },
  { object: 'crypto', property: 'getRandomValues', kind: 'random', advice: RANDOM },
  { object: 'crypto', property: 'randomUUID', kind: 'random', advice: RANDOM },
]);
