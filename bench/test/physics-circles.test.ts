import { beforeAll, describe, expect, it } from 'vitest';
import type { MeasurePlan } from '../lib/measure.js';
import { race, stepsForSample } from '../peers/race.js';
import { buildEngine, ENGINES, isEngine } from '../peers/registry.js';
import { parsePeerReply, PeerProcess, peerProgramArgs } from '../peers/remote.js';
import { circlesInBoxScene, type PhysicsScene } from 'fixedstep';
import { buildFixedstep } from '../peers/fixedstep.js';
import { buildMatter } from '../peers/matter.js';
import { buildPlanck } from '../peers/planck.js';
import { buildRapier, buildRapierDeterministic, initRapier } from '../peers/rapier.js';
import { packageVersion, sceneCircles, type PeerBuilder, type PeerWorld } from '../peers/types.js';
import { expectedPileHeight, sanity, settleSteps } from '../peers/checks.js';

const scene = circlesInBoxScene(60, 7);

/** Every engine, with how closely it can hold the scene's doubles (rapier is f32 inside). */
const peers: { name: string; build: PeerBuilder; tolerance: number }[] = [
  { name: 'fixedstep', build: buildFixedstep, tolerance: 0 },
  { name: 'matter-js', build: buildMatter, tolerance: 1e-12 },
  { name: 'planck', build: buildPlanck, tolerance: 0 },
  { name: 'rapier', build: (s) => buildRapier(s), tolerance: 1e-6 },
  { name: 'rapier rotating', build: (s) => buildRapier(s, { rotation: true }), tolerance: 1e-6 },
];

beforeAll(async () => {
  await initRapier();
});

function read(world: PeerWorld): { x: Float64Array; y: Float64Array } {
  const x = new Float64Array(world.count);
  const y = new Float64Array(world.count);
  world.positions(x, y);
  return { x, y };
}

describe.each(peers)('$name builds the scene', ({ build, tolerance }) => {
  it('with the same bodies, radii and positions, in the same order', () => {
    const world = build(scene);
    try {
      expect(world.count).toBe(60);
      const { x, y } = read(world);
      const r = world.radii();
      scene.bodies.forEach((b, i) => {
        expect(Math.abs(x[i]! - b.x)).toBeLessThanOrEqual(tolerance);
        expect(Math.abs(y[i]! - b.y)).toBeLessThanOrEqual(tolerance);
        expect(Math.abs(r[i]! - b.radius!)).toBeLessThanOrEqual(tolerance);
      });
    } finally {
      world.dispose();
    }
  });

  it('and its bodies fall and stay in the box, awake', () => {
    const world = build(scene);
    try {
      const before = read(world);
      for (let k = 0; k < 150; k++) world.step();
      const check = sanity(world, scene);
      expect(check.inBox).toBe(60);
      expect(check.asleep).toBe(0);
      const after = read(world);
      const meanY = (ys: Float64Array) => ys.reduce((s, v) => s + v, 0) / ys.length;
      expect(meanY(after.y)).toBeLessThan(meanY(before.y));
      expect(check.pileTop).toBeGreaterThan(0.6 * expectedPileHeight(scene));
    } finally {
      world.dispose();
    }
  });
});

describe('the scene helpers', () => {
  it('reads circles and refuses other scenes', () => {
    expect(sceneCircles(scene)).toHaveLength(60);
    const boxed: PhysicsScene = {
      ...scene,
      bodies: [{ x: 0, y: 1, vx: 0, vy: 0, halfWidth: 0.1, halfHeight: 0.1 }],
    };
    expect(() => sceneCircles(boxed)).toThrow(/not a circle/);
    expect(() => sceneCircles({ ...scene, segments: [{ ax: 0, ay: 0, bx: 1, by: 0 }] })).toThrow(
      /segments/,
    );
  });

  it('settles for 120 steps plus the fall of the top row', () => {
    const one: PhysicsScene = { ...scene, bodies: [{ x: 0, y: 4.905, vx: 0, vy: 0, radius: 0.1 }] };
    // fall from 4.905 m at 9.81 m/s²: 1 s = 60 steps
    expect(settleSteps(one)).toBe(180);
  });

  it('expects the pile height from the circles area and the box width', () => {
    const width = scene.inner[2] - scene.inner[0];
    const area = scene.bodies.reduce((s, b) => s + Math.PI * b.radius! ** 2, 0);
    expect(expectedPileHeight(scene, 1)).toBeCloseTo(area / width, 12);
  });

  it('sanity counts bodies out of the box and measures overlaps', () => {
    const two: PhysicsScene = {
      ...scene,
      bodies: [
        { x: 0, y: 0.1, vx: 0, vy: 0, radius: 0.1 },
        { x: 0.15, y: 0.1, vx: 0, vy: 0, radius: 0.1 },
      ],
    };
    let dx = 0;
    const stub: PeerWorld = {
      name: 'stub',
      settings: '',
      count: 2,
      step: () => (dx = 100),
      positions(x, y) {
        x.set([0, 0.15 + dx]);
        y.set([0.1, 0.1]);
      },
      radii: () => Float64Array.of(0.1, 0.1),
      sleeping: () => 0,
      dispose: () => undefined,
    };
    const s = sanity(stub, two);
    expect(s.inBox).toBe(1);
    expect(s.maxOverlap).toBe(0);
    dx = -100.1;
    const t = sanity({ ...stub, step: () => (dx = 0) }, two);
    expect(t.inBox).toBe(2);
    expect(t.maxOverlap).toBeCloseTo(0.05, 12);
  });

  it('names installed versions', () => {
    expect(packageVersion('planck')).toMatch(/^\d+\.\d+\.\d+/);
    expect(packageVersion('matter-js')).toMatch(/^\d+\.\d+\.\d+/);
    expect(packageVersion('no-such-package-here')).toBe('?');
  });
});

