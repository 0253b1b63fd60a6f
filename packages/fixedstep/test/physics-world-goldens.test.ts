import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  PhysicsWorld,
  Random,
  bodiesInBox,
  buildWorld,
  bulletsScene,
  circlesInBox,
  circlesInBoxScene,
  hex64,
  runForHash,
  type CcdMode,
} from 'fixedstep';
import { hashedGridSetting, wallMarksSetting } from '../src/physics/world/broad-phase.js';
import { solverKernelsSetting } from '../src/physics/world/solver-kernels.js';
import { BROAD_PHASE_WASM } from '../src/physics/world/broad-phase-wasm.js';
import { CONTACT_SOLVER_WASM } from '../src/physics/world/contact-solver-wasm.js';
import { KERNELS, assembleKernels, kernelsModule } from '../../../scripts/wasm.mjs';

// Golden hashes over what the solver's speed work touches: big piles (long contact chains),
// boxes with circles, restitution, kinematic bodies waking sleeping ones, a rollback of 8 ticks.
// The values were taken before that work; re-bless only for a deliberate change of behaviour, by
// pasting the printed value.

const none = () => [];

/** The rollback benchmark's scene: 2,000 circles settled into a pile, sleeping off. */
function pile(): PhysicsWorld {
  const scene = circlesInBoxScene(2000, 0xb0d1e5);
  return buildWorld({ ...scene, def: { ...scene.def, enableSleep: false } });
}

/** A pile of boxes and circles, sleeping on, that two kinematic bodies plough through. */
function ploughed(): PhysicsWorld {
  const w = bodiesInBox(400, 9);
  w.createBox({ x: -4, y: 0.6, vx: 1.5, vy: 0, halfWidth: 0.3, halfHeight: 0.3, kinematic: true });
  w.createCircle({ x: 4, y: 1.2, vx: -1.2, vy: 0, radius: 0.25, kinematic: true });
  return w;
}

/**
 * 600 circles apart on a lattice, sleeping off, that {@link crowdEvents} pile onto a 1.2 m spot:
 * from no contact to thousands in one step (past the kernel's first room), then a contact limit
 * they exceed (every step from tick 40 throws).
 */
function crowd(): PhysicsWorld {
  const w = new PhysicsWorld({ enableSleep: false });
  w.addStaticBox(0, -0.5, 20, 0.5);
  for (let k = 0; k < 600; k++)
    w.createCircle({ x: -15 + (k % 60) * 0.5, y: 0.3 + Math.floor(k / 60) * 0.5, radius: 0.15 });
  return w;
}

function crowdEvents(w: PhysicsWorld, tick: number): void {
  if (tick === 10) {
    const r = new Random(7);
    for (let k = 0; k < 600; k++) w.setPosition(k, r.range(-0.6, 0.6), r.range(0.2, 1.4));
  }
  if (tick === 40) w.setDef({ maxContacts: 1500 });
}

/**
 * The 2,000-circle pile with one circle of 2 cm on a ledge 5 km away, sleeping off: its array grid
 * would double its cells three times and crowd the pile, so the grid is hashed (broad-phase.ts).
 */
function outlierPile(): PhysicsWorld {
  const w = pile();
  w.addStaticBox(5000, 0, 1, 0.5);
  w.createCircle({ x: 5000, y: 0.52, vx: 0, vy: 0, radius: 0.02 });
  return w;
}

