import type { Walls } from './walls.js';
import { isFiniteNumber } from './motion.js';
import { REACH_UNKNOWN, cellReach } from './cell-reach.js';
import { UNREACHABLE, shortestPaths } from './nav-paths.js';
import {
  ENTRY,
  GOAL_BLOCKED,
  GOAL_WALLS_SHIFT,
  LENGTH_SHIFT,
  MASK_BITS,
  NODE_BITS,
  NODE_SHIFT,
  NO_ENTRY,
  NavGoals,
  PAIR,
  TO_GOAL,
} from './nav-goals.js';

/** Integer edge costs: orthogonal 5, diagonal 7 (≈ 5√2), so path lengths are exact integers. */
const ORTHO = 5;
const DIAG = 7;

/** Scratch for {@link NavGrid.waypoint}'s goal search; never part of any state. */
const goal = new Int32Array(1);
/**
 * Scratch: the candidate waypoints of a search (at most the 5 × 5 cells), their costs, and the
 * walls a body going straight to each may meet (see {@link NavGrid}'s `ringWalls`).
 */
const candidateNode = new Int32Array(25);
const candidateCost = new Float64Array(25);
const candidateWalls = new Int32Array(25);
/** Scratch: the bits of two coordinates, for {@link NavGrid.nearestNode}'s memo. */
const bits = new Float64Array(2);
const words = new Int32Array(bits.buffer);

/** Entries of {@link NavGrid.nearestNode}'s memo (a power of two: indexed by a hash's top bits). */
const MEMO_BITS = 6;

/**
 * Navigation for the bots: a grid of waypoints at cell centres (those a body of radius
 * `clearance` can stand on), linked to their eight neighbours when a body can move straight
 * between them, with all-pairs shortest path lengths (Dijkstra from every node, integer costs).
 *
 * Built once per arena layout from its walls (static data, not game state; a few ms). Queries are
 * pure functions of their arguments, so a bot that uses them stays deterministic and read-only.
 */
export class NavGrid {
  readonly cols: number;
  readonly rows: number;
  /** Cell size, arena units. */
  readonly spacing: number;
  /** The radius of the body the grid is built for. */
  readonly clearance: number;
  /** Number of waypoints. */
  readonly count: number;
  /** Node index of each cell (`row * cols + col`), or -1 where no body fits. */
  readonly cellNode: Int32Array;
  readonly nodeX: Float64Array;
  readonly nodeY: Float64Array;
  /** Shortest path cost from node i to node j at `i * count + j` (5 per cell straight, 7 diagonal). */
  readonly dist: Int32Array;
  /**
   * The registers of {@link waypointQuery}: from (x, y) in `[0]`, `[1]` to (tx, ty) in `[2]`,
   * `[3]`. Scratch, never part of any state.
   */
  readonly query = new Float64Array(4);
  /** {@link nearestNode}'s point. */
  private readonly point = new Float64Array(2);

  /**
   * Whether `dist` is symmetric (every layout so far: moving straight between two waypoints is
   * clear both ways or neither). Then the costs *to* a goal are its row, in a few cache lines,
   * rather than a column strided across the whole table.
   */
  private readonly symmetric: boolean;

  /**
   * The candidates of the searches, per cell (`row * cols + col`): the waypoints of the 3 × 3
   * cells around it, then those of the ring of the 5 × 5 around those, each in row-major order —
   * what the searches' loops over the neighbouring cells visit, without the bounds and empty
   * cells. Cell c's 3 × 3 are `ringNode[ringStart[2c] … ringStart[2c + 1] − 1]`, its ring up to
   * `ringStart[2c + 2]`.
   */
  private readonly ringStart: Int32Array;
  private readonly ringNode: Int32Array;
  /**
   * Per entry of `ringNode`: the walls a body of radius `clearance` going straight from anywhere
   * in the cell to the waypoint may meet (`cellReach`, static, from the walls). 0: none — the
   * walls' test would say it is clear, so the searches skip it; otherwise they test those walls
   * only (`Walls.clearAmongQuery`), with no grid look-up.
   */
  private readonly ringWalls: Int32Array;

