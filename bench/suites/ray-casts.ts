/**
 * Ray casts in the own PhysicsWorld against Rapier's `castRay`, side by side in one process, on
 * the same scene: `circlesInBoxScene(2000)` (circles in a walled box) settled into a pile, built
 * once in each engine. The same 1,024 rays in both — origins and ends drawn from a seeded PRNG
 * inside the box, so rays run through the pile, across empty space and into the walls — cycled
 * through. Reported: ns per ray and rays per millisecond for
 *
 * - own `castRayClosest` (the closest hit, with point and normal), grid already fresh;
 * - own `castRay` (every hit, sorted);
 * - own `castRayClosest` after the world changed (the query grid rebuilt first: the cost a game
 *   pays for its first ray after a step);
 * - Rapier `castRay` (closest, time of impact only) and `castRayAndGetNormal` (with the normal),
 *   `solid` true, through `@fixedstep/rapier`'s world.
 *
 * A check table counts the rays that hit something in each engine (the piles differ a little:
 * Rapier's circles rotate) and how many own closest hits agree with a hit of `castRay` at index 0.
 */
import { Random, buildWorld, circlesInBoxScene, type PhysicsWorld } from 'fixedstep';
import { RapierSimulation, loadRapier, physicsSceneDef, rapierVersion } from '@fixedstep/rapier';
import type { Candidate } from '../lib/measure.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';
import { settleSteps } from '../peers/checks.js';

const SEED = 0x4a75;
const SIZES = [2000];
const QUICK_SIZES = [500];
/** Rays in the set (a power of two: cycled with a mask). */
const RAYS = 1024;

/** `RAYS` rays as [originX, originY, translationX, translationY], inside the box's inner extent. */
export function raySet(inner: readonly [number, number, number, number]): Float64Array {
  const [minX, minY, maxX, maxY] = inner;
  const r = new Random(SEED);
  const rays = new Float64Array(4 * RAYS);
  for (let k = 0; k < RAYS; k++) {
    const ox = r.range(minX, maxX);
    const oy = r.range(minY, maxY);
    rays[4 * k] = ox;
    rays[4 * k + 1] = oy;
    rays[4 * k + 2] = r.range(minX, maxX) - ox;
    rays[4 * k + 3] = r.range(minY, maxY) - oy;
  }
  return rays;
}

