import { hitPointRoundedBox as hitPointRoundedBox_ } from 'fixedstep';
import { GRID_MAX_RADIUS, GRID_MAX_WALLS, WallGrid } from './wall-grid.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const hitPointRoundedBox = hitPointRoundedBox_;
/** An axis-aligned rectangle by its corners, in arena units (pixels, y pointing down). */
export interface Rect {
  readonly x0: number;
  readonly y0: number;
  readonly x1: number;
  readonly y1: number;
}

/** Scratch for swept-test results (normal, u) and push-out results; never part of any state. */
const contact = new Float64Array(3);
const scratch = new Float64Array(2);

/**
 * The static walls of an arena: axis-aligned boxes, stored as structure of arrays (centre and half
 * extents), in a fixed order. They never change during a game, so they are not part of a saved
 * state — they are part of the game's code and version.
 *
 * Every query here is `+ − × /` and `Math.sqrt` only, so it gives the same bits in every engine.
 */
export class Walls {
  /** Number of walls. */
  readonly count: number;
  /** Centres and half extents, indexed by wall. */
  readonly cx: Float64Array;
  readonly cy: Float64Array;
  readonly hw: Float64Array;
  readonly hh: Float64Array;
  /** The smallest full extent of any wall (its thickness). Arena units. */
  readonly thinnest: number;
  /** The walls as given, for drawing. */
  readonly rects: readonly Rect[];

  /**
   * The broad phase: which walls are near where (static, like the walls). Null for layouts of more
   * than {@link GRID_MAX_WALLS} walls or with coordinates that are not finite: every query then
   * tests every wall.
   */
  private readonly grid: WallGrid | null;

  constructor(rects: readonly Rect[]) {
    const n = rects.length;
    this.count = n;
    this.cx = new Float64Array(n);
    this.cy = new Float64Array(n);
    this.hw = new Float64Array(n);
    this.hh = new Float64Array(n);
    let thinnest = Infinity;
    rects.forEach((r, i) => {
      if (!(r.x1 > r.x0 && r.y1 > r.y0)) {
        throw new RangeError(`Walls: wall ${i} has no area (${r.x0},${r.y0})-(${r.x1},${r.y1})`);
      }
      this.cx[i] = (r.x0 + r.x1) / 2;
      this.cy[i] = (r.y0 + r.y1) / 2;
      this.hw[i] = (r.x1 - r.x0) / 2;
      this.hh[i] = (r.y1 - r.y0) / 2;
      thinnest = Math.min(thinnest, r.x1 - r.x0, r.y1 - r.y0);
    });
    this.thinnest = thinnest;
    this.rects = Object.freeze(rects.map((r) => Object.freeze({ ...r })));
    const finite = rects.every((r) => finite4(r.x0, r.y0, r.x1, r.y1));
    this.grid = n <= GRID_MAX_WALLS && finite ? new WallGrid(this.rects) : null;
  }

  /** Whether a circle of radius `r` at (x, y) overlaps any wall (touching does not count). */
  overlaps(x: number, y: number, r: number): boolean {
    const grid = this.grid;
    if (grid === null || !finite2(x, y) || !(r <= GRID_MAX_RADIUS))
      return this.overlapsAll(x, y, r);
    for (let m = grid.pointMask(x, y); m !== 0; m &= m - 1) {
      if (this.overlapsOne(31 - Math.clz32(m & -m), x, y, r)) return true;
    }
    return false;
  }

  /**
   * Discrete collision response: pushes a circle of radius `r` at (x, y) out of every wall it
   * overlaps, by the minimum translation (out through the *nearer* face), walls in index order,
   * two passes (for inner corners). Writes the new centre to `out[0], out[1]`.
   *
   * This is all a discrete game has. If the centre has crossed the middle of a wall, the nearer
   * face is the far one and the circle comes out on the other side: that is tunnelling. It cannot
   * happen while every step moves the circle at most `thickness / 2 + r` (see `maxSafeSpeed`).
   */
  pushOut(x: number, y: number, r: number, out: Float64Array): void {
    const grid = this.grid;
    if (grid === null || !finite2(x, y) || !(r <= GRID_MAX_RADIUS)) {
      this.pushOutAll(x, y, r, out);
      return;
    }
    // The walls in index order, as the all-walls loop visits them, but only those near the cell
    // the centre is in now: the others are too far to overlap it, and the loop would pass over
    // them. A push moves the centre, so the walls after it come from its new cell.
    for (let pass = 0; pass < 2; pass++) {
      let m = grid.pointMask(x, y);
      while (m !== 0) {
        const i = 31 - Math.clz32(m & -m);
        m &= m - 1;
        if (!pushOne(this, i, x, y, r, scratch)) continue;
        x = scratch[0]!;
        y = scratch[1]!;
        // Bits above i (none when i is 31).
        m = i === 31 ? 0 : grid.pointMask(x, y) & (-2 << i);
      }
    }
    out[0] = x;
    out[1] = y;
  }

