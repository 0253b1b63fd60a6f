import type { Rect } from './walls.js';

/**
 * The largest radius the grid answers for, arena units. Every radius the games use is smaller
 * (bullets 2, lines of sight 6, enemies 9, players 10, the bots' clearance 12, the nav grid's 13);
 * a larger one takes the walls' all-walls path.
 */
export const GRID_MAX_RADIUS = 16;

/** The most walls a layout may have for the grid (one bit per wall in a 32-bit mask). */
export const GRID_MAX_WALLS = 32;

/**
 * Slack around every wall's reach, arena units: more than a thousand million times any rounding
 * error of the queries (≈ 1e-12 on an arena a thousand units across), so what the grid leaves
 * out can never be a near miss that rounding would have turned into a hit.
 */
const SLACK = 1;

/** How far a wall's reach extends past its box: the largest radius plus the slack. */
const REACH = GRID_MAX_RADIUS + SLACK;

/** Entries of the cache of cell pairs' masks (a power of two: indexed by a hash's top bits). */
const PAIR_CACHE_BITS = 16;

/** Cells are at least this big, arena units. */
const MIN_CELL = 32;

/**
 * At most this many cells along either axis (a huge layout gets bigger cells, not more), so a pair
 * of cells has a key below 2³¹.
 */
const MAX_CELLS_PER_AXIS = 128;

/**
 * A broad phase for the static walls of a layout of up to {@link GRID_MAX_WALLS} walls: a uniform
 * grid whose cells hold a bit mask (bit i: wall i) of every wall whose *reach* — its box grown by
 * {@link GRID_MAX_RADIUS} plus a slack — touches the cell.
 *
 * It only ever narrows down which walls the exact tests of `Walls` look at, never what those tests
 * compute, and it leaves out only walls that the exact tests would pass over (no overlap, no hit,
 * no crossing): so the answers stay bit for bit those of the all-walls loops. Why:
 *
 * - A circle of radius `r ≤ GRID_MAX_RADIUS` centred at p can overlap a wall only if p lies in
 *   the wall's reach at least {@link SLACK} inside its edge, so p's cell has the wall's bit.
 * - A swept circle (or a segment, `r = 0`) can touch a wall only at a point p of its path within
 *   `r` plus rounding of the wall's box, which again lies well inside the reach. A path within
 *   one cell: that cell's walls. From one cell to another: every wall whose reach comes within
 *   half a cell (along each axis) of the segment between the two cells' centres, which every
 *   point of the path is ({@link WallGrid.pairMask}).
 * - The grid covers every wall's reach. A query with a point or an end off it (or not finite)
 *   gets no answer here: `Walls` runs its all-walls loop.
 *
 * Built once per layout from its walls (static data, not game state); queries allocate nothing.
 */
export class WallGrid {
  /** Cell size, arena units. */
  readonly cell: number;
  readonly cols: number;
  readonly rows: number;
  /** The grid's top-left corner, arena units. */
  readonly originX: number;
  readonly originY: number;
  /** The walls near each cell (`row * cols + col`), one bit per wall. */
  readonly masks: Int32Array;
  private readonly inverse: number;
  private readonly cells: number;
  private readonly rects: readonly Rect[];
  /**
   * The pairs' cache, 4 numbers an entry so that a look-up reads one cache line: the pair's key
   * (`from × cells + to`; -1: empty), its mask (see {@link fillPair}), and the radii for which every
   * move between the two cells surely touches a wall of it, in 1/256 units: a circle of radius r
   * with `lo < 256 r < hi` moving in a straight line from anywhere in the first cell to anywhere
   * in the second touches one, with {@link SLACK} to spare ({@link blockOf}, lo rounded up and hi
   * down; lo ≥ hi when no wall is sure to). Static, like the masks.
   */
  readonly pairs = new Int32Array(4 << PAIR_CACHE_BITS).fill(-1);
  /** {@link blockOf}'s answer. */
  private readonly block = new Float64Array(2);

