import type { ButtonInput } from 'fixedstep';
import type { GameInfo } from '../game.js';

/** The buttons of both shooters (bit numbers of a {@link ButtonInput}). */
export const ShooterButtons = {
  up: 0,
  down: 1,
  left: 2,
  right: 3,
  /** Hold to fire in the facing direction, as fast as the weapon allows. */
  fire: 4,
  /** Hold to keep facing the same way while moving (strafe). */
  strafe: 5,
} as const;

/** Buttons and keys (`KeyboardEvent.code`) for {@link GameInfo.buttons}. */
export const SHOOTER_BUTTON_INFO: GameInfo['buttons'] = Object.freeze([
  { button: ShooterButtons.up, name: 'Up', keys: ['KeyW', 'ArrowUp'] },
  { button: ShooterButtons.down, name: 'Down', keys: ['KeyS', 'ArrowDown'] },
  { button: ShooterButtons.left, name: 'Left', keys: ['KeyA', 'ArrowLeft'] },
  { button: ShooterButtons.right, name: 'Right', keys: ['KeyD', 'ArrowRight'] },
  { button: ShooterButtons.fire, name: 'Fire', keys: ['Space', 'KeyJ'] },
  { button: ShooterButtons.strafe, name: 'Strafe (keep facing)', keys: ['ShiftLeft', 'KeyK'] },
]);

const S = Math.SQRT1_2;

/**
 * The eight directions, clockwise on screen (y points down) from east: 0 E, 1 SE, 2 S, 3 SW,
 * 4 W, 5 NW, 6 N, 7 NE. Unit vectors; diagonals are exactly `Math.SQRT1_2` on each axis, so
 * movement and aim need no trigonometry at all.
 */
export const DIR_X: Readonly<Float64Array> = Float64Array.of(1, S, 0, -S, -1, -S, 0, S);
export const DIR_Y: Readonly<Float64Array> = Float64Array.of(0, S, 1, S, 0, -S, -1, -S);

/** The input bit of the fire button, and of the strafe button. */
export const FIRE = 1 << ShooterButtons.fire;
export const STRAFE = 1 << ShooterButtons.strafe;

const U = 1 << ShooterButtons.up;
const D = 1 << ShooterButtons.down;
const L = 1 << ShooterButtons.left;
const R = 1 << ShooterButtons.right;

/** The held buttons that move in direction `d` (0–7). */
export const DIR_BUTTONS: Readonly<Uint8Array> = Uint8Array.of(
  R,
  R | D,
  D,
  D | L,
  L,
  L | U,
  U,
  U | R,
);

/** Direction index by (right − left + 1) + 3 · (down − up + 1); -1 for no movement. */
const DIR_OF = Int8Array.of(5, 6, 7, 4, -1, 0, 3, 2, 1);

/** The direction (0–7) the held arrows of `input` ask for, or -1 for none (or opposite keys). */
export function inputDir(input: ButtonInput): number {
  const mx = ((input >>> ShooterButtons.right) & 1) - ((input >>> ShooterButtons.left) & 1);
  const my = ((input >>> ShooterButtons.down) & 1) - ((input >>> ShooterButtons.up) & 1);
  return DIR_OF[mx + 1 + 3 * (my + 1)]!;
}

/** The direction (0–7) closest to the vector (dx, dy); 0 for the zero vector. Exact, no trig. */
export function dirToward(dx: number, dy: number): number {
  towardArgs[0] = dx;
  towardArgs[1] = dy;
  return dirTowardOf(towardArgs);
}

/** {@link dirToward}'s arguments, as {@link dirTowardOf} takes them. */
const towardArgs = new Float64Array(2);

/**
 * {@link dirToward} of the vector (`v[0]`, `v[1]`): the form for the bots, which call it every
 * tick — V8 boxes a fractional number passed to a call it does not inline in a fresh heap object
 * (and whether it inlines this one into the bots' walk depends on what else it inlined there).
 */
export function dirTowardOf(v: Float64Array): number {
  const dx = v[0]!;
  const dy = v[1]!;
  // The loop over DIR_X, DIR_Y unrolled, each dot product as it computes it (dx · DIR_X[d] +
  // dy · DIR_Y[d], the same constants, the same order): the same numbers, NaN and signed zeros
  // included; the first of equals wins. Bots call this every tick.
  let best = 0;
  let bestDot = dx * 1 + dy * 0;
  // (-Infinity < bestDot, unless it is NaN: then the loop would have taken the next number.)
  if (!(bestDot > -Infinity)) bestDot = -Infinity;
  let dot = dx * S + dy * S;
  if (dot > bestDot) {
    bestDot = dot;
    best = 1;
  }
  dot = dx * 0 + dy * 1;
  if (dot > bestDot) {
    bestDot = dot;
    best = 2;
  }
  dot = dx * -S + dy * S;
  if (dot > bestDot) {
    bestDot = dot;
    best = 3;
  }
  dot = dx * -1 + dy * 0;
  if (dot > bestDot) {
    bestDot = dot;
    best = 4;
  }
  dot = dx * -S + dy * -S;
  if (dot > bestDot) {
    bestDot = dot;
    best = 5;
  }
  dot = dx * 0 + dy * -1;
  if (dot > bestDot) {
    bestDot = dot;
    best = 6;
  }
  dot = dx * S + dy * -S;
  if (dot > bestDot) best = 7;
  return best;
}

/**
 * The direction `d` (0–7) whose line from the origin passes closest to (dx, dy), ahead of the
 * origin, with that distance written to `out[0]` (signed: positive when the point lies to the
 * clockwise side of the line). -1 if the point is the origin.
 */
export function nearestLine(dx: number, dy: number, out: Float64Array): number {
  lineArgs[0] = dx;
  lineArgs[1] = dy;
  return nearestLineOf(lineArgs, out);
}

/**
 * {@link nearestLine} of the point (`v[0]`, `v[1]`): the form for the bots, which call it every
 * tick — V8 boxes a fractional number passed to a call it does not inline in a fresh heap object.
 */
export function nearestLineOf(v: Float64Array, out: Float64Array): number {
  const dx = v[0]!;
  const dy = v[1]!;
  let best = -1;
  let bestAbs = Infinity;
  for (let d = 0; d < 8; d++) {
    const ux = DIR_X[d]!;
    const uy = DIR_Y[d]!;
    if (dx * ux + dy * uy <= 0) continue;
    const perp = dy * ux - dx * uy;
    const a = perp < 0 ? -perp : perp;
    if (a < bestAbs) {
      bestAbs = a;
      best = d;
      out[0] = perp;
    }
  }
  return best;
}

/** {@link nearestLine}'s argument, as {@link nearestLineOf} takes it. */
const lineArgs = new Float64Array(2);

/** `v` kept within [lo, hi] (lo ≤ hi). */
export function clamp(v: number, lo: number, hi: number): number {
  return v < lo ? lo : v > hi ? hi : v;
}

/** Whether `x` is a finite number (for validating loaded state). */
export function isFiniteNumber(x: number): boolean {
  return x - x === 0;
}
