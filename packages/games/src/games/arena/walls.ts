import { toiPointRoundedBox as toiPointRoundedBox_ } from 'fixedstep';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const toiPointRoundedBox = toiPointRoundedBox_;
/** An axis-aligned rectangle by its corners, in arena units (pixels, y pointing down). */
export interface Rect {
  readonly x0: number;
  readonly y0: number;
  readonly x1: number;
  readonly y1: number;
}

/** Scratch for contact normals and push-out results; never part of any state. */
const normal = new Float64Array(2);

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
  }

  /** Whether a circle of radius `r` at (x, y) overlaps any wall (touching does not count). */
  overlaps(x: number, y: number, r: number): boolean {
    for (let i = 0; i < this.count; i++) {
      const dx = Math.abs(x - this.cx[i]!);
      const dy = Math.abs(y - this.cy[i]!);
      const hw = this.hw[i]!;
      const hh = this.hh[i]!;
      if (dx >= hw + r || dy >= hh + r) continue;
      if (dx <= hw || dy <= hh) return true;
      const ex = dx - hw;
      const ey = dy - hh;
      if (ex * ex + ey * ey < r * r) return true;
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
    for (let pass = 0; pass < 2; pass++) {
      for (let i = 0; i < this.count; i++) {
        const cx = this.cx[i]!;
        const cy = this.cy[i]!;
        const hw = this.hw[i]!;
        const hh = this.hh[i]!;
        const dx = x - cx;
        const dy = y - cy;
        const ax = dx < 0 ? -dx : dx;
        const ay = dy < 0 ? -dy : dy;
        if (ax >= hw + r || ay >= hh + r) continue;
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
          if (d2 >= r * r) continue;
          const d = Math.sqrt(d2);
          x = qx + (ex / d) * r;
          y = qy + (ey / d) * r;
        }
      }
    }
    out[0] = x;
    out[1] = y;
  }

  /**
   * Continuous detection: the earliest fraction `u ∈ [0, 1]` of the move (dx, dy) at which a
   * circle of radius `r` starting at (x, y) touches a wall, or -1 if it touches none. Uses the
   * library's swept test (`toiPointRoundedBox`: a ray against the wall grown by `r`).
   */
  sweep(x: number, y: number, dx: number, dy: number, r: number): number {
    let best = -1;
    const minX = dx < 0 ? x + dx : x;
    const maxX = dx < 0 ? x : x + dx;
    const minY = dy < 0 ? y + dy : y;
    const maxY = dy < 0 ? y : y + dy;
    for (let i = 0; i < this.count; i++) {
      const cx = this.cx[i]!;
      const cy = this.cy[i]!;
      const hw = this.hw[i]! + r;
      const hh = this.hh[i]! + r;
      // Cheap rejection: the move's bounding box against the grown wall.
      if (maxX <= cx - hw || minX >= cx + hw || maxY <= cy - hh || minY >= cy + hh) continue;
      const u = toiPointRoundedBox(x - cx, y - cy, dx, dy, this.hw[i]!, this.hh[i]!, r, normal);
      if (u >= 0 && (best < 0 || u < best)) best = u;
    }
    return best;
  }

  /** Whether a circle of radius `r` can move in a straight line from (x0, y0) to (x1, y1) without touching a wall. */
  clear(x0: number, y0: number, x1: number, y1: number, r: number): boolean {
    return this.sweep(x0, y0, x1 - x0, y1 - y0, r) < 0;
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
    for (let i = 0; i < this.count; i++) {
      const cx = this.cx[i]!;
      const cy = this.cy[i]!;
      const hw = this.hw[i]!;
      const hh = this.hh[i]!;
      let t0 = 0;
      let t1 = 1;
      if (dx === 0) {
        if (x0 < cx - hw || x0 > cx + hw) continue;
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
        if (t0 > t1) continue;
      }
      if (dy === 0) {
        if (y0 < cy - hh || y0 > cy + hh) continue;
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
        if (t0 > t1) continue;
      }
      return true;
    }
    return false;
  }
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