describe('golden hashes of the solver', () => {
  const golden: [string, () => PhysicsWorld, number, string][] = [
    ['the 2,000-circle pile after 150 ticks', pile, 150, 'cea077fd2c05a52b'],
    ['bodiesInBox(500, 4) after 600 ticks', () => bodiesInBox(500, 4), 600, 'ef349e063c329466'],
    [
      'bodiesInBox(500, 4), sleeping off, after 300 ticks',
      () => bodiesInBox(500, 4, { enableSleep: false }),
      300,
      '95eee08146de1521',
    ],
    [
      'circlesInBox(300, 6) with restitution 0.6 after 400 ticks',
      () => circlesInBox(300, 6, { restitution: 0.6, friction: 0.2, restitutionThreshold: 0.5 }),
      400,
      '2c1888a3773bb4b6',
    ],
    ['a pile ploughed by kinematic bodies after 500 ticks', ploughed, 500, '75ac0e141260b483'],
  ];
  it.each(golden)('%s has its golden hash', (name, make, ticks, expected) => {
    const actual = runForHash(make(), ticks, none);
    if (actual !== expected) console.log(`golden hash for "${name}": ${actual}`);
    expect(actual).toBe(expected);
  });

  it('rolls the 2,000-circle pile back 8 ticks to the same golden hash', () => {
    const w = pile();
    for (let t = 0; t < 150; t++) w.step();
    const confirmed = w.save();
    const hashes: string[] = [];
    for (let round = 0; round < 2; round++) {
      w.load(confirmed);
      for (let t = 0; t < 8; t++) w.step();
      hashes.push(hex64(w.hash()));
    }
    if (hashes[0] !== '10f76a275899f08c') console.log(`golden hash after 158 ticks: ${hashes[0]}`);
    expect(hashes).toEqual(['10f76a275899f08c', '10f76a275899f08c']);
  });
});