describe('the engine registry', () => {
  it('knows every engine by name and builds each', async () => {
    expect(ENGINES).toEqual([
      'fixedstep',
      'matter',
      'planck',
      'rapier',
      'rapier-rotating',
      'rapier-deterministic',
      'rapier-4',
    ]);
    expect(isEngine('planck')).toBe(true);
    expect(isEngine('box2d')).toBe(false);
    for (const engine of ENGINES) {
      const world = await buildEngine(engine, scene);
      expect(world.count).toBe(60);
      world.dispose();
    }
  });
});

describe('Rapier with rotation unlocked', () => {
  it('is another simulation than the locked one: the same pile ends elsewhere', async () => {
    const end = async (world: PeerWorld | Promise<PeerWorld>) => {
      const w = await world;
      for (let k = 0; k < 150; k++) w.step();
      const { x } = read(w);
      w.dispose();
      return x;
    };
    const locked = await end(buildRapier(scene));
    const rotating = await end(buildRapier(scene, { rotation: true }));
    const deterministic = await end(buildRapierDeterministic(scene));
    const moved = (a: Float64Array, b: Float64Array) =>
      a.filter((v, i) => Math.abs(v - b[i]!) > 1e-3).length;
    expect(moved(locked, rotating)).toBeGreaterThan(10);
    // The deterministic build rotates too, and is a build of its own (not bit-identical to 0.21).
    expect(moved(locked, deterministic)).toBeGreaterThan(10);
  });
});

describe('the peer program protocol', () => {
  it('parses JSON replies and refuses anything else', () => {
    expect(parsePeerReply('{"ok":true,"ns":1500}')).toEqual({ ok: true, ns: 1500 });
    expect(parsePeerReply('{"ok":false,"error":"boom"}')).toEqual({ ok: false, error: 'boom' });
    expect(() => parsePeerReply('Segmentation fault')).toThrow(/unexpected output/);
    expect(() => parsePeerReply('{"ns":3}')).toThrow(/unexpected output/);
  });

  it('runs the program with the bench flags', () => {
    expect(peerProgramArgs('rapier-4', 250, 7, 'file:///t/tsx.mjs')).toEqual([
      '--conditions=source',
      '--expose-gc',
      '--import',
      'file:///t/tsx.mjs',
      expect.stringMatching(/bench\/peers\/peer-program\.ts$/),
      'rapier-4',
      '250',
      '7',
    ]);
  });

  it('drives one engine in a process of its own', async () => {
    const peer = await PeerProcess.start('fixedstep', 30, 7, import.meta.resolve('tsx'));
    try {
      expect(peer.info).toMatchObject({ name: 'fixedstep', count: 30 });
      await peer.settle(120);
      const check = await peer.sanity();
      expect(check).toMatchObject({ inBox: 30, asleep: 0 });
      expect(await peer.time(5)).toBeGreaterThan(0);
      await peer.gc();
    } finally {
      await peer.close();
    }
  });
});

describe('race', () => {
  const plan: MeasurePlan = {
    warmupMs: 0.01,
    sampleMs: 0.1,
    rounds: 4,
    allocChunks: 0,
    allocOpsPerChunk: 0,
  };
  /** A contestant whose steps cost `ns` each, exactly; it logs who ran. */
  const fake = (name: string, ns: number, log: string[]) => ({
    time(steps: number) {
      log.push(name);
      return Promise.resolve(steps * ns);
    },
  });

  it('sizes each sample to the plan, alternates the order and gcs after every round', async () => {
    const log: string[] = [];
    let gcs = 0;
    const result = await race([fake('a', 1000, log), fake('b', 3000, log)], plan, {
      gc: () => {
        gcs++;
        return Promise.resolve();
      },
    });
    expect(result.steps).toEqual([100, 33]);
    expect(result.samples).toEqual([
      [1000, 1000, 1000, 1000],
      [3000, 3000, 3000, 3000],
    ]);
    expect(log.slice(-8)).toEqual(['a', 'b', 'b', 'a', 'a', 'b', 'b', 'a']);
    expect(gcs).toBe(5);
  });

  it('can give everybody the same number of steps', async () => {
    const result = await race([fake('a', 1000, []), fake('b', 3000, [])], plan, {
      sameSteps: true,
    });
    expect(result.steps).toEqual([100, 100]);
  });

  it('takes at least one step per sample', () => {
    expect(stepsForSample(15, 2e8)).toBe(1);
    expect(stepsForSample(15, 0)).toBe(1);
    expect(stepsForSample(15, 1e6)).toBe(15);
  });
});
