import { SWEPT, pointRoundedBox as pointRoundedBox_, sweptRegisters } from './swept.js';
import { GRID_MAX_RADIUS, GRID_MAX_WALLS, WallGrid } from './wall-grid.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const pointRoundedBox = pointRoundedBox_;
/** Where the swept test writes the fraction of a hit. */
const U = SWEPT.u;
/** An axis-aligned rectangle by its corners, in arena units (pixels, y pointing down). */
export interface Rect {
  readonly x0: number;
  readonly y0: number;
  readonly x1: number;
  readonly y1: number;
}

/** {@link Walls}' answer for "every wall, by the all-walls loops" (no wall mask is 0.5). */
const ALL = 0.5;

/**
 * Arena units; a million times any rounding of the crossing test on an arena a thousand units
 * across (and the grid answers only there): a wall this far from a segment's bounding box is
 * passed over without the test, which could not have found it met.
 */
const NEAR = 1e-6;

/**
 * The static walls of an arena: axis-aligned boxes, stored as structure of arrays (centre and half
 * extents), in a fixed order. They never change during a game, so they are not part of a saved
 * state — they are part of the game's code and version.
 *
 * Every query here is `+ − × /` and `Math.sqrt` only, so it gives the same bits in every engine.
 *
 * A grid (`WallGrid`) tells each query which walls can matter; the per-wall tests are those
 * of the all-walls loops, so every answer is theirs, bit for bit. Each query also has a
 * *register form* (`clearQuery`, `sweepQuery`, `crossesQuery`, `pushOutQuery`, `overlapsQuery`)
 * that reads its coordinates from {@link query} and takes only small integers: V8 boxes a
 * fractional number passed to a call it does not inline in a fresh heap object, so the games'
 * hot loops write the registers and call those forms, and a step allocates nothing.
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
   * The registers of the register forms, arena units: a point (x, y) in `[0]`, `[1]`; a segment's
   * other end (x1, y1), or a move (dx, dy) for {@link sweepQuery}, in `[2]`, `[3]`; what
   * {@link sweepQuery} found in `[4]`. Write them, then call the form. Scratch, never part of any
   * state.
   */
  readonly query = new Float64Array(5);

  /**
   * The broad phase: which walls are near where (static, like the walls). Null for layouts of more
   * than {@link GRID_MAX_WALLS} walls or with coordinates that are not finite: every query then
   * tests every wall.
   */
  private readonly grid: WallGrid | null;
  /** The move being swept (x, y, dx, dy), and the swept test's registers (see {@link touches}). */
  private readonly move = new Float64Array(4);
  private readonly reg = sweptRegisters();

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
    const finite = rects.every((r) => [r.x0, r.y0, r.x1, r.y1].every((v) => v - v === 0));
    this.grid = n <= GRID_MAX_WALLS && finite ? new WallGrid(this.rects) : null;
  }

  /** Whether a circle of radius `r` at (x, y) overlaps any wall (touching does not count). */
  overlaps(x: number, y: number, r: number): boolean {
    this.query[0] = x;
    this.query[1] = y;
    return this.overlapsQuery(r);
  }

  /** {@link overlaps} of the point in `query[0]`, `query[1]`. */
  overlapsQuery(r: number): boolean {
    const grid = this.grid;
    const cell = grid === null || !(r <= GRID_MAX_RADIUS) ? -1 : grid.cellOf(this.query, 0);
    if (grid === null || cell < 0) return this.overlapsAll(r);
    // The walls near the cell, in index order (see `WallGrid`); the test is the all-walls loop's.
    for (let m = grid.masks[cell]!; m !== 0; m &= m - 1) {
      if (this.overlapsWall(31 - Math.clz32(m & -m), r)) return true;
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
   *
   * Returns whether a wall pushed it: false means the centre was at least `r` from every wall
   * (touching at most) and `out` holds it unchanged.
   */
  pushOut(x: number, y: number, r: number, out: Float64Array): boolean {
    this.query[0] = x;
    this.query[1] = y;
    return this.pushOutQuery(r, out);
  }

  /** {@link pushOut} of the circle centred at `query[0]`, `query[1]`. */
  pushOutQuery(r: number, out: Float64Array): boolean {
    const grid = this.grid;
    let cell = grid === null || !(r <= GRID_MAX_RADIUS) ? -1 : grid.cellOf(this.query, 0);
    if (grid === null || cell < 0) return this.pushOutAll(r, out);
    // The all-walls loop, visiting only the walls near the cell the centre is in now: the others
    // are too far to overlap it, and the loop would pass over them. A push moves the centre, so
    // the walls after it come from its new cell.
    const masks = grid.masks;
    const at = this.move;
    at[0] = this.query[0]!;
    at[1] = this.query[1]!;
    // A pass that pushes nothing leaves nothing for the next one to push (the same walls, at the
    // same place): it is the last.
    let pushed = true;
    let any = false;
    for (let pass = 0; pass < 2 && cell >= 0 && pushed; pass++) {
      pushed = false;
      let m = masks[cell]!;
      while (m !== 0) {
        const i = 31 - Math.clz32(m & -m);
        m &= m - 1;
        if (!this.pushOutOfWall(i, at, r)) continue;
        pushed = true;
        any = true;
        // Moved: the walls after i come from the new cell (bits above i; none when i is 31). A
        // push ends within the wall's reach, so on the grid; were it ever off it, every other
        // wall would be too far to overlap.
        cell = grid.cellOf(at, 0);
        m = cell < 0 || i === 31 ? 0 : masks[cell]! & (-2 << i);
      }
    }
    out[0] = at[0];
    out[1] = at[1];
    return any;
  }

  /**
   * Continuous detection: the earliest fraction `u ∈ [0, 1]` of the move (dx, dy) at which a
   * circle of radius `r` starting at (x, y) touches a wall, or -1 if it touches none: the
   * library's swept test (`toiPointRoundedBox`: a ray against the wall grown by `r`) on every
   * wall, the earliest hit.
   */
  sweep(x: number, y: number, dx: number, dy: number, r: number): number {
    this.setQuery(x, y, dx, dy);
    this.sweepQuery(r);
    return this.query[4]!;
  }

  /**
   * {@link sweep} of the move from `query[0]`, `query[1]` by `query[2]`, `query[3]`: whether it
   * touches a wall, the earliest fraction `u` to `query[4]` if so.
   */
  sweepQuery(r: number): boolean {
    const q = this.query;
    const x = q[0]!;
    const y = q[1]!;
    const dx = q[2]!;
    const dy = q[3]!;
    const ends = this.move;
    ends[0] = x;
    ends[1] = y;
    ends[2] = x + dx;
    ends[3] = y + dy;
    const walls = this.segmentWalls(ends, r);
    let best = -1;
    if (walls === ALL) {
      best = this.sweepAll(x, y, dx, dy, r);
    } else {
      // ends → the move (x, y, dx, dy) that `touches` sweeps.
      ends[2] = dx;
      ends[3] = dy;
      // The earliest of all: the same whatever order the walls come in.
      for (let m = walls; m !== 0; m &= m - 1) {
        if (!this.touches(31 - Math.clz32(m & -m), r)) continue;
        const u = this.reg[U]!;
        if (u >= 0 && (best < 0 || u < best)) best = u;
      }
    }
    q[4] = best;
    return best >= 0;
  }

  /** Whether a circle of radius `r` can move in a straight line from (x0, y0) to (x1, y1) without touching a wall. */
  clear(x0: number, y0: number, x1: number, y1: number, r: number): boolean {
    this.setQuery(x0, y0, x1, y1);
    return this.clearQuery(r);
  }

  /** {@link clear} from `query[0]`, `query[1]` to `query[2]`, `query[3]`. */
  clearQuery(r: number): boolean {
    const grid = this.grid;
    if (grid === null || !(r <= GRID_MAX_RADIUS)) return this.clearAll(r);
    const q = this.query;
    const from = grid.cellOf(q, 0);
    const to = grid.cellOf(q, 2);
    if (from < 0 || to < 0) return this.clearAll(r);
    let walls: number;
    if (from === to) {
      walls = grid.masks[from]!;
    } else {
      // (segmentWalls, and the pair's sure answer: a wall that every such move enters.)
      const pairs = grid.pairs;
      const slot = grid.pairSlot(from, to);
      const r256 = r * 256;
      if (r256 > pairs[slot + 2]! && r256 < pairs[slot + 3]!) return false;
      walls = pairs[slot + 1]!;
    }
    // `sweep(…) < 0`, stopping at the first wall touched.
    const move = this.move;
    const x0 = q[0]!;
    const y0 = q[1]!;
    move[0] = x0;
    move[1] = y0;
    move[2] = q[2]! - x0;
    move[3] = q[3]! - y0;
    for (let m = walls; m !== 0; m &= m - 1) {
      if (this.touches(31 - Math.clz32(m & -m), r) && this.reg[U]! >= 0) return false;
    }
    return true;
  }

  /**
   * {@link clearQuery} testing only the walls of `mask` (bit i: wall i; layouts of up to 32
   * walls), which must hold every wall the move can touch — a static answer for a known region,
   * such as the bots' waypoints' (`cellReach`). Then it answers as {@link clearQuery} does — the
   * same per-wall test, and the walls left out could not have been touched — without the grid's
   * look-ups.
   */
  clearAmongQuery(r: number, mask: number): boolean {
    const q = this.query;
    const move = this.move;
    const x0 = q[0]!;
    const y0 = q[1]!;
    move[0] = x0;
    move[1] = y0;
    move[2] = q[2]! - x0;
    move[3] = q[3]! - y0;
    for (let m = mask; m !== 0; m &= m - 1) {
      if (this.touches(31 - Math.clz32(m & -m), r) && this.reg[U]! >= 0) return false;
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
    this.setQuery(x0, y0, x1, y1);
    return this.crossesQuery();
  }

  /** {@link crosses} from `query[0]`, `query[1]` to `query[2]`, `query[3]`. */
  crossesQuery(): boolean {
    const q = this.query;
    const x0 = q[0]!;
    const y0 = q[1]!;
    const x1 = q[2]!;
    const y1 = q[3]!;
    const walls = this.segmentWalls(q, 0);
    if (walls === ALL) return this.crossesAll();
    // The segment's bounding box, widened by far more than the roundings of the clipping below:
    // a wall clear of it cannot be met.
    const minX = (x0 < x1 ? x0 : x1) - NEAR;
    const maxX = (x0 < x1 ? x1 : x0) + NEAR;
    const minY = (y0 < y1 ? y0 : y1) - NEAR;
    const maxY = (y0 < y1 ? y1 : y0) + NEAR;
    for (let m = walls; m !== 0; m &= m - 1) {
      const i = 31 - Math.clz32(m & -m);
      const cx = this.cx[i]!;
      const cy = this.cy[i]!;
      const hw = this.hw[i]!;
      const hh = this.hh[i]!;
      if (maxX < cx - hw || minX > cx + hw || maxY < cy - hh || minY > cy + hh) continue;
      if (this.crossesWall(i)) return true;
    }
    return false;
  }

  /**
   * {@link clearQuery} by the all-walls loop. (Apart, as are the other rare paths of the hot
   * queries: V8 inlines a function only up to a size, and a query inlined into its caller saves a
   * call per query.)
   */
  private clearAll(r: number): boolean {
    const q = this.query;
    const x0 = q[0]!;
    const y0 = q[1]!;
    return this.sweepAll(x0, y0, q[2]! - x0, q[3]! - y0, r) < 0;
  }

  /** Writes the registers `query[0…3]` for a register form (the plain forms' first step). */
  private setQuery(a: number, b: number, c: number, d: number): void {
    const q = this.query;
    q[0] = a;
    q[1] = b;
    q[2] = c;
    q[3] = d;
  }

  /**
   * The walls a segment query from (`ends[0]`, `ends[1]`) to (`ends[2]`, `ends[3]`) with radius
   * `r` must test, as a bit mask; {@link ALL} for the all-walls loops (no grid, a radius beyond it,
   * an end off the grid or not finite).
   */
  private segmentWalls(ends: Float64Array, r: number): number {
    const grid = this.grid;
    if (grid === null || !(r <= GRID_MAX_RADIUS)) return ALL;
    const from = grid.cellOf(ends, 0);
    const to = grid.cellOf(ends, 2);
    if (from < 0 || to < 0) return ALL;
    return from === to ? grid.masks[from]! : grid.pairMask(from, to);
  }

  /**
   * Whether a circle of radius `r` making the move in `move` (x, y, dx, dy) touches wall `i`, the
   * fraction of the move at which it does in `reg[SWEPT.u]`: the all-walls loop's test — its
   * bounding-box rejection, then the library's `hitPointRoundedBox` (as {@link pointRoundedBox}).
   */
  private touches(i: number, r: number): boolean {
    const move = this.move;
    const x = move[0]!;
    const y = move[1]!;
    const dx = move[2]!;
    const dy = move[3]!;
    const cx = this.cx[i]!;
    const cy = this.cy[i]!;
    const hw = this.hw[i]! + r;
    const hh = this.hh[i]! + r;
    const minX = dx < 0 ? x + dx : x;
    const maxX = dx < 0 ? x : x + dx;
    const minY = dy < 0 ? y + dy : y;
    const maxY = dy < 0 ? y : y + dy;
    if (maxX <= cx - hw || minX >= cx + hw || maxY <= cy - hh || minY >= cy + hh) return false;
    const reg = this.reg;
    reg[0] = x - cx;
    reg[1] = y - cy;
    reg[2] = dx;
    reg[3] = dy;
    reg[4] = this.hw[i]!;
    reg[5] = this.hh[i]!;
    reg[6] = r;
    return pointRoundedBox(reg);
  }

  // --- The tests against one wall, which the grid's paths above and the all-walls loops below
  // share: only which walls a query visits differs. ---

  // (They take their coordinates from registers, like the register forms: see the class comment.)

  /**
   * Whether a circle of radius `r` at (`query[0]`, `query[1]`) overlaps wall `i` (touching does
   * not count).
   */
  private overlapsWall(i: number, r: number): boolean {
    const dx = Math.abs(this.query[0]! - this.cx[i]!);
    const dy = Math.abs(this.query[1]! - this.cy[i]!);
    const hw = this.hw[i]!;
    const hh = this.hh[i]!;
    if (dx >= hw + r || dy >= hh + r) return false;
    if (dx <= hw || dy <= hh) return true;
    const ex = dx - hw;
    const ey = dy - hh;
    return ex * ex + ey * ey < r * r;
  }

  /**
   * Pushes a circle of radius `r` centred at (`at[0]`, `at[1]`) out of wall `i` by the minimum
   * translation — out through the nearer face — writing its new centre back to `at`. Whether it
   * was pushed (false: at least `r` from the wall, `at` unchanged).
   */
  private pushOutOfWall(i: number, at: Float64Array, r: number): boolean {
    const x = at[0]!;
    const y = at[1]!;
    const cx = this.cx[i]!;
    const cy = this.cy[i]!;
    const hw = this.hw[i]!;
    const hh = this.hh[i]!;
    const dx = x - cx;
    const dy = y - cy;
    const ax = dx < 0 ? -dx : dx;
    const ay = dy < 0 ? -dy : dy;
    if (ax >= hw + r || ay >= hh + r) return false;
    const sx = dx < 0 ? -1 : 1;
    const sy = dy < 0 ? -1 : 1;
    if (ax <= hw && ay <= hh) {
      // Centre inside: leave through the nearer face.
      if (hw - ax <= hh - ay) at[0] = cx + sx * (hw + r);
      else at[1] = cy + sy * (hh + r);
    } else if (ax <= hw) {
      at[1] = cy + sy * (hh + r);
    } else if (ay <= hh) {
      at[0] = cx + sx * (hw + r);
    } else {
      const qx = cx + sx * hw;
      const qy = cy + sy * hh;
      const ex = x - qx;
      const ey = y - qy;
      const d2 = ex * ex + ey * ey;
      if (d2 >= r * r) return false;
      const d = Math.sqrt(d2);
      at[0] = qx + (ex / d) * r;
      at[1] = qy + (ey / d) * r;
    }
    return true;
  }

  /**
   * Whether the segment from (`query[0]`, `query[1]`) to (`query[2]`, `query[3]`) meets wall `i`
   * (closed box): Liang–Barsky, the segment's parameter range [0, 1] clipped to the box's x slab,
   * then its y slab.
   */
  private crossesWall(i: number): boolean {
    const q = this.query;
    const x0 = q[0]!;
    const y0 = q[1]!;
    const dx = q[2]! - x0;
    const dy = q[3]! - y0;
    let t0 = 0;
    let t1 = 1;
    for (let axis = 0; axis < 2; axis++) {
      const p = axis === 0 ? x0 : y0;
      const d = axis === 0 ? dx : dy;
      const c = axis === 0 ? this.cx[i]! : this.cy[i]!;
      const h = axis === 0 ? this.hw[i]! : this.hh[i]!;
      if (d === 0) {
        if (p < c - h || p > c + h) return false;
        continue;
      }
      let a = (c - h - p) / d;
      let b = (c + h - p) / d;
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

  // --- The all-walls loops: the queries as they were before the grid, and still are wherever it
  // does not answer. The grid's paths above must agree with them bit for bit (a test checks). ---

  private overlapsAll(r: number): boolean {
    for (let i = 0; i < this.count; i++) if (this.overlapsWall(i, r)) return true;
    return false;
  }
  private pushOutAll(r: number, out: Float64Array): boolean {
    const at = this.move;
    at[0] = this.query[0]!;
    at[1] = this.query[1]!;
    let any = false;
    for (let pass = 0; pass < 2; pass++) {
      for (let i = 0; i < this.count; i++) if (this.pushOutOfWall(i, at, r)) any = true;
    }
    out[0] = at[0];
    out[1] = at[1];
    return any;
  }
  private sweepAll(x: number, y: number, dx: number, dy: number, r: number): number {
    const move = this.move;
    move[0] = x;
    move[1] = y;
    move[2] = dx;
    move[3] = dy;
    let best = -1;
    for (let i = 0; i < this.count; i++) {
      if (!this.touches(i, r)) continue;
      const u = this.reg[U]!;
      if (u >= 0 && (best < 0 || u < best)) best = u;
    }
    return best;
  }
  private crossesAll(): boolean {
    for (let i = 0; i < this.count; i++) if (this.crossesWall(i)) return true;
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