  /**
   * Continuous detection: the earliest fraction `u ∈ [0, 1]` of the move (dx, dy) at which a
   * circle of radius `r` starting at (x, y) touches a wall, or -1 if it touches none. Uses the
   * library's swept test (`hitPointRoundedBox`: a ray against the wall grown by `r`).
   */
  sweep(x: number, y: number, dx: number, dy: number, r: number): number {
    const grid = this.grid;
    let best = -1;
    if (grid === null || !finite4(x, y, dx, dy) || !(r <= GRID_MAX_RADIUS)) {
      for (let i = 0; i < this.count; i++) {
        if (this.touches(i, x, y, dx, dy, r) && (best < 0 || contact[2]! < best))
          best = contact[2]!;
      }
      return best;
    }
    // The earliest of all, so the order the walls come in does not matter.
    for (let m = grid.segmentMask(x, y, dx, dy); m !== 0; m &= m - 1) {
      const i = 31 - Math.clz32(m & -m);
      if (this.touches(i, x, y, dx, dy, r) && (best < 0 || contact[2]! < best)) best = contact[2]!;
    }
    return best;
  }

  /** Whether a circle of radius `r` can move in a straight line from (x0, y0) to (x1, y1) without touching a wall. */
  clear(x0: number, y0: number, x1: number, y1: number, r: number): boolean {
    // `sweep(…) < 0`, stopping at the first wall touched.
    const dx = x1 - x0;
    const dy = y1 - y0;
    const grid = this.grid;
    if (grid === null || !finite4(x0, y0, dx, dy) || !(r <= GRID_MAX_RADIUS)) {
      for (let i = 0; i < this.count; i++) if (this.touches(i, x0, y0, dx, dy, r)) return false;
      return true;
    }
    for (let m = grid.segmentMask(x0, y0, dx, dy); m !== 0; m &= m - 1) {
      if (this.touches(31 - Math.clz32(m & -m), x0, y0, dx, dy, r)) return false;
    }
    return true;
  }

  /**
   * Whether the segment from (x0, y0) to (x1, y1) meets the inside of a wall (closed box): the
   * tunnelling detector. A circle's centre never legitimately gets there — the response keeps it
   * `r` away from every wall, and a centre path that touches a wall's box between two positions
   * at least `r` from it is at least `2r` long — so for a mover whose step is shorter than its
   * diameter, a `true` here means it went through the wall. Liang–Barsky clipping, independent
   * of the collision code it checks.
   */
  crosses(x0: number, y0: number, x1: number, y1: number): boolean {
    const dx = x1 - x0;
    const dy = y1 - y0;
    const grid = this.grid;
    if (grid === null || !finite4(x0, y0, dx, dy)) {
      for (let i = 0; i < this.count; i++) if (this.crossesOne(i, x0, y0, dx, dy)) return true;
      return false;
    }
    for (let m = grid.segmentMask(x0, y0, dx, dy); m !== 0; m &= m - 1) {
      if (this.crossesOne(31 - Math.clz32(m & -m), x0, y0, dx, dy)) return true;
    }
    return false;
  }

  // --- one wall at a time: the exact tests, shared by the grid and the all-walls paths ---

  private overlapsOne(i: number, x: number, y: number, r: number): boolean {
    const dx = Math.abs(x - this.cx[i]!);
    const dy = Math.abs(y - this.cy[i]!);
    const hw = this.hw[i]!;
    const hh = this.hh[i]!;
    if (dx >= hw + r || dy >= hh + r) return false;
    if (dx <= hw || dy <= hh) return true;
    const ex = dx - hw;
    const ey = dy - hh;
    return ex * ex + ey * ey < r * r;
  }

  /**
   * Whether a circle of radius `r` moving from (x, y) by (dx, dy) touches wall `i`; if so, the
   * fraction of the move at which it does is in `contact[2]` (≥ 0).
   */
  private touches(i: number, x: number, y: number, dx: number, dy: number, r: number): boolean {
    const cx = this.cx[i]!;
    const cy = this.cy[i]!;
    const hw = this.hw[i]! + r;
    const hh = this.hh[i]! + r;
    // Cheap rejection: the move's bounding box against the grown wall.
    const minX = dx < 0 ? x + dx : x;
    const maxX = dx < 0 ? x : x + dx;
    const minY = dy < 0 ? y + dy : y;
    const maxY = dy < 0 ? y : y + dy;
    if (maxX <= cx - hw || minX >= cx + hw || maxY <= cy - hh || minY >= cy + hh) return false;
    // (A hit's u is never negative nor NaN, so this is the `toi… ≥ 0` of the swept test.)
    return (
      hitPointRoundedBox(x - cx, y - cy, dx, dy, this.hw[i]!, this.hh[i]!, r, contact) &&
      contact[2]! >= 0
    );
  }

