/**
 * The own PhysicsWorld's snapshots and rollback cost, on `bodiesInBoxScene` (circles and boxes
 * falling into a box, sleeping off so every body is simulated every tick).
 *
 * - **Throughput**, at N = 100, 500 and 2,000 bodies: `saveInto` into a reused buffer, `save()`
 *   (a new array each time), `load`, side by side with a plain `Uint8Array.set` copy of the same
 *   number of bytes — the speed a snapshot could have if it were nothing but a copy. GB/s and
 *   bytes per body.
 * - **Rollback**: µs to save a tick, to load one, to re-simulate 8 ticks, and a whole rollback of
 *   8 ticks as a rollback session does it (load the snapshot 8 ticks back, then step and save 8
 *   times); then the largest N whose rollback of 8 ticks fits in 4 ms (not in `--quick`).
 * - **Allocation** per save, load and rollback: a rollback loop must not make garbage.
 */
import { bodiesInBox, bodiesInBoxScene, type PhysicsWorld } from 'fixedstep';
import { formatBytes } from '../lib/format.js';
import { runAllocation, runInterleaved, type MeasurePlan } from '../lib/measure.js';
import { ALLOCATION_NOISE_BYTES } from '../lib/report.js';
import { bytesPerOp, median } from '../lib/stats.js';
import { defineSuite, type Candidate, type SuiteContext } from '../lib/suite.js';

export const SEED = 0x5a7e;
/** Body counts of the throughput and rollback tables. */
export const SIZES = [100, 500, 2000];
/** Ticks a rollback re-simulates. */
export const ROLLBACK_TICKS = 8;
/** The rollback budget: a 60 Hz frame has 16.7 ms; a quarter of it for re-simulation. */
export const BUDGET_MS = 4;

/**
 * The scene at `n` bodies, settled `base` ticks after the top row has landed; sleeping off
 * unless `sleep` (then a settled pile sleeps, and steps cost almost nothing).
 */
export function settledWorld(n: number, base = 120, sleep = false): PhysicsWorld {
  const scene = bodiesInBoxScene(n, SEED, { enableSleep: sleep });
  const top = Math.max(0, ...scene.bodies.map((b) => b.y));
  const fall = Math.ceil(Math.sqrt((2 * top) / 9.81) / scene.def.timeStep);
  const world = bodiesInBox(n, SEED, { enableSleep: sleep });
  for (let t = 0; t < base + fall; t++) world.step();
  return world;
}

/**
 * A plain copy of `size` bytes into a second buffer: the speed of light for a snapshot. Each op
 * changes one source byte first, so the copy is real; returns the last copied value.
 */
export function copyControl(size: number): Candidate {
  const from = new Uint8Array(size).fill(1);
  const to = new Uint8Array(size);
  return {
    name: 'Uint8Array.set (same bytes)',
    run(ops) {
      for (let k = 0; k < ops; k++) {
        from[k & 63] = k;
        to.set(from);
      }
      return to[(ops - 1) & 63]!;
    },
  };
}

/** `world.saveInto` into one reused buffer. */
export function saveIntoCandidate(world: PhysicsWorld): Candidate {
  const out = new Uint8Array(world.snapshotSize);
  return {
    name: 'saveInto (reused buffer)',
    run(ops) {
      let n = 0;
      for (let k = 0; k < ops; k++) n += world.saveInto(out);
      return n;
    },
  };
}

/** `world.save()`: a new array each time. */
export function saveCandidate(world: PhysicsWorld): Candidate {
  return {
    name: 'save() (new array)',
    run(ops) {
      let n = 0;
      for (let k = 0; k < ops; k++) n += world.save().length;
      return n;
    },
  };
}

/** `world.load` of its own snapshot. */
export function loadCandidate(world: PhysicsWorld): Candidate {
  const bytes = world.save();
  return {
    name: 'load',
    run(ops) {
      for (let k = 0; k < ops; k++) world.load(bytes);
      return world.tick;
    },
  };
}

/**
 * A rollback of `ticks` ticks, from the world's current state: load the snapshot, then step
 * `ticks` times, saving each tick into a ring of buffers (with `save` false: steps only, which
 * minus a load is the cost of re-simulating). Every op does the very same work.
 */
