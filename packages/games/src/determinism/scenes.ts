/**
 * The catalogue's built-in scenes: the deterministic math helpers and the PRNG over fixed inputs,
 * the ball scene through `LoopRig`, the physics world scenes, a spring rope under each integrator.
 */
import {
  ByteWriter,
  FixedLoop,
  INTEGRATOR_METHODS,
  Random,
  SpringSystem,
  bulletsScene,
  buildWorld,
  circlesInBox,
  dacos,
  dasin,
  datan,
  datan2,
  dcos,
  dexp,
  dhypot,
  dlog,
  dsin,
  dsincos,
  dtan,
  springChain,
  springCloth,
  wrapAngle,
  type IntegratorMethod,
  type PhysicsWorld,
  type SpringSystemDef,
} from 'fixedstep';
import { BallButtons } from '../scenes/ball.js';
import { WallRange, type WallRangeOptions } from '../scenes/collisions.js';
import { OscillatorRace } from '../scenes/physics.js';
import { Rope, type RopePoke } from '../scenes/springs.js';
import { LoopRig, defaultBallScript, type ScriptedInput } from '../scenes/loop-rig.js';
import {
  displayRun,
  rateLabel,
  timestepOf,
  traceDisplay,
  TRACE_DISPLAY_HITCHES,
  TRACE_MAX_ACCUMULATOR_MS,
} from './display.js';
import { ballFields, physicsWorldFields, springSystemFields } from './layouts.js';
import { StateLayout } from './state-fields.js';
import type { TraceRun, TraceScene } from './trace.js';

// ----------------------------------------------------------------------------- function probes

/** One function probed over generated inputs. */
export interface FunctionProbe {
  /** How the report names it, e.g. `dsin`. */
  readonly name: string;
  /** Number of arguments. */
  readonly arity: number;
  /** Number of results written by {@link FunctionProbe.apply} (1, or 2 for sincos). */
  readonly results?: number;
  /** Arguments of sample `k` (k counts up from 0 over the whole run). */
  inputs(rng: Random, k: number): readonly number[];
  /** Computes the results of `args` into `out[0 … results − 1]`. */
  apply(args: readonly number[], out: Float64Array): void;
}

/** Options of {@link functionProbeScene}. */
export interface FunctionProbeSceneOptions {
  id: string;
  title: string;
  ticks: number;
  /** Samples of each function per tick. */
  samplesPerTick: number;
  seed: number;
  probes: readonly FunctionProbe[];
  informational?: boolean;
}

/**
 * A "scene" whose state at tick t is the inputs and results of every probe's samples of that
 * tick (canonical f64 bytes): its trace is a hash of every result's bits, never a sum that could
 * hide a difference. The field map names each result, e.g. `dsin(x#1234)`.
 */
export function functionProbeScene(o: FunctionProbeSceneOptions): TraceScene {
  const layout = new StateLayout();
  for (let s = 0; s < o.samplesPerTick; s++) {
    for (const p of o.probes) {
      const args = p.arity === 1 ? ['x'] : p.arity === 2 ? ['y', 'x'] : ['a', 'b', 'c', 'd'];
      for (let i = 0; i < p.arity; i++)
        layout.add('f64', `${p.name}(sample ${s}) argument ${args[i] ?? String(i)}`);
      const results = p.results ?? 1;
      for (let r = 0; r < results; r++) {
        layout.add('f64', `${p.name}(sample ${s})${results > 1 ? `[${r}]` : ''}`);
      }
    }
  }
  const base: TraceScene = {
    id: o.id,
    title: o.title,
    ticks: o.ticks,
    start(): TraceRun {
      const rng = new Random(o.seed);
      const w = new ByteWriter(layout.length);
      const out = new Float64Array(4);
      const counters = o.probes.map(() => 0);
      return {
        next(): Uint8Array {
          w.reset();
          for (let s = 0; s < o.samplesPerTick; s++) {
            for (let i = 0; i < o.probes.length; i++) {
              const p = o.probes[i]!;
              const args = p.inputs(rng, counters[i]!++);
              for (const a of args) w.f64(a);
              out.fill(0);
              p.apply(args, out);
              for (let r = 0; r < (p.results ?? 1); r++) w.f64(out[r]!);
            }
          }
          return w.peek();
        },
      };
    },
    fields: (state) => layout.covering(state.length),
  };
  return o.informational ? { ...base, informational: true } : base;
}

