import { sharedNav, type NavGrid } from '../arena/nav.js';
import { Walls, border } from '../arena/walls.js';

/**
 * Survival's numbers. Units: arena units (think pixels), seconds; y points down. Changing any of
 * them changes the simulation: bump {@link SURVIVAL_VERSION}.
 */
export const SURVIVAL = {
  width: 800,
  height: 600,
  /** Thickness of the border walls. */
  border: 16,
  /** Player slots (co-op). */
  maxPlayers: 2,
  playerRadius: 10,
  /** Units per second (3.33 per step at 60 Hz). */
  playerSpeed: 200,
  /** Lives each player starts with, as on the slide ("Lives: 15"). */
  lives: 15,
  /** Seconds a player cannot be touched after losing a life. */
  invulnerableTime: 1.5,
  enemyRadius: 9,
  /** Enemy pool capacity. */
  enemyCapacity: 96,
  /** The fastest an enemy runs, units per second (5.5 per step at 60 Hz). */
  maxEnemySpeed: 330,
  /** Most that enemies shoving each other move one enemy in one step or update, units. */
  maxShove: 1.5,
  bulletRadius: 2,
  /** Units per second (14 per step at 60 Hz). */
  bulletSpeed: 840,
  bulletLife: 0.7,
  bulletCapacity: 48,
  /** Seconds between two shots of one player. */
  fireCooldown: 0.14,
  /** Seconds of calm before each wave (the first after `firstWaveDelay`). */
  breather: 2.5,
  firstWaveDelay: 1,
} as const;

/** The simulation version: bump it whenever a change alters what a step does. */
export const SURVIVAL_VERSION = 1;

/** Enemies in wave `w` (1, 2, …). */
export function waveSize(w: number): number {
  return Math.min(90, 4 + 3 * w);
}

/** The typical speed of wave `w`'s enemies (each varies ±15 %, capped at `maxEnemySpeed`). */
export function waveSpeed(w: number): number {
  return Math.min(SURVIVAL.maxEnemySpeed, 130 + 20 * w);
}

/** Seconds between two spawns in wave `w`. */
export function waveInterval(w: number): number {
  return Math.max(0.2, 0.7 - 0.04 * w);
}

/** Where the players start. */
export const START_X: readonly number[] = [400, 440];
export const START_Y: readonly number[] = [380, 380];

/**
 * The arena: the border (16 thick) and eight obstacles 10 thick — thicker than the farthest any
 * enemy moves in one fixed step (5.5 + 1.5 shove = 7), as the talk's rule demands.
 */
export const SURVIVAL_WALLS = new Walls([
  ...border(SURVIVAL.width, SURVIVAL.height, SURVIVAL.border),
  { x0: 160, y0: 140, x1: 260, y1: 150 },
  { x0: 540, y0: 140, x1: 640, y1: 150 },
  { x0: 160, y0: 450, x1: 260, y1: 460 },
  { x0: 540, y0: 450, x1: 640, y1: 460 },
  { x0: 110, y0: 250, x1: 120, y1: 350 },
  { x0: 680, y0: 250, x1: 690, y1: 350 },
  { x0: 380, y0: 280, x1: 420, y1: 320 },
  { x0: 395, y0: 70, x1: 405, y1: 170 },
]);

/** The bot's navigation grid (built on first use, then shared: it is static data). */
export const survivalNav: () => NavGrid = sharedNav(
  SURVIVAL_WALLS,
  SURVIVAL.width,
  SURVIVAL.height,
  SURVIVAL.playerRadius,
);
