import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import { PhysicsWorld, circlesInBox, hex64, type RayHit } from 'fixedstep';
import { solverKernelsSetting } from '../src/physics/world/solver-kernels.js';

/**
 * Queries, filters, sensors and events of the own world (issue 26): rays against known geometry
 * give exact hits, the grid answers exactly what testing every body answers, filters follow
 * Box2D's table in both the JavaScript and WebAssembly paths, sensors report a scripted motion on
 * the tick, and all of it survives save → load.
 */

/** A world without gravity, so bodies stay where they are put. */
const still = (options: { contactEvents?: boolean } = {}) =>
  new PhysicsWorld({ gravityY: 0, enableSleep: false }, options);

describe('ray casts against known geometry', () => {
  it('hit a circle, a box, a segment and a static box exactly where they are', () => {
    const w = still();
    const circle = w.createCircle({ x: 5, y: 0, radius: 1 });
    const box = w.createBox({ x: 0, y: 5, halfWidth: 1, halfHeight: 0.5 });
    const floor = w.addSegment(-5, -2, 5, -2);
    const block = w.addStaticBox(-10, 0, 1, 1);
    expect(w.castRayClosest(0, 0, 10, 0)).toEqual({
      body: circle,
      wall: -1,
      x: 4,
      y: 0,
      normalX: -1,
      normalY: 0,
      fraction: 0.4,
    });
    expect(w.castRayClosest(0, 0, 0, 10)).toEqual({
      body: box,
      wall: -1,
      x: 0,
      y: 4.5,
      normalX: 0,
      normalY: -1,
      fraction: 0.45,
    });
    expect(w.castRayClosest(0, 0, 0, -10)).toEqual({
      body: -1,
      wall: floor,
      x: 0,
      y: -2,
      normalX: 0,
      normalY: 1,
      fraction: 0.2,
    });
    expect(w.castRayClosest(0, 0, -20, 0)).toEqual({
      body: -1,
      wall: block,
      x: -9,
      y: 0,
      normalX: 1,
      normalY: 0,
      fraction: 0.45,
    });
    // Too short, and pointing at nothing.
    expect(w.castRayClosest(0, 0, 3.9, 0)).toBeNull();
    expect(w.castRayClosest(0, 0, 1, 1)).toBeNull();
    expect(w.castRayClosest(0, 0, 0, 0)).toBeNull();
  });

  it('meet a circle off-centre where the chord says: normal from the centre through the point', () => {
    const w = still();
    w.createCircle({ x: 3, y: 4, radius: 5 }); // passes through the origin's neighbourhood
    // A horizontal ray at y = 8 meets the circle x = 3 ± 3.
    const hit = w.castRayClosest(-10, 8, 20, 0)!;
    expect(hit.x).toBe(0);
    expect(hit.y).toBe(8);
    expect(hit.normalX).toBeCloseTo(-0.6, 15);
    expect(hit.normalY).toBeCloseTo(0.8, 15);
    expect(hit.fraction).toBeCloseTo(0.5, 15);
  });

  it('list every hit sorted by fraction, then bodies before walls, then id', () => {
    const w = still();
    const far = w.createCircle({ x: 8, y: 0, radius: 1 });
    const near = w.createBox({ x: 2, y: 0, halfWidth: 1, halfHeight: 1 });
    // Two bodies entered at the same fraction: the lower id first.
    const twinA = w.createBox({ x: 5, y: 0.5, halfWidth: 1, halfHeight: 0.5 });
    const twinB = w.createBox({ x: 5, y: -0.5, halfWidth: 1, halfHeight: 0.5 });
    const wall = w.addSegment(1, -3, 1, 3); // at x = 1, where the near box is entered too
    const hits = w.castRay(-10, 0, 30, 0);
    expect(hits.map((h) => [h.body, h.wall, h.fraction])).toEqual([
      [near, -1, 11 / 30],
      [-1, wall, 11 / 30],
      [twinA, -1, 14 / 30],
      [twinB, -1, 14 / 30],
      [far, -1, 17 / 30],
    ]);
    // The closest agrees with the first.
    expect(w.castRayClosest(-10, 0, 30, 0)!.body).toBe(near);
    // Walls left out on request.
    expect(w.castRay(-10, 0, 30, 0, { walls: false }).map((h) => h.body)).toEqual([
      near,
      twinA,
      twinB,
      far,
    ]);
  });

  it('do not hit a shape they start inside', () => {
    const w = still();
    const inside = w.createCircle({ x: 0, y: 0, radius: 1 });
    const other = w.createCircle({ x: 5, y: 0, radius: 1 });
    expect(w.castRay(0, 0, 10, 0).map((h) => h.body)).toEqual([other]);
    expect(w.castRayClosest(0.5, 0, -10, 0)).toBeNull();
    expect(inside).toBe(0);
  });

  it('follow the filter: category and mask (Box2D b2QueryFilter), sensors, a predicate', () => {
    const w = still();
    const team1 = w.createCircle({ x: 2, y: 0, radius: 0.5, filter: { categoryBits: 2 } });
    const team2 = w.createCircle({ x: 4, y: 0, radius: 0.5, filter: { categoryBits: 4 } });
    const zone = w.createCircle({ x: 1, y: 0, radius: 0.25, sensor: true, kinematic: true });
    const deaf = w.createCircle({ x: 6, y: 0, radius: 0.5, filter: { maskBits: 2 } });
    const ids = (hits: RayHit[]) => hits.map((h) => h.body);
    expect(ids(w.castRay(0, 0, 10, 0))).toEqual([team1, team2]); // deaf's mask lacks bit 1
    expect(ids(w.castRay(0, 0, 10, 0, { maskBits: 4 }))).toEqual([team2]);
    expect(ids(w.castRay(0, 0, 10, 0, { categoryBits: 2 }))).toEqual([team1, team2, deaf]);
    expect(ids(w.castRay(0, 0, 10, 0, { sensors: true }))).toEqual([zone, team1, team2]);
    expect(w.castRayClosest(0, 0, 10, 0, { predicate: (b) => b !== team1 })!.body).toBe(team2);
    expect(w.castRayClosest(0, 0, 10, 0, { maskBits: 0 })).toBeNull();
  });

  it('refuse bad arguments with errors naming them', () => {
    const w = still();
    w.createCircle({ x: 0, y: 0, radius: 1 });
    expect(() => w.castRayClosest(NaN, 0, 1, 0)).toThrow(
      'PhysicsWorld.castRayClosest: originX must be a finite number from -1000000000 to 1000000000 (metres), got NaN',
    );
    expect(() => w.castRay(0, 0, Infinity, 0)).toThrow(RangeError);
    expect(() => w.castRay(0, 0, '1' as unknown as number, 0)).toThrow(TypeError);
    expect(() => w.castRay(0, 0, 1, 0, { mask: 1 } as never)).toThrow(
      'PhysicsWorld.castRay: unknown filter field "mask"',
    );
    expect(() => w.castRay(0, 0, 1, 0, { maskBits: -1 })).toThrow(
      'PhysicsWorld.castRay: filter: maskBits must be an integer from 0 to 0xFFFFFFFF (4294967295), got -1',
    );
    expect(() => w.overlapAABB(1, 0, 0, 1)).toThrow('needs minX ≤ maxX');
    expect(() => w.overlapCircle(0, 0, -1)).toThrow(RangeError);
  });
});

