/**
 * Physics: integrators (explicit and semi-implicit Euler, backward Euler, Verlet, velocity
 * Verlet, RK4) and springs, swept (continuous) collision for fast bodies, and the rigid-body
 * world with its shapes, broad phase, contacts and snapshots — all deterministic.
 * @module
 */
export * from './dynamics/index.js';
export * from './world/index.js';
