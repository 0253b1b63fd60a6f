/**
 * The walls' grid (the broad phase in front of every query) changes which walls a query looks at,
 * never its answer: every query of `Walls` (and the line test told which walls to look at, told
 * all of them) against the all-walls loops as they were before the grid (walls.ts keeps them for
 * where the grid does not answer), bit for bit — on the two arenas and on random layouts, at
 * points and along moves built to land on faces, corners and cell edges, for every radius the
 * games use and beyond the grid's (and at coordinates that are not finite).
 */
import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import { Random, dsincos } from 'fixedstep';
import { CTF_WALLS, SURVIVAL_WALLS, Walls, type Rect } from '@fixedstep/games';
import { GRID_MAX_RADIUS, WallGrid } from '../src/games/arena/wall-grid.js';

/**
 * `Walls`' all-walls loops (private): its queries as they were before the grid. Like the register
 * forms, some read their coordinates from `query`.
 */
interface AllWallsLoops {
  overlapsAll(r: number): boolean;
  pushOutAll(r: number, out: Float64Array): boolean;
  sweepAll(x: number, y: number, dx: number, dy: number, r: number): number;
  crossesAll(): boolean;
}

/** The walls' queries as they were before the grid: every wall, in index order. */
class AllWalls {
  private readonly walls: Walls;
  private readonly loops: AllWallsLoops;

  constructor(rects: readonly Rect[]) {
    this.walls = new Walls(rects);
    this.loops = this.walls as unknown as AllWallsLoops;
  }

  overlaps(x: number, y: number, r: number): boolean {
    this.walls.query.set([x, y]);
    return this.loops.overlapsAll(r);
  }
  pushOut(x: number, y: number, r: number, out: Float64Array): void {
    this.walls.query.set([x, y]);
    this.loops.pushOutAll(r, out);
  }
  sweep(x: number, y: number, dx: number, dy: number, r: number): number {
    return this.loops.sweepAll(x, y, dx, dy, r);
  }
  clear(x0: number, y0: number, x1: number, y1: number, r: number): boolean {
    return this.sweep(x0, y0, x1 - x0, y1 - y0, r) < 0;
  }
  crosses(x0: number, y0: number, x1: number, y1: number): boolean {
    this.walls.query.set([x0, y0, x1, y1]);
    return this.loops.crossesAll();
  }
}

/** Radii of the games (2, 6, 9, 10, 12, 13), the grid's limit (16) and beyond it. */
const RADII = [0, 2, 6, 9, 10, 12, 13, 16, 16.5, 17, 40];

/** A query's answers, from either implementation. */
function answers(w: Walls | AllWalls, x: number, y: number, dx: number, dy: number, r: number) {
  const out = new Float64Array(2);
  w.pushOut(x, y, r, out);
  return {
    overlaps: w.overlaps(x, y, r),
    pushOut: [out[0]!, out[1]!],
    sweep: w.sweep(x, y, dx, dy, r),
    clear: w.clear(x, y, x + dx, y + dy, r),
    // The line test told to look at every wall (the form the bots' waypoints use with fewer).
    clearAmong:
      w instanceof Walls && w.count <= 32
        ? clearAmongAll(w, x, y, x + dx, y + dy, r)
        : w.clear(x, y, x + dx, y + dy, r),
    crosses: w.crosses(x, y, x + dx, y + dy),
  };
}

/** `Walls.clearAmongQuery` with the mask of every wall (a layout of up to 32). */
function clearAmongAll(w: Walls, x0: number, y0: number, x1: number, y1: number, r: number) {
  w.query.set([x0, y0, x1, y1]);
  return w.clearAmongQuery(r, w.count === 32 ? -1 : (1 << w.count) - 1);
}

/**
 * A coordinate near the layout: anywhere around it, or on a wall's face or corner (± the radius,
 * ± a hair), or on a whole or half unit — where rounding and cell edges bite.
 */
function coordinate(rng: Random, rects: readonly Rect[], r: number, along: 'x' | 'y'): number {
  const kind = rng.int(4);
  if (kind === 0 || rects.length === 0) return rng.range(-60, 1060);
  if (kind === 1) return rng.int(2100) / 2 - 30;
  const rect = rects[rng.int(rects.length)]!;
  const edge =
    along === 'x' ? (rng.int(2) === 0 ? rect.x0 : rect.x1) : rng.int(2) === 0 ? rect.y0 : rect.y1;
  const offsets = [0, r, -r, 1e-9, -1e-9, 0.5, -0.5, r + 1e-12, -r - 1e-12];
  return edge + offsets[rng.int(offsets.length)]!;
}

