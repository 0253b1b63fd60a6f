/**
 * The bots' searches try their candidates cheapest first (and the nav grid remembers its nearest
 * nodes), so they make fewer line-of-sight tests — and must answer exactly as the scans they
 * replace, which keep the cheapest reachable candidate while going through all of them (nav.ts
 * and seek.ts keep them, for points that are not finite). Both arenas, random points and targets (repeated ones too, for the memo),
 * equal distances for the ties, and points that are not finite.
 */
import { describe, expect, it } from 'vitest';
import { Random } from 'fixedstep';
import { CTF_WALLS, SURVIVAL_WALLS, Walls, ctfNav, type NavGrid } from '@fixedstep/games';
import { survivalNav } from '../src/games/survival/layout.js';
import { nearestVisible, scanVisible } from '../src/games/arena/seek.js';
import { scanNearest } from '../src/games/arena/nav.js';
import { scanWaypoint } from './nav-scans.js';

/** `NavGrid`'s private candidate lists (see its `ringStart`). */
interface NavCandidates {
  readonly ringStart: Int32Array;
  readonly ringNode: Int32Array;
  readonly ringWalls: Int32Array;
}

/** A point on or near the field: anywhere, on a whole or half unit, or a waypoint. */
function point(rng: Random, nav: NavGrid): [number, number] {
  switch (rng.int(4)) {
    case 0: {
      const nd = rng.int(nav.count);
      return [nav.nodeX[nd]!, nav.nodeY[nd]!];
    }
    case 1:
      return [rng.int(2000) / 2 - 20, rng.int(1400) / 2 - 20];
    default:
      return [
        rng.range(-20, nav.cols * nav.spacing + 20),
        rng.range(-20, nav.rows * nav.spacing + 20),
      ];
  }
}

const ARENAS: [string, NavGrid][] = [
  ['capture the flag', ctfNav()],
  ['survival', survivalNav()],
];

