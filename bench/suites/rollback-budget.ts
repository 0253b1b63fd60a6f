/**
 * The rollback budget: what a rollback of 8 ticks costs in fixedstep's own PhysicsWorld and in
 * Rapier's deterministic build under `@fixedstep/rapier`, side by side in one process, for the
 * same scene (`circlesInBoxScene(N)`: circles falling into a box, settled into a pile; sleeping
 * off in both, since a sleeping pile costs nothing; Rapier's bodies rotate, the own world's do
 * not). Per N: µs to save a tick, to load one, to step 8 ticks, and a whole rollback as
 * `RollbackSession` does it — load the confirmed tick, then 8 × (step + save); for two piles: the
 * settled one (120 ticks after the top row landed) and the livelier one (30 ticks after: more
 * motion, more contacts changing, the pile the search below uses). Then the largest N whose
 * rollback fits in 4 ms (a quarter of a 60 Hz frame), searched by bisection on N.
 *
 * **Outliers**: the own world's rollback of the same pile with one tiny body 500 m away, with the
 * grid before (cells doubled until the whole span fits the budget, crowding the pile) and now
 * (the crowded grid hashed at the bodies' size; see broad-phase.ts), side by side with the pile
 * alone.
 *
 * The own world is used only through its public API (see {@link ownWorld}): `load()`, `step()`,
 * and `saveInto` a buffer kept per tick, as `RollbackSession` saves a simulation that has
 * `snapshotSize` and `saveInto`.
 */
import { ByteWriter, buildWorld, circlesInBoxScene, fnv1a64, type PhysicsScene } from 'fixedstep';
import {
  RapierSimulation,
  loadRapier,
  physicsSceneDef,
  rapierVersion,
  writeCanonicalState,
  type RapierModule,
} from '@fixedstep/rapier';
import { formatRatio } from '../lib/format.js';
import type { Candidate } from '../lib/measure.js';
import type { ComparisonSection } from '../lib/report.js';
import { median } from '../lib/stats.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';
import { settleSteps } from '../peers/checks.js';
// The switch a test or this benchmark flips to run the grid as it was before (internal).
import { hashedGridSetting } from '../../packages/fixedstep/src/physics/world/broad-phase.js';

const SEED = 0xb0d1e5;
/** Ticks a rollback re-simulates. */
export const DEPTH = 8;
/** The budget for one rollback, ms: a quarter of a 60 Hz frame. */
export const BUDGET_MS = 4;
const SIZES = [100, 500, 2000];
const QUICK_SIZES = [100, 500];
/** Ticks the two piles settle after the top row has landed: settled, and livelier. */
const PILES = [
  { base: 120, name: 'settled' },
  { base: 30, name: 'livelier' },
] as const;
/** Where the outlier is: one circle of 2 cm, this far to the right of the pile. Metres. */
const OUTLIER_X = 5000;

/** One world under test: the operations a rollback needs. */
export interface RollbackWorld {
  readonly name: string;
  /** The state of the current tick. */
  save(): Uint8Array;
  /**
   * The state of the current tick written into the `slot`-th buffer the world keeps, as
   * `RollbackSession` does with a simulation that has `saveInto` (one buffer per tick of its
   * history, rewritten in place): valid until that slot is saved again. Worlds without it save().
   */
  saveKept?(slot: number): Uint8Array;
  /** Restore a state from {@link save}. */
  load(bytes: Uint8Array): void;
  /** One fixed step. */
  step(): void;
  /** A hash of the current state (for the checks). */
  hash(): bigint;
  dispose(): void;
}

/** fixedstep's PhysicsWorld, sleeping off, through its public API. */
export function ownWorld(scene: PhysicsScene): RollbackWorld {
  const world = buildWorld({ ...scene, def: { ...scene.def, enableSleep: false } });
  const kept: Uint8Array[] = [];
  return {
    name: 'fixedstep PhysicsWorld',
    save: () => world.save(),
    saveKept: (slot) => {
      const size = world.snapshotSize;
      let buffer = kept[slot];
      if (buffer === undefined || buffer.length < size) buffer = kept[slot] = new Uint8Array(size);
      return buffer.subarray(0, world.saveInto(buffer));
    },
    load: (bytes) => {
      world.load(bytes);
    },
    step: () => {
      world.step();
    },
    hash: () => world.hash(),
    dispose: () => undefined,
  };
}

