/**
 * The navigation grid's table for fixed goals (`NavGoals`) must change no answer: from every
 * sub-cell toward every fixed goal, the waypoint is the one the scans give (the search as it was
 * before any shortcut), and every claim an entry makes — the goal surely out of reach, the one or
 * two candidates that can come first — holds at the sub-cell's corners, its edges a hair inside
 * and beyond, and random points in it. Capture the flag's grid with its goals, and survival's
 * layout with goals placed at random (its game has none).
 */
import { describe, expect, it } from 'vitest';
import { Random } from 'fixedstep';
import { CTF_WALLS, NavGrid, SURVIVAL, SURVIVAL_WALLS, Walls, ctfNav } from '@fixedstep/games';
import { CTF_GOALS } from '../src/games/ctf/layout.js';
import { scanWaypoint } from './nav-scans.js';
import { UNREACHABLE } from '../src/games/arena/nav-paths.js';
import {
  ENTRY,
  GOAL_BLOCKED,
  GOAL_WALLS_SHIFT,
  LENGTH_SHIFT,
  MASK_BITS,
  NODE_BITS,
  NODE_SHIFT,
  NO_ENTRY,
  PAIR,
  TO_GOAL,
  type NavGoals,
} from '../src/games/arena/nav-goals.js';

/**
 * The order in which the search tries its candidates from (x, y) toward goal node g: the 3 × 3
 * cells around, costed as the search costs them, cheapest first (of equals, the first in
 * row-major order).
 */
function tryOrder(nav: NavGrid, x: number, y: number, g: number): number[] {
  const col = Math.floor(x / nav.spacing);
  const row = Math.floor(y / nav.spacing);
  const scale = (5 * 0.9) / nav.spacing;
  const found: { nd: number; cost: number }[] = [];
  for (let dr = -1; dr <= 1; dr++) {
    for (let dc = -1; dc <= 1; dc++) {
      const r2 = row + dr;
      const c2 = col + dc;
      if (r2 < 0 || c2 < 0 || r2 >= nav.rows || c2 >= nav.cols) continue;
      const nd = nav.cellNode[r2 * nav.cols + c2]!;
      if (nd < 0) continue;
      const rest = nav.dist[nd * nav.count + g]!;
      if (rest === UNREACHABLE) continue;
      const ex = nav.nodeX[nd]! - x;
      const ey = nav.nodeY[nd]! - y;
      found.push({ nd, cost: Math.sqrt(ex * ex + ey * ey) * scale + rest });
    }
  }
  // (A stable sort: equals keep their row-major order.)
  return found.sort((a, b) => a.cost - b.cost).map((c) => c.nd);
}

/** Points of the square [x0, x0 + size]²: corners, edges a hair inside and beyond, inside. */
function samples(rng: Random, x0: number, y0: number, size: number): [number, number][] {
  const hair = 1e-9;
  const out: [number, number][] = [
    [x0, y0],
    [x0 + size - hair, y0 + size - hair],
    [x0 + size / 2, y0 + size / 2],
    [x0 + rng.range(0, size), y0 - hair],
    [x0 + size + hair, y0 + rng.range(0, size)],
  ];
  for (let k = 0; k < 3; k++) out.push([x0 + rng.range(0, size), y0 + rng.range(0, size)]);
  return out;
}

/** The node at `place` among the candidates of the cell of the last `entryOf`'s point. */
function ringNodeOf(nav: NavGrid, table: NavGoals, place: number): number {
  return (nav as unknown as { ringNode: Int32Array }).ringNode[table.firstCandidate + place]!;
}

const survivalGoals = (() => {
  const rng = new Random(23);
  const goals: [number, number][] = [];
  for (let k = 0; k < 6; k++) {
    goals.push([rng.int(SURVIVAL.width * 2) / 2, rng.int(SURVIVAL.height * 2) / 2]);
  }
  // And one in a wall, whose nearest waypoint may be missing.
  goals.push([8, 8]);
  return goals;
})();

const ARENAS: [string, NavGrid, readonly (readonly [number, number])[]][] = [
  ['capture the flag', ctfNav(), CTF_GOALS],
  [
    'survival',
    new NavGrid(SURVIVAL_WALLS, SURVIVAL.width, SURVIVAL.height, 40, 12, survivalGoals),
    survivalGoals,
  ],
];