const words = new DataView(new ArrayBuffer(8));

/** A double from its two 32-bit halves, exactly. */
function fromWords(hi: number, lo: number): number {
  words.setUint32(0, hi >>> 0);
  words.setUint32(4, lo >>> 0);
  return words.getFloat64(0);
}

/** A random double of either sign with a binary exponent uniform in [minExp, maxExp] (≥ −1022). */
export function randomDouble(rng: Random, minExp: number, maxExp: number): number {
  const e = minExp + rng.int(maxExp - minExp + 1);
  const sign = rng.nextU32() & 0x80000000;
  const hi = sign | ((e + 1023) << 20) | (rng.nextU32() & 0xfffff);
  return fromWords(hi, rng.nextU32());
}

/** Inputs every function must survive: signed zeros, infinities, NaN, subnormals, extremes. */
export const SPECIAL_DOUBLES: readonly number[] = Object.freeze([
  0,
  -0,
  Infinity,
  -Infinity,
  NaN,
  Number.MIN_VALUE,
  -Number.MIN_VALUE,
  2.2250738585072014e-308,
  Number.MAX_VALUE,
  -Number.MAX_VALUE,
  1,
  -1,
  0.5,
  Math.PI,
  -Math.PI,
  Math.PI / 2,
  Math.PI / 4,
  1.6e6,
  -1.6e6,
  1e22,
  709.78,
  -745.13,
  1e-300,
]);

/** A mix of everyday, medium, huge, tiny, near-π/2-multiple and special arguments for sample k. */
export function angleInput(rng: Random, k: number): number {
  switch (k % 8) {
    case 0:
    case 1:
    case 2:
      return rng.range(-4, 4);
    case 3:
      return rng.range(-200, 200);
    case 4:
      return randomDouble(rng, -40, 20);
    case 5:
      return randomDouble(rng, 20, 1023);
    case 6: {
      const n = rng.int(20001) - 10000;
      return n * 1.5707963267948966 + rng.range(-1e-9, 1e-9);
    }
    default:
      return SPECIAL_DOUBLES[(k >>> 3) % SPECIAL_DOUBLES.length]!;
  }
}

function generalInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(-10, 10);
    case 1:
      return randomDouble(rng, -1022, 1023);
    case 2:
      return randomDouble(rng, -60, 60);
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

function unitInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
    case 1:
      return rng.range(-1, 1);
    case 2:
      return randomDouble(rng, -60, -1);
    default:
      return k % 8 === 3
        ? rng.range(-1.5, 1.5)
        : SPECIAL_DOUBLES[(k >>> 3) % SPECIAL_DOUBLES.length]!;
  }
}

function expInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(-20, 20);
    case 1:
      return rng.range(-750, 712);
    case 2:
      return randomDouble(rng, -60, -1);
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

function positiveInput(rng: Random, k: number): number {
  switch (k % 4) {
    case 0:
      return rng.range(0, 100);
    case 1:
      return Math.abs(randomDouble(rng, -1022, 1023));
    case 2:
      return fromWords(0, rng.nextU32()) + fromWords(rng.int(0x100000), 0); // subnormals
    default:
      return SPECIAL_DOUBLES[(k >>> 2) % SPECIAL_DOUBLES.length]!;
  }
}

/** A probe of a function of one number, its inputs drawn by `input` (sample k of a tick). */
export function unaryProbe(
  name: string,
  f: (x: number) => number,
  input: (rng: Random, k: number) => number,
): FunctionProbe {
  return {
    name,
    arity: 1,
    inputs: (rng, k) => [input(rng, k)],
    apply: (args, out) => {
      out[0] = f(args[0]!);
    },
  };
}

/**
 * A probe of a function of two numbers, drawn by `a` and `b` — by default `a` again, at half the
 * sample index (so the pairs are not all on the diagonal).
 */