/** The same scene in Rapier under `@fixedstep/rapier`: rotation unlocked, sleeping off. */
export function rapierWorld(scene: PhysicsScene): RollbackWorld {
  const sim = new RapierSimulation(physicsSceneDef(scene, { id: 'rollback-budget' }));
  const none: readonly number[] = [0];
  return {
    name: `Rapier ${rapierVersion()} (deterministic)`,
    save: () => sim.save(),
    load: (bytes) => {
      sim.load(bytes);
    },
    step: () => {
      sim.step(none);
    },
    hash: () => sim.hash(),
    dispose: () => {
      sim.dispose();
    },
  };
}

/**
 * Rapier bare: the same world with its own `takeSnapshot()` / `World.restoreSnapshot()` (and
 * `free()` of the replaced world), no adapter — shows what the adapter's header, checks and
 * checksum add. Needs the module from `loadRapier()`.
 */
export function rapierBare(rapier: RapierModule): (scene: PhysicsScene) => RollbackWorld {
  return (scene) => {
    const def = physicsSceneDef(scene, { id: 'rollback-budget' });
    let world = new rapier.World(def.gravity ?? { x: 0, y: -9.81 });
    world.timestep = Math.fround(1 / (def.tickRate ?? 60));
    if (def.solverIterations !== undefined) world.numSolverIterations = def.solverIterations;
    def.build(world, rapier);
    const canonical = new ByteWriter(4096);
    return {
      name: `Rapier ${rapierVersion()} bare snapshots`,
      save: () => world.takeSnapshot(),
      load: (bytes) => {
        const next = rapier.World.restoreSnapshot(bytes);
        world.free();
        world = next;
      },
      step: () => {
        world.step();
      },
      hash: () =>
        fnv1a64(writeCanonicalState(canonical.reset(), world, 0, new Uint8Array(0)).peek()),
      dispose: () => {
        world.free();
      },
    };
  };
}

/** Builds `circlesInBoxScene(n)` in `make` and lets the circles fall into a pile. */
export function settled(
  make: (scene: PhysicsScene) => RollbackWorld,
  n: number,
  base = 120,
): RollbackWorld {
  const scene = circlesInBoxScene(n, SEED);
  const world = make(scene);
  const steps = settleSteps(scene, base);
  for (let k = 0; k < steps; k++) world.step();
  return world;
}

/** A tick's save the way a rollback keeps it: into a kept buffer where the world can. */
function save(world: RollbackWorld, slot: number): Uint8Array {
  return world.saveKept ? world.saveKept(slot) : world.save();
}

/**
 * The four operations on a settled world as benchmark candidates. `rollback`: load the saved
 * tick, then `DEPTH` × (step + save) — what `RollbackSession` does per correction. Each op
 * returns a number derived from its result (the harness keeps it).
 */
export function operations(
  world: RollbackWorld,
): Record<'save' | 'load' | 'steps' | 'rollback', Candidate> {
  const start = world.save();
  let last = start;
  return {
    save: {
      name: world.name,
      run(ops) {
        let n = 0;
        for (let i = 0; i < ops; i++) n += save(world, i % DEPTH).length;
        return n;
      },
    },
    load: {
      name: world.name,
      run(ops) {
        for (let i = 0; i < ops; i++) world.load(start);
        return ops;
      },
    },
    steps: {
      name: world.name,
      run(ops) {
        for (let i = 0; i < ops; i++) for (let k = 0; k < DEPTH; k++) world.step();
        return ops;
      },
    },
    rollback: {
      name: world.name,
      run(ops) {
        let n = 0;
        for (let i = 0; i < ops; i++) {
          world.load(start);
          for (let k = 0; k < DEPTH; k++) {
            world.step();
            last = save(world, k);
          }
          n += last.length;
        }
        return n;
      },
    },
  };
}

/**
 * The fastest and the median of `reps` rollbacks (load + DEPTH × (step + save)) of a settled
 * world of `n` bodies, ms. The work is the same every time, so whatever else the machine does only
 * adds to it: on a shared machine the fastest is the best estimate of the cost.
 */