describe('overlap queries', () => {
  it('find the bodies touching a box, a circle or a point, in ascending id', () => {
    const w = still();
    const a = w.createCircle({ x: 0, y: 0, radius: 1 });
    const b = w.createBox({ x: 3, y: 0, halfWidth: 1, halfHeight: 1 });
    const c = w.createCircle({ x: 0, y: 3, radius: 1 });
    w.createCircle({ x: 10, y: 10, radius: 1 });
    expect(w.overlapAABB(-0.5, -0.5, 2, 2.5)).toEqual([a, b, c]);
    // The box's corner (0.8, 0.8) is outside the circle of radius 1 (0.8² + 0.8² = 1.28 > 1).
    expect(w.overlapAABB(0.8, 0.8, 1.9, 1.9)).toEqual([]);
    expect(w.overlapAABB(0.8, 0.8, 2.1, 1.9)).toEqual([b]);
    // Touching counts.
    expect(w.overlapAABB(1, -0.1, 2, 0.1)).toEqual([a, b]);
    expect(w.overlapCircle(1.5, 1.5, 0.5)).toEqual([]);
    expect(w.overlapCircle(0, 1.5, 0.6)).toEqual([a, c]);
    expect(w.overlapPoint(2, 1)).toEqual([b]); // a corner
    expect(w.overlapPoint(0, 2)).toEqual([c]);
    expect(w.overlapPoint(0, 2, { maskBits: 0 })).toEqual([]);
    expect(w.overlapPoint(0, 2, { predicate: (id) => id !== c })).toEqual([]);
  });
});