  /** {@link nearestNode}'s last answers by hash of the coordinates: a cache, not state (NaN: empty). */
  private readonly memoX = new Float64Array(1 << MEMO_BITS).fill(NaN);
  private readonly memoY = new Float64Array(1 << MEMO_BITS).fill(NaN);
  private readonly memoNode = new Int32Array(1 << MEMO_BITS);

  /**
   * The search for the layout's fixed goals, where it does not depend on where in a small sub-cell
   * the bot stands (`NavGoals`); null when there are none (or more than 32 walls, which the
   * walls' masks cannot hold).
   */
  private readonly goals: NavGoals | null;

  /**
   * `goals`: points the bots head for again and again (flag stands, guard posts, lanes), for which
   * the search keeps what it can per sub-cell (`NavGoals`, arena/nav-goals.ts). The answers are the same
   * with or without them.
   */
  constructor(
    readonly walls: Walls,
    width: number,
    height: number,
    spacing: number,
    clearance: number,
    goals: readonly (readonly [number, number])[] = [],
  ) {
    this.spacing = spacing;
    this.clearance = clearance;
    this.cols = Math.floor(width / spacing);
    this.rows = Math.floor(height / spacing);
    const cells = this.cols * this.rows;
    this.cellNode = new Int32Array(cells).fill(-1);
    const xs: number[] = [];
    const ys: number[] = [];
    for (let row = 0; row < this.rows; row++) {
      for (let col = 0; col < this.cols; col++) {
        const x = (col + 0.5) * spacing;
        const y = (row + 0.5) * spacing;
        if (walls.overlaps(x, y, clearance + 1)) continue;
        this.cellNode[row * this.cols + col] = xs.length;
        xs.push(x);
        ys.push(y);
      }
    }
    const n = xs.length;
    this.count = n;
    this.nodeX = Float64Array.from(xs);
    this.nodeY = Float64Array.from(ys);
    // Adjacency: up to 8 neighbours per node.
    const adj = new Int32Array(n * 8).fill(-1);
    const cost = new Int32Array(n * 8);
    for (let row = 0; row < this.rows; row++) {
      for (let col = 0; col < this.cols; col++) {
        const a = this.cellNode[row * this.cols + col]!;
        if (a < 0) continue;
        let k = 0;
        for (let dr = -1; dr <= 1; dr++) {
          for (let dc = -1; dc <= 1; dc++) {
            if (dr === 0 && dc === 0) continue;
            const r2 = row + dr;
            const c2 = col + dc;
            if (r2 < 0 || c2 < 0 || r2 >= this.rows || c2 >= this.cols) continue;
            const b = this.cellNode[r2 * this.cols + c2]!;
            if (b < 0) continue;
            if (!walls.clear(xs[a]!, ys[a]!, xs[b]!, ys[b]!, clearance)) continue;
            adj[a * 8 + k] = b;
            cost[a * 8 + k] = dr !== 0 && dc !== 0 ? DIAG : ORTHO;
            k++;
          }
        }
      }
    }
    this.dist = shortestPaths(n, adj, cost);
    let symmetric = true;
    for (let i = 0; i < n && symmetric; i++) {
      for (let j = i + 1; j < n; j++) {
        if (this.dist[i * n + j] !== this.dist[j * n + i]) {
          symmetric = false;
          break;
        }
      }
    }
    this.symmetric = symmetric;

    // The searches' candidates per cell, and the walls in the way of each.
    const ringStart = new Int32Array(cells * 2 + 1);
    const ringNode: number[] = [];
    const ringWalls: number[] = [];
    for (let row = 0; row < this.rows; row++) {
      for (let col = 0; col < this.cols; col++) {
        const c = row * this.cols + col;
        for (let rad = 1; rad <= 2; rad++) {
          for (let dr = -rad; dr <= rad; dr++) {
            for (let dc = -rad; dc <= rad; dc++) {
              if (rad === 2 && dr > -2 && dr < 2 && dc > -2 && dc < 2) continue;
              const r2 = row + dr;
              const c2 = col + dc;
              if (r2 < 0 || c2 < 0 || r2 >= this.rows || c2 >= this.cols) continue;
              const nd = this.cellNode[r2 * this.cols + c2]!;
              if (nd < 0) continue;
              ringNode.push(nd);
              ringWalls.push(
                cellReach(
                  walls,
                  col * spacing,
                  row * spacing,
                  spacing,
                  xs[nd]!,
                  ys[nd]!,
                  clearance,
                ),
              );
            }
          }
          ringStart[2 * c + rad] = ringNode.length;
        }
      }
    }
    this.ringStart = ringStart;
    this.ringNode = Int32Array.from(ringNode);
    this.ringWalls = Int32Array.from(ringWalls);

    const count = n;
    const node = new Int32Array(1);
    this.goals =
      goals.length === 0 || walls.count > 32
        ? null
        : new NavGoals(
            {
              walls,
              spacing,
              cols: this.cols,
              rows: this.rows,
              clearance,
              nodeX: this.nodeX,
              nodeY: this.nodeY,
              unreachable: UNREACHABLE,
              scale: (ORTHO * 0.9) / spacing,
              rest: (nd, g) => this.dist[nd * count + g]!,
              ringStart: this.ringStart,
              ringNode: this.ringNode,
              ringWalls: this.ringWalls,
              nodeNear: (x, y) => (this.nearestNode(x, y, node) ? node[0]! : -1),
            },
            goals,
          );
  }

