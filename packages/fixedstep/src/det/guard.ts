/**
 * A development-mode tripwire: while a simulation step runs, the ambient sources of
 * non-determinism — clocks, `Math.random`, `crypto`, and the engine-dependent `Math` functions —
 * are replaced by stubs that throw a {@link DeterminismError} naming the call and the tick.
 *
 * The ESLint rule catches such calls in the simulation's own source; the guard also catches
 * them in dependencies and in code reached through callbacks. It patches globals, so it is for
 * development and tests only: it costs two dozen property writes per guarded call, and any
 * other code that runs synchronously inside the guarded function sees the stubs too.
 *
 * @module
 */
import { FORBIDDEN_FUNCTIONS, type ForbiddenFunction } from './forbidden.js';

/** Thrown by a trapped call made while a determinism guard is active. */
export class DeterminismError extends Error {
  override readonly name = 'DeterminismError';

  constructor(
    /** The call that was trapped, e.g. `"Math.random"`. */
    readonly call: string,
    /** The tick being stepped, if the guard knew it. */
    readonly tick: number | undefined,
    advice: string,
  ) {
    super(
      `${call} called during a simulation step${tick === undefined ? '' : ` (tick ${tick})`}: ${advice}`,
    );
  }
}

interface Trap {
  /** Where the function lives, looked up at install time (`performance`, `crypto` may be missing). */
  readonly owner: () => object | undefined;
  readonly key: string;
  readonly label: string;
  readonly advice: string;
}

const global = globalThis as unknown as Record<string, unknown>;

/** The owner of a forbidden function, looked up at install time (`performance` or `crypto` may be missing). */
function ownerOf(name: ForbiddenFunction['object']): () => object | undefined {
  return () => {
    const value = name === 'Math' ? Math : name === 'Date' ? Date : global[name];
    return (typeof value === 'object' || typeof value === 'function') && value !== null
      ? value
      : undefined;
  };
}

// Names are looked up dynamically: this module replaces these functions, it never calls them.
const TRAPS: readonly Trap[] = FORBIDDEN_FUNCTIONS.map((f) => ({
  owner: ownerOf(f.object),
  key: f.property,
  label: `${f.object}.${f.property}`,
  advice: f.advice,
}));

interface Saved {
  readonly owner: object;
  readonly key: string;
  /** The owner's own descriptor before patching, or undefined if the function was inherited. */
  readonly own: PropertyDescriptor | undefined;
}

interface Frame {
  readonly tick: number | undefined;
  violation: DeterminismError | undefined;
}

/** Active guards, innermost last. Globals are patched while this is non-empty. */
const frames: Frame[] = [];
let saved: Saved[] = [];

/** The tick of the innermost guard that named one. */
function currentTick(): number | undefined {
  for (let i = frames.length - 1; i >= 0; i--) {
    const tick = frames[i]!.tick;
    if (tick !== undefined) return tick;
  }
  return undefined;
}

function install(): void {
  saved = [];
  for (const trap of TRAPS) {
    const owner = trap.owner();
    if (owner === undefined || typeof Reflect.get(owner, trap.key) !== 'function') continue;
    const own = Object.getOwnPropertyDescriptor(owner, trap.key);
    if (own !== undefined && own.configurable !== true) continue; // cannot patch and restore it
    const stub = (): never => {
      const error = new DeterminismError(trap.label, currentTick(), trap.advice);
      for (const frame of frames) frame.violation ??= error;
      throw error;
    };
    Object.defineProperty(owner, trap.key, {
      value: stub,
      writable: true,
      configurable: true,
      enumerable: own?.enumerable ?? false,
    });
    saved.push({ owner, key: trap.key, own });
  }
}

function uninstall(): void {
  // Reverse order, so that a key patched twice would end with its first saved state.
  for (let i = saved.length - 1; i >= 0; i--) {
    const s = saved[i]!;
    if (s.own === undefined) Reflect.deleteProperty(s.owner, s.key);
    else Object.defineProperty(s.owner, s.key, s.own);
  }
  saved = [];
}

/** True while a determinism guard is active (inside {@link withDeterminismGuard}). */
export function isGuardActive(): boolean {
  return frames.length > 0;
}

/**
 * Runs `fn` with the determinism traps installed and returns its result; the original
 * functions are restored when `fn` returns or throws. Guards nest: an inner guard only changes
 * the tick named in messages, and the globals are restored when the outermost one exits.
 * Functions whose property is not configurable (a frozen `Math`, say) are left untrapped.
 *
 * If `fn` catches a {@link DeterminismError} and carries on, the guard throws that first error
 * once `fn` returns (every enclosing guard does too), so a violation cannot be swallowed.
 *
 * `fn` must be synchronous: the guard covers only the code that runs before `fn` returns (a
 * promise it returns is passed through, unguarded). Development and tests only — see the module
 * note.
 *
 * @param tick — the tick being stepped, named in error messages.
 */
export function withDeterminismGuard<T>(fn: () => T, tick?: number): T {
  const frame: Frame = { tick, violation: undefined };
  if (frames.length === 0) install();
  frames.push(frame);
  let result: T;
  try {
    result = fn();
  } finally {
    frames.pop();
    if (frames.length === 0) uninstall();
  }
  if (frame.violation !== undefined) throw frame.violation;
  return result;
}