export function rollbackMs(
  make: (scene: PhysicsScene) => RollbackWorld,
  n: number,
  reps: number,
): { min: number; median: number } {
  const world = settled(make, n, 30);
  const op = operations(world).rollback;
  op.run(2); // warm-up
  const times: number[] = [];
  for (let r = 0; r < reps; r++) {
    const t0 = process.hrtime.bigint();
    op.run(1);
    times.push(Number(process.hrtime.bigint() - t0) / 1e6);
  }
  world.dispose();
  return { min: Math.min(...times), median: median(times) };
}

/**
 * The largest N (to within 5 %) whose fastest rollback takes at most `budgetMs`, by bisection
 * between N = 25 and `maxN`; `probes` lists every N tried with its fastest and median time.
 */
export function largestWithin(
  make: (scene: PhysicsScene) => RollbackWorld,
  budgetMs: number,
  maxN: number,
  reps: number,
): { n: number; probes: [n: number, min: number, median: number][] } {
  const probes: [number, number, number][] = [];
  const fits = (n: number) => {
    const ms = rollbackMs(make, n, reps);
    probes.push([n, ms.min, ms.median]);
    return ms.min <= budgetMs;
  };
  let lo = 25;
  if (!fits(lo)) return { n: 0, probes };
  let hi = lo * 4;
  while (hi < maxN && fits(hi)) {
    lo = hi;
    hi *= 4;
  }
  if (hi >= maxN) {
    if (fits(maxN)) return { n: maxN, probes };
    hi = maxN;
  }
  while (hi / lo > 1.05) {
    const mid = Math.round(Math.sqrt(lo * hi));
    if (fits(mid)) lo = mid;
    else hi = mid;
  }
  return { n: lo, probes };
}

const us = (section: ComparisonSection, i: number): number =>
  section.candidates[i]!.ns.median / 1e3;

async function run(ctx: SuiteContext): Promise<void> {
  const bare = rapierBare(await loadRapier());
  const sizes = ctx.quick ? QUICK_SIZES : SIZES;
  ctx.note(
    `circlesInBoxScene(N, ${SEED}) (radii 0.10–0.15 m, dt 1/60 s), settled into a pile; sleeping off ` +
      'in both. fixedstep PhysicsWorld: saveInto() a kept buffer per tick (what RollbackSession ' +
      'does with a simulation that has saveInto; save() allocates a new array each tick), load(), ' +
      'step(), no rotation. Rapier: ' +
      '@fixedstep/rapier RapierSimulation (save = header + takeSnapshot() + checksum, load = ' +
      `World.restoreSnapshot()), bodies rotate, numSolverIterations = the scene's velocity iterations; ` +
      'Rapier bare: the same world saved and loaded by takeSnapshot()/restoreSnapshot() alone. ' +
      `A rollback = load + ${DEPTH} × (step + save), as RollbackSession does it.`,
  );
  const rows: string[][] = [];
  for (const n of sizes) {
    for (const pile of PILES) {
      const worlds = [
        settled(ownWorld, n, pile.base),
        settled(rapierWorld, n, pile.base),
        settled(bare, n, pile.base),
      ];
      rows.push(...budgetRows(ctx, n, pile, worlds));
      for (const w of worlds) w.dispose();
    }
  }
  ctx.table(
    `The rollback budget: µs per operation (medians of the sections above)`,
    [
      'N',
      'pile',
      'world',
      'bytes/body',
      'save µs',
      'load µs',
      `${DEPTH} steps µs`,
      'rollback µs',
      `≤ ${BUDGET_MS} ms`,
      'vs own',
    ],
    rows,
  );
  outliers(ctx, sizes[sizes.length - 1]!);
  if (ctx.quick) {
    ctx.note('Quick run: no search for the largest N (npm run bench -- rollback-budget does it).');
    return;
  }
  const reps = 15;
  const found = [ownWorld, rapierWorld].map((make) => ({
    name: make === ownWorld ? 'fixedstep PhysicsWorld' : `Rapier ${rapierVersion()}`,
    ...largestWithin(make, BUDGET_MS, 16_000, reps),
  }));
  ctx.table(
    `The largest N whose ${DEPTH}-tick rollback takes ≤ ${BUDGET_MS} ms on the livelier pile (bisection to 5 %; the fastest of ${reps} rollbacks per probe decides, the median in brackets)`,
    ['world', 'largest N', 'probes (N: ms)'],
    found.map((f) => [
      f.name,
      String(f.n),
      f.probes.map(([n, min, med]) => `${n}: ${min.toFixed(2)} (${med.toFixed(2)})`).join(', '),
    ]),
  );
}