  /**
   * Where to head for next to reach (tx, ty) from (x, y): the target itself when a body can go
   * straight there; otherwise, among the waypoints of the 3 × 3 cells around (x, y) (5 × 5 if none will do) that it can
   * go straight to, the one that minimises the distance to it plus the path length from it to
   * the waypoint nearest the target (distances to waypoints are discounted a little, so it
   * heads for the farthest useful one rather than dithering at the nearest; of equals, the first
   * in row-major order). Writes the point to `out[0], out[1]`. Falls back to the target when no
   * waypoint is usable.
   */
  waypoint(x: number, y: number, tx: number, ty: number, out: Float64Array): void {
    const q = this.query;
    q[0] = x;
    q[1] = y;
    q[2] = tx;
    q[3] = ty;
    this.waypointQuery(out);
  }

  /**
   * {@link waypoint} from `query[0]`, `query[1]` to `query[2]`, `query[3]` (a register form, as
   * `Walls` has: no fractional number crosses a call, so nothing is allocated). Leaves `query` as
   * it was.
   */
  waypointQuery(out: Float64Array): void {
    const q = this.query;
    out[0] = q[2]!;
    out[1] = q[3]!;
    const goals = this.goals;
    if (goals !== null) {
      const k = goals.indexOf(q);
      if (k >= 0) {
        const e = goals.entryOf(k, q);
        if (e >= 0) {
          this.towardGoal(goals, k, e, out);
          return;
        }
      }
    }
    this.fromScratch(out);
  }

  /** {@link waypointQuery} with no help from the fixed goals' table (`out` holds the target). */
  private fromScratch(out: Float64Array): void {
    const q = this.query;
    const x = q[0]!;
    const y = q[1]!;
    const walls = this.walls;
    const wq = walls.query;
    wq[0] = x;
    wq[1] = y;
    wq[2] = q[2]!;
    wq[3] = q[3]!;
    if (walls.clearQuery(this.clearance)) return;
    if (!this.nearestTo(q, 2, goal)) return;
    const g = goal[0]!;
    if (!(isFiniteNumber(x) && isFiniteNumber(y))) {
      scanWaypoints(this, x, y, g, out);
      return;
    }
    this.search(g, out);
  }