export function binaryProbe(
  name: string,
  f: (a: number, b: number) => number,
  a: (rng: Random, k: number) => number,
  b: (rng: Random, k: number) => number = (rng, k) => a(rng, k >>> 1),
): FunctionProbe {
  return {
    name,
    arity: 2,
    inputs: (rng, k) => [a(rng, k), b(rng, k)],
    apply: (args, out) => {
      out[0] = f(args[0]!, args[1]!);
    },
  };
}

/** The deterministic math helpers of `fixedstep` (and the exact `Math.sqrt` they build on). */
export const DET_MATH_PROBES: readonly FunctionProbe[] = Object.freeze([
  unaryProbe('dsin', dsin, angleInput),
  unaryProbe('dcos', dcos, angleInput),
  unaryProbe('dtan', dtan, angleInput),
  {
    name: 'dsincos',
    arity: 1,
    results: 2,
    inputs: (rng, k) => [angleInput(rng, k)],
    apply: (args, out) => {
      dsincos(args[0]!, out, 0);
    },
  },
  unaryProbe('wrapAngle', wrapAngle, angleInput),
  unaryProbe('datan', datan, generalInput),
  binaryProbe('datan2', datan2, generalInput),
  unaryProbe('dasin', dasin, unitInput),
  unaryProbe('dacos', dacos, unitInput),
  unaryProbe('dexp', dexp, expInput),
  unaryProbe('dlog', dlog, positiveInput),
  binaryProbe('dhypot', dhypot, generalInput),
  unaryProbe('Math.sqrt', Math.sqrt, positiveInput),
]);

/** `fixedstep`'s deterministic math over 32 samples of each function per tick. */
export function detMathScene(ticks = 256): TraceScene {
  return functionProbeScene({
    id: 'math/det',
    title: 'deterministic math helpers (dsin … dhypot, Math.sqrt) over fixed inputs',
    ticks,
    samplesPerTick: 32,
    seed: 0x5eed,
    probes: DET_MATH_PROBES,
  });
}

// ----------------------------------------------------------------------------- Random

/** The `Random` stream: per tick, its state and 24 draws of every kind, plus a fresh seeding. */
export function randomScene(ticks = 2000): TraceScene {
  const layout = new StateLayout()
    .array('u32', 4, (i) => `rng.s${i}`)
    .array('u32', 8, (i) => `nextU32 #${i}`)
    .array('f64', 4, (i) => `next() #${i}`)
    .array('f64', 4, (i) => `range(-3, 7) #${i}`)
    .add('u32', 'int(1)')
    .add('u32', 'int(6)')
    .add('u32', 'int(1000)')
    .add('u32', 'int(3^20)')
    .add('u32', 'int(2^32)')
    .add('u32', 'new Random(tick × 0x9e3779b9).nextU32()');
  return {
    id: 'random/xoshiro',
    title: 'Random (xoshiro128**): state, nextU32, next, range, int, seeding',
    ticks,
    start(): TraceRun {
      const rng = new Random(20261122);
      const w = new ByteWriter(layout.length);
      let tick = 0;
      return {
        next(): Uint8Array {
          tick++;
          w.reset().ints(rng.getState());
          for (let i = 0; i < 8; i++) w.u32(rng.nextU32());
          for (let i = 0; i < 4; i++) w.f64(rng.next());
          for (let i = 0; i < 4; i++) w.f64(rng.range(-3, 7));
          w.u32(rng.int(1)).u32(rng.int(6)).u32(rng.int(1000)).u32(rng.int(3486784401));
          w.u32(rng.int(4294967296));
          w.u32(new Random(Math.imul(tick, 0x9e3779b9)).nextU32());
          return w.peek();
        },
      };
    },
    fields: (state) => layout.covering(state.length),
  };
}

// ----------------------------------------------------------------------------- ball / LoopRig

/**
 * The ball scene's input script for `seconds`: the loop chapter's two throws and push, then a
 * press every ~0.8 s — a throw, or left/right held 50–600 ms — at times drawn by a seeded Random.
 */
