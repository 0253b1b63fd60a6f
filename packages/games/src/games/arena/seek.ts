import type { ButtonInput } from 'fixedstep';
import { DIR_BUTTONS as DIR_BUTTONS_, dirToward as dirToward_ } from './motion.js';
import type { NavGrid } from './nav.js';
import type { Walls } from './walls.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const DIR_BUTTONS = DIR_BUTTONS_;
const dirToward = dirToward_;

/** Scratch for {@link walkTo}'s waypoint; never part of any state. */
const wp = new Float64Array(2);

/**
 * The live body nearest to (x, y) among bodies in structure-of-arrays form (`alive[i]` 0 or 1,
 * centres `xs[i]`, `ys[i]`), the first of equals in index order: its index, or -1 if none lives.
 * Its squared distance goes to `out[0]` (Infinity when none).
 */
export function nearestLive(
  x: number,
  y: number,
  alive: Uint8Array,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
): number {
  let found = -1;
  let best = Infinity;
  for (let i = 0; i < alive.length; i++) {
    if (alive[i] === 0) continue;
    const dx = xs[i]! - x;
    const dy = ys[i]! - y;
    const d2 = dx * dx + dy * dy;
    if (d2 < best) {
      best = d2;
      found = i;
    }
  }
  out[0] = best;
  return found;
}

/**
 * What a bot may shoot at: the live body nearest to (x, y), closer than `range`, that a circle of
 * radius `clearance` (a bullet and some room) can reach from there in a straight line without
 * touching a wall — line of sight as a swept test, so thin walls block it as they block bullets.
 * Bodies as in {@link nearestLive}; only `first`, `first + stride`, … are considered (every other
 * slot: the other team). Returns its index, or -1, and writes its squared distance to `out[0]`
 * (`range²` when none).
 */
export function nearestVisible(
  walls: Walls,
  x: number,
  y: number,
  range: number,
  clearance: number,
  alive: Uint8Array,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
  first = 0,
  stride = 1,
): number {
  let found = -1;
  let best = range * range;
  for (let i = first; i < alive.length; i += stride) {
    if (alive[i] === 0) continue;
    const dx = xs[i]! - x;
    const dy = ys[i]! - y;
    const d2 = dx * dx + dy * dy;
    if (d2 >= best) continue;
    if (!walls.clear(x, y, xs[i]!, ys[i]!, clearance)) continue;
    best = d2;
    found = i;
  }
  out[0] = best;
  return found;
}

/** The arrows a bot at (x, y) holds to walk to (gx, gy) by `nav`: toward its next waypoint. */
export function walkTo(nav: NavGrid, x: number, y: number, gx: number, gy: number): ButtonInput {
  nav.waypoint(x, y, gx, gy, wp);
  return DIR_BUTTONS[dirToward(wp[0]! - x, wp[1]! - y)]!;
}