  /**
   * {@link waypointQuery} toward fixed goal k from a point of the sub-cell whose entry in
   * `goals.entries` begins at `e`: what the entry knows, then (if need be) the search.
   */
  private towardGoal(goals: NavGoals, k: number, e: number, out: Float64Array): void {
    const entries = goals.entries;
    const head = entries[e + ENTRY.head]!;
    if ((head & NO_ENTRY) !== 0) {
      this.fromScratch(out);
      return;
    }
    const q = this.query;
    const masks = goals.masks;
    const indexBits = (1 << MASK_BITS) - 1;
    const walls = this.walls;
    const wq = walls.query;
    wq[0] = q[0]!;
    wq[1] = q[1]!;
    if ((head & GOAL_BLOCKED) === 0) {
      // Straight to the goal: only the walls that can be in the way, if any.
      const toGoal = masks[(head >>> GOAL_WALLS_SHIFT) & indexBits]!;
      if (toGoal === 0) return;
      wq[2] = q[2]!;
      wq[3] = q[3]!;
      if (walls.clearAmongQuery(this.clearance, toGoal)) return;
    }
    if ((head & TO_GOAL) !== 0) return;
    const g = goals.nodeOf(k);
    // The candidates the search would try first, in its order: the first in reach is its answer.
    const inTheWay = entries[e + ENTRY.walls]!;
    const listed = (head >>> LENGTH_SHIFT) & 3;
    const single = (head & PAIR) === 0 ? listed : listed - 2;
    const first = goals.firstCandidate;
    const placeBits = (1 << NODE_BITS) - 1;
    for (let i = 0; i < listed; i++) {
      let nd = this.ringNode[first + ((head >>> (NODE_SHIFT + i * NODE_BITS)) & placeBits)]!;
      let toPick = masks[(inTheWay >>> (i * MASK_BITS)) & indexBits]!;
      if (i >= single) {
        // A pair: the cheaper of the two as the search costs them (of equals, the first).
        const other =
          this.ringNode[first + ((head >>> (NODE_SHIFT + (i + 1) * NODE_BITS)) & placeBits)]!;
        // (Computed here, not by a call: V8 boxes a fractional number a call it does not inline
        // returns, an allocation per pair.)
        const scale = (ORTHO * 0.9) / this.spacing;
        const restAt = this.symmetric ? g * this.count : g;
        const restStride = this.symmetric ? 1 : this.count;
        let ex = this.nodeX[nd]! - q[0]!;
        let ey = this.nodeY[nd]! - q[1]!;
        const cost = Math.sqrt(ex * ex + ey * ey) * scale + this.dist[restAt + nd * restStride]!;
        ex = this.nodeX[other]! - q[0]!;
        ey = this.nodeY[other]! - q[1]!;
        const rest = this.dist[restAt + other * restStride]!;
        if (Math.sqrt(ex * ex + ey * ey) * scale + rest < cost) {
          nd = other;
          toPick = masks[(inTheWay >>> ((i + 1) * MASK_BITS)) & indexBits]!;
        }
        i = listed;
      }
      wq[2] = this.nodeX[nd]!;
      wq[3] = this.nodeY[nd]!;
      if (toPick === 0 || walls.clearAmongQuery(this.clearance, toPick)) {
        out[0] = wq[2];
        out[1] = wq[3];
        return;
      }
    }
    this.search(g, out);
  }

