/**
 * What the two shooters share: the game shell (config checks, step and update, snapshots, the
 * player's walk) and the state's common part, walls and their collision queries, movement in
 * eight directions, a bullet pool with discrete and continuous detection, the bots' navigation
 * grid and searches, and a helper that plays a game on a simulated display.
 * @module
 */
export { Walls, border, mirrored } from './walls.js';
export type { Rect } from './walls.js';
export {
  ShooterButtons,
  SHOOTER_BUTTON_INFO,
  DIR_X,
  DIR_Y,
  DIR_BUTTONS,
  inputDir,
  dirToward,
  nearestLine,
} from './motion.js';
export { ArenaGame, ArenaState } from './game.js';
export type { ArenaSpec, ArenaStateFormat } from './game.js';
export { Bullets } from './bullets.js';
export type { BulletTargets } from './bullets.js';
export { NavGrid } from './nav.js';
export { playOnDisplay } from './drive.js';
export type { PlayOnDisplayOptions, PlayOnDisplayResult } from './drive.js';
