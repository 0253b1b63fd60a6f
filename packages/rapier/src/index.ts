/**
 * @fixedstep/rapier — Rapier 2D's deterministic build under fixedstep: a Rapier world as a
 * fixedstep `Simulation` (fixed step, inputs per tick, snapshots, a canonical hash), so the loop,
 * replays, lockstep, rollback and sync-test sessions work with rotating bodies, polygons and
 * joints. See docs/rapier.md.
 * @packageDocumentation
 * @module @fixedstep/rapier
 */
export { loadRapier, rapierReady, rapierVersion } from './rapier.js';
export type { RapierModule } from './rapier.js';
export { RapierSimulation, createRapierSimulation } from './simulation.js';
export type { RapierSceneDef } from './simulation.js';
export { BODY_BYTES, canonicalFields, splitHandle, writeCanonicalState } from './canonical.js';
export type { CanonicalField } from './canonical.js';
export {
  TowerButtons,
  JointsButtons,
  towerScene,
  buildTower,
  jointsScene,
  physicsSceneDef,
  checkButtons,
} from './scenes.js';
export type { TowerOptions, Tower, Joints, PhysicsSceneOptions } from './scenes.js';
/** Rapier's world, as `build`, `applyInputs` and `RapierSimulation.world` hand it over. */
export type { World } from '@dimforge/rapier2d-deterministic-compat';
export { rapierGame } from './net.js';
export type { RapierGameOptions } from './net.js';
