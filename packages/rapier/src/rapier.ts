/**
 * The one Rapier module every simulation of this package uses: Rapier 2D's deterministic build
 * (`@dimforge/rapier2d-deterministic-compat`, the WebAssembly embedded as base64, so a bundler
 * ships it inside the bundle and a page loads it with no network request).
 */
import RAPIER from '@dimforge/rapier2d-deterministic-compat';

/** The Rapier module (`import RAPIER from '@dimforge/rapier2d-deterministic-compat'`). */
export type RapierModule = typeof RAPIER;

let ready: Promise<RapierModule> | undefined;
let initialized = false;

/**
 * Instantiates Rapier's WebAssembly (once per JavaScript realm; later calls return the same
 * promise) and resolves to the module. Every other function of this package is synchronous and
 * needs this to have finished: `await loadRapier()` once at start-up.
 */
export function loadRapier(): Promise<RapierModule> {
  ready ??= RAPIER.init().then(() => {
    initialized = true;
    return RAPIER;
  });
  return ready;
}

/** Whether {@link loadRapier} has finished, so Rapier can be used synchronously. */
export function rapierReady(): boolean {
  return initialized;
}

/** The module, or a clear error if {@link loadRapier} has not finished. */
export function readyRapier(who: string): RapierModule {
  if (!initialized) {
    throw new Error(`${who}: Rapier is not initialised yet: await loadRapier() once first`);
  }
  return RAPIER;
}

/** The version of Rapier's WebAssembly build, e.g. `0.20.0`. Needs {@link loadRapier}. */
export function rapierVersion(): string {
  return readyRapier('rapierVersion').version();
}