/** One size and pile: the four sections side by side, and the table's rows for them. */
function budgetRows(
  ctx: SuiteContext,
  n: number,
  pile: (typeof PILES)[number],
  worlds: RollbackWorld[],
): string[][] {
  const rows: string[][] = [];
  {
    const bytes = worlds.map((w) => w.save().length);
    const ops = worlds.map(operations);
    const section = (what: 'save' | 'load' | 'steps' | 'rollback', title: string) =>
      ctx.compare(
        `N = ${n}, ${pile.name} pile: ${title}`,
        ops.map((o) => o[what]),
        { unit: what === 'steps' ? `${DEPTH} steps` : what },
      );
    const save = section('save', 'save one tick');
    const load = section('load', 'load one tick');
    const steps = section('steps', `step ${DEPTH} ticks`);
    const rollback = section(
      'rollback',
      `roll back ${DEPTH} ticks: load + ${DEPTH} × (step + save)`,
    );
    for (const [i, w] of worlds.entries()) {
      rows.push([
        String(n),
        pile.name,
        w.name,
        (bytes[i]! / n).toFixed(0),
        us(save, i).toFixed(1),
        us(load, i).toFixed(1),
        us(steps, i).toFixed(0),
        us(rollback, i).toFixed(0),
        us(rollback, i) <= BUDGET_MS * 1000 ? 'yes' : 'no',
        i === 0 ? '' : formatRatio(us(rollback, i) / us(rollback, 0)),
      ]);
    }
  }
  return rows;
}

/** `circlesInBoxScene(n)` with one circle of 2 cm at {@link OUTLIER_X} m, resting on a ledge (5 km: the pile's grid doubles its cells three times). */
function outlierScene(n: number): PhysicsScene {
  const scene = circlesInBoxScene(n, SEED);
  return {
    ...scene,
    walls: [...scene.walls, { x: OUTLIER_X, y: 0, halfWidth: 1, halfHeight: 0.5 }],
    bodies: [...scene.bodies, { x: OUTLIER_X, y: 0.52, vx: 0, vy: 0, radius: 0.02 }],
  };
}

/**
 * The own world's rollback of the livelier pile of `n` circles, alone and with one far tiny body:
 * with the grid before (`hashedGridSetting` off while it runs) and now.
 */
function outliers(ctx: SuiteContext, n: number): void {
  const pile = settled(ownWorld, n, 30);
  const scene = outlierScene(n);
  const far = ownWorld(scene);
  for (let k = 0; k < settleSteps(scene, 30); k++) far.step();
  const before = ownWorld(scene);
  before.load(far.save());
  const rollback = (world: RollbackWorld, name: string, hashed: boolean): Candidate => {
    const op = operations(world).rollback;
    return {
      name,
      run(ops) {
        hashedGridSetting.enabled = hashed;
        try {
          return op.run(ops);
        } finally {
          hashedGridSetting.enabled = true;
        }
      },
    };
  };
  const section = ctx.compare(
    `Outliers, N = ${n} (livelier pile): roll back ${DEPTH} ticks with one 2 cm circle ${OUTLIER_X} m away`,
    [
      rollback(pile, 'the pile alone', true),
      rollback(before, `+ far body, grid before (cells doubled to fit the span)`, false),
      rollback(far, '+ far body, grid now (crowded grid hashed)', true),
    ],
    { unit: 'rollback' },
  );
  ctx.table(
    `Outliers: the ${DEPTH}-tick rollback of ${n} circles with one far tiny body, µs (medians of the section above)`,
    ['world', 'rollback µs', 'vs the pile alone'],
    section.candidates.map((c, i) => [
      c.name,
      us(section, i).toFixed(0),
      formatRatio(us(section, i) / us(section, 0)),
    ]),
  );
}

export default defineSuite({
  name: 'rollback-budget',
  description: `save, load, ${DEPTH}-tick re-simulation and the largest N within ${BUDGET_MS} ms: own PhysicsWorld vs Rapier`,
  run,
});