  /**
   * {@link waypointQuery}'s search among the waypoints around the point `query[0]`, `query[1]`
   * (finite) for goal node `g`, when the goal is not in reach.
   */
  private search(g: number, out: Float64Array): void {
    const q = this.query;
    const x = q[0]!;
    const y = q[1]!;
    const col = Math.floor(x / this.spacing);
    const row = Math.floor(y / this.spacing);
    const scale = (ORTHO * 0.9) / this.spacing;
    // The cost from node nd to the goal is at nd × count + g, or (the same number) at g × count + nd.
    const count = this.count;
    const restAt = this.symmetric ? g * count : g;
    const restStride = this.symmetric ? 1 : count;
    // The 3 × 3 cells around, or the ring of the 5 × 5 around those if none of them will do. The
    // cheapest first: the first that a body can go straight to is the one to head for, so the
    // line tests (the costly part) stop there.
    const ringStart = this.ringStart;
    const ringNode = this.ringNode;
    const ringWalls = this.ringWalls;
    const onGrid = col >= 0 && row >= 0 && col < this.cols && row < this.rows;
    const cell = 2 * (row * this.cols + col);
    for (let rad = 1; rad <= 2; rad++) {
      let n = 0;
      // The cheapest candidate as they come (of equals, the first): the search's first pick.
      let least = Infinity;
      let first = -1;
      if (onGrid) {
        for (let k = ringStart[cell + rad - 1]!, end = ringStart[cell + rad]!; k < end; k++) {
          const nd = ringNode[k]!;
          const rest = this.dist[restAt + nd * restStride]!;
          if (rest === UNREACHABLE) continue;
          const ex = this.nodeX[nd]! - x;
          const ey = this.nodeY[nd]! - y;
          const cost = Math.sqrt(ex * ex + ey * ey) * scale + rest;
          candidateNode[n] = nd;
          candidateCost[n] = cost;
          candidateWalls[n] = ringWalls[k]!;
          if (cost < least) {
            least = cost;
            first = n;
          }
          n++;
        }
      } else {
        // Off the grid (a point beyond the field): the neighbouring cells one by one.
        for (let dr = -rad; dr <= rad; dr++) {
          for (let dc = -rad; dc <= rad; dc++) {
            if (rad === 2 && dr > -2 && dr < 2 && dc > -2 && dc < 2) continue; // tried already
            const r2 = row + dr;
            const c2 = col + dc;
            if (r2 < 0 || c2 < 0 || r2 >= this.rows || c2 >= this.cols) continue;
            const nd = this.cellNode[r2 * this.cols + c2]!;
            if (nd < 0) continue;
            const rest = this.dist[restAt + nd * restStride]!;
            if (rest === UNREACHABLE) continue;
            const ex = this.nodeX[nd]! - x;
            const ey = this.nodeY[nd]! - y;
            const cost = Math.sqrt(ex * ex + ey * ey) * scale + rest;
            candidateNode[n] = nd;
            candidateCost[n] = cost;
            candidateWalls[n] = REACH_UNKNOWN;
            if (cost < least) {
              least = cost;
              first = n;
            }
            n++;
          }
        }
      }
      const nd = this.firstClear(q, 0, n, first);
      if (nd >= 0) {
        out[0] = this.nodeX[nd]!;
        out[1] = this.nodeY[nd]!;
        return;
      }
    }
  }

  /**
   * The waypoint among the 3 × 3 (else 5 × 5) cells around (x, y) nearest to it that a body can
   * reach in a straight line from there (of equals, the first in row-major order), in `out[0]`;
   * false if there is none.
   *
   * Remembers its last answers (by the exact coordinates): bots ask it for the same few goals —
   * flag stands, guard posts, lanes — tick after tick.
   */
  nearestNode(x: number, y: number, out: Int32Array): boolean {
    this.point[0] = x;
    this.point[1] = y;
    return this.nearestTo(this.point, 0, out);
  }

  /** {@link nearestNode} of the point in `from[at]`, `from[at + 1]`. */
  private nearestTo(from: Float64Array, at: number, out: Int32Array): boolean {
    const x = from[at]!;
    const y = from[at + 1]!;
    if (!(isFiniteNumber(x) && isFiniteNumber(y))) return scanNearest(this, x, y, out);
    bits[0] = x;
    bits[1] = y;
    const h =
      (Math.imul(words[0]! ^ words[1]!, 0x9e3779b1) ^
        Math.imul(words[2]! ^ words[3]!, 0x85ebca6b)) >>>
      (32 - MEMO_BITS);
    if (this.memoX[h] === x && this.memoY[h] === y) {
      out[0] = this.memoNode[h]!;
      return out[0] >= 0;
    }
    return this.searchNearest(from, at, h, out);
  }