describe('the solver kernels', () => {
  it.each([
    ['contact-solver.wat', 'contact-solver-wasm.ts', () => CONTACT_SOLVER_WASM],
    ['broad-phase.wat', 'broad-phase-wasm.ts', () => BROAD_PHASE_WASM],
  ] as const)(
    'are %s, assembled: the committed bytes are not stale, and under 4 KB',
    async (wat, ts, committed) => {
      const kernel = KERNELS.find((k) => k.wat === wat)!;
      const bytes = await assembleKernels(kernel);
      expect(Array.from(committed())).toEqual(Array.from(bytes));
      const generated = readFileSync(
        new URL(`../src/physics/world/${ts}`, import.meta.url),
        'utf8',
      );
      expect(generated).toBe(kernelsModule(bytes, kernel));
      // Chromium builds and WebViews still in use refuse to compile more than 4 KB synchronously on
      // the main thread (this machine's Chromium 156 allows 8 MB; Android WebViews do not).
      expect(bytes.length).toBeLessThanOrEqual(4096);
    },
  );

  it('give the JavaScript loops’ bits, tick for tick, with and without WebAssembly', () => {
    const scenes: [string, () => PhysicsWorld][] = [
      ['pile', pile],
      ['ploughed', ploughed],
      ['bullets', () => buildWorld(bulletsScene(3))],
      ['restitution', () => circlesInBox(200, 2, { restitution: 0.5, restitutionThreshold: 0.3 })],
      ['crowd', crowd],
      // A body 900,000 km away: the grid's cells grow until it fits the budget (a huge span in
      // the WebAssembly bounds and counting sort), the pile shares a few cells, and the grid is
      // hashed (its pairs in JavaScript then, the solvers in WebAssembly).
      ['outlier', outlierPile],
      [
        'far',
        () => {
          const w = circlesInBox(400, 5, { enableSleep: false });
          w.createCircle({ x: 9e8, y: 3, vx: -40, vy: 0, radius: 0.2 });
          return w;
        },
      ],
    ];
    const kernels = (w: PhysicsWorld) =>
      (w as unknown as { schedule: { kernels: object | null | undefined } }).schedule.kernels;
    solverKernelsSetting.minContacts = 0; // WebAssembly from the first contact on
    try {
      for (const [name, make] of scenes) {
        const wasm = make();
        solverKernelsSetting.enabled = false;
        let js: PhysicsWorld;
        try {
          js = make();
        } finally {
          solverKernelsSetting.enabled = true;
        }
        let first = -1;
        let threw = 0;
        for (let t = 0; t < 150 && first < 0; t++) {
          if (name === 'crowd') for (const w of [wasm, js]) crowdEvents(w, t);
          const errors = [wasm, js].map((w) => {
            try {
              w.step();
              return '';
            } catch (e) {
              return String(e);
            }
          });
          if (errors[0] !== errors[1] || hex64(wasm.hash()) !== hex64(js.hash())) first = t;
          if (errors[0] !== '') threw++;
        }
        // Only the crowd goes past its limit: from tick 40 on, every step.
        expect(threw).toBe(name === 'crowd' ? 110 : 0);
        if (first >= 0)
          console.log(`${name}: WebAssembly and JavaScript differ from tick ${first}`);
        expect(first).toBe(-1);
        expect(kernels(wasm)).toBeTruthy();
        expect(kernels(js)).toBeNull();
      }
    } finally {
      solverKernelsSetting.minContacts = 256;
    }
  });

  it('plan contacts so each body meets them in list order, the two visits of a pair sharing no body', () => {
    const w = pile();
    for (let t = 0; t < 150; t++) w.step();
    // The world's own contacts and plan after the last step.
    const { contacts, schedule } = w as unknown as {
      contacts: { count: number; bodyPairCount: number; bodyA: Int32Array; bodyB: Int32Array };
      schedule: { order: Int32Array; count: number; visits: number; slots: number };
    };
    const count = contacts.count;
    expect(schedule.count).toBe(count);
    expect(count).toBeGreaterThan(3000);
    // Every contact once, and pads (-1) where a pair's second visit would share a body with its
    // first: a few (3 of 3,500 visits here), not one a wave.
    const order = Array.from(schedule.order.subarray(0, schedule.visits));
    expect(order.length % 2).toBe(0);
    const pads = order.filter((k) => k === -1).length;
    expect(order.filter((k) => k !== -1).sort((p, q) => p - q)).toEqual([...Array(count).keys()]);
    expect(pads).toBeLessThan(count / 200);
    const bodies = (k: number) =>
      k === -1
        ? []
        : k < contacts.bodyPairCount
          ? [contacts.bodyA[k]!, contacts.bodyB[k]!]
          : [contacts.bodyA[k]!];
    // Per body, the contacts in visiting order are in list order.
    const seen = new Map<number, number>();
    let outOfOrder = 0;
    let sharing = 0;
    for (let s = 0; s < order.length; s++) {
      const k = order[s]!;
      for (const b of bodies(k)) {
        if ((seen.get(b) ?? -1) > k) outOfOrder++;
        seen.set(b, k);
      }
      if (s % 2 === 1 && bodies(order[s - 1]!).some((b) => bodies(k).includes(b))) sharing++;
    }
    expect(outOfOrder).toBe(0);
    expect(sharing).toBe(0);
  });
});

