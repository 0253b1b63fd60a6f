/**
 * A particle + spring world step through the library's public API against the same update as a
 * plain C loop (bench/c/springs.c, compiled with gcc -O2 at bench time).
 *
 * Scenes: a rope from `springChain` and a cloth (a grid hung by its top row), damped Hooke springs
 * under gravity, stepped at 1/60 s with semi-implicit Euler (the library's default and the world's
 * method) or velocity Verlet. The C program keeps the library's data layout (flat x, v, a; springs
 * as parallel arrays) and does the same arithmetic in the same order, so both states must be
 * bit-identical after any number of steps: the suite checks that before it times anything.
 *
 * Candidates, all stepping the same scene the same number of steps per round:
 * - `SpringSystem.step`: the Simulation (integrator step + the render copy of the positions).
 *   Its arrays come from `SpringModel.allocate`, so a 2D model of ≥ 64 springs runs the
 *   WebAssembly kernel (kernels.wat);
 * - `Integrator.step, plain arrays`: `createIntegrator(method, new SpringModel(def))` on a
 *   `new DynamicsState(size)` of plain Float64Arrays: the JavaScript kernel;
 * - hand-written JS: the C loop written in TypeScript (2D, scalars, a plain function taking the
 *   arrays) — what JavaScript itself costs for this loop, the floor for a reusable library kernel;
 * - C (gcc -O2).
 * The JS contestants run in a program of their own (bench/c/springs-js.ts, a fresh node with the
 * bench's flags), the C one in springs.c; both time themselves (hrtime, clock_gettime) and answer
 * over a pipe, so no start-up or pipe latency is in the numbers, and both are pinned to the same
 * CPU (taskset, where there is one). Rounds alternate JS and C. A fresh process also keeps the
 * numbers independent of the suites that ran before (rapier's WASM memory growth, for one,
 * detaches an ArrayBuffer, after which V8 checks every typed-array access for detachment).
 */
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { SpringModel, springChain, springCloth, type SpringSystemDef } from 'fixedstep';
import {
  compileSprings,
  encodeSpringScene,
  gccVersion,
  GCC_FLAGS,
  jsProgramArgs,
  JS_CONTESTANTS,
  lastAllowedCpu,
  sceneOfModel,
  SpringsProcess,
  type CMethod,
} from '../c/springs.js';
import { race } from '../peers/race.js';
import { formatRange, formatRatio } from '../lib/format.js';
import { summarize } from '../lib/stats.js';
import { defineSuite, type SuiteContext } from '../lib/suite.js';

const DT = 1 / 60;
/** Steps from the start state before the C and JS states are compared. */
const CHECK_STEPS = 600;

interface Scene {
  readonly name: string;
  readonly method: CMethod;
  readonly def: SpringSystemDef;
}

/** A rope of `n` particles hung between two pins 5 cm apart per link (library builder). */
function rope(n: number, method: CMethod): Scene {
  return {
    name: `rope ${n}`,
    method,
    def: springChain({
      count: n,
      from: [0, 0],
      to: [(n - 1) * 0.05, 0],
      mass: 0.1,
      stiffness: 200,
      damping: 0.2,
      dt: DT,
      integrator: method,
    }),
  };
}

/**
 * A `w × h` cloth, 5 cm spacing, 10 g particles, 20 N/m links (k/m = 2000 s⁻², so ω·dt ≈ 1.5 on
 * the stiffest mode: stable at 1/60 s), hung by its whole top row. Structural springs only,
 * numbered particle by particle: right neighbour, then the one below.
 */
function cloth(w: number, h: number, method: CMethod): Scene {
  return {
    name: `cloth ${w}×${h}`,
    method,
    def: springCloth({ columns: w, rows: h, spacing: 0.05, dt: DT, integrator: method }),
  };
}

/** One contestant, in one of the two programs. */
interface Contestant {
  readonly name: string;
  readonly proc: SpringsProcess;
  /** Its index in springs-js.ts; undefined for springs.c. */
  readonly who: number | undefined;
}

/** How two dumps (x then v) differ: how many doubles, and by how much at most. */
function stateDiff(a: Float64Array, b: Float64Array): { differ: number; max: number } {
  let differ = 0;
  let max = 0;
  for (let i = 0; i < a.length; i++) {
    if (Object.is(a[i], b[i])) continue;
    differ++;
    max = Math.max(max, Math.abs(a[i]! - b[i]!));
  }
  return { differ, max };
}

