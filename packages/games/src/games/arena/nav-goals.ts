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
 * What {@link NavGoals.entries} holds per goal and sub-cell: two numbers, 8 bytes. A bot reads a
 * new entry every other tick or so, and that read is a cache miss more often than not: in a
 * profile of the recorded match, the instruction waiting for it took 5.8 % of the step's samples
 * with entries of 32 bytes, 3 % with 16 and 1.7 % with 8. So nodes are named by their place among
 * the candidates of their cell, and the walls' masks are kept once, in {@link NavGoals.masks},
 * and named by index.
 */
export const ENTRY = {
  /**
   * Flags ({@link FILLED}, {@link GOAL_BLOCKED}, {@link TO_GOAL}, {@link NO_ENTRY}); the
   * candidates the search tries first, in its order ({@link LENGTH_SHIFT}: how many, 0 to 3;
   * {@link PAIR}: the last two are a pair, see {@link NavGoals}), each as its place among the
   * cell's candidates ({@link NODE_SHIFT}, {@link NODE_BITS} bits each); and the index of the
   * mask of the walls in the way of the goal ({@link GOAL_WALLS_SHIFT}).
   */
  head: 0,
  /** The indices of the masks of the walls in the way of each candidate, {@link MASK_BITS} bits each. */
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
/** Where {@link ENTRY.head} says how many candidates it lists (2 bits). */
export const LENGTH_SHIFT = 4;
/** Flag: the last two candidates listed are a pair. */
export const PAIR = 64;
/** Where the candidates' places are in {@link ENTRY.head}. */
export const NODE_SHIFT = 7;
/** Bits per candidate's place. */
export const NODE_BITS = 4;
/** Where the index of the goal's mask is in {@link ENTRY.head}. */
export const GOAL_WALLS_SHIFT = 19;
/** Bits per mask index. */
export const MASK_BITS = 10;
/** The most candidates an entry lists. */
const MAX_LISTED = 3;

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
  /** The search's candidates, and the walls in the way of each from its cell (see `NavGrid.ringStart`). */
  readonly ringStart: Int32Array;
  readonly ringNode: Int32Array;
  readonly ringWalls: Int32Array;
  /** The waypoint nearest a goal (the search's `nearestNode`), or -1. */
  nodeNear(x: number, y: number): number;
}

/** Registers for the swept test of {@link blocksAll}. */
const reg = sweptRegisters();

/**
 * Scratch of {@link NavGoals}' fills (a fill must not allocate: the allocation bench counts the
 * bytes a tick allocates, and bots fill entries as they go): the cell's candidates (at most the
 * 3 × 3 cells') — place, node, bounds of the cost, whether still to be ranked — and the list.
 */
const candidatePlace = new Int32Array(9);
const candidateNode = new Int32Array(9);
const candidateLow = new Float64Array(9);
const candidateHigh = new Float64Array(9);
const candidateLeft = new Uint8Array(9);
const listedPlace = new Int32Array(MAX_LISTED);
const listedMask = new Int32Array(MAX_LISTED);

/** Slots of the hash of the masks' indices (twice the masks: open addressing stays short). */
const MASK_SLOTS = 2 << MASK_BITS;