export function ballTraceScript(seconds: number): ScriptedInput[] {
  const rng = new Random(77);
  const out = defaultBallScript();
  for (let t = 3000; t < seconds * 1000 - 700; t += rng.range(500, 1100)) {
    const pick = rng.int(3);
    const button =
      pick === 0 ? BallButtons.throw : pick === 1 ? BallButtons.left : BallButtons.right;
    out.push({ timeMs: t, button, down: true });
    out.push({
      timeMs: t + rng.range(pick === 0 ? 5 : 50, pick === 0 ? 80 : 600),
      button,
      down: false,
    });
  }
  return out;
}

/** The ball scene, through `LoopRig` with the production loop (60 Hz step) on a display of `hz`. */
function ballRun(ticks: number, hz: number | undefined): TraceRun {
  const rig = new LoopRig({
    loop: { kind: 'fixed', fixed: { maxAccumulatorMs: TRACE_MAX_ACCUMULATOR_MS } },
    display:
      hz === undefined ? { hz: 60 } : { ...traceDisplay(hz), events: [...TRACE_DISPLAY_HITCHES] },
    script: ballTraceScript(Math.ceil(ticks / 60) + 2),
    trace: true,
  });
  const loop = rig.loop;
  let at = 0;
  const state = new Float64Array(6);
  const bytes = new Uint8Array(state.buffer);
  return {
    next(): Uint8Array {
      while (rig.trace.length < (at + 1) * 6) {
        rig.frame();
        if (loop instanceof FixedLoop && loop.droppedUnits() !== 0) {
          throw new Error(`ball at ${String(hz)} Hz dropped ${String(loop.droppedMs())} ms`);
        }
      }
      for (let i = 0; i < 6; i++) state[i] = rig.trace[at * 6 + i]!;
      at++;
      return bytes;
    },
  };
}

/** The ball scene at 60 Hz on a steady 60 Hz display, then on every jittery, hitching display. */
export function ballScenes(ticks: number, rates: readonly number[]): TraceScene[] {
  const base: TraceScene = {
    id: 'ball/loop-rig',
    title: 'the loop chapter’s ball, LoopRig + FixedLoop(60 Hz), steady 60 Hz display',
    ticks,
    start: () => ballRun(ticks, undefined),
    fields: ballFields,
  };
  return [
    base,
    ...rates.map((hz): TraceScene => ({
      id: `ball/loop-rig@${rateLabel(hz)}`,
      title: `the ball through LoopRig on a ${String(hz)} Hz display, ±30 % jitter, hitches`,
      ticks,
      sameAs: base.id,
      start: () => ballRun(ticks, hz),
      fields: ballFields,
    })),
  ];
}

// ----------------------------------------------------------------------------- physics world

function worldRun(make: () => PhysicsWorld): TraceRun {
  const world = make();
  return {
    next(): Uint8Array {
      world.step();
      return world.save();
    },
  };
}

/** The benchmark scene `circlesInBox(250, seed)`. */
export function circlesScene(ticks = 600, n = 250, seed = 7): TraceScene {
  return {
    id: `physics/circles-${String(n)}`,
    title: `circlesInBox(${String(n)}, ${String(seed)}): circles falling into a box, 1/60 s`,
    ticks,
    start: () => worldRun(() => circlesInBox(n, seed)),
    fields: physicsWorldFields,
  };
}