async function runScene(
  ctx: SuiteContext,
  scene: Scene,
  binary: string,
  dir: string,
  cpu: number | undefined,
): Promise<void> {
  const model = new SpringModel(scene.def);
  const sceneBin = join(dir, 'scene.bin');
  const sceneJson = join(dir, 'scene.json');
  writeFileSync(sceneBin, encodeSpringScene(sceneOfModel(model, scene.method, DT)));
  writeFileSync(sceneJson, JSON.stringify({ def: scene.def, method: scene.method }));
  const tsx = import.meta.resolve('tsx');
  const [c, js] = await Promise.all([
    SpringsProcess.start(binary, [sceneBin], cpu),
    SpringsProcess.start(process.execPath, jsProgramArgs(sceneJson, tsx), cpu),
  ]);
  try {
    const contestants: Contestant[] = [
      ...JS_CONTESTANTS.map((name, who) => ({ name, proc: js, who })),
      { name: 'C (gcc -O2)', proc: c, who: undefined },
    ];

    // Equivalence: CHECK_STEPS steps from the same start, then the states' bytes.
    for (const k of contestants) await k.proc.step(CHECK_STEPS, k.who);
    const hashes = await Promise.all(contestants.map((k) => k.proc.hash(k.who)));
    const cHash = hashes.at(-1)!;
    const mismatched = contestants.filter((_, i) => hashes[i] !== cHash).map((k) => k.name);
    let detail = `bit-identical to every JS contestant (positions and velocities, ${2 * model.size} doubles)`;
    if (mismatched.length > 0) {
      const read = async (k: Contestant, file: string) => {
        await k.proc.dump(join(dir, file), k.who);
        const bytes = readFileSync(join(dir, file));
        return new Float64Array(
          bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length),
        );
      };
      const lib = await read(contestants[0]!, 'js.bin');
      const ref = await read(contestants.at(-1)!, 'c.bin');
      const diff = stateDiff(lib, ref);
      detail =
        `DIFFERS from ${mismatched.join(', ')}: the library's state differs in ${diff.differ} of ` +
        `${2 * model.size} doubles, by up to ${diff.max.toExponential(2)}`;
    }
    ctx.note(
      `${scene.name} (${model.count} particles, ${model.springA.length} springs, ${scene.method}, ` +
        `dt 1/60 s): after ${CHECK_STEPS} steps the C state hash is ${cHash}; ${detail}`,
    );
    if (mismatched.length > 0) {
      throw new Error(`${scene.name}: the C loop and the library do not compute the same thing`);
    }

    const timed = contestants.map((k) => ({ time: (steps: number) => k.proc.time(steps, k.who) }));
    const result = await race(timed, ctx.plan, { sameSteps: true, gc: () => js.gc() });
    const steps = result.steps[0]!;
    const perParticle = result.samples.map((s) => s.map((ns) => ns / model.count));
    const summary = summarize(
      contestants.map((k) => k.name),
      perParticle,
      contestants.length - 1,
    );
    ctx.table(
      `${scene.name}, ${scene.method}: ${steps} steps per sample, ${ctx.plan.rounds} interleaved rounds`,
      ['candidate', 'ns/particle-step', 'µs/step', 'ratio to C', 'min–max'],
      summary.map((s) => [
        s.name,
        s.ns.median.toFixed(2),
        ((s.ns.median * model.count) / 1e3).toFixed(1),
        s.ratio ? formatRatio(s.ratio.median) : formatRatio(1),
        s.ratio ? formatRange(s.ratio.min, s.ratio.max) : '(baseline)',
      ]),
    );
  } finally {
    await Promise.all([c.close(), js.close()]);
  }
}

export default defineSuite({
  name: 'physics-springs',
  description: 'Spring world step (rope, cloth) through the public API vs the same loop in C -O2',
  async run(ctx) {
    const gcc = gccVersion();
    if (gcc === undefined) {
      ctx.note('SKIPPED: no gcc on the PATH, so there is no C baseline to compare with.');
      return;
    }
    const dir = mkdtempSync(join(tmpdir(), 'fixedstep-springs-'));
    try {
      const binary = join(dir, 'springs');
      compileSprings(binary);
      ctx.note(`C baseline: bench/c/springs.c, ${gcc}, ${GCC_FLAGS.join(' ')}, built in ${dir}`);
      const cpu = lastAllowedCpu();
      ctx.note(
        cpu === undefined
          ? 'Not pinned (no taskset): JS and C may run on differently loaded CPUs; mind the spread.'
          : `The JS and C programs both run on CPU ${cpu} (taskset), so both see the same ` +
              'contention from the rest of the machine.',
      );
      const scenes = ctx.quick
        ? [rope(1000, 'semi-implicit-euler'), cloth(100, 100, 'semi-implicit-euler')]
        : [
            rope(1000, 'semi-implicit-euler'),
            cloth(100, 100, 'semi-implicit-euler'),
            cloth(100, 100, 'velocity-verlet'),
          ];
      for (const scene of scenes) await runScene(ctx, scene, binary, dir, cpu);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  },
});
