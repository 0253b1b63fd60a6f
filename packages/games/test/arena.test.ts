import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import { ByteReader, ByteWriter, maxSafeSpeed, minWallSize, packButtons } from 'fixedstep';
import {
  Bullets,
  CTF,
  CTF_WALLS,
  DIR_BUTTONS,
  DIR_X,
  DIR_Y,
  SURVIVAL,
  SURVIVAL_WALLS,
  ShooterButtons,
  Walls,
  ctfNav,
  dirToward,
  inputDir,
  nearestLine,
  type BulletTargets,
} from '@fixedstep/games';

const STEP = 1 / 60;
const out = new Float64Array(2);

/** No targets: bullets against walls only. */
const noTargets: BulletTargets = {
  targetCount: 0,
  targetX: new Float64Array(0),
  targetY: new Float64Array(0),
  targetRadius: 0,
  canHit: () => false,
  hit: () => undefined,
};

/** One thin vertical wall, 4 units thick, from x = 100 to 104, very tall. */
const thin = new Walls([{ x0: 100, y0: -1e6, x1: 104, y1: 1e6 }]);

describe('walls', () => {
  it('push a circle out through the nearer face: back if it is short of the middle, through if past it', () => {
    thin.pushOut(95, 0, 10, out); // overlapping the near face
    expect([...out]).toEqual([90, 0]);
    thin.pushOut(101.9, 0, 10, out); // centre inside, short of the middle (102)
    expect([...out]).toEqual([90, 0]);
    thin.pushOut(102.1, 0, 10, out); // centre past the middle: out on the far side — tunnelling
    expect([...out]).toEqual([114, 0]);
    // A corner: out along the line from the corner.
    const box = new Walls([{ x0: 0, y0: 0, x1: 10, y1: 10 }]);
    box.pushOut(13, 14, 5, out);
    expect(out[0]).toBeCloseTo(13, 12);
    expect(out[1]).toBeCloseTo(14, 12);
    box.pushOut(12, 12, 5, out);
    expect(Math.hypot(out[0]! - 10, out[1]! - 10)).toBeCloseTo(5, 12);
  });

  it('sweep finds the moment a move first touches a wall, however fast', () => {
    // A radius-2 bullet from x = 50 moving 100 to the right touches the wall at x = 98: u = 0.48.
    expect(thin.sweep(50, 0, 100, 0, 2)).toBeCloseTo(0.48, 12);
    expect(thin.sweep(50, 0, 40, 0, 2)).toBe(-1); // stops short
    expect(thin.sweep(110, 0, 100, 0, 2)).toBe(-1); // beyond, moving away
    // The same move seen discretely: both ends are clear of the wall.
    expect(thin.overlaps(50, 0, 2)).toBe(false);
    expect(thin.overlaps(150, 0, 2)).toBe(false);
    expect(thin.clear(50, 0, 150, 0, 2)).toBe(false);
    expect(thin.clear(50, 0, 95, 0, 2)).toBe(true);
  });

  it('crosses: a centre path that meets a wall box', () => {
    expect(thin.crosses(90, 0, 110, 0)).toBe(true);
    expect(thin.crosses(90, 0, 99, 0)).toBe(false);
    expect(thin.crosses(102, 5, 102, 6)).toBe(true); // inside
    expect(thin.crosses(90, 2e6, 110, 2e6)).toBe(false); // past its end
  });

  it('rejects a wall with no area', () => {
    expect(() => new Walls([{ x0: 0, y0: 0, x1: 0, y1: 10 }])).toThrow(RangeError);
  });
});

describe("the talk's rule on both arenas, at the fixed step of 1/60 s", () => {
  const movers = [
    { name: 'ctf player', walls: CTF_WALLS, step: CTF.playerSpeed * STEP, r: CTF.playerRadius },
    {
      name: 'survival player',
      walls: SURVIVAL_WALLS,
      step: SURVIVAL.playerSpeed * STEP,
      r: SURVIVAL.playerRadius,
    },
    {
      name: 'survival enemy (running + shoved)',
      walls: SURVIVAL_WALLS,
      step: SURVIVAL.maxEnemySpeed * STEP + SURVIVAL.maxShove,
      r: SURVIVAL.enemyRadius,
    },
  ];
  for (const m of movers) {
    it(`every wall is thick enough for a ${m.name}`, () => {
      const speed = m.step / STEP;
      expect(m.walls.thinnest).toBeGreaterThanOrEqual(minWallSize(speed, STEP));
      // The stronger bound for discrete detection with push-out (docs/collisions.md).
      expect(speed).toBeLessThanOrEqual(maxSafeSpeed(m.walls.thinnest, m.r, STEP));
    });
  }

  it('bullets break it, so they are swept (continuous detection)', () => {
    expect(CTF_WALLS.thinnest).toBe(4);
    expect(SURVIVAL_WALLS.thinnest).toBe(10);
    // 15 units a step against 4-unit walls: more than the wall plus the bullet's diameter.
    expect(minWallSize(CTF.bulletSpeed, STEP)).toBeGreaterThan(
      CTF_WALLS.thinnest + 2 * CTF.bulletRadius,
    );
    expect(minWallSize(SURVIVAL.bulletSpeed, STEP)).toBeGreaterThan(SURVIVAL_WALLS.thinnest);
  });
});