async function run(ctx: SuiteContext): Promise<void> {
  await loadRapier();
  const sizes = ctx.quick ? QUICK_SIZES : SIZES;
  ctx.note(
    `circlesInBoxScene(N, ${SEED}) settled (sleep on in both), ${RAYS} seeded rays inside the box, ` +
      'cycled. Own world: castRayClosest / castRay (fraction, point, normal, body or wall id; its ' +
      'own query grid, rebuilt on the first query after the world changes). Rapier ' +
      `${rapierVersion()} (deterministic build): world.castRay(ray, 1, true) and ` +
      'castRayAndGetNormal (its query pipeline, updated by step()).',
  );
  const rows: string[][] = [];
  const checks: string[][] = [];
  for (const n of sizes) {
    const scene = circlesInBoxScene(n, SEED);
    const steps = settleSteps(scene, 60);
    const own: PhysicsWorld = buildWorld(scene);
    for (let t = 0; t < steps; t++) own.step();
    const sim = new RapierSimulation(physicsSceneDef(scene, { id: 'ray-casts' }));
    const none: readonly number[] = [0];
    for (let t = 0; t < steps; t++) sim.step(none);
    const world = sim.world;
    const rapier = await loadRapier();
    const rays = raySet(scene.inner);
    const ray = new rapier.Ray({ x: 0, y: 0 }, { x: 1, y: 0 });
    const at = (k: number) => 4 * (k & (RAYS - 1));
    let cursor = 0;
    const candidates: Candidate[] = [
      {
        name: 'own castRayClosest',
        run(ops) {
          let hits = 0;
          for (let i = 0; i < ops; i++) {
            const p = at(cursor++);
            const hit = own.castRayClosest(rays[p]!, rays[p + 1]!, rays[p + 2]!, rays[p + 3]!);
            if (hit !== null) hits++;
          }
          return hits;
        },
      },
      {
        name: 'own castRay (all hits)',
        run(ops) {
          let hits = 0;
          for (let i = 0; i < ops; i++) {
            const p = at(cursor++);
            hits += own.castRay(rays[p]!, rays[p + 1]!, rays[p + 2]!, rays[p + 3]!).length;
          }
          return hits;
        },
      },
      {
        name: 'own castRayClosest, grid rebuilt first',
        run(ops) {
          let hits = 0;
          for (let i = 0; i < ops; i++) {
            own.setPosition(0, own.x[0]!, own.y[0]!); // changes nothing, but the grid is stale
            const p = at(cursor++);
            const hit = own.castRayClosest(rays[p]!, rays[p + 1]!, rays[p + 2]!, rays[p + 3]!);
            if (hit !== null) hits++;
          }
          return hits;
        },
      },
      {
        name: `Rapier castRay`,
        run(ops) {
          let hits = 0;
          for (let i = 0; i < ops; i++) {
            const p = at(cursor++);
            ray.origin = { x: rays[p]!, y: rays[p + 1]! };
            ray.dir = { x: rays[p + 2]!, y: rays[p + 3]! };
            if (world.castRay(ray, 1, true) !== null) hits++;
          }
          return hits;
        },
      },
      {
        name: `Rapier castRayAndGetNormal`,
        run(ops) {
          let hits = 0;
          for (let i = 0; i < ops; i++) {
            const p = at(cursor++);
            ray.origin = { x: rays[p]!, y: rays[p + 1]! };
            ray.dir = { x: rays[p + 2]!, y: rays[p + 3]! };
            if (world.castRayAndGetNormal(ray, 1, true) !== null) hits++;
          }
          return hits;
        },
      },
    ];
    const section = ctx.compare(`N = ${n}: one ray`, candidates, { unit: 'ray' });
    for (const [i, c] of section.candidates.entries()) {
      const ns = c.ns.median;
      rows.push([
        String(n),
        c.name,
        ns.toFixed(0),
        (1e6 / ns).toFixed(0),
        i === 0 ? '' : `${(ns / section.candidates[0]!.ns.median).toFixed(2)}×`,
      ]);
    }
    // Checks: hits per engine over the whole set, and closest = first of all hits.
    let ownHits = 0;
    let rapierHits = 0;
    let agree = 0;
    for (let k = 0; k < RAYS; k++) {
      const p = 4 * k;
      const closest = own.castRayClosest(rays[p]!, rays[p + 1]!, rays[p + 2]!, rays[p + 3]!);
      const all = own.castRay(rays[p]!, rays[p + 1]!, rays[p + 2]!, rays[p + 3]!);
      if (closest !== null) ownHits++;
      if ((closest?.body ?? -2) === (all[0]?.body ?? -2)) agree++;
      ray.origin = { x: rays[p]!, y: rays[p + 1]! };
      ray.dir = { x: rays[p + 2]!, y: rays[p + 3]! };
      if (world.castRay(ray, 1, true) !== null) rapierHits++;
    }
    checks.push([String(n), String(ownHits), String(rapierHits), `${agree} / ${RAYS}`]);
    sim.dispose();
  }
  ctx.table(
    'Ray casts: ns per ray and rays per ms (medians of the section above)',
    ['N', 'query', 'ns/ray', 'rays/ms', 'vs own closest'],
    rows,
  );
  ctx.table(
    `Checks over the ${RAYS} rays`,
    ['N', 'own rays that hit', 'Rapier rays that hit', 'own closest = castRay()[0]'],
    checks,
  );
}

export default defineSuite({
  name: 'ray-casts',
  description:
    'ray casts per ms in a settled pile: own PhysicsWorld castRayClosest/castRay vs Rapier castRay',
  run,
});
