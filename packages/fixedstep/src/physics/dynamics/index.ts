/**
 * Dynamics: integrators on flat typed arrays (explicit, semi-implicit and backward Euler,
 * position and velocity Verlet, RK4), the harmonic oscillator, springs and spring systems.
 * See docs/integrators.md.
 */
export { BandMatrix } from './band-matrix.js';
export { DynamicsState, allocateFor, isImplicitModel } from './model.js';
export type { DynamicsModel, ImplicitModel } from './model.js';
export { createIntegrator, INTEGRATOR_METHODS, INTEGRATOR_INFO } from './integrators.js';
export type {
  Integrator,
  IntegratorInfo,
  IntegratorMethod,
  IntegratorOptions,
} from './integrators.js';
export { HarmonicOscillator } from './oscillator.js';
export {
  SpringModel,
  SpringSystem,
  springChain,
  springCloth,
  WASM_MIN_SPRINGS,
} from './springs.js';
export { springKernelsAvailable } from './wasm.js';
export type {
  ParticleDef,
  SpringDef,
  SpringModelDef,
  SpringSystemDef,
  SpringChainOptions,
  SpringClothOptions,
} from './springs.js';