/**
 * The navigation grid's search for a layout's fixed goals (flag stands, guard posts, lanes), as
 * far as it does not depend on where in a small sub-cell the bot stands. Per goal and sub-cell
 * ({@link ENTRY}):
 *
 * - whether a straight move from the sub-cell to the goal surely meets a wall, else the walls it
 *   can touch (`cellReach`; 0: every such move is clear) — so the search's first question, can
 *   it go straight there, needs no line test or only one against those walls, with no grid
 *   look-up;
 * - the candidates the search tries first, in its order, as far as that order is the same from
 *   anywhere in the sub-cell: each candidate's cost (a distance times a scale, plus a path length)
 *   is bounded over it, and the search's next pick is the one whose highest cost is below every
 *   other's lowest, by more than {@link MARGIN}. One that surely cannot be reached (`blocksAll`)
 *   is passed over — the search's line test would fail; one that surely can (no wall in the way)
 *   ends the list — it is the answer. Where two can be next, they are listed as a pair and the
 *   search's costs of the two, computed as it computes them, tell which it tries (the earlier in
 *   its order of equals), and the list ends. Up to {@link MAX_LISTED}. At a query, the first of
 *   them that a line test against the walls in its way finds clear is the answer; if none is,
 *   the search runs as before.
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
  /** How many of {@link masks} there are. */
  private maskCount = 1;
  /** Where each mask is in {@link masks}: a hash, open addressing, index + 1 (0: free). */
  private readonly maskSlots = new Int32Array(MASK_SLOTS);
  /**
   * Where the candidates of the cell of the last {@link entryOf}'s point begin in the search's
   * list (`NavGrid.ringNode`): an entry's places count from there.
   */
  firstCandidate = 0;
  /** The waypoint nearest each goal (the search's goal node), or -1; -2 until it is needed. */
  private readonly goalNode: Int32Array;
  /**
   * Per goal and navigation cell, the walls in the way of the goal from the cell (`cellReach`),
   * so that a sub-cell's need look at those only; `cellToGoalDone` says which are there yet.
   */
  private readonly cellToGoal: Int32Array;
  private readonly cellToGoalDone: Uint8Array;

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
    this.cellToGoal = new Int32Array(goals.length * grid.cols * grid.rows);
    this.cellToGoalDone = new Uint8Array(goals.length * grid.cols * grid.rows);
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
    const fx = q[0]! / this.size;
    const fy = q[1]! / this.size;
    // (False for NaN too.)
    if (!(fx >= 0 && fy >= 0 && fx < this.subCols && fy < this.subRows)) return -1;
    // Truncation is the floor here: both are ≥ 0.
    const sx = fx | 0;
    const sy = fy | 0;
    const e = STRIDE * ((k * this.subRows + sy) * this.subCols + sx);
    if (this.entries[e] === 0) this.fill(k, sx, sy, e);
    this.firstCandidate =
      this.grid.ringStart[2 * (((sy / SUBDIV) | 0) * this.grid.cols + ((sx / SUBDIV) | 0))]!;
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
    // The walls looked at narrowed down to those in the way from the whole cell: a fill took
    // 3–4 µs before, about 2 µs after (warm code; the recorded match fills 6,371 entries).
    const col = Math.floor(sx / SUBDIV);
    const row = Math.floor(sy / SUBDIV);
    const c = (k * grid.rows + row) * grid.cols + col;
    if (this.cellToGoalDone[c] === 0) {
      const spacing = grid.spacing;
      this.cellToGoal[c] = cellReach(walls, col * spacing, row * spacing, spacing, gx, gy, r);
      this.cellToGoalDone[c] = 1;
    }
    const toGoal = cellReach(walls, x0, y0, size, gx, gy, r, this.cellToGoal[c]);
    let head = FILLED;
    if (blocksAll(walls, toGoal, x0, y0, size, gx, gy, r)) head |= GOAL_BLOCKED;
    const g = this.nodeOf(k);
    if (g < 0) head |= TO_GOAL;
    const listed = g < 0 ? 0 : this.list(g, sx, sy);
    const pair = listed < 0;
    const count = pair ? -listed : listed;
    let goalIndex = this.indexOfMask(toGoal);
    let inTheWay = 0;
    for (let i = 0; i < count && goalIndex >= 0; i++) {
      const index = this.indexOfMask(listedMask[i]!);
      if (index < 0) goalIndex = -1;
      head |= listedPlace[i]! << (NODE_SHIFT + i * NODE_BITS);
      inTheWay |= index << (i * MASK_BITS);
    }
    if (goalIndex < 0) {
      entries[e + ENTRY.head] = FILLED | NO_ENTRY;
      return;
    }
    head |= count << LENGTH_SHIFT;
    if (pair) head |= PAIR;
    head |= goalIndex << GOAL_WALLS_SHIFT;
    entries[e + ENTRY.walls] = inTheWay;
    entries[e + ENTRY.head] = head;
  }

  /** The index of `mask` in {@link masks} (added if new), or -1 when they are full. */
  private indexOfMask(mask: number): number {
    if (mask === 0) return 0;
    const slots = this.maskSlots;
    for (
      let h = Math.imul(mask, 0x9e3779b1) >>> (32 - MASK_BITS - 1);
      ;
      h = (h + 1) & (MASK_SLOTS - 1)
    ) {
      const at = slots[h]!;
      if (at === 0) {
        if (this.maskCount === this.masks.length) return -1;
        this.masks[this.maskCount] = mask;
        slots[h] = ++this.maskCount;
        return this.maskCount - 1;
      }
      if (this.masks[at - 1] === mask) return at - 1;
    }
  }

  /**
   * The candidates the search tries first toward goal node `g` from anywhere in sub-cell (sx, sy)
   * (see {@link NavGoals}), into `listedPlace` (their places among the cell's candidates, the 3 × 3
   * cells around it) and `listedMask` (the walls in the way of each): how many, negative when the
   * last two are a pair.
   */
  private list(g: number, sx: number, sy: number): number {
    const grid = this.grid;
    const size = this.size;
    const x0 = sx * size;
    const y0 = sy * size;
    const cell = 2 * (Math.floor(sy / SUBDIV) * grid.cols + Math.floor(sx / SUBDIV));
    const left = x0 - EDGE;
    const right = x0 + size + EDGE;
    const top = y0 - EDGE;
    const bottom = y0 + size + EDGE;
    // The candidates with a way to the goal: place, node, bounds of the cost.
    const start = grid.ringStart[cell]!;
    let n = 0;
    for (let j = start, end = grid.ringStart[cell + 1]!; j < end; j++) {
      const nd = grid.ringNode[j]!;
      const rest = grid.rest(nd, g);
      if (rest === grid.unreachable) continue;
      const nx = grid.nodeX[nd]!;
      const ny = grid.nodeY[nd]!;
      const nearX = Math.max(left - nx, 0, nx - right);
      const nearY = Math.max(top - ny, 0, ny - bottom);
      const farX = Math.max(nx - left, right - nx);
      const farY = Math.max(ny - top, bottom - ny);
      candidatePlace[n] = j - start;
      candidateNode[n] = nd;
      candidateLow[n] = Math.sqrt(nearX * nearX + nearY * nearY) * grid.scale + rest;
      candidateHigh[n] = Math.sqrt(farX * farX + farY * farY) * grid.scale + rest;
      candidateLeft[n] = 1;
      n++;
    }
    let listed = 0;
    for (let remaining = n; listed < MAX_LISTED && remaining > 0; remaining--) {
      let leastHigh = Infinity;
      for (let c = 0; c < n; c++) {
        if (candidateLeft[c] === 1) leastHigh = Math.min(leastHigh, candidateHigh[c]!);
      }
      // Those that can be next (in the search's order), the first two of them.
      let next = -1;
      let after = -1;
      let many = false;
      for (let c = 0; c < n; c++) {
        if (candidateLeft[c] === 0 || !(candidateLow[c]! <= leastHigh + MARGIN)) continue;
        if (next < 0) next = c;
        else if (after < 0) after = c;
        else many = true;
      }
      if (many || (after >= 0 && listed + 2 > MAX_LISTED)) break;
      if (after >= 0) {
        listedPlace[listed] = candidatePlace[next]!;
        listedMask[listed] = this.reach(start, candidatePlace[next]!, candidateNode[next]!, x0, y0);
        listedPlace[listed + 1] = candidatePlace[after]!;
        listedMask[listed + 1] = this.reach(
          start,
          candidatePlace[after]!,
          candidateNode[after]!,
          x0,
          y0,
        );
        listed += 2;
        return -listed;
      }
      candidateLeft[next] = 0;
      const nd = candidateNode[next]!;
      const mask = this.reach(start, candidatePlace[next]!, nd, x0, y0);
      // Surely out of reach: the search's line test fails; it goes on to the next.
      const r = grid.clearance;
      if (blocksAll(grid.walls, mask, x0, y0, size, grid.nodeX[nd]!, grid.nodeY[nd]!, r)) continue;
      listedPlace[listed] = candidatePlace[next]!;
      listedMask[listed] = mask;
      listed++;
      // Surely in reach: the answer.
      if (mask === 0) break;
    }
    return listed;
  }

  /**
   * The walls in the way of node `nd`, at `place` among the candidates from `start` in the
   * search's list, from the sub-cell at (x0, y0) (of those in its way from the whole cell).
   */
  private reach(start: number, place: number, nd: number, x0: number, y0: number): number {
    const grid = this.grid;
    const only = grid.ringWalls[start + place]!;
    return cellReach(
      grid.walls,
      x0,
      y0,
      this.size,
      grid.nodeX[nd]!,
      grid.nodeY[nd]!,
      grid.clearance,
      only,
    );
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