describe.each(ARENAS)('the bots’ searches on %s', (_name, nav) => {
  it('waypoint and nearestNode answer as the scans, for new and repeated targets', () => {
    const rng = new Random(nav.count);
    const targets: [number, number][] = [];
    const out = new Float64Array(2);
    const node = new Int32Array(1);
    const want = new Int32Array(1);
    for (let k = 0; k < 6000; k++) {
      const [x, y] = point(rng, nav);
      // Half the time a target asked before (as bots do tick after tick); 300 of them, more than
      // the memo holds, so entries get replaced.
      const [tx, ty] =
        targets.length > 0 && rng.int(2) === 0
          ? targets[rng.int(targets.length)]!
          : point(rng, nav);
      if (targets.length < 300) targets.push([tx, ty]);
      nav.waypoint(x, y, tx, ty, out);
      expect({ x, y, tx, ty, to: [...out] }).toEqual({
        x,
        y,
        tx,
        ty,
        to: scanWaypoint(nav, x, y, tx, ty),
      });
      const found = nav.nearestNode(tx, ty, node);
      expect({ tx, ty, found, node: node[0] }).toEqual({
        tx,
        ty,
        found: scanNearest(nav, tx, ty, want),
        node: want[0],
      });
    }
  });

  it('leaves out of a waypoint’s line test only walls that no move from the cell can touch', () => {
    // The searches' candidates per cell, and the walls each line test looks at (private fields,
    // read here to check them against the walls' own line test, wall by wall).
    const { ringStart, ringNode, ringWalls } = nav as unknown as NavCandidates;
    const walls = nav.walls;
    const single = walls.rects.map((rect) => new Walls([rect]));
    const rng = new Random(11 + nav.count);
    const s = nav.spacing;
    let sure = 0;
    let leftOut = 0;
    const touched: { x: number; y: number; nd: number; wall: number }[] = [];
    for (let row = 0; row < nav.rows; row++) {
      for (let col = 0; col < nav.cols; col++) {
        const c = row * nav.cols + col;
        for (let k = ringStart[2 * c]!; k < ringStart[2 * c + 2]!; k++) {
          const mask = ringWalls[k]!;
          if (mask === 0) sure++;
          const nd = ringNode[k]!;
          // The cell's corners and edges (and a hair beyond), and points inside.
          for (let j = 0; j < 12; j++) {
            const fx = j < 4 ? j & 1 : j < 8 ? rng.int(2) * (1 + 1e-12) - 1e-12 : rng.range(0, 1);
            const fy = j < 4 ? j >> 1 : rng.range(0, 1);
            const x = (col + fx) * s;
            const y = (row + fy) * s;
            // Every wall left out is clear of the move on its own.
            for (let i = 0; i < walls.count; i++) {
              if ((mask & (1 << i)) !== 0) continue;
              leftOut++;
              if (!single[i]!.clear(x, y, nav.nodeX[nd]!, nav.nodeY[nd]!, nav.clearance)) {
                touched.push({ x, y, nd, wall: i });
              }
            }
          }
        }
      }
    }
    expect(touched).toEqual([]);
    // Enough of them to matter: a quarter need no line test at all, and most walls are left out.
    expect(sure).toBeGreaterThan(ringNode.length / 4);
    expect(leftOut).toBeGreaterThan(ringNode.length * 12 * walls.count * 0.75);
  });

  it('waypoint and nearestNode answer as the scans at points that are not finite', () => {
    const out = new Float64Array(2);
    const node = new Int32Array(1);
    const want = new Int32Array(1);
    for (const bad of [NaN, Infinity, -Infinity]) {
      for (const [x, y, tx, ty] of [
        [bad, 100, 300, 300],
        [100, 100, bad, 300],
        [bad, bad, bad, bad],
      ] as const) {
        nav.waypoint(x, y, tx, ty, out);
        expect([...out]).toEqual(scanWaypoint(nav, x, y, tx, ty));
        expect([nav.nearestNode(tx, ty, node), node[0]]).toEqual([
          scanNearest(nav, tx, ty, want),
          want[0],
        ]);
      }
    }
  });

  it('nearestVisible answers as the scan, ties included', () => {
    const walls = nav.walls;
    const rng = new Random(7 + nav.count);
    const n = 12;
    const alive = new Uint8Array(n);
    const xs = new Float64Array(n);
    const ys = new Float64Array(n);
    const from = new Float64Array(2);
    const out = new Float64Array(1);
    for (let k = 0; k < 3000; k++) {
      for (let i = 0; i < n; i++) {
        alive[i] = rng.int(4) === 0 ? 0 : 1;
        // Now and then the same spot as another body: equal distances.
        const [x, y] = i > 0 && rng.int(4) === 0 ? [xs[i - 1]!, ys[i - 1]!] : point(rng, nav);
        xs[i] = x;
        ys[i] = y;
      }
      [from[0], from[1]] = point(rng, nav);
      const range = [0, 70, 100, 320, 480, 2000][rng.int(6)]!;
      const clearance = [2, 6, 10][rng.int(3)]!;
      const stride = 1 + rng.int(2);
      const first = rng.int(stride);
      const found = nearestVisible(
        walls,
        from,
        from.subarray(1),
        0,
        range,
        clearance,
        alive,
        xs,
        ys,
        out,
        first,
        stride,
      );
      const want = new Float64Array(1);
      const wanted = scanVisible(
        walls,
        from[0],
        from[1],
        range * range,
        clearance,
        alive,
        xs,
        ys,
        want,
        first,
        stride,
      );
      expect([found, out[0]]).toEqual([wanted, want[0]]);
    }
  });
});

describe('the walls the nav grids were built on', () => {
  it('are the arenas’ own', () => {
    expect(ctfNav().walls).toBe(CTF_WALLS);
    expect(survivalNav().walls).toBe(SURVIVAL_WALLS);
  });
});
