import type { Walls } from './walls.js';
import { cellReach } from './cell-reach.js';
import { pointRoundedBox, sweptRegisters } from './swept.js';

/**
 * Sub-cells per navigation cell along each axis: a power of two, so that a point's sub-cell lies
 * in the cell the search takes it to be in (`floor(x / (spacing / 8))` is exactly 8 ×
 * `floor(x / spacing)` plus 0 to 7: dividing by a power of two more rounds the same way). With the
 * 40-unit cells of both arenas, sub-cells of 5 units: small enough that the waypoint's cost (a
 * distance from the bot plus a path length) ranks the candidates the same way from anywhere in
 * most sub-cells.
 */
const SUBDIV = 8;

/**
 * How much more than the least highest cost a candidate's lowest must be for the table to leave it
 * out: far more than the rounding of the search's costs (≈ 1e-13 for costs of a few hundred).
 */
const MARGIN = 1e-6;

/** How far beyond its sub-cell a point may round (≈ 1e-13 units): the bounds allow for far more. */
const EDGE = 1e-6;

/**
 * What {@link NavGoals.entries} holds per goal and sub-cell: two numbers, 8 bytes. The table is
 * read at random, once per bot and tick, and its look-up is a cache miss more often than not
 * (on a busy machine, other processes evict it between ticks): at 32 bytes an entry it cost 6 % of
 * a capture-the-flag step, at 16 bytes 5 %, so the walls' masks are kept once, in
 * {@link NavGoals.masks}, and an entry holds their indices.
 */
export const ENTRY = {
  /**
   * Flags ({@link FILLED}, {@link GOAL_BLOCKED}, {@link TO_GOAL}, {@link NO_ENTRY}), and the
   * search's candidates that can come first (the cheapest) from somewhere in the sub-cell: one or
   * two nodes in the search's order, each plus one at {@link FIRST_SHIFT} and
   * {@link SECOND_SHIFT} ({@link NODE_BITS} bits; 0: none). No first one: more than two can.
   */
  head: 0,
  /**
   * The walls that a straight move from the sub-cell can touch — to the goal, to the first and
   * to the second candidate — as indices in {@link NavGoals.masks}, {@link MASK_BITS} bits each
   * from bit 0 up.
   */
  walls: 1,
} as const;

/** Numbers per entry. */
const STRIDE = 2;

/** Flag: the entry is filled (0: not yet, the table's memory untouched). */
const FILLED = 1;
/** Flag: every straight move from the sub-cell to the goal touches a wall (see `blocksAll`). */
export const GOAL_BLOCKED = 2;
/** Flag: the goal has no waypoint — when it is not in reach, the search heads for it anyway. */
export const TO_GOAL = 4;
/** Flag: the entry knows nothing (the layout has more masks than an index can name): search. */
export const NO_ENTRY = 8;
/** Where the candidates' nodes (plus one) are in {@link ENTRY.head}. */
export const FIRST_SHIFT = 4;
export const SECOND_SHIFT = 18;
/** Bits per node in {@link ENTRY.head}: grids of more nodes have no table. */
export const NODE_BITS = 14;
/** The most nodes a grid with a table may have. */
export const MAX_NODES = (1 << NODE_BITS) - 2;
/** Bits per mask index in {@link ENTRY.walls}. */
export const MASK_BITS = 10;

/**
 * Arena units by which a move must miss (or enter) a wall's grown box for the table to take the
 * walls' test's answer for granted: as `cellReach`'s slack, a million times any rounding.
 */
const SLACK = 1;

/** What {@link NavGoals} needs of a `NavGrid`: its layout and its search's tables. */
export interface NavGoalsGrid {
  readonly walls: Walls;
  readonly spacing: number;
  readonly cols: number;
  readonly rows: number;
  readonly clearance: number;
  readonly nodeX: Float64Array;
  readonly nodeY: Float64Array;
  /** The search's unreachable path length. */
  readonly unreachable: number;
  /** The search's cost of a unit of distance to a waypoint. */
  readonly scale: number;
  /** The path length from node `nd` to node `g`. */
  rest(nd: number, g: number): number;
  /** The search's candidates (see `NavGrid.ringStart`). */
  readonly ringStart: Int32Array;
  readonly ringNode: Int32Array;
  /** The waypoint nearest a goal (the search's `nearestNode`), or -1. */
  nodeNear(x: number, y: number): number;
}

/** Registers for the swept test of {@link blocksAll}. */
const reg = sweptRegisters();

