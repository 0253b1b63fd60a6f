/**
 * The determinism guard (det/guard.ts) applied to a {@link Simulation}: a guarded step, and a
 * guarded view of a whole simulation, naming the tick in every error.
 * @module
 */
import { withDeterminismGuard } from '../det/guard.js';
import type { Simulation } from './simulation.js';

/** Steps `sim` once with `inputs`, guarded, naming `sim.tick` in any error. */
export function guardStep<I>(sim: Simulation<I>, inputs: readonly I[]): void {
  const tick = sim.tick;
  withDeterminismGuard(() => {
    sim.step(inputs);
  }, tick);
}

/**
 * A view of `sim` whose `step`, `save`, `load` and `hash` run under
 * {@link withDeterminismGuard} (naming the current tick); every other property reads through to
 * `sim`, with methods bound to it. Use it in development builds and tests; ship the bare `sim`.
 */
export function guardSimulation<S extends Simulation<never>>(sim: S): S {
  const guarded: Record<PropertyKey, unknown> = {
    step: (inputs: readonly never[]) => {
      guardStep(sim, inputs);
    },
    save: () => withDeterminismGuard(() => sim.save(), sim.tick),
    load: (bytes: Uint8Array) => {
      withDeterminismGuard(() => {
        sim.load(bytes);
      }, sim.tick);
    },
    hash: () => withDeterminismGuard(() => sim.hash(), sim.tick),
  };
  if (typeof sim.skip === 'function') {
    guarded.skip = (ticks: number) => {
      withDeterminismGuard(() => {
        sim.skip!(ticks);
      }, sim.tick);
    };
  }
  return new Proxy(sim, {
    get(target, key) {
      if (Object.hasOwn(guarded, key)) return guarded[key];
      const value: unknown = Reflect.get(target, key, target);
      return typeof value === 'function'
        ? (value as (...a: unknown[]) => unknown).bind(target)
        : value;
    },
  });
}