  /** `rects`: at most {@link GRID_MAX_WALLS}, with finite coordinates (checked by the caller). */
  constructor(rects: readonly Rect[]) {
    let x0 = Infinity;
    let y0 = Infinity;
    let x1 = -Infinity;
    let y1 = -Infinity;
    for (const r of rects) {
      x0 = Math.min(x0, r.x0 - REACH);
      y0 = Math.min(y0, r.y0 - REACH);
      x1 = Math.max(x1, r.x1 + REACH);
      y1 = Math.max(y1, r.y1 + REACH);
    }
    if (rects.length === 0) {
      x0 = y0 = 0;
      x1 = y1 = MIN_CELL;
    }
    this.cell = Math.max(MIN_CELL, Math.ceil(Math.max(x1 - x0, y1 - y0) / MAX_CELLS_PER_AXIS));
    this.inverse = 1 / this.cell;
    this.originX = x0;
    this.originY = y0;
    this.cols = Math.max(1, Math.ceil((x1 - x0) * this.inverse));
    this.rows = Math.max(1, Math.ceil((y1 - y0) * this.inverse));
    const cols = this.cols;
    this.masks = new Int32Array(cols * this.rows);
    rects.forEach((r, wall) => {
      const c0 = this.col(r.x0 - REACH);
      const c1 = this.col(r.x1 + REACH);
      for (let row = this.row(r.y0 - REACH); row <= this.row(r.y1 + REACH); row++) {
        for (let col = c0; col <= c1; col++) this.masks[row * cols + col]! |= 1 << wall;
      }
    });
    this.cells = cols * this.rows;
    this.rects = rects;
  }

  /** The column of x, clamped onto the grid (for building it). */
  private col(x: number): number {
    const c = Math.floor((x - this.originX) * this.inverse);
    return c < 0 ? 0 : c >= this.cols ? this.cols - 1 : c;
  }

  /** The row of y, clamped onto the grid (for building it). */
  private row(y: number): number {
    const r = Math.floor((y - this.originY) * this.inverse);
    return r < 0 ? 0 : r >= this.rows ? this.rows - 1 : r;
  }

  /**
   * The cell (`row * cols + col`) of the point (`p[at]`, `p[at + 1]`), or -1 off the grid (and for
   * coordinates that are not finite). A circle there of radius up to {@link GRID_MAX_RADIUS} can
   * overlap only the walls of `masks[cell]`. (The point comes in an array: V8 boxes a fractional
   * number passed to a call it does not inline.)
   */
  cellOf(p: Float64Array, at: number): number {
    const col = (p[at]! - this.originX) * this.inverse;
    const row = (p[at + 1]! - this.originY) * this.inverse;
    if (!(col >= 0 && col < this.cols && row >= 0 && row < this.rows)) return -1;
    // Truncation is the floor here: both are ≥ 0.
    return (row | 0) * this.cols + (col | 0);
  }

  /**
   * The walls that a circle of radius up to {@link GRID_MAX_RADIUS} moving from anywhere in cell
   * `from` to anywhere in cell `to` can touch (and more), remembered (see {@link fillPair}).
   */
  pairMask(from: number, to: number): number {
    return this.pairs[this.pairSlot(from, to) + 1]!;
  }

  /**
   * Where in {@link pairs} the entry of the pair (`from`, `to`) of different cells begins, filled
   * now if it held another pair.
   */
  pairSlot(from: number, to: number): number {
    const key = from * this.cells + to;
    const slot = (Math.imul(key, 0x9e3779b1) >>> (32 - PAIR_CACHE_BITS)) << 2;
    if (this.pairs[slot] === key) return slot;
    return this.fillPair(from, to, key, slot);
  }