  /**
   * {@link nearestTo} when its memo does not hold the point (finite, hashed to `h`): the search,
   * remembered. (Apart, so that the look-up above is small enough for V8 to inline.)
   */
  private searchNearest(from: Float64Array, at: number, h: number, out: Int32Array): boolean {
    const x = from[at]!;
    const y = from[at + 1]!;
    const col = Math.floor(x / this.spacing);
    const row = Math.floor(y / this.spacing);
    const ringStart = this.ringStart;
    const ringNode = this.ringNode;
    const ringWalls = this.ringWalls;
    const onGrid = col >= 0 && row >= 0 && col < this.cols && row < this.rows;
    const cell = 2 * (row * this.cols + col);
    let found = -1;
    for (let rad = 1; rad <= 2 && found < 0; rad++) {
      let n = 0;
      // The cheapest candidate as they come (of equals, the first): the search's first pick.
      let least = Infinity;
      let first = -1;
      if (onGrid) {
        for (let k = ringStart[cell + rad - 1]!, end = ringStart[cell + rad]!; k < end; k++) {
          const nd = ringNode[k]!;
          const ex = this.nodeX[nd]! - x;
          const ey = this.nodeY[nd]! - y;
          const d2 = ex * ex + ey * ey;
          candidateNode[n] = nd;
          candidateCost[n] = d2;
          candidateWalls[n] = ringWalls[k]!;
          if (d2 < least) {
            least = d2;
            first = n;
          }
          n++;
        }
      } else {
        for (let dr = -rad; dr <= rad; dr++) {
          for (let dc = -rad; dc <= rad; dc++) {
            if (rad === 2 && dr > -2 && dr < 2 && dc > -2 && dc < 2) continue; // tried already
            const r2 = row + dr;
            const c2 = col + dc;
            if (r2 < 0 || c2 < 0 || r2 >= this.rows || c2 >= this.cols) continue;
            const nd = this.cellNode[r2 * this.cols + c2]!;
            if (nd < 0) continue;
            const ex = this.nodeX[nd]! - x;
            const ey = this.nodeY[nd]! - y;
            const d2 = ex * ex + ey * ey;
            candidateNode[n] = nd;
            candidateCost[n] = d2;
            candidateWalls[n] = REACH_UNKNOWN;
            if (d2 < least) {
              least = d2;
              first = n;
            }
            n++;
          }
        }
      }
      found = this.firstClear(from, at, n, first);
    }
    this.memoX[h] = x;
    this.memoY[h] = y;
    this.memoNode[h] = found;
    out[0] = found;
    return found >= 0;
  }

  /**
   * Of the first `n` candidates (`candidateNode`, `candidateCost`), the cheapest that a body can
   * reach in a straight line from the point in `from[at]`, `from[at + 1]` — of equals, the
   * first — or -1. Tries them cheapest first, so it answers what a scan keeping the cheapest
   * reachable one would, with fewer line tests: none for a candidate that no wall can be in the way
   * of (`candidateWalls` 0), and only against the walls that can be for the others. `first` is the cheapest of all (of equals, the first;
   * -1 when n is 0), which the caller found while writing them. Uses up the candidates.
   */
  private firstClear(from: Float64Array, at: number, n: number, first: number): number {
    const x = from[at]!;
    const y = from[at + 1]!;
    const walls = this.walls;
    const wq = walls.query;
    let pick = first;
    for (;;) {
      if (pick < 0) return -1;
      const nd = candidateNode[pick]!;
      candidateNode[pick] = -1;
      const inTheWay = candidateWalls[pick]!;
      if (inTheWay === 0) return nd;
      wq[0] = x;
      wq[1] = y;
      wq[2] = this.nodeX[nd]!;
      wq[3] = this.nodeY[nd]!;
      if (
        inTheWay === REACH_UNKNOWN
          ? walls.clearQuery(this.clearance)
          : walls.clearAmongQuery(this.clearance, inTheWay)
      ) {
        return nd;
      }
      // The next cheapest of those left.
      pick = -1;
      let least = Infinity;
      for (let k = 0; k < n; k++) {
        if (candidateNode[k]! >= 0 && candidateCost[k]! < least) {
          least = candidateCost[k]!;
          pick = k;
        }
      }
    }
  }
}