/**
 * The navigation grid's search for a layout's fixed goals (flag stands, guard posts, lanes), as
 * far as it does not depend on where in a small sub-cell the bot stands. Per goal and sub-cell
 * ({@link ENTRY}):
 *
 * - whether a straight move from the sub-cell to the goal surely meets a wall, else the walls it
 *   can touch (`cellReach`; 0: every such move is clear) — so the search's first question, can
 *   it go straight there, needs no line test or only one against those walls, with no grid
 *   look-up;
 * - the one or two candidate waypoints that can be the search's first pick (the cheapest) from
 *   somewhere in the sub-cell — every other one costs more than they do from anywhere in it, by
 *   more than {@link MARGIN} — with their path lengths and the walls in the way of each. The
 *   search's costs of those two, computed as it computes them, tell which it picks first (the
 *   earlier in its order of equals); when the way there is clear, the search stops there: that
 *   is its answer. Otherwise the search runs as before.
 *
 * Filled entry by entry as bots come by (a few µs each), then kept: static data of the layout,
 * not game state — so the answers are the search's, whatever is filled. The table's memory is
 * touched only where bots go.
 */
export class NavGoals {
  /** Goal k at (`goalX[k]`, `goalY[k]`). */
  readonly goalX: Float64Array;
  readonly goalY: Float64Array;
  /** Sub-cell size, arena units. */
  readonly size: number;
  readonly subCols: number;
  readonly subRows: number;
  /**
   * Per goal and sub-cell (`k × subCols × subRows + row × subCols + col`), {@link STRIDE}
   * numbers at the offsets of {@link ENTRY}.
   */
  readonly entries: Int32Array;
  /** The walls' masks that the entries name (bit i: wall i), 0 first. */
  readonly masks = new Int32Array(1 << MASK_BITS);
  /** Where each mask is in {@link masks}. */
  private readonly maskIndex = new Map<number, number>([[0, 0]]);
  /** The waypoint nearest each goal (the search's goal node), or -1; -2 until it is needed. */
  private readonly goalNode: Int32Array;

  constructor(
    private readonly grid: NavGoalsGrid,
    goals: readonly (readonly [number, number])[],
  ) {
    this.goalX = Float64Array.from(goals, (g) => g[0]);
    this.goalY = Float64Array.from(goals, (g) => g[1]);
    this.size = grid.spacing / SUBDIV;
    this.subCols = grid.cols * SUBDIV;
    this.subRows = grid.rows * SUBDIV;
    this.entries = new Int32Array(STRIDE * goals.length * this.subCols * this.subRows);
    this.goalNode = new Int32Array(goals.length).fill(-2);
  }

  /** The goal at (`q[2]`, `q[3]`), or -1. */
  indexOf(q: Float64Array): number {
    const x = q[2]!;
    const y = q[3]!;
    const gx = this.goalX;
    for (let k = 0; k < gx.length; k++) {
      if (gx[k] === x && this.goalY[k] === y) return k;
    }
    return -1;
  }

  /**
   * Where goal k's entry for the point (`q[0]`, `q[1]`) begins in {@link entries} (filled now if
   * it was not), or -1 when the point is off the grid or not finite.
   */
  entryOf(k: number, q: Float64Array): number {
    const sx = Math.floor(q[0]! / this.size);
    const sy = Math.floor(q[1]! / this.size);
    // (False for NaN too.)
    if (!(sx >= 0 && sy >= 0 && sx < this.subCols && sy < this.subRows)) return -1;
    const e = STRIDE * ((k * this.subRows + sy) * this.subCols + sx);
    if (this.entries[e] === 0) this.fill(k, sx, sy, e);
    return e;
  }

  /** The search's goal node of goal k. */
  nodeOf(k: number): number {
    if (this.goalNode[k] === -2) {
      this.goalNode[k] = this.grid.nodeNear(this.goalX[k]!, this.goalY[k]!);
    }
    return this.goalNode[k]!;
  }

  private fill(k: number, sx: number, sy: number, e: number): void {
    const grid = this.grid;
    const size = this.size;
    const x0 = sx * size;
    const y0 = sy * size;
    const gx = this.goalX[k]!;
    const gy = this.goalY[k]!;
    const walls = grid.walls;
    const r = grid.clearance;
    const entries = this.entries;
    const toGoal = cellReach(walls, x0, y0, size, gx, gy, r);
    let head = FILLED;
    if (blocksAll(walls, toGoal, x0, y0, size, gx, gy, r)) head |= GOAL_BLOCKED;
    const g = this.nodeOf(k);
    const [first, second] = g < 0 ? [-1, -1] : this.contenders(g, sx, sy);
    if (g < 0) head |= TO_GOAL;
    head |= ((first + 1) << FIRST_SHIFT) | ((second + 1) << SECOND_SHIFT);
    const reach = (nd: number): number =>
      nd < 0 ? 0 : cellReach(walls, x0, y0, size, grid.nodeX[nd]!, grid.nodeY[nd]!, r);
    const indices = [toGoal, reach(first), reach(second)].map((m) => this.indexOfMask(m));
    if (indices.includes(-1)) {
      entries[e + ENTRY.head] = FILLED | NO_ENTRY;
      return;
    }
    entries[e + ENTRY.walls] =
      indices[0]! | (indices[1]! << MASK_BITS) | (indices[2]! << (2 * MASK_BITS));
    entries[e + ENTRY.head] = head;
  }

