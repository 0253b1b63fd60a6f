import { describe, expect, it } from 'vitest';
import { PhysicsWorld, bodiesInBox } from 'fixedstep';

/**
 * The own world's limits, measured (docs/physics-world.md quotes these numbers; this file is
 * their source: `npx vitest run packages/fixedstep/test/physics-world-limits.test.ts`). The
 * world is the talk's arcade world: circles and axis-aligned boxes that never rotate.
 */

/** Half the height of a stacked box (they are 1 m × 0.5 m, density 1). Metres. */
const HALF_HEIGHT = 0.25;

interface Stack {
  world: PhysicsWorld;
  /** How far the top box is below where it would sit on a perfect stack. Metres. */
  sag: number;
  /** The largest overlap between a box and the one under it (or the ground). Metres. */
  worstOverlap: number;
  /** The fastest box. m/s. */
  maxSpeed: number;
}

/**
 * `boxes` boxes stacked on the ground, the top one `topDensity` times denser, stepped `ticks`
 * ticks of 1/60 s with `velocityIterations` (the default 3 position iterations, 5 mm slop), no
 * sleeping (a sleeping stack would stop where it is).
 */
function stack(boxes: number, velocityIterations: number, ticks: number, topDensity = 1): Stack {
  const world = new PhysicsWorld({ velocityIterations, enableSleep: false });
  world.addStaticBox(0, -0.5, 20, 0.5);
  for (let k = 0; k < boxes; k++) {
    world.createBox({
      x: 0,
      y: HALF_HEIGHT + 2 * HALF_HEIGHT * k,
      halfWidth: 0.5,
      halfHeight: HALF_HEIGHT,
      density: k === boxes - 1 ? topDensity : 1,
    });
  }
  for (let t = 0; t < ticks; t++) world.step();
  let worstOverlap = HALF_HEIGHT - world.y[0]!;
  let maxSpeed = 0;
  for (let k = 0; k < boxes; k++) {
    if (k > 0)
      worstOverlap = Math.max(worstOverlap, 2 * HALF_HEIGHT - (world.y[k]! - world.y[k - 1]!));
    maxSpeed = Math.max(maxSpeed, world.speed(k));
  }
  const ideal = HALF_HEIGHT + 2 * HALF_HEIGHT * (boxes - 1);
  return { world, sag: ideal - world.y[boxes - 1]!, worstOverlap, maxSpeed };
}

const mm = (metres: number) => Math.round(metres * 10_000) / 10;

describe('limits of the own world', () => {
  it('stack sag: with 4+ velocity iterations a stack of N boxes settles about one linear slop (5 mm) per box low', () => {
    // After 40 s. Rows: boxes; columns: 4, 8, 16 velocity iterations; sag in mm.
    const expected: Record<number, [number, number, number]> = {
      5: [22.2, 22.1, 22.1],
      10: [50.0, 50.0, 50.0],
      20: [100.0, 100.0, 100.0],
      40: [200.3, 200.5, 200.6],
    };
    for (const [boxes, sags] of Object.entries(expected)) {
      const measured = [4, 8, 16].map((it) => stack(Number(boxes), it, 2400));
      expect(
        measured.map((s) => mm(s.sag)),
        `${boxes} boxes`,
      ).toEqual(sags);
      // Settled: nothing moves faster than 2 mm/s.
      expect(Math.max(...measured.map((s) => s.maxSpeed)), `${boxes} boxes`).toBeLessThan(2e-3);
    }
  });

  it('stack sag: 1 or 2 velocity iterations do not hold a stack of 20 (still bouncing after 40 s)', () => {
    for (const it of [1, 2]) {
      const s = stack(20, it, 2400);
      expect(s.maxSpeed, `${it} iterations`).toBeGreaterThan(0.5);
      expect(s.sag, `${it} iterations`).toBeGreaterThan(0.4);
    }
  });

  it('mass ratio: a box k× denser on a stack of 5 holds to ~250×, sinks into the box below from ~300×, and passes through it at 1200×', () => {
    // Worst overlap between neighbours after 20 s at 8 iterations, mm (a box is 500 mm high).
    const expected: [number, number][] = [
      [1, 5.0],
      [10, 5.0],
      [100, 5.2],
      [200, 10.4],
      [300, 31.4],
      [1000, 229.5],
      [1200, 557.6],
    ];
    const measured = expected.map(([k]) => [k, mm(stack(5, 8, 1200, k).worstOverlap)]);
    expect(measured).toEqual(expected);
    // Given time, up to ~250× the overlap drains back to the slop (40 s):
    expect(mm(stack(5, 8, 2400, 250).worstOverlap)).toBe(6.2);
  });

  it('a leaning tower whose centre of mass is 2 m past the edge of its base stays up: boxes cannot rotate', () => {
    // 11 boxes, each 1 m wide and 0.5 m to the right of the one below: the centre of mass is at
    // x = 2.5 m, the base's right edge at 0.5 m. A rotating engine topples it; this world cannot.
    const world = new PhysicsWorld({ enableSleep: false });
    world.addStaticBox(0, -0.5, 20, 0.5);
    for (let k = 0; k <= 10; k++)
      world.createBox({ x: 0.5 * k, y: 0.25 + 0.5 * k, halfWidth: 0.5, halfHeight: 0.25 });
    for (let t = 0; t < 600; t++) world.step();
    let centre = 0;
    for (let k = 0; k <= 10; k++) {
      expect(world.x[k], `box ${k}`).toBe(0.5 * k);
      centre += world.x[k]! / 11;
    }
    expect(centre).toBe(2.5);
    // It only sags, one slop per contact: 11 × 5 mm.
    expect(mm(0.25 + 0.5 * 10 - world.y[10]!)).toBe(55);
  });
});

describe('the body arrays are for reading', () => {
  it('a NaN or ±∞ written into them is refused by the next step, naming the body, and nothing changes', () => {
    const world = bodiesInBox(31, 4);
    for (let t = 0; t < 30; t++) world.step();
    const before = world.hash();
    const tick = world.tick;
    for (const [field, value] of [
      ['x', Number.NaN],
      ['vy', Number.POSITIVE_INFINITY],
    ] as const) {
      const column = world[field];
      const was = column[7]!;
      column[7] = value;
      expect(() => {
        world.step();
      }).toThrow(
        new RegExp(
          `body 7's ${field} is ${String(value)}, written into world\\.${field} from outside`,
        ),
      );
      expect(world.tick).toBe(tick);
      column[7] = was;
      expect(world.hash()).toBe(before);
    }
    // Put back, the world steps on; a finite write is the caller's business.
    world.step();
    expect(world.tick).toBe(tick + 1);
  });
});