/** A reference: every body tested, by the textbook formulas. */
function referenceClosest(
  w: PhysicsWorld,
  ox: number,
  oy: number,
  dx: number,
  dy: number,
): { body: number; fraction: number } | null {
  let best: { body: number; fraction: number } | null = null;
  for (let i = 0; i < w.slotCount; i++) {
    if (!w.isAlive(i)) continue;
    const x = w.x[i]!;
    const y = w.y[i]!;
    const hw = w.halfWidth[i]!;
    const hh = w.halfHeight[i]!;
    let t: number | null = null;
    if (w.isBox(i)) {
      let lo = -Infinity;
      let hi = Infinity;
      for (const [o, d, c, h] of [
        [ox, dx, x, hw],
        [oy, dy, y, hh],
      ] as const) {
        if (d === 0) {
          if (o < c - h || o > c + h) lo = Infinity;
          continue;
        }
        const t1 = (c - h - o) / d;
        const t2 = (c + h - o) / d;
        lo = Math.max(lo, Math.min(t1, t2));
        hi = Math.min(hi, Math.max(t1, t2));
      }
      if (lo <= hi && lo >= 0 && lo <= 1) t = lo;
    } else {
      const sx = ox - x;
      const sy = oy - y;
      const a = dx * dx + dy * dy;
      const b = sx * dx + sy * dy;
      const c = sx * sx + sy * sy - hw * hw;
      const disc = b * b - a * c;
      if (c >= 0 && disc >= 0) {
        const root = (-b - Math.sqrt(disc)) / a;
        if (root >= 0 && root <= 1) t = root;
      }
    }
    if (t !== null && (best === null || t < best.fraction)) best = { body: i, fraction: t };
  }
  return best;
}

describe('the query grid', () => {
  it('answers what testing every body answers, on random worlds and rays (property)', () => {
    fc.assert(
      fc.property(
        fc.integer({ min: 1, max: 1000 }),
        fc.integer({ min: 0, max: 90 }),
        fc.array(
          fc.tuple(
            fc.double({ min: -12, max: 12, noNaN: true }),
            fc.double({ min: -2, max: 14, noNaN: true }),
            fc.double({ min: -30, max: 30, noNaN: true }),
            fc.double({ min: -30, max: 30, noNaN: true }),
          ),
          { minLength: 20, maxLength: 20 },
        ),
        (seed, steps, rays) => {
          const w = circlesInBox(300, seed);
          // A few boxes of other sizes, so cells hold mixed shapes.
          for (let k = 0; k < 10; k++)
            w.createBox({ x: -8 + 1.7 * k, y: 9, halfWidth: 0.05 + 0.04 * k, halfHeight: 0.3 });
          for (let t = 0; t < steps; t++) w.step();
          for (const [ox, oy, dx, dy] of rays) {
            const got = w.castRayClosest(ox, oy, dx, dy, { walls: false });
            const want = referenceClosest(w, ox, oy, dx, dy);
            expect(got?.body ?? -1).toBe(want?.body ?? -1);
            expect(Math.abs((got?.fraction ?? 0) - (want?.fraction ?? 0))).toBeLessThan(1e-9);
            const all = w.castRay(ox, oy, dx, dy, { walls: false });
            expect(all[0]?.body ?? -1).toBe(got?.body ?? -1);
            // All hits, sorted.
            for (let k = 1; k < all.length; k++)
              expect(all[k]!.fraction).toBeGreaterThanOrEqual(all[k - 1]!.fraction);
            const box = w.overlapAABB(
              Math.min(ox, ox + dx / 4),
              Math.min(oy, oy + dy / 4),
              Math.max(ox, ox + dx / 4),
              Math.max(oy, oy + dy / 4),
            );
            const wantBox: number[] = [];
            for (let i = 0; i < w.slotCount; i++) {
              if (!w.isAlive(i)) continue;
              const minX = Math.min(ox, ox + dx / 4);
              const maxX = Math.max(ox, ox + dx / 4);
              const minY = Math.min(oy, oy + dy / 4);
              const maxY = Math.max(oy, oy + dy / 4);
              const qx = Math.min(Math.max(w.x[i]!, minX), maxX);
              const qy = Math.min(Math.max(w.y[i]!, minY), maxY);
              const ok = w.isBox(i)
                ? Math.abs(qx - w.x[i]!) <= w.halfWidth[i]! &&
                  Math.abs(qy - w.y[i]!) <= w.halfHeight[i]!
                : (qx - w.x[i]!) ** 2 + (qy - w.y[i]!) ** 2 <= w.halfWidth[i]! ** 2;
              if (ok) wantBox.push(i);
            }
            expect(box).toEqual(wantBox);
          }
        },
      ),
      { numRuns: 25 },
    );
  });

  it('is rebuilt only after bodies moved', () => {
    const w = circlesInBox(50, 1);
    const builds = () => (w as unknown as { queries: { builds: number } }).queries.builds;
    w.castRayClosest(0, 0, 1, 1);
    w.castRay(0, 0, 1, 1);
    w.overlapPoint(0, 0);
    expect(builds()).toBe(1);
    w.step();
    w.castRayClosest(0, 0, 1, 1);
    expect(builds()).toBe(2);
    w.setPosition(0, 1, 1);
    w.overlapPoint(1, 1);
    expect(builds()).toBe(3);
  });
});