describe('bullets', () => {
  it('continuous detection: no bullet ever passes a wall, at any speed up to 6000 units/s', () => {
    fc.assert(
      fc.property(
        fc.double({ min: -300, max: 300, noNaN: true }),
        fc.double({ min: -300, max: 300, noNaN: true }),
        fc.double({ min: -3.2, max: 3.2, noNaN: true }),
        fc.double({ min: 50, max: 6000, noNaN: true }),
        (x, y, angle, speed) => {
          if (thin.overlaps(x, y, 2)) return;
          const b = new Bullets(4, 2);
          // Aim by a unit vector built without engine trig: (1 − t², 2t)/(1 + t²), t = angle/4.
          const t = angle / 4;
          const vx = ((1 - t * t) / (1 + t * t)) * speed;
          const vy = ((2 * t) / (1 + t * t)) * speed;
          b.spawn(0, 0, x, y, x < 102 ? vx : -vx, vy, 5);
          const side = x < 102;
          let wrongSide = 0;
          for (let i = 0; i < 120 && b.live > 0; i++) {
            b.advance(STEP, thin, noTargets, true);
            if (b.live > 0 && b.x[0]! < 102 !== side) wrongSide++;
          }
          expect(wrongSide).toBe(0);
          expect(b.throughWalls).toBe(0);
        },
      ),
      { numRuns: 400 },
    );
  });

  it('discrete detection lets fast bullets through a thin wall, and counts them', () => {
    const b = new Bullets(64, 2);
    // 64 bullets at 900 units/s from x = 0 to 63: every starting phase over one 15-unit step.
    for (let i = 0; i < 64; i++) b.spawn(0, 0, i, i * 10, 900, 0, 1);
    for (let i = 0; i < 20; i++) b.advance(STEP, thin, noTargets, false);
    let beyond = 0;
    for (let i = 0; i < 64; i++) if (b.alive[i] === 1 && b.x[i]! > 104) beyond++;
    // A 15-unit jump over an 8-unit zone (wall + diameter): about 7/15 of the phases get through.
    expect(beyond).toBe(b.throughWalls);
    expect(beyond).toBeGreaterThan(20);
    expect(beyond).toBeLessThan(40);
  });

  it('take the lowest free slot, zero the slots they leave, and read back what they wrote', () => {
    const b = new Bullets(4, 2);
    expect([b.spawn(1, 1, 1, 2, 3, 4, 1), b.spawn(2, 0, 5, 6, 7, 8, 1)]).toEqual([0, 1]);
    b.remove(0);
    expect([b.alive[0], b.x[0], b.serial[0], b.live]).toEqual([0, 0, 0, 1]);
    expect(b.spawn(3, 1, 9, 9, 9, 9, 1)).toBe(0);
    expect(b.serial[0]).toBe(3);
    const w = new ByteWriter();
    b.write(w);
    const c = new Bullets(4, 2);
    c.read(new ByteReader(w.finish()), 7, 1);
    const w2 = new ByteWriter();
    c.write(w2);
    expect(w2.finish()).toEqual(w.finish());
    expect(c.live).toBe(2);
    // A slot marked empty but not zeroed is refused.
    b.x[3] = 1;
    const bad = new ByteWriter();
    b.write(bad);
    expect(() => {
      new Bullets(4, 2).read(new ByteReader(bad.finish()), 7, 1);
    }).toThrow(/not zeroed/);
  });
});

