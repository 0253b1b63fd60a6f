/**
 * The JavaScript side of the `physics-springs` suite, as a program of its own that speaks
 * springs.c's line protocol (see springs.c), so that JS and C are measured alike: each in a fresh
 * process, pinned to the same CPU, timing itself. A fresh process also keeps the measurement
 * independent of what ran before it in the bench process (see bench/peers/remote.ts: once any
 * ArrayBuffer in a process has been detached, V8 checks every typed-array access for it).
 *
 * Usage: node --conditions=source --expose-gc --import tsx springs-js.ts SCENE_JSON, where the
 * file holds `{ "def": SpringSystemDef, "method": CMethod }`. It hosts three contestants, by
 * index (`JS_CONTESTANTS` in springs.ts): 0 `SpringSystem.step`, 1 `Integrator.step` on a DynamicsState,
 * 2 the hand-written loop. Commands: `time K I`, `step K I`, `hash I`, `dump I PATH`, `gc`,
 * `quit`; the replies are springs.c's.
 */
import { readFileSync, writeFileSync } from 'node:fs';
import { createInterface } from 'node:readline';
import {
  createIntegrator,
  DynamicsState,
  SpringModel,
  SpringSystem,
  type SpringSystemDef,
} from 'fixedstep';
import { stateHash, type CMethod } from './springs.js';

/** A contestant: its own copy of the scene. */
interface Runner {
  /** Runs `steps` steps. */
  run(steps: number): void;
  readonly x: Float64Array;
  readonly v: Float64Array;
}

/** The arrays and constants of a 2D spring scene, for the hand-written loop. */
interface Arrays {
  readonly count: number;
  readonly x: Float64Array;
  readonly v: Float64Array;
  readonly a: Float64Array;
  readonly im: Float64Array;
  readonly sa: Int32Array;
  readonly sb: Int32Array;
  readonly rest: Float64Array;
  readonly stiff: Float64Array;
  readonly damp: Float64Array;
  readonly gx: number;
  readonly gy: number;
}

/**
 * springs.c's `accelerations` in TypeScript: module-level, everything passed in (like C's
 * globals: no closure context for V8 to specialise on, so every scene runs the same code).
 */
function handAccelerations(
  count: number,
  x: Float64Array,
  v: Float64Array,
  a: Float64Array,
  im: Float64Array,
  sa: Int32Array,
  sb: Int32Array,
  rest: Float64Array,
  stiff: Float64Array,
  damp: Float64Array,
  gx: number,
  gy: number,
): void {
  for (let p = 0; p < count; p++) {
    const free = im[p]! > 0;
    a[2 * p] = free ? gx : 0;
    a[2 * p + 1] = free ? gy : 0;
  }
  const springs = sa.length;
  for (let s = 0; s < springs; s++) {
    const pa = sa[s]!;
    const pb = sb[s]!;
    const ia = 2 * pa;
    const ib = 2 * pb;
    let len2 = 0;
    const ex = x[ia]! - x[ib]!;
    len2 += ex * ex;
    const ey = x[ia + 1]! - x[ib + 1]!;
    len2 += ey * ey;
    if (len2 === 0) continue;
    const len = Math.sqrt(len2);
    const inv = 1 / len;
    let uw = 0;
    const ux = ex * inv;
    uw += ux * (v[ia]! - v[ib]!);
    const uy = ey * inv;
    uw += uy * (v[ia + 1]! - v[ib + 1]!);
    const f = stiff[s]! * (len - rest[s]!) + damp[s]! * uw;
    const fa = f * im[pa]!;
    const fb = f * im[pb]!;
    a[ia] = a[ia]! - fa * ux;
    a[ib] = a[ib]! + fb * ux;
    a[ia + 1] = a[ia + 1]! - fa * uy;
    a[ib + 1] = a[ib + 1]! + fb * uy;
  }
}

function handAcc(s: Arrays): void {
  handAccelerations(s.count, s.x, s.v, s.a, s.im, s.sa, s.sb, s.rest, s.stiff, s.damp, s.gx, s.gy);
}

function handSemiImplicit(s: Arrays, dt: number, steps: number): void {
  const { x, v, a } = s;
  const n = 2 * s.count;
  for (let k = 0; k < steps; k++) {
    handAcc(s);
    for (let i = 0; i < n; i++) {
      const vi = v[i]! + a[i]! * dt;
      v[i] = vi;
      x[i] = x[i]! + vi * dt;
    }
  }
}

