export { PhysicsWorld } from './world.js';
export type { StaticShape, WorldOptions } from './world.js';
export { defaultWorldDef } from './def.js';
export type { WorldDef, CcdMode, BodyOptions, CircleOptions, BoxOptions, Exact } from './def.js';
export { WORLD_LIMITS } from './validate.js';
export { worldStateColumns } from './snapshot-schema.js';
export type { WorldStateSchemaOptions } from './snapshot-schema.js';
export { defaultFilter } from './filter.js';
export type { BodyFilter } from './filter.js';
export type { QueryFilter, RayFilter, RayHit } from './queries.js';
export type { SensorEvent, ContactEvent, StepEvents } from './events.js';
export { worldKernelsAvailable } from './solver-kernels.js';
export { minWallSize, maxSafeSpeed, tunnellingShare, checkTunnellingRule } from './rule.js';
export type { TunnellingWarning } from './rule.js';
export {
  hitPointCircle,
  hitPointRoundedBox,
  hitPointCapsule,
  hitBoxSegment,
  toiPointCircle,
  toiPointRoundedBox,
  toiPointCapsule,
  toiBoxSegment,
} from './swept.js';
export {
  circlesInBox,
  circlesInBoxScene,
  bodiesInBox,
  bodiesInBoxScene,
  bulletsScene,
  buildWorld,
} from './scenes.js';
export type { PhysicsScene, SceneBody, SceneBox, SceneSegment } from './scenes.js';