  private crossesOne(i: number, x0: number, y0: number, dx: number, dy: number): boolean {
    const cx = this.cx[i]!;
    const cy = this.cy[i]!;
    const hw = this.hw[i]!;
    const hh = this.hh[i]!;
    let t0 = 0;
    let t1 = 1;
    if (dx === 0) {
      if (x0 < cx - hw || x0 > cx + hw) return false;
    } else {
      let a = (cx - hw - x0) / dx;
      let b = (cx + hw - x0) / dx;
      if (a > b) {
        const s = a;
        a = b;
        b = s;
      }
      if (a > t0) t0 = a;
      if (b < t1) t1 = b;
      if (t0 > t1) return false;
    }
    if (dy === 0) {
      if (y0 < cy - hh || y0 > cy + hh) return false;
    } else {
      let a = (cy - hh - y0) / dy;
      let b = (cy + hh - y0) / dy;
      if (a > b) {
        const s = a;
        a = b;
        b = s;
      }
      if (a > t0) t0 = a;
      if (b < t1) t1 = b;
      if (t0 > t1) return false;
    }
    return true;
  }

  // --- every wall: for radii beyond the grid's, coordinates that are not finite, big layouts ---

  private overlapsAll(x: number, y: number, r: number): boolean {
    for (let i = 0; i < this.count; i++) if (this.overlapsOne(i, x, y, r)) return true;
    return false;
  }

  private pushOutAll(x: number, y: number, r: number, out: Float64Array): void {
    for (let pass = 0; pass < 2; pass++) {
      for (let i = 0; i < this.count; i++) {
        if (!pushOne(this, i, x, y, r, scratch)) continue;
        x = scratch[0]!;
        y = scratch[1]!;
      }
    }
    out[0] = x;
    out[1] = y;
  }
}

/**
 * One wall's push-out of a circle of radius `r` at (x, y) (see {@link Walls.pushOut}): false when
 * the circle does not overlap wall `i`; else true, with the new centre in `out[0], out[1]`.
 */
function pushOne(
  walls: Walls,
  i: number,
  x: number,
  y: number,
  r: number,
  out: Float64Array,
): boolean {
  const cx = walls.cx[i]!;
  const cy = walls.cy[i]!;
  const hw = walls.hw[i]!;
  const hh = walls.hh[i]!;
  const dx = x - cx;
  const dy = y - cy;
  const ax = dx < 0 ? -dx : dx;
  const ay = dy < 0 ? -dy : dy;
  if (ax >= hw + r || ay >= hh + r) return false;
  const sx = dx < 0 ? -1 : 1;
  const sy = dy < 0 ? -1 : 1;
  if (ax <= hw && ay <= hh) {
    // Centre inside: leave through the nearer face.
    if (hw - ax <= hh - ay) x = cx + sx * (hw + r);
    else y = cy + sy * (hh + r);
  } else if (ax <= hw) {
    y = cy + sy * (hh + r);
  } else if (ay <= hh) {
    x = cx + sx * (hw + r);
  } else {
    const qx = cx + sx * hw;
    const qy = cy + sy * hh;
    const ex = x - qx;
    const ey = y - qy;
    const d2 = ex * ex + ey * ey;
    if (d2 >= r * r) return false;
    const d = Math.sqrt(d2);
    x = qx + (ex / d) * r;
    y = qy + (ey / d) * r;
  }
  out[0] = x;
  out[1] = y;
  return true;
}

/** Whether both numbers are finite. */
function finite2(a: number, b: number): boolean {
  return a - a === 0 && b - b === 0;
}

/** Whether all four numbers are finite. */
function finite4(a: number, b: number, c: number, d: number): boolean {
  return a - a === 0 && b - b === 0 && c - c === 0 && d - d === 0;
}
/** `rects` followed by their mirror images about the vertical line x = `width / 2`. */
export function mirrored(rects: readonly Rect[], width: number): Rect[] {
  return [
    ...rects,
    ...rects.map((r) => ({ x0: width - r.x1, y0: r.y0, x1: width - r.x0, y1: r.y1 })),
  ];
}

/** Four walls of thickness `t` lining the inside of a `width × height` field. */
export function border(width: number, height: number, t: number): Rect[] {
  return [
    { x0: 0, y0: 0, x1: width, y1: t },
    { x0: 0, y0: height - t, x1: width, y1: height },
    { x0: 0, y0: t, x1: t, y1: height - t },
    { x0: width - t, y0: t, x1: width, y1: height - t },
  ];
}