/** Box2D's b2ShouldShapesCollide table: [catA, maskA, groupA, catB, maskB, groupB, collide]. */
const FILTER_TABLE: [number, number, number, number, number, number, boolean][] = [
  [1, 0xffffffff, 0, 1, 0xffffffff, 0, true], // defaults
  [2, 0xffffffff, 0, 4, 0xffffffff, 0, true], // any category, full masks
  [2, 0xfffffffb, 0, 4, 0xffffffff, 0, false], // A's mask lacks B's category
  [2, 0xffffffff, 0, 4, 0xfffffffd, 0, false], // B's mask lacks A's category
  [2, 4, 0, 4, 2, 0, true], // each in the other's mask
  [2, 4, -1, 4, 2, -1, false], // same negative group: never, whatever the bits
  [2, 0, 3, 4, 0, 3, true], // same positive group: always, whatever the bits
  [2, 4, -1, 4, 2, -2, true], // different groups: the bits decide
  [2, 0, -1, 4, 0, 1, false], // different groups, empty masks
  [0x80000000, 0x80000000, 0, 0x80000000, 0x80000000, 0, true], // the 32nd bit
];

describe('collision filtering', () => {
  it.each(FILTER_TABLE)(
    'A (%i, %i, %i) and B (%i, %i, %i): collide %s',
    (catA, maskA, groupA, catB, maskB, groupB, collide) => {
      // B falls onto kinematic A; the floor below catches it if they do not collide.
      const w = new PhysicsWorld({ timeStep: 1 / 64 });
      w.addStaticBox(0, -5, 10, 0.5);
      w.createBox({
        x: 0,
        y: 0,
        halfWidth: 2,
        halfHeight: 0.5,
        kinematic: true,
        filter: { categoryBits: catA, maskBits: (maskA | 1) >>> 0, groupIndex: groupA },
      });
      // Bit 1 added to the masks: it is the walls' category (no category in the table but the
      // defaults' is 1, so it changes no case).
      const b = w.createCircle({
        x: 0,
        y: 2,
        radius: 0.5,
        filter: { categoryBits: catB, maskBits: (maskB | 1) >>> 0, groupIndex: groupB },
      });
      for (let t = 0; t < 120; t++) w.step();
      expect(w.y[b]! > 0).toBe(collide);
      expect(w.y[b]).toBeCloseTo(collide ? 1 : -4, 1);
    },
  );

  it('lets a body whose mask lacks bit 1 (the walls’ category) pass through walls', () => {
    const w = new PhysicsWorld({ timeStep: 1 / 64 });
    w.addSegment(-5, 0, 5, 0);
    const ghost = w.createCircle({ x: 0, y: 1, radius: 0.25, filter: { maskBits: 0xfffffffe } });
    const solid = w.createCircle({ x: 2, y: 1, radius: 0.25 });
    for (let t = 0; t < 60; t++) w.step();
    expect(w.y[ghost]).toBeLessThan(-1);
    expect(w.y[solid]).toBeCloseTo(0.25, 1);
  });

  it('stops fast bodies only where the filter says (continuous detection)', () => {
    const w = new PhysicsWorld({ gravityY: 0 });
    w.addSegment(0, -5, 0, 5);
    const bullet = w.createCircle({ x: -2, y: 0, vx: 400, radius: 0.05, bullet: true });
    const ghost = w.createCircle({
      x: -2,
      y: 2,
      vx: 400,
      radius: 0.05,
      bullet: true,
      filter: { maskBits: 0 },
    });
    w.step();
    expect(w.x[bullet]).toBeLessThan(0);
    expect(w.x[ghost]).toBeCloseTo(-2 + 400 / 60, 9);
  });

  it('refuses bad filters with errors naming the field, changing nothing', () => {
    const w = still();
    const id = w.createCircle({ x: 0, y: 0, radius: 1 });
    expect(() => {
      w.setFilter(id, { categoryBits: -1 });
    }).toThrow(
      'PhysicsWorld.setFilter: body 0: categoryBits must be an integer from 0 to 0xFFFFFFFF (4294967295), got -1',
    );
    expect(() => {
      w.setFilter(id, { maskBits: 2 ** 32 });
    }).toThrow(RangeError);
    expect(() => {
      w.setFilter(id, { maskBits: 1.5 });
    }).toThrow(RangeError);
    expect(() => {
      w.setFilter(id, { groupIndex: 2 ** 31 });
    }).toThrow('groupIndex must be an integer from -2147483648 to 2147483647, got 2147483648');
    expect(() => {
      w.setFilter(id, { categoryBits: '1' as unknown as number });
    }).toThrow(TypeError);
    expect(() => {
      w.setFilter(id, { category: 1 } as never);
    }).toThrow('PhysicsWorld.setFilter: body 0: unknown filter field "category"');
    expect(() => w.createCircle({ x: 0, y: 0, radius: 1, filter: { maskBits: NaN } })).toThrow(
      'PhysicsWorld.createCircle: body 1: maskBits must be an integer',
    );
    expect(() =>
      w.createCircle({ x: 0, y: 0, radius: 1, sensor: 1 as unknown as boolean }),
    ).toThrow('PhysicsWorld.createCircle: body 1: sensor must be true or false, got 1');
    expect(w.bodyCount).toBe(1);
    expect(w.getFilter(id)).toEqual({ categoryBits: 1, maskBits: 0xffffffff, groupIndex: 0 });
    w.setFilter(id, { groupIndex: -3 });
    expect(w.getFilter(id)).toEqual({ categoryBits: 1, maskBits: 0xffffffff, groupIndex: -3 });
  });

  it('gives the same bits in JavaScript and WebAssembly (a filtered pile with sensors)', () => {
    const make = () => {
      const w = circlesInBox(400, 7);
      // Three teams: same-team circles pass through each other (negative groups); every 17th
      // circle a sensor.
      for (let i = 0; i < w.slotCount; i++) {
        if (i % 3 !== 0) w.setFilter(i, { groupIndex: -(i % 3), categoryBits: 1 << (i % 3) });
        if (i % 17 === 0) w.setSensor(i, true);
      }
      return w;
    };
    solverKernelsSetting.minContacts = 0;
    try {
      const wasm = make();
      solverKernelsSetting.enabled = false;
      let js: PhysicsWorld;
      try {
        js = make();
      } finally {
        solverKernelsSetting.enabled = true;
      }
      let first = -1;
      for (let t = 0; t < 150 && first < 0; t++) {
        wasm.step();
        js.step();
        if (hex64(wasm.hash()) !== hex64(js.hash())) first = t;
      }
      expect(first).toBe(-1);
      const kernels = (w: PhysicsWorld) =>
        (w as unknown as { schedule: { kernels: object | null | undefined } }).schedule.kernels;
      expect(kernels(wasm)).toBeTruthy();
      expect(kernels(js)).toBeNull();
    } finally {
      solverKernelsSetting.minContacts = 256;
    }
  });
});

