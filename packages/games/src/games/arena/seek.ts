import type { ButtonInput } from 'fixedstep';
import { DIR_BUTTONS as DIR_BUTTONS_, dirTowardOf as dirTowardOf_ } from './motion.js';
import type { NavGrid } from './nav.js';
import type { Walls } from './walls.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const DIR_BUTTONS = DIR_BUTTONS_;
const dirTowardOf = dirTowardOf_;

/** Scratch for {@link walkTo}'s waypoint; never part of any state. */
const wp = new Float64Array(2);
/** Scratch for {@link nearestVisible}: bodies in range and their squared distances (grown on demand). */
let nearIndex = new Int32Array(16);
let nearD2 = new Float64Array(16);

/**
 * The live body nearest to (x, y) = (`px[from]`, `py[from]`) among bodies in structure-of-arrays
 * form (`alive[i]` 0 or 1, centres `xs[i]`, `ys[i]`), the first of equals in index order: its
 * index, or -1 if none lives. Its squared distance goes to `out[0]` (Infinity when none).
 *
 * The searches here take their point from arrays, not as numbers: V8 boxes a fractional number
 * passed to a call it does not inline in a fresh heap object, and bots and steps call them every
 * tick.
 */
export function nearestLive(
  px: Float64Array,
  py: Float64Array,
  from: number,
  alive: Uint8Array,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
): number {
  const x = px[from]!;
  const y = py[from]!;
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
 * What a bot may shoot at: the live body nearest to (x, y) = (`px[from]`, `py[from]`), closer than `range`, that a circle of
 * radius `clearance` (a bullet and some room) can reach from there in a straight line without
 * touching a wall — line of sight as a swept test, so thin walls block it as they block bullets.
 * Bodies as in {@link nearestLive}; only `first`, `first + stride`, … are considered (every other
 * slot: the other team). Returns its index, or -1, and writes its squared distance to `out[0]`
 * (`range²` when none).
 */
export function nearestVisible(
  walls: Walls,
  px: Float64Array,
  py: Float64Array,
  from: number,
  range: number,
  clearance: number,
  alive: Uint8Array,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
  first = 0,
  stride = 1,
): number {
  const x = px[from]!;
  const y = py[from]!;
  // Those in range, then the nearest first: the first in sight is the one (of equals, the first
  // in slot order) — what keeping the nearest in sight while going through them all would find,
  // with fewer line-of-sight tests. Mostly none is in range: this part is small enough for V8 to
  // inline into a bot, the rest is apart.
  const limit = range * range;
  if (nearIndex.length < alive.length) growNear(alive.length);
  const index = nearIndex;
  const d2s = nearD2;
  let n = 0;
  for (let i = first; i < alive.length; i += stride) {
    if (alive[i] === 0) continue;
    const dx = xs[i]! - x;
    const dy = ys[i]! - y;
    const d2 = dx * dx + dy * dy;
    // A position that is not a number: the plain scan, whatever it makes of that.
    if (d2 !== d2)
      return scanVisible(walls, x, y, limit, clearance, alive, xs, ys, out, first, stride);
    if (!(d2 < limit)) continue;
    index[n] = i;
    d2s[n] = d2;
    n++;
  }
  if (n === 0) {
    out[0] = limit;
    return -1;
  }
  return nearestInSight(walls, px, py, from, limit, clearance, xs, ys, out, n);
}

/** Makes the scratch of {@link nearestVisible} hold `length` bodies. */
function growNear(length: number): void {
  nearIndex = new Int32Array(length);
  nearD2 = new Float64Array(length);
}

/**
 * {@link nearestVisible}'s second part: of the `n` bodies in range (`nearIndex`, `nearD2`), the
 * nearest in sight from (`px[from]`, `py[from]`); `limit` is the squared range.
 */
function nearestInSight(
  walls: Walls,
  px: Float64Array,
  py: Float64Array,
  from: number,
  limit: number,
  clearance: number,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
  n: number,
): number {
  const x = px[from]!;
  const y = py[from]!;
  const index = nearIndex;
  const d2s = nearD2;
  for (;;) {
    let pick = -1;
    // Every body listed is nearer than the range (`d2 < limit`), so starting from Infinity picks
    // the same one. Not from `limit`: that comes in tagged (a call's argument) and would make V8
    // keep `least` tagged too, boxing every squared distance assigned to it in a fresh heap
    // number — the 22 bytes per tick capture the flag's re-simulation allocated.
    let least = Infinity;
    for (let k = 0; k < n; k++) {
      if (index[k]! >= 0 && d2s[k]! < least) {
        least = d2s[k]!;
        pick = k;
      }
    }
    if (pick < 0) break;
    const i = index[pick]!;
    index[pick] = -1;
    const q = walls.query;
    q[0] = x;
    q[1] = y;
    q[2] = xs[i]!;
    q[3] = ys[i]!;
    if (walls.clearQuery(clearance)) {
      out[0] = least;
      return i;
    }
  }
  out[0] = limit;
  return -1;
}

/**
 * {@link nearestVisible} by going through them all, keeping the nearest in sight (the search
 * above must answer as it does; it takes over for positions that are not numbers): `limit` is the
 * squared range.
 */
export function scanVisible(
  walls: Walls,
  x: number,
  y: number,
  limit: number,
  clearance: number,
  alive: Uint8Array,
  xs: Float64Array,
  ys: Float64Array,
  out: Float64Array,
  first: number,
  stride: number,
): number {
  let found = -1;
  let best = limit;
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

/**
 * The arrows a bot holds to walk from `nav.query[0]`, `nav.query[1]` to `nav.query[2]`,
 * `nav.query[3]` by `nav`: toward its next waypoint.
 */
export function walkTo(nav: NavGrid): ButtonInput {
  nav.waypointQuery(wp);
  const q = nav.query;
  wp[0] = wp[0]! - q[0]!;
  wp[1] = wp[1]! - q[1]!;
  return DIR_BUTTONS[dirTowardOf(wp)]!;
}
