import { sharedNav, type NavGrid } from '../arena/nav.js';
import { Walls, border, mirrored, type Rect } from '../arena/walls.js';

/**
 * Capture the flag's numbers. Units: arena units (think pixels), seconds; y points down.
 * Changing any of them changes the simulation: bump {@link CTF_VERSION}.
 */
export const CTF = {
  /** Field size. */
  width: 960,
  height: 640,
  /** Thickness of the border walls. */
  border: 16,
  /** Player slots: 4 per team, red on even slots, blue on odd ones. */
  slots: 8,
  playerRadius: 10,
  /** Units per second (2.67 per step at 60 Hz). */
  playerSpeed: 160,
  bulletRadius: 2,
  /** Units per second: 15 per step at 60 Hz — four times the thinnest wall. */
  bulletSpeed: 900,
  /** Seconds a bullet flies before it fades. */
  bulletLife: 0.8,
  /** Bullet pool capacity (more than 8 players × life / cooldown). */
  bulletCapacity: 64,
  /** Half the angle of the bullets' spread, radians (±3°). */
  spread: 0.05,
  /** Hits a player takes before dying. */
  health: 3,
  /** Seconds between two shots of one player. */
  fireCooldown: 0.3,
  /** Seconds dead before respawning at the base. */
  respawnTime: 3,
  /** Seconds of spawn protection (ends when the player fires or takes a flag). */
  protectTime: 1,
  /** Seconds a dropped flag lies before it returns home by itself. */
  flagReturnTime: 10,
  /** Centre distance at which a player takes (or returns) a flag. */
  pickupRadius: 20,
  /** Centre distance to the own flag stand at which a carried flag scores. */
  captureRadius: 24,
  /** Captures that win the match. */
  captureLimit: 5,
  /** Seconds a match lasts at most. */
  timeLimit: 600,
} as const;

/** The simulation version: bump it whenever a change alters what a step does. */
export const CTF_VERSION = 1;

/** Flag stands (the flag's home), by team: red left, blue right. */
export const FLAG_STAND_X: readonly number[] = [80, CTF.width - 80];
export const FLAG_STAND_Y: readonly number[] = [320, 320];

/** Spawn points inside each base, by team (4 each; slot k of a team starts at point k). */
export const SPAWN_X: readonly (readonly number[])[] = [
  [40, 40, 130, 130],
  [CTF.width - 40, CTF.width - 40, CTF.width - 130, CTF.width - 130],
];
export const SPAWN_Y: readonly (readonly number[])[] = [
  [290, 350, 250, 390],
  [290, 350, 250, 390],
];

/** Where a defender waits: in front of its flag, inside the base. */
export const GUARD_X: readonly number[] = [150, CTF.width - 150];
export const GUARD_Y: readonly number[] = [320, 320];

/** The four ways across the centre line, at x = width / 2 (the bots' lanes). */
export const LANE_Y: readonly number[] = [60, 190, 450, 580];

/** The left half; the right half is its mirror image. Thin walls are 4 units thick. */
const LEFT: Rect[] = [
  // The base: a room with two openings at its front corners.
  { x0: 16, y0: 216, x1: 200, y1: 220 },
  { x0: 16, y0: 420, x1: 200, y1: 424 },
  { x0: 196, y0: 272, x1: 200, y1: 368 },
  // Pillars on the flanks.
  { x0: 300, y0: 80, x1: 316, y1: 180 },
  { x0: 300, y0: 460, x1: 316, y1: 560 },
  // Thin cover in the middle lanes.
  { x0: 330, y0: 318, x1: 430, y1: 322 },
  { x0: 398, y0: 150, x1: 402, y1: 240 },
  { x0: 398, y0: 400, x1: 402, y1: 490 },
];

/** On the centre line (their own mirror images). */
const CENTRE: Rect[] = [
  { x0: 460, y0: 250, x1: 500, y1: 390 },
  { x0: 440, y0: 100, x1: 520, y1: 116 },
  { x0: 440, y0: 524, x1: 520, y1: 540 },
];

/** The arena's walls: the border, both halves, the centre pieces. */
export const CTF_WALLS = new Walls([
  ...border(CTF.width, CTF.height, CTF.border),
  ...mirrored(LEFT, CTF.width),
  ...CENTRE,
]);

/**
 * The points the bots head for again and again: the flag stands (each team's home, and the enemy
 * flag while it is at home), the guard posts and the lanes.
 */
export const CTF_GOALS: readonly (readonly [number, number])[] = [
  ...FLAG_STAND_X.map((x, t) => [x, FLAG_STAND_Y[t]!] as const),
  ...GUARD_X.map((x, t) => [x, GUARD_Y[t]!] as const),
  ...LANE_Y.map((y) => [CTF.width / 2, y] as const),
];

/** The bots' navigation grid (built on first use, then shared: it is static data). */
export const ctfNav: () => NavGrid = sharedNav(
  CTF_WALLS,
  CTF.width,
  CTF.height,
  CTF.playerRadius,
  CTF_GOALS,
);