describe.each(ARENAS)('the fixed goals’ table on %s', (_name, nav, goals) => {
  const table = (nav as unknown as { goals: NavGoals }).goals;

  it('exists and holds the goals', () => {
    expect(table).not.toBeNull();
    expect([...table.goalX]).toEqual(goals.map((g) => g[0]));
    expect([...table.goalY]).toEqual(goals.map((g) => g[1]));
    expect(CTF_WALLS.count).toBeLessThanOrEqual(32);
  });

  it('answers as the scans from every sub-cell toward every goal, and its claims hold', () => {
    const rng = new Random(nav.count);
    const out = new Float64Array(2);
    const q = new Float64Array(4);
    const wrong: unknown[] = [];
    const stats = { blocked: 0, toGoal: 0, listed: [0, 0, 0, 0], pair: 0 };
    const size = table.size;
    const walls = nav.walls;
    const r = nav.clearance;
    /** Whether the walls of `mask` alone answer as all of them do, from (x, y) to (tx, ty). */
    const subsets = new Map<number, Walls>();
    const among = (mask: number, x: number, y: number, tx: number, ty: number): boolean => {
      let only = subsets.get(mask);
      if (only === undefined) {
        only = new Walls(walls.rects.filter((_, i) => (mask & (1 << i)) !== 0));
        subsets.set(mask, only);
      }
      return only.clear(x, y, tx, ty, r) === walls.clear(x, y, tx, ty, r);
    };
    const placeBits = (1 << NODE_BITS) - 1;
    const indexBits = (1 << MASK_BITS) - 1;
    for (let k = 0; k < goals.length; k++) {
      const [gx, gy] = goals[k]!;
      const g = table.nodeOf(k);
      for (let sy = 0; sy < table.subRows; sy++) {
        for (let sx = 0; sx < table.subCols; sx++) {
          const x0 = sx * size;
          const y0 = sy * size;
          q[0] = x0 + size / 2;
          q[1] = y0 + size / 2;
          const e = table.entryOf(k, q);
          const head = table.entries[e + ENTRY.head]!;
          const inTheWay = table.entries[e + ENTRY.walls]!;
          expect(head & NO_ENTRY).toBe(0);
          const toGoal = table.masks[(head >>> GOAL_WALLS_SHIFT) & indexBits]!;
          const listed = (head >>> LENGTH_SHIFT) & 3;
          const pair = (head & PAIR) !== 0;
          const nodes: number[] = [];
          const masks: number[] = [];
          for (let i = 0; i < listed; i++) {
            const place = (head >>> (NODE_SHIFT + i * NODE_BITS)) & placeBits;
            nodes.push(ringNodeOf(nav, table, place));
            masks.push(table.masks[(inTheWay >>> (i * MASK_BITS)) & indexBits]!);
          }
          if ((head & GOAL_BLOCKED) !== 0) stats.blocked++;
          if ((head & TO_GOAL) !== 0) stats.toGoal++;
          else stats.listed[listed]!++;
          if (pair) stats.pair++;
          if ((head & TO_GOAL) !== 0 && g >= 0) wrong.push({ k, sx, sy, toGoal: g });
          for (const [x, y] of samples(rng, x0, y0, size)) {
            // Claims hold only for points of the sub-cell; the answers everywhere.
            const inside = Math.floor(x / size) === sx && Math.floor(y / size) === sy;
            if (inside) {
              if ((head & GOAL_BLOCKED) !== 0 && walls.clear(x, y, gx, gy, r)) {
                wrong.push({ k, x, y, blocked: 'but clear' });
              }
              if (!among(toGoal, x, y, gx, gy)) wrong.push({ k, x, y, toGoal });
              if (g >= 0 && (head & TO_GOAL) === 0) {
                // The listed candidates come in the search's order; those passed over between
                // them are out of reach; each one's walls answer as all of them.
                const order = tryOrder(nav, x, y, g);
                let j = 0;
                for (let i = 0; i < listed; i++) {
                  const last = pair && i === listed - 2;
                  const isNext = (nd: number): boolean =>
                    nd === nodes[i] || (last && nd === nodes[i + 1]);
                  while (j < order.length && !isNext(order[j]!)) {
                    const nd = order[j]!;
                    if (walls.clear(x, y, nav.nodeX[nd]!, nav.nodeY[nd]!, r)) {
                      wrong.push({ k, x, y, passedOver: nd, nodes });
                    }
                    j++;
                  }
                  if (j === order.length) wrong.push({ k, x, y, missing: nodes[i], order });
                  j++;
                  if (last) break;
                }
                nodes.forEach((nd, i) => {
                  if (!among(masks[i]!, x, y, nav.nodeX[nd]!, nav.nodeY[nd]!)) {
                    wrong.push({ k, x, y, nd, mask: masks[i] });
                  }
                });
              }
            }
            nav.waypoint(x, y, gx, gy, out);
            const want = scanWaypoint(nav, x, y, gx, gy);
            if (out[0] !== want[0] || out[1] !== want[1]) {
              wrong.push({ k, x, y, got: [...out], want });
            }
          }
        }
      }
    }
    expect(wrong.slice(0, 5)).toEqual([]);
    // Enough of them to matter: most entries list candidates, many know the goal is out of reach.
    const entries = table.subCols * table.subRows * goals.length;
    expect(stats.listed[0]).toBeLessThan((entries - stats.toGoal) * 0.05);
    expect(stats.blocked).toBeGreaterThan(entries * 0.2);
  });
});