describe('sensors', () => {
  /** A kinematic sensor box at the origin; a circle crossing it at 8 m/s, dt = 1/64 (exact sums). */
  const crossing = () => {
    const w = new PhysicsWorld({ gravityY: 0, timeStep: 1 / 64 });
    w.addStaticBox(0, -3, 20, 0.5); // a wall the sensor must not touch
    const sensor = w.createBox({
      x: 0,
      y: -2,
      halfWidth: 1,
      halfHeight: 1,
      kinematic: true,
      sensor: true,
    });
    const ball = w.createCircle({ x: -5, y: -2, vx: 8, radius: 0.5 });
    return { w, sensor, ball };
  };

  it('report begin on the tick a body first touches and end on the tick it has left', () => {
    const { w, sensor, ball } = crossing();
    const log: string[] = [];
    for (let t = 1; t <= 80; t++) {
      w.step();
      const e = w.sensorEvents();
      for (const b of e.begin) log.push(`${t} begin ${b.sensor} ${b.visitor}`);
      for (const b of e.end) log.push(`${t} end ${b.sensor} ${b.visitor}`);
    }
    // x = −5 + t/8: touching from x = −1.5 (t = 28) to x = 1.5 (t = 52); gone at t = 53.
    expect(log).toEqual([`28 begin ${sensor} ${ball}`, `53 end ${sensor} ${ball}`]);
    // No response: the ball kept its speed, the sensor its place.
    expect(w.vx[ball]).toBe(8);
    expect(w.x[sensor]).toBe(0);
    expect(w.y[sensor]).toBe(-2);
  });

  it('report the same events after save → load mid-overlap (rollback fires no pickup twice)', () => {
    const { w } = crossing();
    for (let t = 0; t < 40; t++) w.step();
    const bytes = w.save();
    expect(new DataView(bytes.buffer).getUint32(4, true)).toBe(2); // version 2: it has a sensor
    const b = crossing().w;
    b.load(bytes);
    const events = (x: PhysicsWorld) => JSON.stringify(x.sensorEvents());
    for (let t = 0; t < 40; t++) {
      w.step();
      b.step();
      expect(events(b)).toBe(events(w));
      expect(hex64(b.hash())).toBe(hex64(w.hash()));
    }
  });

  it('do not see other sensors, and follow filters', () => {
    const w = still();
    const zone = w.createCircle({ x: 0, y: 0, radius: 2, kinematic: true, sensor: true });
    w.createCircle({ x: 1, y: 0, radius: 0.5, kinematic: true, sensor: true });
    const friend = w.createCircle({ x: -1, y: 0, radius: 0.5, filter: { groupIndex: -1 } });
    w.setFilter(zone, { groupIndex: -1 });
    const stranger = w.createCircle({ x: 0, y: 1, radius: 0.5 });
    w.step();
    expect(w.sensorEvents().begin).toEqual([{ sensor: zone, visitor: stranger }]);
    expect(friend).toBe(2);
  });
});