describe('the hashed grid', () => {
  interface Internals {
    grid: { hashed: boolean; cols: number; cellSize: number };
    contacts: { count: number; bodyA: Int32Array; bodyB: Int32Array };
  }
  const internals = (w: PhysicsWorld) => w as unknown as Internals;
  /** This step's contacts as "a-b" (a body–wall contact's b is its wall's reference), sorted. */
  const pairs = (w: PhysicsWorld) => {
    const c = internals(w).contacts;
    const out: string[] = [];
    for (let k = 0; k < c.count; k++) out.push(`${c.bodyA[k]!}-${c.bodyB[k]!}`);
    return out.sort((p, q) => (p < q ? -1 : p > q ? 1 : 0));
  };

  it('takes over from a crowded array grid, and finds the very contacts it would find', () => {
    const hashed = outlierPile();
    for (let t = 0; t < 60; t++) hashed.step();
    const state = hashed.save();
    const array = outlierPile();
    array.load(state);
    hashed.step();
    hashedGridSetting.enabled = false;
    try {
      array.step();
    } finally {
      hashedGridSetting.enabled = true;
    }
    expect(internals(hashed).grid.hashed).toBe(true);
    expect(internals(hashed).grid.cellSize).toBeCloseTo(0.3, 4); // the circles' size, not 2.4 m
    expect(internals(array).grid.hashed).toBe(false);
    expect(internals(array).grid.cellSize).toBeCloseTo(8 * 0.3, 4);
    expect(pairs(hashed).length).toBeGreaterThan(2000);
    expect(pairs(hashed)).toEqual(pairs(array));
  });

  it('rolls an outlier pile back to the same hash, loaded into a fresh world', () => {
    const w = outlierPile();
    for (let t = 0; t < 30; t++) w.step();
    const confirmed = w.save();
    for (let t = 0; t < 8; t++) w.step();
    const fresh = new PhysicsWorld();
    fresh.load(confirmed);
    for (let t = 0; t < 8; t++) fresh.step();
    expect(hex64(fresh.hash())).toBe(hex64(w.hash()));
  });

  it('leaves alone a grid that doubled without crowding: the bullet room keeps its array grid', () => {
    const w = buildWorld(bulletsScene(3));
    let doubled = 0;
    for (let t = 0; t < 300; t++) {
      w.step();
      const grid = internals(w).grid;
      expect(grid.hashed).toBe(false);
      if (grid.cellSize > 0.5) doubled++;
    }
    expect(doubled).toBe(300);
  });
});

