import type { Walls } from './walls.js';

/**
 * Arena units by which a straight move from a cell to a point must miss a wall (beyond the body's
 * radius) for {@link cellReach} to leave it out: a million times more than any rounding of the
 * walls' line test on an arena a thousand units across, so that test could not find it touched.
 */
export const REACH_SLACK = 1;

/**
 * {@link cellReach}'s answer when the layout has more walls than a mask has bits (32) and some
 * wall may be in the way: "ask the walls".
 */
export const REACH_UNKNOWN = -1;

/**
 * The walls that a circle of radius `r` moving in a straight line from anywhere in the square cell
 * [x0, x0 + size] × [y0, y0 + size] to (px, py) can come within `r` + {@link REACH_SLACK} of, as a
 * bit mask (bit i: wall i): those whose box grown by `r + REACH_SLACK` (square corners: more than
 * the round ones) meets the convex hull of the cell and the point. Every wall that the walls' line
 * test (`Walls.clear`) could find touched by such a move is in it, so testing only those gives its
 * answer (`Walls.clearAmongQuery`); 0 means every such move is clear.
 *
 * The separating-axis test on the hull's and the box's edge directions: the axes, and the normals
 * of the segments from each corner to the point, which include the hull's edges. Static data for
 * the bots' waypoints, computed once per layout. Layouts of more than 32 walls get 0 or
 * {@link REACH_UNKNOWN}.
 *
 * `only`: look at these walls only (bit i: wall i; all by default) — the answer for a region that
 * holds the cell, whose hull then holds this one's: every wall this one can meet is in it.
 */
export function cellReach(
  walls: Walls,
  x0: number,
  y0: number,
  size: number,
  px: number,
  py: number,
  r: number,
  only = -1,
): number {
  const x1 = x0 + size;
  const y1 = y0 + size;
  // The hull's box, for the x and y axes.
  const hx0 = Math.min(x0, px);
  const hx1 = Math.max(x1, px);
  const hy0 = Math.min(y0, py);
  const hy1 = Math.max(y1, py);
  const grow = r + REACH_SLACK;
  let mask = 0;
  for (let i = 0; i < walls.count; i++) {
    if (i < 32 && (only & (1 << i)) === 0) continue;
    const bx0 = walls.cx[i]! - walls.hw[i]! - grow;
    const bx1 = walls.cx[i]! + walls.hw[i]! + grow;
    const by0 = walls.cy[i]! - walls.hh[i]! - grow;
    const by1 = walls.cy[i]! + walls.hh[i]! + grow;
    if (hx1 < bx0 || bx1 < hx0 || hy1 < by0 || by1 < hy0) continue; // the x or the y axis
    let separated = false;
    // The normals of the segments from the cell's corners to the point.
    for (let k = 0; k < 4 && !separated; k++) {
      const cx = (k & 1) === 0 ? x0 : x1;
      const cy = (k & 2) === 0 ? y0 : y1;
      const ax = cy - py;
      const ay = px - cx;
      if (ax === 0 && ay === 0) continue;
      let hullMin = px * ax + py * ay;
      let hullMax = hullMin;
      for (let j = 0; j < 4; j++) {
        const v = ((j & 1) === 0 ? x0 : x1) * ax + ((j & 2) === 0 ? y0 : y1) * ay;
        hullMin = Math.min(hullMin, v);
        hullMax = Math.max(hullMax, v);
      }
      let boxMin = Infinity;
      let boxMax = -Infinity;
      for (let j = 0; j < 4; j++) {
        const v = ((j & 1) === 0 ? bx0 : bx1) * ax + ((j & 2) === 0 ? by0 : by1) * ay;
        boxMin = Math.min(boxMin, v);
        boxMax = Math.max(boxMax, v);
      }
      separated = hullMax < boxMin || boxMax < hullMin;
    }
    if (separated) continue;
    if (walls.count > 32) return REACH_UNKNOWN;
    mask |= 1 << i;
  }
  return mask;
}