describe('contact events', () => {
  it('begin when a ball lands, end when it is lifted; sorted by body, then walls', () => {
    const w = new PhysicsWorld({ timeStep: 1 / 64, enableSleep: false }, { contactEvents: true });
    const floor = w.addSegment(-10, 0, 10, 0);
    const a = w.createCircle({ x: 0, y: 0.4, radius: 0.5 }); // overlapping the floor at once
    const b = w.createCircle({ x: 0, y: 1.4, radius: 0.5 }); // on a
    const c = w.createCircle({ x: 5, y: 3, radius: 0.5 }); // falls
    const log: string[] = [];
    const show = (e: { bodyA: number; bodyB: number; wall: number }) =>
      e.wall >= 0 ? `${e.bodyA}-wall${e.wall}` : `${e.bodyA}-${e.bodyB}`;
    for (let t = 1; t <= 90; t++) {
      if (t === 60) w.setPosition(c, 5, 6);
      w.step();
      const e = w.contactEvents();
      if (e.begin.length) log.push(`${t} begin ${e.begin.map(show).join(' ')}`);
      if (e.end.length) log.push(`${t} end ${e.end.map(show).join(' ')}`);
    }
    expect(log[0]).toBe(`1 begin ${a}-${b} ${a}-wall${floor}`);
    const landing = log.find((l) => l.includes(`${c}-wall`))!;
    expect(landing).toMatch(new RegExp(`^\\d+ begin ${c}-wall${floor}$`));
    expect(log).toContain(`60 end ${c}-wall${floor}`);
    // Each begin of c on the floor is matched by one end before the next begin.
    const cEvents = log.filter((l) => l.includes(`${c}-wall`)).map((l) => l.split(' ')[1]);
    for (let k = 1; k < cEvents.length; k++) expect(cEvents[k]).not.toBe(cEvents[k - 1]);
  });

  it('are empty unless asked for, and change no result', () => {
    const on = circlesInBox(200, 3);
    const withEvents = new PhysicsWorld(on.def, { contactEvents: true });
    withEvents.load(on.save());
    for (let t = 0; t < 60; t++) {
      on.step();
      withEvents.step();
      expect(on.contactEvents().begin).toEqual([]);
      expect(hex64(withEvents.hash())).toBe(hex64(on.hash()));
    }
  });
});

