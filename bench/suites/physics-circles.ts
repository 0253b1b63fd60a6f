/**
 * N circles falling into a closed box: fixedstep's PhysicsWorld against matter-js, planck.js and
 * Rapier, every engine building the very same scene (`circlesInBoxScene`: radii and positions from
 * fixedstep's seeded Random, the same walls, gravity, dt, friction and restitution, the same
 * solver iterations where the engine has such a setting). Sleeping is off everywhere, since a
 * sleeping pile costs nothing; rotation is locked in the peers, since fixedstep's bodies do not
 * rotate — except in two Rapier rows that show what rotation costs: the same build with rotation
 * unlocked, and Rapier's deterministic build under `@fixedstep/rapier` (rotating, as a game under
 * fixedstep runs it). See bench/peers/*.ts for each engine's settings.
 *
 * Every engine runs in a node process of its own (bench/peers/peer-program.ts): a fresh V8 isolate
 * each, so no engine pays for another's garbage, JIT state or process-wide V8 state. The worlds
 * settle in parallel (120 steps plus the time the top row takes to fall), are checked (all bodies
 * in the box and awake, a plausible pile), then all programs are pinned to one CPU and timed in
 * interleaved rounds, each timing its own steps.
 */
import { circlesInBoxScene } from 'fixedstep';
import { lastAllowedCpu } from '../c/springs.js';
import { formatRange, formatRatio } from '../lib/format.js';
import { median, ratios, spread } from '../lib/stats.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';
import { expectedPileHeight, PACKING, settleSteps, type Sanity } from '../peers/checks.js';
import { race } from '../peers/race.js';
import { ENGINES } from '../peers/registry.js';
import { PeerProcess } from '../peers/remote.js';

const SEED = 0xc1c1e;
const SIZES = [250, 1000, 4000];
const QUICK_SIZES = [250];

function sanityTable(
  ctx: SuiteContext,
  title: string,
  peers: readonly PeerProcess[],
  checks: readonly Sanity[],
  n: number,
): void {
  ctx.table(
    title,
    ['engine', 'in box', 'asleep', 'pile top p95 (m)', 'max overlap (mm)', 'mean speed (m/s)'],
    peers.map((p, i) => {
      const c = checks[i]!;
      return [
        p.info.name,
        `${c.inBox}/${n}`,
        String(c.asleep),
        c.pileTop.toFixed(2),
        (c.maxOverlap * 1e3).toFixed(1),
        c.meanSpeed.toFixed(3),
      ];
    }),
  );
}

async function runSize(
  ctx: SuiteContext,
  n: number,
  tsx: string,
  cpu: number | undefined,
  describe: boolean,
): Promise<void> {
  const scene = circlesInBoxScene(n, SEED);
  // A quick run leaves out the 4-iteration and deterministic Rapier rows and settles 60 steps less.
  const engines = ctx.quick
    ? ENGINES.filter((e) => e !== 'rapier-4' && e !== 'rapier-deterministic')
    : ENGINES;
  const peers = await Promise.all(engines.map((e) => PeerProcess.start(e, n, SEED, tsx)));
  try {
    if (describe) {
      ctx.note(
        `Same scene in every engine (seed ${SEED}, radii 0.10–0.15 m, density 1, friction 0.6, ` +
          `restitution 0, gravity −9.81 m/s², dt 1/60 s); sleeping off everywhere. Each engine ` +
          `runs in a node process of its own and times itself` +
          (cpu === undefined ? '.' : `; all are pinned to CPU ${cpu} while timed.`) +
          peers.map((p) => `\n  ${p.info.name}: ${p.info.settings}`).join(''),
      );
    }
    const settle = settleSteps(scene, ctx.quick ? 60 : 120);
    await Promise.all(peers.map((p) => p.settle(settle)));
    const checks = await Promise.all(peers.map((p) => p.sanity()));
    const expected = expectedPileHeight(scene);
    const [minX, , maxX, maxY] = scene.inner;
    sanityTable(
      ctx,
      `N = ${n}: after ${settle} steps (${(settle * scene.def.timeStep).toFixed(1)} s) in a ` +
        `${(maxX - minX).toFixed(1)} × ${maxY.toFixed(1)} m box; a pile at packing ${PACKING} ` +
        `would be ${expected.toFixed(2)} m high`,
      peers,
      checks,
      n,
    );
    const bad = peers.filter((_, i) => {
      const c = checks[i]!;
      return (
        c.inBox !== n || c.asleep !== 0 || !(c.pileTop > 0.4 * expected && c.pileTop < 3 * expected)
      );
    });
    if (bad.length > 0) {
      throw new Error(
        `implausible scene in ${bad.map((p) => p.info.name).join(', ')}: bodies out of the box ` +
          `or asleep, or a pile far from ${expected.toFixed(2)} m (see the table above)`,
      );
    }
    // Lower than perfectly packed circles could be: they must overlap.
    const dense = expected * PACKING;
    const soft = peers.filter((_, i) => checks[i]!.pileTop < dense).map((p) => p.info.name);
    if (soft.length > 0) {
      ctx.note(
        `${soft.join(', ')}: the pile is lower than circles packed without gaps could be ` +
          `(${dense.toFixed(2)} m): its circles sink into each other at these solver settings.`,
      );
    }

    if (cpu !== undefined) for (const p of peers) p.pin(cpu);
    const result = await race(peers, ctx.plan, {
      gc: async () => {
        await Promise.all(peers.map((p) => p.gc()));
      },
    });
    const us = result.samples.map((s) => s.map((ns) => ns / 1e3));
    const ours = us[0]!;
    ctx.table(
      `N = ${n}: time per step, ${ctx.plan.rounds} interleaved rounds of ~${ctx.plan.sampleMs} ms`,
      ['engine', 'µs/step', 'µs/body-step', 'ours/theirs', 'min–max'],
      peers.map((p, i) => {
        const t = median(us[i]!);
        const ratio = i === 0 ? undefined : spread(ratios(ours, us[i]!));
        return [
          p.info.name,
          t.toFixed(0),
          (t / n).toFixed(3),
          ratio ? formatRatio(ratio.median) : '(ours)',
          ratio ? formatRange(ratio.min, ratio.max) : '',
        ];
      }),
    );
    const after = await Promise.all(peers.map((p) => p.sanity()));
    const lost = peers.filter((_, i) => after[i]!.inBox !== n || after[i]!.asleep !== 0);
    if (lost.length > 0) {
      throw new Error(
        `bodies left the box or fell asleep while timing: ${lost.map((p) => p.info.name).join(', ')}`,
      );
    }
  } finally {
    await Promise.all(peers.map((p) => p.close()));
  }
}

export default defineSuite({
  name: 'physics-circles',
  description:
    'N circles falling into a box: fixedstep vs matter-js, planck.js, Rapier (WASM; rotation locked and unlocked)',
  async run(ctx) {
    const tsx = import.meta.resolve('tsx');
    const cpu = lastAllowedCpu();
    const sizes = ctx.quick ? QUICK_SIZES : SIZES;
    for (const [i, n] of sizes.entries()) await runSize(ctx, n, tsx, cpu, i === 0);
  },
});