function move(rng: Random): number {
  switch (rng.int(6)) {
    case 0:
      return 0;
    case 1:
      return rng.range(-4, 4);
    case 2:
      return rng.range(-90, 90);
    case 3:
      return rng.range(-900, 900);
    case 4:
      return rng.int(61) - 30;
    default:
      return rng.int(2) === 0 ? 32 : -32;
  }
}

/** `n` random queries on `rects`: the grid's answers and the all-walls loops' must be the same. */
function expectSameAnswers(rects: readonly Rect[], n: number, seed: number): void {
  const walls = new Walls(rects);
  const all = new AllWalls(rects);
  const rng = new Random(seed);
  for (let k = 0; k < n; k++) {
    const r = RADII[rng.int(RADII.length)]!;
    const x = coordinate(rng, rects, r, 'x');
    const y = coordinate(rng, rects, r, 'y');
    const dx = move(rng);
    const dy = rng.int(5) === 0 ? 0 : move(rng);
    // (toEqual tells 0 from -0 and takes NaN as NaN: bit for bit, as far as numbers go.)
    expect({ x, y, dx, dy, r, ...answers(walls, x, y, dx, dy, r) }).toEqual({
      x,
      y,
      dx,
      dy,
      r,
      ...answers(all, x, y, dx, dy, r),
    });
  }
}

/** A wall of a random layout: integer or fractional sizes, some reaching past the field. */
const rect = fc
  .record({
    x: fc.integer({ min: -20, max: 980 }),
    y: fc.integer({ min: -20, max: 680 }),
    w: fc.oneof(fc.integer({ min: 1, max: 300 }), fc.double({ min: 0.5, max: 40, noNaN: true })),
    h: fc.oneof(fc.integer({ min: 1, max: 300 }), fc.double({ min: 0.5, max: 40, noNaN: true })),
  })
  .map((r): Rect => ({ x0: r.x, y0: r.y, x1: r.x + r.w, y1: r.y + r.h }));

describe('the walls’ grid', () => {
  it('answers as the all-walls loops on capture the flag’s walls', () => {
    expectSameAnswers(CTF_WALLS.rects, 15000, 1);
  });

  it('answers as the all-walls loops on survival’s walls', () => {
    expectSameAnswers(SURVIVAL_WALLS.rects, 15000, 2);
  });

  it('answers as the all-walls loops on random layouts of up to 32 walls (and 40: no grid)', () => {
    fc.assert(
      fc.property(
        fc.oneof(
          fc.array(rect, { minLength: 0, maxLength: 32 }),
          fc.array(rect, { minLength: 40, maxLength: 40 }),
        ),
        fc.integer({ min: 1, max: 1 << 30 }),
        (rects, seed) => {
          expectSameAnswers(rects, 150, seed);
        },
      ),
      { numRuns: 150, seed: 3 },
    );
  });

  it('answers as the all-walls loops at coordinates that are not finite', () => {
    const walls = new Walls(CTF_WALLS.rects);
    const all = new AllWalls(CTF_WALLS.rects);
    for (const bad of [NaN, Infinity, -Infinity, 1e300]) {
      for (const [x, y, dx, dy] of [
        [bad, 300, 5, 5],
        [300, bad, 5, 5],
        [300, 300, bad, 5],
        [300, 300, 5, bad],
        [bad, bad, bad, bad],
      ] as const) {
        for (const r of [0, 10, 40]) {
          expect(answers(walls, x, y, dx, dy, r)).toEqual(answers(all, x, y, dx, dy, r));
        }
      }
    }
  });
});