  /**
   * {@link pairSlot} when the entry holds another pair: fills it with this one. Apart from the
   * look-up, and in one piece with the mask's loop: V8 inlines only small functions, and this rare
   * path inlined into the queries would use up what V8 inlines there.
   */
  private fillPair(from: number, to: number, key: number, slot: number): number {
    const pairs = this.pairs;
    // The mask: the walls that a segment from anywhere in cell `from` to anywhere in cell `to` can
    // come within GRID_MAX_RADIUS of (and more). Every such segment lies within half a cell (along
    // each axis) of the segment joining the two cells' centres — the set of them is that segment
    // grown by the square of a cell — so it can come that near a wall only if the centres' segment
    // meets the wall's box grown by the reach plus half a cell. Liang–Barsky against that box
    // grown by one more unit, so its own rounding cannot leave a wall out.
    const cols = this.cols;
    const half = this.cell / 2;
    const x0 = this.originX + (from % cols) * this.cell + half;
    const y0 = this.originY + Math.floor(from / cols) * this.cell + half;
    const dx = this.originX + (to % cols) * this.cell + half - x0;
    const dy = this.originY + Math.floor(to / cols) * this.cell + half - y0;
    const grow = REACH + half + SLACK;
    const rects = this.rects;
    let m = 0;
    for (let i = 0; i < rects.length; i++) {
      const r = rects[i]!;
      if (segmentMeetsBox(x0, y0, dx, dy, r.x0 - grow, r.y0 - grow, r.x1 + grow, r.y1 + grow)) {
        m |= 1 << i;
      }
    }
    this.blockOf(from, to, m);
    // Radii beyond 32 matter to no query of the grid (at most GRID_MAX_RADIUS).
    const lo = Math.ceil(Math.min(this.block[0]!, 32) * 256);
    const hi = Math.floor(Math.min(this.block[1]!, 32) * 256);
    pairs[slot] = key;
    pairs[slot + 1] = m;
    pairs[slot + 2] = lo < hi ? lo : 0;
    pairs[slot + 3] = lo < hi ? hi : 0;
    return slot;
  }

  /**
   * The radii r (lo < r < hi, to `block[0]`, `block[1]`; lo ≥ hi: none) for which a circle of
   * radius r moving in a straight line from anywhere in cell `from` to anywhere in cell `to`
   * surely touches one of the walls of `mask`: the swept test would say so for every such move.
   *
   * A wall does when the first cell lies on one side of it, clear of it by more than r plus
   * {@link SLACK} along one axis (so the move starts outside the wall grown by r and enters it),
   * the second cell lies beyond the wall's centre line across that axis (so every move crosses
   * that line), and every such move crosses the centre line within the wall's half-length plus r,
   * less {@link SLACK}: inside the grown wall (its rounded corners are off the centre line). Where
   * the moves cross the line is the hull of the two cells cut by it: its ends are on segments
   * between a corner of each cell. Of the walls' intervals, those that overlap are joined and the
   * widest kept.
   */
  private blockOf(from: number, to: number, mask: number): void {
    const cols = this.cols;
    const size = this.cell;
    const ax0 = this.originX + (from % cols) * size;
    const ay0 = this.originY + Math.floor(from / cols) * size;
    const bx0 = this.originX + (to % cols) * size;
    const by0 = this.originY + Math.floor(to / cols) * size;
    let lo = 0;
    let hi = 0;
    for (let m = mask; m !== 0; m &= m - 1) {
      const r = this.rects[31 - Math.clz32(m & -m)]!;
      const cx = (r.x0 + r.x1) / 2;
      const cy = (r.y0 + r.y1) / 2;
      const hw = (r.x1 - r.x0) / 2;
      const hh = (r.y1 - r.y0) / 2;
      // Across the wall's vertical centre line, then across its horizontal one.
      for (let axis = 0; axis < 2; axis++) {
        const block = this.block;
        if (axis === 0) crossing(ax0, ay0, bx0, by0, size, cx, cy, hw, hh, block);
        else crossing(ay0, ax0, by0, bx0, size, cy, cx, hh, hw, block);
        const l = block[0]!;
        const h = block[1]!;
        if (!(l < h)) continue;
        if (lo < hi && l <= hi && lo <= h) {
          lo = Math.min(lo, l);
          hi = Math.max(hi, h);
        } else if (!(lo < hi) || coverage(l, h) > coverage(lo, hi)) {
          lo = l;
          hi = h;
        }
      }
    }
    this.block[0] = lo;
    this.block[1] = hi;
  }
}