// --- The scans that NavGrid's searches shortcut: what they answer, found by going through every
// candidate and keeping the cheapest reachable one. NavGrid uses them for coordinates that are not
// finite; a test holds the searches to them everywhere else. ---

/**
 * The waypoint among the 3 × 3 (else 5 × 5) cells around (x, y) from which goal node `g` is
 * cheapest to reach (straight there, then along the grid) that a body can go straight to from
 * (x, y), in `out[0]`, `out[1]`; `out` unchanged if there is none.
 */
export function scanWaypoints(
  nav: NavGrid,
  x: number,
  y: number,
  g: number,
  out: Float64Array,
): void {
  const col = Math.floor(x / nav.spacing);
  const row = Math.floor(y / nav.spacing);
  const scale = (ORTHO * 0.9) / nav.spacing;
  let best = Infinity;
  for (let rad = 1; rad <= 2 && best === Infinity; rad++) {
    for (let dr = -rad; dr <= rad; dr++) {
      for (let dc = -rad; dc <= rad; dc++) {
        const r2 = row + dr;
        const c2 = col + dc;
        if (r2 < 0 || c2 < 0 || r2 >= nav.rows || c2 >= nav.cols) continue;
        const nd = nav.cellNode[r2 * nav.cols + c2]!;
        if (nd < 0) continue;
        const rest = nav.dist[nd * nav.count + g]!;
        if (rest === UNREACHABLE) continue;
        const nx = nav.nodeX[nd]!;
        const ny = nav.nodeY[nd]!;
        const ex = nx - x;
        const ey = ny - y;
        const c = Math.sqrt(ex * ex + ey * ey) * scale + rest;
        if (c >= best) continue;
        if (!nav.walls.clear(x, y, nx, ny, nav.clearance)) continue;
        best = c;
        out[0] = nx;
        out[1] = ny;
      }
    }
  }
}

/** {@link NavGrid.nearestNode} by going through every candidate, keeping the nearest reachable. */
export function scanNearest(nav: NavGrid, x: number, y: number, out: Int32Array): boolean {
  const col = Math.floor(x / nav.spacing);
  const row = Math.floor(y / nav.spacing);
  let best = Infinity;
  let found = -1;
  for (let rad = 1; rad <= 2 && found < 0; rad++) {
    for (let dr = -rad; dr <= rad; dr++) {
      for (let dc = -rad; dc <= rad; dc++) {
        const r2 = row + dr;
        const c2 = col + dc;
        if (r2 < 0 || c2 < 0 || r2 >= nav.rows || c2 >= nav.cols) continue;
        const nd = nav.cellNode[r2 * nav.cols + c2]!;
        if (nd < 0) continue;
        const ex = nav.nodeX[nd]! - x;
        const ey = nav.nodeY[nd]! - y;
        const d2 = ex * ex + ey * ey;
        if (d2 >= best) continue;
        if (!nav.walls.clear(x, y, nav.nodeX[nd]!, nav.nodeY[nd]!, nav.clearance)) continue;
        best = d2;
        found = nd;
      }
    }
  }
  out[0] = found;
  return found >= 0;
}

/**
 * An arena's navigation grid for its bots, as a getter: built on first use (a few ms), then
 * shared — it is static data. Cells of 40 units, for a player of radius `playerRadius` with 2
 * units to spare; `goals` as {@link NavGrid}'s.
 */
export function sharedNav(
  walls: Walls,
  width: number,
  height: number,
  playerRadius: number,
  goals: readonly (readonly [number, number])[] = [],
): () => NavGrid {
  let nav: NavGrid | undefined;
  return () => (nav ??= new NavGrid(walls, width, height, 40, playerRadius + 2, goals));
}