describe('snapshots with filters and sensors', () => {
  const featured = () => {
    const w = circlesInBox(120, 11);
    for (let i = 0; i < w.slotCount; i += 5)
      w.setFilter(i, { categoryBits: 2, maskBits: 0xfffffffd, groupIndex: i % 2 ? 7 : -7 });
    w.setSensor(3, true);
    w.createBox({ x: 0, y: 2, halfWidth: 2, halfHeight: 1, kinematic: true, sensor: true });
    return w;
  };

  it('round-trip: save A, load into B, step both 120 steps, equal hashes every step', () => {
    const a = featured();
    for (let t = 0; t < 30; t++) a.step();
    const b = new PhysicsWorld();
    b.load(a.save());
    expect(b.isSensor(3)).toBe(true);
    expect(b.getFilter(5)).toEqual({ categoryBits: 2, maskBits: 0xfffffffd, groupIndex: 7 });
    for (let t = 0; t < 120; t++) {
      a.step();
      b.step();
      expect(hex64(b.hash())).toBe(hex64(a.hash()));
    }
  });

  it('hash the filters and the sensor flag', () => {
    const a = featured();
    const b = featured();
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
    b.setFilter(0, { groupIndex: 1 });
    expect(hex64(b.hash())).not.toBe(hex64(a.hash()));
    const c = featured();
    c.setSensor(4, true);
    expect(hex64(c.hash())).not.toBe(hex64(a.hash()));
  });

  it('write version 1, byte for byte as before, while no body uses them', () => {
    const w = circlesInBox(30, 2);
    const before = w.save();
    expect(new DataView(before.buffer).getUint32(4, true)).toBe(1);
    w.setFilter(0, { groupIndex: 2 });
    expect(new DataView(w.save().buffer).getUint32(4, true)).toBe(2);
    w.setFilter(0, { groupIndex: 0 });
    expect(w.save()).toEqual(before);
  });

  it('refuse a broken version 2 section, naming it', () => {
    const w = featured();
    const bytes = w.save();
    const n = w.slotCount;
    const view = new DataView(bytes.buffer);
    // The overlaps' count sits after the three filter columns.
    const countAt =
      bytes.length - 4 - 8 * (w as unknown as { overlaps: { count: number } }).overlaps.count;
    const filtersAt = countAt - 12 * n;
    const broken = bytes.slice();
    new DataView(broken.buffer).setUint32(countAt, 1, true);
    expect(() => {
      new PhysicsWorld().load(broken);
    }).toThrow(/PhysicsWorld.load: /);
    // A version 2 snapshot of a world that needs none.
    const plain = circlesInBox(3, 1);
    const v1 = plain.save();
    const v2 = new Uint8Array(v1.length + 12 * plain.slotCount + 4);
    v2.set(v1);
    new DataView(v2.buffer).setUint32(4, 2, true);
    for (let i = 0; i < plain.slotCount; i++) {
      new DataView(v2.buffer).setUint32(v1.length + 4 * i, 1, true);
      new DataView(v2.buffer).setUint32(v1.length + 4 * (plain.slotCount + i), 0xffffffff, true);
    }
    expect(() => {
      new PhysicsWorld().load(v2);
    }).toThrow('not canonical: that is version 1');
    expect(view.getUint32(filtersAt, true)).toBe(2); // body 0's category, as set
    // An older world's message for a newer version.
    const v9 = bytes.slice();
    new DataView(v9.buffer).setUint32(4, 9, true);
    expect(() => {
      new PhysicsWorld().load(v9);
    }).toThrow('unsupported snapshot version 9');
  });
});