/** Whether the segment from (x0, y0) by (dx, dy) meets the closed box [bx0, bx1] × [by0, by1]. */
/** How much of the grid's radii, 0 to {@link GRID_MAX_RADIUS}, the interval (lo, hi) holds. */
function coverage(lo: number, hi: number): number {
  return Math.min(hi, GRID_MAX_RADIUS) - Math.max(lo, 0);
}

/**
 * {@link WallGrid}'s `blockOf` for one wall and one axis, written with u along the axis and v
 * across it: the cells [au0, au0 + size] × [av0, av0 + size] (the start) and from bu0, bv0 (the
 * end), the wall centred at (cu, cv), half-extents hu, hv. The radii (lo, hi) for which every move
 * from the first cell to the second surely enters the wall grown by the radius through its centre
 * line u = cu, to `out[0]`, `out[1]` (lo ≥ hi: none).
 */
function crossing(
  au0: number,
  av0: number,
  bu0: number,
  bv0: number,
  size: number,
  cu: number,
  cv: number,
  hu: number,
  hv: number,
  out: Float64Array,
): void {
  out[0] = 0;
  out[1] = 0;
  const au1 = au0 + size;
  const bu1 = bu0 + size;
  // The start clear of the grown wall along u (r < gap − SLACK), the end beyond the centre line.
  let gap: number;
  if (au1 < cu && bu0 > cu + SLACK) gap = cu - hu - au1;
  else if (au0 > cu && bu1 < cu - SLACK) gap = au0 - (cu + hu);
  else return;
  const hi = gap - SLACK;
  if (!(hi > 0)) return;
  // Where the moves cross u = cu: between a corner of each cell.
  let vMin = Infinity;
  let vMax = -Infinity;
  for (let j = 0; j < 4; j++) {
    const pu = (j & 1) === 0 ? au0 : au1;
    const pv = (j & 2) === 0 ? av0 : av0 + size;
    for (let k = 0; k < 4; k++) {
      const qu = (k & 1) === 0 ? bu0 : bu1;
      const qv = (k & 2) === 0 ? bv0 : bv0 + size;
      const v = pv + ((qv - pv) * (cu - pu)) / (qu - pu);
      vMin = Math.min(vMin, v);
      vMax = Math.max(vMax, v);
    }
  }
  // Within hv + r − SLACK of the centre: r > (farthest − hv) + SLACK.
  const lo = Math.max(vMax - cv, cv - vMin) - hv + SLACK;
  out[0] = Math.max(lo, 0);
  out[1] = hi;
}

function segmentMeetsBox(
  x0: number,
  y0: number,
  dx: number,
  dy: number,
  bx0: number,
  by0: number,
  bx1: number,
  by1: number,
): boolean {
  let t0 = 0;
  let t1 = 1;
  if (dx === 0) {
    if (x0 < bx0 || x0 > bx1) return false;
  } else {
    let a = (bx0 - x0) / dx;
    let b = (bx1 - x0) / dx;
    if (a > b) [a, b] = [b, a];
    t0 = Math.max(t0, a);
    t1 = Math.min(t1, b);
    if (t0 > t1) return false;
  }
  if (dy === 0) return y0 >= by0 && y0 <= by1;
  let a = (by0 - y0) / dy;
  let b = (by1 - y0) / dy;
  if (a > b) [a, b] = [b, a];
  return Math.max(t0, a) <= Math.min(t1, b);
}
