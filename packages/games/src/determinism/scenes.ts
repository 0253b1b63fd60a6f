/**
 * The catalogue's built-in scenes: the PRNG over fixed inputs, the ball scene through `LoopRig`,
 * the physics world scenes, a spring rope under each integrator, the lab's scenes (the math
 * function probes are in probes.ts).
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
  PhysicsWorld,
  springChain,
  springCloth,
  type IntegratorMethod,
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
import {
  ballFields,
  filtersSensorsFields,
  physicsWorldFields,
  springSystemFields,
} from './layouts.js';
import { StateLayout } from './state-fields.js';
import type { TraceRun, TraceScene } from './trace.js';

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

/**
 * `circlesInBox(n, seed)` with materials on some bodies (its snapshot is version 3): friction of
 * their own (mixed by `Math.sqrt`, on the JavaScript sweeps), restitution (the world's 0.1, some
 * up to 0.9) and linear damping.
 */
export function materialsWorld(n = 250, seed = 7): PhysicsWorld {
  const w = circlesInBox(n, seed);
  w.setDef({ restitution: 0.1 });
  for (let i = 0; i < w.slotCount; i++) {
    if (i % 5 === 0) w.setFriction(i, 0.05 + (i % 7) * 0.2);
    if (i % 7 === 0) w.setRestitution(i, 0.3 + (i % 3) * 0.3);
    if (i % 11 === 0) w.setLinearDamping(i, 0.5 + (i % 4));
  }
  return w;
}

/** {@link materialsWorld} stepped at 1/60 s. */
export function materialsScene(ticks = 600, n = 250, seed = 7): TraceScene {
  return {
    id: `physics/materials-${String(n)}`,
    title: `materialsWorld(${String(n)}, ${String(seed)}): circlesInBox with own friction, restitution and linear damping, 1/60 s`,
    ticks,
    start: () => worldRun(() => materialsWorld(n, seed)),
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

/** Collision categories of {@link filtersSensorsWorld}. */
const TEAM_RED = 0x0002;
const TEAM_BLUE = 0x0004;
const GHOST = 0x0008;

/**
 * A world that uses every filter and sensor feature (its snapshot is version 2): a box of 48
 * circles and boxes in two teams whose members never collide with each other (negative groups),
 * ghosts that pass through both teams and the walls (a mask without the wall category), a
 * kinematic sensor sweeping back and forth across the pile and a fixed sensor zone on the floor.
 * Contact events on.
 */
export function filtersSensorsWorld(seed = 5): PhysicsWorld {
  const rng = new Random(seed);
  const world = new PhysicsWorld({}, { contactEvents: true });
  world.addSegment(-8, 0, 8, 0);
  world.addSegment(-8, 0, -8, 12);
  world.addSegment(8, 0, 8, 12);
  world.addStaticBox(0, 3, 1.5, 0.25);
  for (let i = 0; i < 48; i++) {
    const x = rng.range(-7, 7);
    const y = rng.range(4.5, 14);
    const vx = rng.range(-2, 2);
    const team = i % 3;
    const filter =
      team === 0
        ? { categoryBits: TEAM_RED, groupIndex: -1 }
        : team === 1
          ? { categoryBits: TEAM_BLUE, groupIndex: -2 }
          : { categoryBits: GHOST, maskBits: ~(TEAM_RED | TEAM_BLUE | 1) >>> 0 };
    if (i % 2 === 0) world.createCircle({ x, y, vx, radius: rng.range(0.2, 0.45), filter });
    else {
      world.createBox({
        x,
        y,
        vx,
        halfWidth: rng.range(0.2, 0.4),
        halfHeight: rng.range(0.2, 0.4),
        filter,
      });
    }
  }
  // The sweeper sees the red team and the ghosts only; the zone sees everything.
  world.createBox({
    x: -6,
    y: 2,
    vx: 3,
    halfWidth: 1,
    halfHeight: 2,
    kinematic: true,
    sensor: true,
    filter: { maskBits: TEAM_RED | GHOST },
  });
  world.createCircle({ x: 4, y: 0.8, radius: 1.2, kinematic: true, sensor: true });
  return world;
}

/**
 * {@link filtersSensorsWorld} stepped at 1/60 s; each tick's state is the snapshot (version 2:
 * filter columns, sensor overlaps) and then what a game reads after the step: the sensor and
 * contact event counts, the closest hit of a ray down the middle (body, wall, fraction, point),
 * the red bodies in an AABB and every body in a circle. The sweeper turns round at the walls.
 */
export function filtersSensorsScene(ticks = 600, seed = 5): TraceScene {
  return {
    id: 'physics/filters-sensors',
    title: `filtersSensorsWorld(${String(seed)}): two teams, ghosts, a sweeping and a fixed sensor, ray and overlap queries, 1/60 s`,
    ticks,
    start(): TraceRun {
      const world = filtersSensorsWorld(seed);
      const sweeper = world.bodyCount - 2;
      const w = new ByteWriter(0);
      return {
        next(): Uint8Array {
          const x = world.x[sweeper]!;
          if (x > 6 && world.vx[sweeper]! > 0) world.setVelocity(sweeper, -3, 0);
          else if (x < -6 && world.vx[sweeper]! < 0) world.setVelocity(sweeper, 3, 0);
          world.step();
          const sensors = world.sensorEvents();
          const contacts = world.contactEvents();
          const hit = world.castRayClosest(0.3, 14, 0, -14);
          const red = world.overlapAABB(-4, 0, 4, 6, { categoryBits: TEAM_RED });
          const near = world.overlapCircle(-3, 1, 2.5, { sensors: true });
          w.reset();
          w.bytes(world.save());
          w.u32(sensors.begin.length).u32(sensors.end.length);
          w.u32(contacts.begin.length).u32(contacts.end.length);
          w.u32(hit === null ? 0xffffffff : hit.body >>> 0).u32(
            hit === null ? 0xffffffff : hit.wall >>> 0,
          );
          w.u32(red.length).u32(near.length);
          w.f64(hit?.fraction ?? -1)
            .f64(hit?.x ?? 0)
            .f64(hit?.y ?? 0);
          return w.peek();
        },
      };
    },
    fields: filtersSensorsFields,
  };
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
