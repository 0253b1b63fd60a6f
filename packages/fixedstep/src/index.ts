/**
 * fixedstep — fixed-step, deterministic simulation. Everything in one import, or by topic from a
 * sub-path: `fixedstep/time`, `fixedstep/sim`, `fixedstep/input`, `fixedstep/det`,
 * `fixedstep/physics`, `fixedstep/replay`, `fixedstep/net`, `fixedstep/testing`. No name is
 * exported by two sub-paths (a test holds it), so the root is their union.
 * @packageDocumentation
 * @module fixedstep
 */
export * from './time/index.js';
export * from './sim/index.js';
export * from './input/index.js';
export * from './det/index.js';
export * from './physics/index.js';
export * from './replay/index.js';
export * from './net/index.js';
export * from './testing/index.js';