describe('pushOut’s answer', () => {
  /**
   * The games skip the tunnelling diagnostic (`crosses`) of a move that no wall pushed and that is
   * shorter than the mover's radius less a unit: sound only if "not pushed" means "left where it
   * was, at least r from every wall", so that no such move ending there meets a wall.
   */
  function expectUnpushedMeansClear(rects: readonly Rect[], n: number, seed: number): void {
    const walls = new Walls(rects);
    const all = new AllWalls(rects);
    const rng = new Random(seed);
    const out = new Float64Array(2);
    const want = new Float64Array(2);
    const sc = new Float64Array(2);
    let unpushed = 0;
    for (let k = 0; k < n; k++) {
      const r = RADII[rng.int(RADII.length)]!;
      const x = coordinate(rng, rects, r, 'x');
      const y = coordinate(rng, rects, r, 'y');
      const pushed = walls.pushOut(x, y, r, out);
      all.pushOut(x, y, r, want);
      expect([...out]).toEqual([...want]);
      if (pushed) continue;
      unpushed++;
      expect({ x, y, r, out: [...out], overlaps: all.overlaps(x, y, r) }).toEqual({
        x,
        y,
        r,
        out: [x, y],
        overlaps: false,
      });
      // Moves shorter than r − 1 that end there, some along the axes and the diagonals.
      for (let j = 0; j < 8 && r > 1; j++) {
        const len = rng.range(0, r - 1);
        const d = rng.int(8);
        dsincos(j < 4 ? rng.range(0, 2 * Math.PI) : (d * Math.PI) / 4, sc);
        const mx = len * sc[1]!;
        const my = len * sc[0]!;
        expect({ x, y, r, mx, my, crosses: walls.crosses(x - mx, y - my, x, y) }).toEqual({
          x,
          y,
          r,
          mx,
          my,
          crosses: false,
        });
      }
    }
    expect(unpushed).toBeGreaterThan(n / 10);
  }

  it('is false only for a centre at least r from every wall, left as it was (both arenas)', () => {
    expectUnpushedMeansClear(CTF_WALLS.rects, 8000, 4);
    expectUnpushedMeansClear(SURVIVAL_WALLS.rects, 8000, 5);
  });

  it('is true whenever the centre moved', () => {
    const out = new Float64Array(2);
    // Overlapping the near face of a 4-unit wall at x 100–104: pushed.
    const thin = new Walls([{ x0: 100, y0: -50, x1: 104, y1: 50 }]);
    expect(thin.pushOut(95, 0, 10, out)).toBe(true);
    expect([...out]).toEqual([90, 0]);
    // Touching it (exactly r away): not pushed.
    expect(thin.pushOut(90, 0, 10, out)).toBe(false);
    expect([...out]).toEqual([90, 0]);
    // Off the grid (no grid for > 32 walls, or a point beyond it): the all-walls loop says so too.
    expect(thin.pushOut(1e300, 0, 10, out)).toBe(false);
    expect(thin.pushOut(NaN, 0, 10, out)).toBe(true);
  });
});

describe('the grid’s sure-blocked cell pairs', () => {
  /**
   * `Walls.clear` answers false at once for a move between two cells for whose pair the grid
   * holds an interval of radii (lo, hi) containing r: sound only if every such move, from
   * anywhere in the first cell to anywhere in the second, touches a wall. Checked against the
   * all-walls loop from the cells' corners, edges and insides, at radii across the interval and
   * within a hair of its ends.
   */
  function expectSureBlocked(rects: readonly Rect[], pairs: number, seed: number): number {
    const grid = new WallGrid(rects);
    const all = new AllWalls(rects);
    const rng = new Random(seed);
    const cells = grid.cols * grid.rows;
    const at = (cell: number, u: number, v: number): [number, number] => [
      grid.originX + ((cell % grid.cols) + u) * grid.cell,
      grid.originY + (Math.floor(cell / grid.cols) + v) * grid.cell,
    ];
    const fractions = [0, 1, 0.5, 1e-9, 1 - 1e-9];
    const fraction = (): number =>
      rng.int(2) === 0 ? fractions[rng.int(fractions.length)]! : rng.next();
    let blocked = 0;
    for (let k = 0; k < pairs; k++) {
      const from = rng.int(cells);
      const to = rng.int(cells);
      if (from === to) continue;
      const slot = grid.pairSlot(from, to);
      const lo = grid.pairs[slot + 2]! / 256;
      const hi = grid.pairs[slot + 3]! / 256;
      expect(grid.pairs[slot + 1]).toBe(grid.pairMask(from, to));
      if (!(lo < hi)) continue;
      blocked++;
      expect(lo).toBeGreaterThanOrEqual(0);
      for (let j = 0; j < 6; j++) {
        const top = Math.min(hi, GRID_MAX_RADIUS);
        const r = j === 0 ? lo + 1e-9 : j === 1 ? top - 1e-9 : lo + (top - lo) * rng.next();
        if (!(r > lo && r < hi && r <= GRID_MAX_RADIUS)) continue;
        const [x0, y0] = at(from, fraction(), fraction());
        const [x1, y1] = at(to, fraction(), fraction());
        expect({
          rects: rects.length,
          from,
          to,
          x0,
          y0,
          x1,
          y1,
          r,
          clear: all.clear(x0, y0, x1, y1, r),
        }).toEqual({ rects: rects.length, from, to, x0, y0, x1, y1, r, clear: false });
      }
    }
    return blocked;
  }

  it('hold only moves that touch a wall, on both arenas', () => {
    expect(expectSureBlocked(CTF_WALLS.rects, 20000, 6)).toBeGreaterThan(1000);
    expect(expectSureBlocked(SURVIVAL_WALLS.rects, 20000, 7)).toBeGreaterThan(100);
  });

  it('hold only moves that touch a wall, on random layouts', () => {
    fc.assert(
      fc.property(
        fc.array(rect, { minLength: 1, maxLength: 32 }),
        fc.integer({ min: 1, max: 1 << 30 }),
        (rects, seed) => {
          expectSureBlocked(rects, 400, seed);
        },
      ),
      { numRuns: 100, seed: 8 },
    );
  });
});