describe('movement', () => {
  it('arrows map to the eight directions; opposite keys cancel', () => {
    const U = 1 << ShooterButtons.up;
    const D = 1 << ShooterButtons.down;
    const L = 1 << ShooterButtons.left;
    const R = 1 << ShooterButtons.right;
    expect(
      [R, R | D, D, D | L, L, L | U, U, U | R].map((b) => inputDir(packButtons(b, 0))),
    ).toEqual([0, 1, 2, 3, 4, 5, 6, 7]);
    expect(inputDir(0)).toBe(-1);
    expect(inputDir(L | R)).toBe(-1);
    expect(inputDir(U | D | R)).toBe(0);
    for (let d = 0; d < 8; d++) {
      expect(inputDir(DIR_BUTTONS[d]!)).toBe(d);
      expect(DIR_X[d]! * DIR_X[d]! + DIR_Y[d]! * DIR_Y[d]!).toBeCloseTo(1, 15);
      expect(dirToward(DIR_X[d]! * 7, DIR_Y[d]! * 7)).toBe(d);
    }
  });

  it('dirToward: the largest dot product with the eight directions, the first of equals', () => {
    // The definition, as a loop over the table (dirToward itself is unrolled).
    const byLoop = (dx: number, dy: number): number => {
      let best = 0;
      let bestDot = -Infinity;
      for (let d = 0; d < 8; d++) {
        const dot = dx * DIR_X[d]! + dy * DIR_Y[d]!;
        if (dot > bestDot) {
          bestDot = dot;
          best = d;
        }
      }
      return best;
    };
    const special = [
      0,
      -0,
      1,
      -1,
      1e-300,
      -1e-300,
      5e-324,
      1e300,
      -1e300,
      Infinity,
      -Infinity,
      NaN,
    ];
    for (const dx of special) {
      for (const dy of special)
        expect({ dx, dy, d: dirToward(dx, dy) }).toEqual({ dx, dy, d: byLoop(dx, dy) });
    }
    // Ties and near-ties: on the axes, the diagonals and the boundaries between sectors.
    const t = Math.tan(Math.PI / 8);
    fc.assert(
      fc.property(
        fc.oneof(fc.double({ noNaN: false }), fc.integer({ min: -50, max: 50 })),
        fc.oneof(
          fc.double({ noNaN: false }),
          fc.integer({ min: -50, max: 50 }),
          fc.constantFrom(0, 1, -1, t, -t, 1 / t, -1 / t),
        ),
        (a, b) => {
          for (const [dx, dy] of [
            [a, b],
            [a, a * b],
            [a * b, a],
          ] as const) {
            expect({ dx, dy, d: dirToward(dx, dy) }).toEqual({ dx, dy, d: byLoop(dx, dy) });
          }
        },
      ),
      { numRuns: 20000, seed: 9 },
    );
  });

  it('nearestLine: the firing line closest to a point, with the signed miss distance', () => {
    const perp = new Float64Array(1);
    expect(nearestLine(100, 3, perp)).toBe(0);
    expect(perp[0]).toBe(3);
    expect(nearestLine(-50, -52, perp)).toBe(5);
    expect(Math.abs(perp[0]!)).toBeCloseTo(Math.SQRT1_2 * 2, 12);
    expect(nearestLine(0, 0, perp)).toBe(-1);
  });

  it('a mover at the fixed step never goes through a wall (random walks against the thin walls)', () => {
    fc.assert(
      fc.property(
        fc.array(fc.integer({ min: 0, max: 7 }), { minLength: 50, maxLength: 400 }),
        (dirs) => {
          let x = 300;
          let y = 320;
          for (const d of dirs) {
            for (let k = 0; k < 8; k++) {
              CTF_WALLS.pushOut(
                x + DIR_X[d]! * CTF.playerSpeed * STEP,
                y + DIR_Y[d]! * CTF.playerSpeed * STEP,
                CTF.playerRadius,
                out,
              );
              expect(CTF_WALLS.crosses(x, y, out[0]!, out[1]!)).toBe(false);
              x = out[0]!;
              y = out[1]!;
            }
          }
          expect(CTF_WALLS.overlaps(x, y, CTF.playerRadius - 1e-9)).toBe(false);
        },
      ),
      { numRuns: 100 },
    );
  });
});

describe('navigation grid', () => {
  it('links every waypoint of the capture-the-flag arena to every other', () => {
    const nav = ctfNav();
    expect(nav.count).toBeGreaterThan(200);
    let unreachable = 0;
    for (let i = 0; i < nav.dist.length; i++) if (nav.dist[i] === 0x7fffffff) unreachable++;
    expect(unreachable).toBe(0);
  });

  it('following waypoints leads from one base to the other', () => {
    const nav = ctfNav();
    const wp = new Float64Array(2);
    let x = 40;
    let y = 290;
    const tx = CTF.width - 80;
    const ty = 320;
    let steps = 0;
    while ((x - tx) ** 2 + (y - ty) ** 2 > 16 && steps < 2000) {
      nav.waypoint(x, y, tx, ty, wp);
      const d = dirToward(wp[0]! - x, wp[1]! - y);
      CTF_WALLS.pushOut(x + DIR_X[d]! * 2.5, y + DIR_Y[d]! * 2.5, CTF.playerRadius, out);
      x = out[0]!;
      y = out[1]!;
      steps++;
    }
    expect(steps).toBeLessThan(600);
  });
});