export function rollbackCandidate(world: PhysicsWorld, ticks: number, save: boolean): Candidate {
  const start = world.save();
  const ring = Array.from({ length: ticks }, () => new Uint8Array(2 * world.snapshotSize + 4096));
  return {
    name: save ? `rollback: load + ${ticks} × (step + saveInto)` : `load + ${ticks} steps`,
    run(ops) {
      for (let k = 0; k < ops; k++) {
        world.load(start);
        for (let t = 0; t < ticks; t++) {
          world.step();
          if (save) world.saveInto(ring[t]!);
        }
      }
      return world.tick;
    },
  };
}

/**
 * Heap allocated per op, each candidate with its own number of ops per chunk (a rollback takes
 * milliseconds; 10,000 of them per chunk would take minutes), after `warm` ops so that V8 has
 * optimised everything (code still running unoptimised boxes its doubles: garbage that a warm
 * loop does not make). Needs `--expose-gc` (`npm run bench` passes it).
 */
function allocationTable(
  ctx: SuiteContext,
  n: number,
  warm: number,
  candidates: readonly (readonly [Candidate, number])[],
): void {
  const rows: string[][] = [];
  for (const [candidate, ops] of candidates) {
    candidate.run(warm);
    const run = runAllocation([candidate], ctx.plan.allocChunks, ops);
    if (run === undefined) {
      rows.push([candidate.name, 'needs node --expose-gc', '', String(ops)]);
      continue;
    }
    const bytes = bytesPerOp(run.chunks[0]!, run.empty, ops).median;
    rows.push([
      candidate.name,
      formatBytes(bytes),
      `< ${formatBytes(ALLOCATION_NOISE_BYTES / ops)}`,
      String(ops),
    ]);
  }
  ctx.table(
    `N = ${n}: heap allocated per op (median of ${ctx.plan.allocChunks} chunks, after ${warm} ops)`,
    ['op', 'B/op', 'noise', 'ops/chunk'],
    rows,
  );
}

/** Median µs per op of each candidate, timed interleaved. */
function microseconds(candidates: readonly Candidate[], plan: MeasurePlan): number[] {
  return runInterleaved(candidates, plan).samples.map((s) => median(s) / 1e3);
}

interface SizeResult {
  n: number;
  bytes: number;
  copyUs: number;
  saveUs: number;
  loadUs: number;
  resimUs: number;
  rollbackUs: number;
}

function measureSize(ctx: SuiteContext, n: number): SizeResult {
  const world = settledWorld(n, ctx.quick ? 30 : 120);
  const bytes = world.snapshotSize;
  // Separate worlds for the candidates that change the state, all in the same settled state.
  const twin = () => {
    const w = bodiesInBox(n, SEED, { enableSleep: false });
    w.load(world.save());
    return w;
  };
  const candidates = [
    copyControl(bytes),
    saveIntoCandidate(world),
    saveCandidate(world),
    loadCandidate(twin()),
    rollbackCandidate(twin(), ROLLBACK_TICKS, false),
    rollbackCandidate(twin(), ROLLBACK_TICKS, true),
  ];
  const section = ctx.compare(
    `N = ${n}: snapshot of ${formatBytes(bytes)} (${(bytes / n).toFixed(1)} B/body)`,
    candidates,
  );
  const us = section.candidates.map((c) => c.ns.median / 1e3);
  return {
    n,
    bytes,
    copyUs: us[0]!,
    saveUs: us[1]!,
    loadUs: us[3]!,
    resimUs: us[4]! - us[3]!,
    rollbackUs: us[5]!,
  };
}

/** The rollback of {@link ROLLBACK_TICKS} ticks at `n` bodies, ms (median of a short run). */
function rollbackMs(n: number, plan: MeasurePlan): number {
  const world = settledWorld(n);
  return microseconds([rollbackCandidate(world, ROLLBACK_TICKS, true)], plan)[0]! / 1e3;
}

/**
 * The largest N (to about 5 %) whose rollback fits in {@link BUDGET_MS}: doubles from 2,000
 * until over, then bisects.
 */