/** `bulletsScene(seed)` built with `buildWorld`, stepped directly, then on every display. */
export function bulletsScenes(ticks: number, rates: readonly number[], seed = 3): TraceScene[] {
  const scene = () => buildWorld(bulletsScene(seed));
  const base: TraceScene = {
    id: 'physics/bullets',
    title: `bulletsScene(${String(seed)}): 30 bullets at 200–1000 m/s with CCD, 0.03 s step`,
    ticks,
    start: () => worldRun(scene),
    fields: physicsWorldFields,
  };
  const variants = rates.map((hz): TraceScene => ({
    id: `physics/bullets@${rateLabel(hz)}`,
    title: `bulletsScene(${String(seed)}) through FixedLoop(30 ms) on a ${String(hz)} Hz display, jitter, hitches`,
    ticks,
    sameAs: base.id,
    start() {
      const world = scene();
      return displayRun({
        step: timestepOf(world.def.timeStep),
        display: traceDisplay(hz),
        scripts: [],
        advance: () => {
          world.step();
          return world.save();
        },
      });
    },
    fields: physicsWorldFields,
  }));
  const reloaded: TraceScene = {
    id: 'physics/bullets/reloaded',
    title: `bulletsScene(${String(seed)}), moved every 50 ticks into a freshly built world by save() → load()`,
    ticks,
    sameAs: base.id,
    start(): TraceRun {
      let world = scene();
      let tick = 0;
      return {
        next(): Uint8Array {
          world.step();
          const state = world.save();
          if (++tick % 50 === 0) {
            // Into a world built like the first one: a world of another capacity (e.g. a bare
            // `new PhysicsWorld()`) steps differently today — see e2e/determinism/findings.
            world = scene();
            world.load(state);
          }
          return state;
        },
      };
    },
    fields: physicsWorldFields,
  };
  return [base, reloaded, ...variants];
}

// ----------------------------------------------------------------------------- springs

/**
 * A rope of 24 particles pinned at both ends, sagging under gravity, with a kick to particle 8.
 * Stiff enough that explicit Euler gains energy but stays finite for a few thousand ticks.
 */
export function ropeDef(integrator: IntegratorMethod): SpringSystemDef {
  const def = springChain({
    count: 24,
    from: [0, 0],
    to: [4.6, 0],
    mass: 0.1,
    stiffness: 40,
    damping: 0.01,
    dt: 1 / 60,
    integrator,
  });
  return {
    ...def,
    particles: def.particles.map((p, i) => (i === 8 ? { ...p, velocity: [0.7, 2.5] } : p)),
  };
}

/** The rope under each of the six integrators, and (for the methods with memory) a snapshot round trip. */
export function ropeScenes(ticks = 1200): TraceScene[] {
  const fieldsOf = (method: IntegratorMethod) => {
    let system: SpringSystem | undefined;
    return (state: Uint8Array) => {
      system ??= new SpringSystem(ropeDef(method));
      return springSystemFields(system, state);
    };
  };
  const run = (method: IntegratorMethod, reloadEvery: number): TraceRun => {
    let s = new SpringSystem(ropeDef(method));
    let tick = 0;
    return {
      next(): Uint8Array {
        s.step();
        const state = s.save();
        if (reloadEvery > 0 && ++tick % reloadEvery === 0) {
          s = new SpringSystem(ropeDef(method));
          s.load(state);
        }
        return state;
      },
    };
  };
  const scenes = INTEGRATOR_METHODS.map((method): TraceScene => ({
    id: `springs/rope-${method}`,
    title: `SpringSystem rope (24 particles), ${method}, 1/60 s`,
    ticks,
    start: () => run(method, 0),
    fields: fieldsOf(method),
  }));
  const withMemory: IntegratorMethod[] = ['backward-euler', 'position-verlet', 'velocity-verlet'];
  for (const method of withMemory) {
    scenes.push({
      id: `springs/rope-${method}/reloaded`,
      title: `the ${method} rope, moved every 100 ticks into a fresh SpringSystem by save() → load()`,
      ticks,
      sameAs: `springs/rope-${method}`,
      start: () => run(method, 100),
      fields: fieldsOf(method),
    });
  }
  return scenes;
}

/**
 * A 12 × 10 cloth hung by its top row, kicked in one corner: 218 springs, so SpringSystem runs it
 * on the WebAssembly kernel (SpringModel.allocate) wherever WebAssembly runs — each engine's
 * WebAssembly must give the JavaScript kernel's bits.
 */
export function clothDef(integrator: IntegratorMethod): SpringSystemDef {
  const def = springCloth({ columns: 12, rows: 10, dt: 1 / 60, integrator });
  const corner = 9 * 12;
  return {
    ...def,
    particles: def.particles.map((p, i) => (i === corner ? { ...p, velocity: [0.4, 0.9] } : p)),
  };
}