function handVelocityVerlet(s: Arrays, dt: number, steps: number): void {
  const { x, v, a } = s;
  const n = 2 * s.count;
  const half = 0.5 * dt;
  for (let k = 0; k < steps; k++) {
    for (let i = 0; i < n; i++) {
      const vh = v[i]! + a[i]! * half;
      v[i] = vh;
      x[i] = x[i]! + vh * dt;
    }
    handAcc(s);
    for (let i = 0; i < n; i++) v[i] = v[i]! + a[i]! * half;
  }
}

/** The library's Simulation: integrator step plus the render copy of the positions. */
function springSystem(def: SpringSystemDef): Runner {
  const sys = new SpringSystem(def);
  return {
    run(steps) {
      for (let k = 0; k < steps; k++) sys.step();
    },
    x: sys.state.x,
    v: sys.state.v,
  };
}

/** `createIntegrator(method, new SpringModel(def))` stepping a DynamicsState. */
function integratorStep(def: SpringSystemDef, method: CMethod): Runner {
  const model = new SpringModel(def);
  const integrator = createIntegrator(method, model);
  const state = new DynamicsState(model.size);
  state.x.set(model.startPosition);
  state.v.set(model.startVelocity);
  integrator.start(state, def.dt);
  return {
    run(steps) {
      for (let k = 0; k < steps; k++) integrator.step(state, def.dt);
    },
    x: state.x,
    v: state.v,
  };
}

/**
 * springs.c in TypeScript: the same 2D loop over the same arrays, scalars instead of the model's
 * dimension loops and scratch array. Not the library: the yardstick for what JS costs by itself.
 */
function handWritten(def: SpringSystemDef, method: CMethod): Runner {
  const model = new SpringModel(def);
  const s: Arrays = {
    count: model.count,
    x: Float64Array.from(model.startPosition),
    v: Float64Array.from(model.startVelocity),
    a: new Float64Array(model.size),
    im: model.inverseMass,
    sa: model.springA,
    sb: model.springB,
    rest: model.restLength,
    stiff: model.stiffness,
    damp: model.damping,
    gx: model.gravity[0]!,
    gy: model.gravity[1]!,
  };
  const vv = method === 'velocity-verlet';
  if (vv) handAcc(s);
  return {
    run(steps) {
      if (vv) handVelocityVerlet(s, def.dt, steps);
      else handSemiImplicit(s, def.dt, steps);
    },
    x: s.x,
    v: s.v,
  };
}

function main(): void {
  const file = process.argv[2];
  if (file === undefined) throw new Error('usage: springs-js.ts SCENE_JSON');
  const { def, method } = JSON.parse(readFileSync(file, 'utf8')) as {
    def: SpringSystemDef;
    method: CMethod;
  };
  const runners = [springSystem(def), integratorStep(def, method), handWritten(def, method)];
  const out = (line: string) => process.stdout.write(`${line}\n`);
  const who = (text: string | undefined): Runner => {
    const r = runners[Number(text)];
    if (r === undefined) throw new Error(`no contestant ${text}`);
    return r;
  };
  out(`ready ${def.particles.length} ${def.springs.length}`);
  createInterface({ input: process.stdin }).on('line', (line) => {
    const [verb, a, b] = line.trim().split(' ');
    try {
      if (verb === 'time') {
        const r = who(b);
        const steps = Number(a);
        const t0 = process.hrtime.bigint();
        r.run(steps);
        out(`time ${process.hrtime.bigint() - t0}`);
      } else if (verb === 'step') {
        who(b).run(Number(a));
        out('ok');
      } else if (verb === 'hash') {
        const r = who(a);
        out(`hash ${stateHash(r.x, r.v)}`);
      } else if (verb === 'dump') {
        const r = who(a);
        const path = line.trim().slice(`dump ${a} `.length);
        const bytes = (x: Float64Array) => new Uint8Array(x.buffer, x.byteOffset, x.byteLength);
        writeFileSync(path, Buffer.concat([bytes(r.x), bytes(r.v)]));
        out('ok');
      } else if (verb === 'gc') {
        globalThis.gc?.();
        out('ok');
      } else if (verb === 'quit') {
        process.exit(0);
      } else {
        out('error unknown command');
      }
    } catch (e) {
      out(`error ${e instanceof Error ? e.message : String(e)}`);
    }
  });
}

main();