  /** The index of `mask` in {@link masks} (added if new), or -1 when they are full. */
  private indexOfMask(mask: number): number {
    let i = this.maskIndex.get(mask);
    if (i === undefined) {
      i = this.maskIndex.size;
      if (i === this.masks.length) return -1;
      this.masks[i] = mask;
      this.maskIndex.set(mask, i);
    }
    return i;
  }

  /**
   * The search's candidates (among the 3 × 3 cells around the sub-cell's) for goal node `g` that
   * can be the cheapest from somewhere in sub-cell (sx, sy), in the search's order: each
   * candidate's cost bounded over the sub-cell (its distance from the nearest and the farthest
   * point, times the scale, plus its path length to `g`); those whose lowest cost is within
   * {@link MARGIN} of the least highest one can. [-1, -1] when none or more than two can; the second
   * -1 when one can.
   */
  private contenders(g: number, sx: number, sy: number): [number, number] {
    const grid = this.grid;
    const cell = 2 * (Math.floor(sy / SUBDIV) * grid.cols + Math.floor(sx / SUBDIV));
    const left = sx * this.size - EDGE;
    const right = (sx + 1) * this.size + EDGE;
    const top = sy * this.size - EDGE;
    const bottom = (sy + 1) * this.size + EDGE;
    const nodes: number[] = [];
    const lows: number[] = [];
    let leastHigh = Infinity;
    for (let j = grid.ringStart[cell]!, end = grid.ringStart[cell + 1]!; j < end; j++) {
      const nd = grid.ringNode[j]!;
      const rest = grid.rest(nd, g);
      if (rest === grid.unreachable) continue;
      const nx = grid.nodeX[nd]!;
      const ny = grid.nodeY[nd]!;
      const nearX = Math.max(left - nx, 0, nx - right);
      const nearY = Math.max(top - ny, 0, ny - bottom);
      const farX = Math.max(nx - left, right - nx);
      const farY = Math.max(ny - top, bottom - ny);
      nodes.push(nd);
      lows.push(Math.sqrt(nearX * nearX + nearY * nearY) * grid.scale + rest);
      leastHigh = Math.min(leastHigh, Math.sqrt(farX * farX + farY * farY) * grid.scale + rest);
    }
    const can = nodes.filter((_, i) => lows[i]! <= leastHigh + MARGIN);
    if (can.length === 0 || can.length > 2) return [-1, -1];
    return [can[0]!, can[1] ?? -1];
  }
}

/**
 * Whether every straight move of a circle of radius `r` from the square [x0, x0 + size]² to
 * (gx, gy) surely touches one of the walls of `mask` (by the walls' swept test, starting outside
 * it): true when one wall is more than `r` + {@link SLACK} from the square and the moves from its
 * four corners come within `r` − {@link SLACK} of it. The wall grown by `r` − SLACK is convex, so
 * it meets the move from any point of the square too (that point is a weighted mean of the
 * corners, and the move from it crosses the hull of where the corners' moves meet the wall); and
 * the move starts outside the wall grown by `r`, so it enters it by more than SLACK — far beyond
 * any rounding of the swept test.
 */
function blocksAll(
  walls: Walls,
  mask: number,
  x0: number,
  y0: number,
  size: number,
  gx: number,
  gy: number,
  r: number,
): boolean {
  for (let m = mask; m !== 0; m &= m - 1) {
    const i = 31 - Math.clz32(m & -m);
    const cx = walls.cx[i]!;
    const cy = walls.cy[i]!;
    const hw = walls.hw[i]!;
    const hh = walls.hh[i]!;
    const gapX = Math.max(cx - hw - (x0 + size), x0 - (cx + hw), 0);
    const gapY = Math.max(cy - hh - (y0 + size), y0 - (cy + hh), 0);
    if (!(Math.sqrt(gapX * gapX + gapY * gapY) > r + SLACK)) continue;
    let all = true;
    for (let c = 0; c < 4 && all; c++) {
      const px = x0 + (c & 1) * size;
      const py = y0 + (c >> 1) * size;
      reg[0] = px - cx;
      reg[1] = py - cy;
      reg[2] = gx - px;
      reg[3] = gy - py;
      reg[4] = hw;
      reg[5] = hh;
      reg[6] = r - SLACK;
      all = pointRoundedBox(reg);
    }
    if (all) return true;
  }
  return false;
}