function largestWithinBudget(plan: MeasurePlan): {
  n: number;
  ms: number;
  over: number;
  overMs: number;
} {
  let lo = 0;
  let loMs = 0;
  let hi = 2000;
  let hiMs = rollbackMs(hi, plan);
  while (hiMs <= BUDGET_MS && hi < 64_000) {
    lo = hi;
    loMs = hiMs;
    hi *= 2;
    hiMs = rollbackMs(hi, plan);
  }
  if (hiMs <= BUDGET_MS) return { n: hi, ms: hiMs, over: hi, overMs: hiMs };
  if (lo === 0) {
    lo = 250;
    loMs = rollbackMs(lo, plan);
  }
  while (hi - lo > 0.05 * hi) {
    const mid = Math.round((lo + hi) / 2);
    const ms = rollbackMs(mid, plan);
    if (ms <= BUDGET_MS) {
      lo = mid;
      loMs = ms;
    } else {
      hi = mid;
      hiMs = ms;
    }
  }
  return { n: lo, ms: loMs, over: hi, overMs: hiMs };
}

export default defineSuite({
  name: 'physics-world-snapshot',
  description:
    "The own world's snapshots (GB/s vs a plain copy, B/body, allocation) and rollback cost",
  run(ctx) {
    ctx.note(
      `bodiesInBoxScene(N, ${SEED}): circles and boxes falling into a box, sleeping off, ` +
        `settled ${ctx.quick ? 30 : 120} ticks after the top row landed; 1/60 s, 8 + 3 iterations.`,
    );
    const results = SIZES.map((n) => measureSize(ctx, n));
    const gbps = (bytes: number, us: number) => (bytes / (us * 1e3)).toFixed(2);
    ctx.table(
      'Snapshot throughput (GB/s = bytes per ns)',
      ['N', 'bytes', 'B/body', 'saveInto GB/s', 'load GB/s', 'Uint8Array.set GB/s'],
      results.map((r) => [
        String(r.n),
        String(r.bytes),
        (r.bytes / r.n).toFixed(1),
        gbps(r.bytes, r.saveUs),
        gbps(r.bytes, r.loadUs),
        gbps(r.bytes, r.copyUs),
      ]),
    );
    ctx.table(
      `Rollback of ${ROLLBACK_TICKS} ticks, µs (re-simulate = load + ${ROLLBACK_TICKS} steps − load)`,
      [
        'N',
        'save a tick',
        'load',
        `re-simulate ${ROLLBACK_TICKS}`,
        'whole rollback',
        `of ${BUDGET_MS} ms`,
      ],
      results.map((r) => [
        String(r.n),
        r.saveUs.toFixed(1),
        r.loadUs.toFixed(1),
        r.resimUs.toFixed(0),
        r.rollbackUs.toFixed(0),
        `${((100 * r.rollbackUs) / (BUDGET_MS * 1e3)).toFixed(0)} %`,
      ]),
    );

    // Allocation does not depend on N once the code is warm: measured at the smallest size, where
    // thousands of warm-up rollbacks take a second.
    const small = SIZES[0]!;
    const world = settledWorld(small, ctx.quick ? 30 : 120);
    const twin = bodiesInBox(small, SEED, { enableSleep: false });
    twin.load(world.save());
    allocationTable(ctx, small, ctx.quick ? 100 : 3000, [
      [saveIntoCandidate(world), 1000],
      [loadCandidate(twin), 1000],
      [rollbackCandidate(twin, ROLLBACK_TICKS, true), ctx.quick ? 20 : 100],
      [saveCandidate(world), 200],
    ]);

    const n = SIZES[SIZES.length - 1]!;

    if (ctx.quick) {
      ctx.note(`The largest N within ${BUDGET_MS} ms is searched in a full run only.`);
      return;
    }
    // For scale: the same rollback once the pile has fallen asleep (the default def sleeps).
    const sleeping = bodiesInBox(n, SEED);
    for (let t = 0; t < 3600 && sleeping.sleepingCount < sleeping.bodyCount; t++) sleeping.step();
    const [sleepingUs] = microseconds(
      [rollbackCandidate(sleeping, ROLLBACK_TICKS, true)],
      ctx.plan,
    );
    ctx.note(
      `With sleeping on (the default def), after ${sleeping.tick} ticks ${sleeping.sleepingCount} of ` +
        `the ${n} bodies sleep, and a rollback of ${ROLLBACK_TICKS} ticks takes ${sleepingUs!.toFixed(0)} µs.`,
    );

    const best = largestWithinBudget({ ...ctx.plan, warmupMs: 100, rounds: 10 });
    ctx.table(
      `The largest N that rolls back ${ROLLBACK_TICKS} ticks within ${BUDGET_MS} ms`,
      ['N', 'rollback ms', 'next N tried', 'its ms'],
      [[String(best.n), best.ms.toFixed(2), String(best.over), best.overMs.toFixed(2)]],
    );
  },
});