/** The cloth under each of the six integrators. */
export function clothScenes(ticks = 600): TraceScene[] {
  return INTEGRATOR_METHODS.map((method): TraceScene => {
    let fieldsSystem: SpringSystem | undefined;
    return {
      id: `springs/cloth-${method}`,
      title: `SpringSystem cloth 12 × 10 (218 springs: the WebAssembly kernel), ${method}, 1/60 s`,
      ticks,
      start(): TraceRun {
        const s = new SpringSystem(clothDef(method));
        return {
          next(): Uint8Array {
            s.step();
            return s.save();
          },
        };
      },
      fields: (state) => {
        fieldsSystem ??= new SpringSystem(clothDef(method));
        return springSystemFields(fieldsSystem, state);
      },
    };
  });
}

// ----------------------------------------------------------------------------- the lab's scenes

/** A scene stepped by `step(t)` (t = 1, 2, …) and saved after every tick. */
function simScene(
  id: string,
  title: string,
  ticks: number,
  make: () => { save(): Uint8Array; step: (t: number) => void },
): TraceScene {
  return {
    id,
    title,
    ticks,
    start(): TraceRun {
      const sim = make();
      let t = 0;
      return {
        next(): Uint8Array {
          sim.step(++t);
          return sim.save();
        },
      };
    },
  };
}

/** Frame times of a 30 Hz display with ±30 % jitter and a 250 ms hitch every 200 frames, s. */
function jitteryFrames(seed: number): () => number {
  const rng = new Random(seed);
  let frame = 0;
  return () => (++frame % 200 === 0 ? 0.25 : (1 / 30) * rng.range(0.7, 1.3));
}

/**
 * The scenes chapters 3 and 4 of the lab run live: the firing range (fixed step, with and
 * without CCD, and one step per frame of a jittery display — a variable-Δt run is
 * reproducible too, given the same Δts), the six-integrator race on the talk's spring, and the
 * pokeable rope under explicit Euler (it explodes: the stop must land on the same tick in every
 * engine) and velocity Verlet.
 */
export function labScenes(ticks = 600): TraceScene[] {
  const range = (options: WallRangeOptions, dts?: () => number) => () => {
    const r = new WallRange(options);
    return {
      save: () => r.save(),
      step: () => {
        if (dts) r.stepBy(dts());
        else r.step();
      },
    };
  };
  const rope = (integrator: IntegratorMethod) => () => {
    const r = new Rope({ dt: 0.03, integrator });
    const none: RopePoke[] = [];
    return {
      save: () => r.save(),
      step: (t: number) => {
        r.step(t % 37 === 5 ? [{ bead: 1 + (t % 14), dvx: 2, dvy: -1 }] : none);
      },
    };
  };
  return [
    simScene(
      'lab/wall-range',
      'WallRange: 80 m/s against a 1.8 m wall, 30 ms fixed step, discrete detection',
      ticks,
      range({ speed: 80, wall: 1.8 }),
    ),
    simScene(
      'lab/wall-range-ccd',
      'WallRange: 300 m/s against a 0.3 m wall, 30 ms fixed step, CCD',
      ticks,
      range({ speed: 300, wall: 0.3, ccd: true }),
    ),
    simScene(
      'lab/wall-range-variable',
      'WallRange: 60 m/s against 3.5 m, one step per frame of a jittery 30 Hz display',
      ticks,
      range({ speed: 60, wall: 3.5 }, jitteryFrames(11)),
    ),
    simScene(
      'lab/oscillator-race',
      'OscillatorRace: k 20 N/m on 1 kg at dt 0.03 s, six integrators in lockstep',
      ticks,
      () => {
        const race = new OscillatorRace({ omega: Math.sqrt(20), dt: 0.03, explodeAt: 1e6 });
        return {
          save: () => race.save(),
          step: () => {
            race.step();
          },
        };
      },
    ),
    ...(['explicit-euler', 'velocity-verlet'] as const).map((m) =>
      simScene(
        `lab/rope-${m}`,
        `the lab's rope (16 beads, 40 N/m, 30 ms), ${m}, a poke every 37 ticks`,
        ticks,
        rope(m),
      ),
    ),
  ];
}