describe('the cells marked near walls', () => {
  /** A field of bodies among walls: some fast, some bullets, walls in the middle of the crowd. */
  const field = fc.record({
    seed: fc.integer({ min: 1, max: 2 ** 31 - 1 }),
    bodies: fc.integer({ min: 40, max: 160 }),
    walls: fc.integer({ min: 1, max: 8 }),
    ccd: fc.constantFrom<CcdMode>('auto', 'bullets', 'off'),
    maxCcdIterations: fc.integer({ min: 1, max: 4 }),
    cellSize: fc.constantFrom(0, 0.7),
    enableSleep: fc.boolean(),
  });

  function build(spec: typeof field extends fc.Arbitrary<infer T> ? T : never): PhysicsWorld {
    const r = new Random(spec.seed);
    const w = new PhysicsWorld({
      ccd: spec.ccd,
      maxCcdIterations: spec.maxCcdIterations,
      cellSize: spec.cellSize,
      enableSleep: spec.enableSleep,
    });
    w.addStaticBox(0, -0.5, 12, 0.5);
    for (let k = 0; k < spec.walls; k++) {
      // Walls of up to 3 m among the bodies (long ones would have every cell marked).
      const ax = r.range(-10, 10);
      const ay = r.range(0, 8);
      if (r.next() < 0.5) w.addSegment(ax, ay, ax + r.range(-3, 3), ay + r.range(-3, 3));
      else w.addStaticBox(ax, ay, r.range(0.02, 1.5), r.range(0.02, 1.5));
    }
    for (let k = 0; k < spec.bodies; k++) {
      // Speeds from resting to several cells a step (a cell is 0.6 m here, a step 1/60 s).
      const speed = [3, 30, 90, 250][Math.floor(r.next() * 4)]!;
      const common = {
        x: r.range(-11, 11),
        y: r.range(0.2, 9),
        vx: r.range(-speed, speed),
        vy: r.range(-speed, speed),
        bullet: r.next() < 0.1,
      };
      if (r.next() < 0.3)
        w.createBox({ ...common, halfWidth: r.range(0.05, 0.3), halfHeight: r.range(0.05, 0.3) });
      else w.createCircle({ ...common, radius: r.range(0.05, 0.3) });
    }
    return w;
  }

  it('skip only bodies no wall can reach: the same bits as testing every body (property)', () => {
    let marked = 0;
    let markedHashed = 0;
    let runs = 0;
    fc.assert(
      fc.property(field, (spec) => {
        const fast = build(spec);
        wallMarksSetting.enabled = false;
        const slow = build(spec);
        try {
          for (let t = 0; t < 60; t++) {
            wallMarksSetting.enabled = true;
            fast.step();
            wallMarksSetting.enabled = false;
            slow.step();
            if (fast.hash() !== slow.hash()) return false;
            const grid = (fast as unknown as { grid: { wallMarks: boolean; hashed: boolean } })
              .grid;
            if (grid.wallMarks) {
              marked++;
              if (grid.hashed) markedHashed++;
            }
          }
        } finally {
          wallMarksSetting.enabled = true;
        }
        runs++;
        return true;
      }),
      // A fixed seed: the share of steps that use marks below is a count over these worlds.
      { numRuns: 60, seed: 26 },
    );
    // The marks were in use in many steps (a test of nothing otherwise), in the hashed grid too:
    // bodies flung at up to 250 m/s leave the field, and the grid of the crowd left behind is
    // hashed (broad-phase.ts), whose marks give up sooner (walls covering more cells than there
    // are buckets, about two a body).
    expect(marked).toBeGreaterThan(runs * 60 * 0.25);
    expect(markedHashed).toBeGreaterThan(runs * 2);
  });

  it('let the wall guard skip only paths that cannot cross a wall (property)', () => {
    // The guard moves a body back where its path crossed a wall. Steps seldom give it a long
    // path (continuous detection stops those first), so paths of up to 1 or 5 cells are made here,
    // from where each body started its last step, and the guard runs with and without the marks.
    let guarded = 0;
    let skipped = 0;
    fc.assert(
      fc.property(field, fc.integer({ min: 1, max: 2 ** 31 - 1 }), (spec, pathSeed) => {
        const w = build(spec);
        w.step();
        const { bodies, grid, ccd } = w as unknown as {
          bodies: {
            slotCount: number;
            x: Float64Array;
            y: Float64Array;
            startX: Float64Array;
            startY: Float64Array;
          };
          grid: { wallMarks: boolean; cellSize: number; nearWall: Uint8Array; cellOf: Int32Array };
          ccd: { guardWalls(all: boolean): void };
        };
        if (!grid.wallMarks) return true;
        const r = new Random(pathSeed);
        const n = bodies.slotCount;
        const cell = grid.cellSize;
        for (let i = 0; i < n; i++) {
          // Half the paths within a cell along each axis (the guard may skip those), half longer.
          const reach = r.next() < 0.5 ? cell : 5 * cell;
          bodies.x[i] = bodies.startX[i]! + r.range(-reach, reach);
          bodies.y[i] = bodies.startY[i]! + r.range(-reach, reach);
        }
        const x = bodies.x.slice(0, n);
        const y = bodies.y.slice(0, n);
        ccd.guardWalls(true);
        const markedX = bodies.x.slice(0, n);
        const markedY = bodies.y.slice(0, n);
        bodies.x.set(x);
        bodies.y.set(y);
        grid.wallMarks = false;
        ccd.guardWalls(true);
        for (let i = 0; i < n; i++) {
          if (markedX[i] !== bodies.x[i] || markedY[i] !== bodies.y[i]) return false;
          if (bodies.x[i] !== x[i] || bodies.y[i] !== y[i]) guarded++;
          const short =
            Math.abs(x[i]! - bodies.startX[i]!) <= cell &&
            Math.abs(y[i]! - bodies.startY[i]!) <= cell;
          if (grid.nearWall[grid.cellOf[i]!] === 0 && short) skipped++;
        }
        return true;
      }),
      { numRuns: 60 },
    );
    // Paths were cut, and bodies were skipped (far from every wall, a short path).
    expect(guarded).toBeGreaterThan(100);
    expect(skipped).toBeGreaterThan(100);
  });
});
