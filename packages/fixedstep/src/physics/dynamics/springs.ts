import { ByteReader, ByteWriter } from '../../det/bytes.js';
import { springKernels, type SpringKernels } from './wasm.js';
import { fnv1a64 } from '../../det/hash.js';
import type { Simulation } from '../../sim/simulation.js';
import type { BandMatrix } from './band-matrix.js';
import {
  createIntegrator,
  INTEGRATOR_METHODS,
  type Integrator,
  type IntegratorMethod,
} from './integrators.js';
import { DynamicsState, type ImplicitModel } from './model.js';

/** One point mass of a spring system. */
export interface ParticleDef {
  /** Start position in m, one number per dimension. */
  position: readonly number[];
  /** Start velocity in m/s, one number per dimension. Default 0. */
  velocity?: readonly number[];
  /** Mass in kg, > 0. Default 1. Ignored for a fixed particle. */
  mass?: number;
  /**
   * Fixed: infinite mass, moved by no force. It keeps its start velocity (0 by default), so a
   * fixed particle with a velocity is a kinematic anchor moving in a straight line. Default false.
   */
  fixed?: boolean;
}

/**
 * A damped Hooke spring between particles `a` and `b`. With d = x_a − x_b, length ℓ = |d|,
 * direction u = d/ℓ, the force on `a` is −(k·(ℓ − L) + c·u·(v_a − v_b))·u and on `b` its
 * opposite. A spring of length exactly 0 exerts no force (its direction is undefined).
 */
export interface SpringDef {
  /** Index of the first particle. */
  a: number;
  /** Index of the second particle (≠ a). */
  b: number;
  /** Stiffness k in N/m, ≥ 0. */
  stiffness: number;
  /** Damping c along the spring in N·s/m, ≥ 0. Default 0. */
  damping?: number;
  /** Rest length L in m, ≥ 0. Default: the distance between the particles' start positions. */
  restLength?: number;
}

/** Particles, springs and gravity: everything that defines the forces. */
export interface SpringModelDef {
  /** Dimensions: 1, 2 or 3. Default 2. Positions are flat: (x0, y0, x1, y1, …) in 2D. */
  dim?: 1 | 2 | 3;
  /** Gravity in m/s², one number per dimension, applied to every free particle. Default 0. */
  gravity?: readonly number[];
  /** The particles, in order; their index is their place in the state arrays. */
  particles: readonly ParticleDef[];
  /** The springs. Numbering particles along chains keeps the backward-Euler band narrow. */
  springs: readonly SpringDef[];
}

/** A whole spring scene: forces, step and method. */
export interface SpringSystemDef extends SpringModelDef {
  /** The fixed step in s, > 0 (e.g. `Timestep.seconds`; the talk's is 0.03). */
  dt: number;
  /** Integration method. Default `'semi-implicit-euler'` (the talk's code). */
  integrator?: IntegratorMethod;
  /** Backward Euler only: Newton iterations per step (default 1; see `IntegratorOptions`). */
  newtonIterations?: number;
}

function finite(v: number, what: string): number {
  if (!Number.isFinite(v)) throw new RangeError(`SpringModel: ${what} must be finite, got ${v}`);
  return v;
}

/** Numbers per spring in {@link SpringModel}'s packed spring data: k, L, c, 1/m_a, 1/m_b. */
const SPRING_DATA = 5;
/** 2D models with at least this many springs run on the WebAssembly kernel (see SpringModel.allocate). */
export const WASM_MIN_SPRINGS = 64;
/** How many state-sized arrays a model's kernel memory holds (a state, RK4's scratch, spare). */
const WASM_ARRAYS = 12;

function sizeError(x: Float64Array, v: Float64Array, out: Float64Array, size: number): RangeError {
  return new RangeError(
    `SpringModel.accelerations: x, v and out need ${size} numbers, got ${x.length}, ${v.length}, ${out.length}`,
  );
}

/*
 * The acceleration kernels of SpringModel, one per dimension. Each starts from `base` (gravity on
 * free particles, 0 on fixed ones) and adds the springs: with d = x_a − x_b, ℓ = |d|, u = d/ℓ,
 * f = k·(ℓ − L) + c·u·(v_a − v_b), then a_a −= f/m_a·u and a_b += f/m_b·u; a spring of length
 * exactly 0 is skipped. The dimension loop is written out with scalars in the loop's operation
 * order (the sums keep the loop's leading `0 +`, which turns a −0 into +0), so the kernels give
 * the bits of the generic loop they replace.
 *
 * Why this shape, for V8 (measured on Node 20; see the physics-springs bench):
 * - scalars instead of a `u[d]` scratch array and a `dim` loop V8 does not unroll;
 * - module-level functions taking every array as an argument: one monomorphic body per
 *   dimension, whether or not V8 inlines it into the integrator's step;
 * - in a loop that stores into a typed array V8 reloads (and for arguments re-checks) every
 *   typed array it reads on every iteration, so a spring touches five arrays (x, v, out and the
 *   packed `idx`: dim·a, dim·b and `data`: k, L, c, 1/m_a, 1/m_b) instead of nine;
 * - `out.set(base)` (a memcpy) instead of a loop choosing gravity or 0 per particle.
 */

function accelerations1(
  x: Float64Array,
  v: Float64Array,
  out: Float64Array,
  base: Float64Array,
  idx: Int32Array,
  data: Float64Array,
): void {
  const size = base.length;
  if (x.length !== size || v.length !== size || out.length !== size) {
    throw sizeError(x, v, out, size);
  }
  out.set(base);
  const n = idx.length >> 1;
  for (let s = 0; s < n; s++) {
    const ia = idx[2 * s]!;
    const ib = idx[2 * s + 1]!;
    const ex = x[ia]! - x[ib]!;
    const len2 = 0 + ex * ex;
    if (len2 === 0) continue;
    const len = Math.sqrt(len2);
    const inv = 1 / len;
    const ux = ex * inv;
    const uw = 0 + ux * (v[ia]! - v[ib]!);
    const o = SPRING_DATA * s;
    const f = data[o]! * (len - data[o + 1]!) + data[o + 2]! * uw;
    const fa = f * data[o + 3]!;
    const fb = f * data[o + 4]!;
    out[ia] = out[ia]! - fa * ux;
    out[ib] = out[ib]! + fb * ux;
  }
}

function accelerations2(
  x: Float64Array,
  v: Float64Array,
  out: Float64Array,
  base: Float64Array,
  idx: Int32Array,
  data: Float64Array,
): void {
  const size = base.length;
  if (x.length !== size || v.length !== size || out.length !== size) {
    throw sizeError(x, v, out, size);
  }
  out.set(base);
  const n = idx.length >> 1;
  for (let s = 0; s < n; s++) {
    const ia = idx[2 * s]!;
    const ib = idx[2 * s + 1]!;
    const ex = x[ia]! - x[ib]!;
    const ey = x[ia + 1]! - x[ib + 1]!;
    const len2 = 0 + ex * ex + ey * ey;
    if (len2 === 0) continue;
    const len = Math.sqrt(len2);
    const inv = 1 / len;
    const ux = ex * inv;
    const uy = ey * inv;
    const uw = 0 + ux * (v[ia]! - v[ib]!) + uy * (v[ia + 1]! - v[ib + 1]!);
    const o = SPRING_DATA * s;
    const f = data[o]! * (len - data[o + 1]!) + data[o + 2]! * uw;
    const fa = f * data[o + 3]!;
    const fb = f * data[o + 4]!;
    out[ia] = out[ia]! - fa * ux;
    out[ib] = out[ib]! + fb * ux;
    out[ia + 1] = out[ia + 1]! - fa * uy;
    out[ib + 1] = out[ib + 1]! + fb * uy;
  }
}

function accelerations3(
  x: Float64Array,
  v: Float64Array,
  out: Float64Array,
  base: Float64Array,
  idx: Int32Array,
  data: Float64Array,
): void {
  const size = base.length;
  if (x.length !== size || v.length !== size || out.length !== size) {
    throw sizeError(x, v, out, size);
  }
  out.set(base);
  const n = idx.length >> 1;
  for (let s = 0; s < n; s++) {
    const ia = idx[2 * s]!;
    const ib = idx[2 * s + 1]!;
    const ex = x[ia]! - x[ib]!;
    const ey = x[ia + 1]! - x[ib + 1]!;
    const ez = x[ia + 2]! - x[ib + 2]!;
    const len2 = 0 + ex * ex + ey * ey + ez * ez;
    if (len2 === 0) continue;
    const len = Math.sqrt(len2);
    const inv = 1 / len;
    const ux = ex * inv;
    const uy = ey * inv;
    const uz = ez * inv;
    const uw =
      0 + ux * (v[ia]! - v[ib]!) + uy * (v[ia + 1]! - v[ib + 1]!) + uz * (v[ia + 2]! - v[ib + 2]!);
    const o = SPRING_DATA * s;
    const f = data[o]! * (len - data[o + 1]!) + data[o + 2]! * uw;
    const fa = f * data[o + 3]!;
    const fb = f * data[o + 4]!;
    out[ia] = out[ia]! - fa * ux;
    out[ib] = out[ib]! + fb * ux;
    out[ia + 1] = out[ia + 1]! - fa * uy;
    out[ib + 1] = out[ib + 1]! + fb * uy;
    out[ia + 2] = out[ia + 2]! - fa * uz;
    out[ib + 2] = out[ib + 2]! + fb * uz;
  }
}

/**
 * Forces of particles joined by damped Hooke springs under uniform gravity, as an
 * {@link ImplicitModel}: accelerations plus exact Jacobians, so every integrator, backward Euler
 * included, can drive it. Evaluation allocates nothing.
 *
 * The configuration is fixed at construction. The public arrays (gravity, masses, springs)
 * describe it and are read-only in effect: evaluation works on packed copies the constructor
 * makes, so writing into them changes no force (build a new model instead).
 *
 * It is linear (one Newton iteration of backward Euler is exact) in 1D, while no spring turns
 * over, and in any dimension when every spring has rest length 0 and no damping. Otherwise the
 * spring direction makes it nonlinear and backward Euler's first Newton iteration is the
 * linearly-implicit step.
 */
export class SpringModel implements ImplicitModel {
  /** Dimensions (1, 2 or 3). */
  readonly dim: number;
  /** Number of particles N. */
  readonly count: number;
  /** Degrees of freedom n = dim·N. */
  readonly size: number;
  /** Half-bandwidth of the Jacobians (from the index distance of the farthest-apart spring). */
  readonly bandwidth: number;
  /** See the class comment. */
  readonly linear: boolean;
  /** Gravity in m/s², length dim. */
  readonly gravity: Float64Array;
  /** Mass of each particle in kg (Infinity if fixed). */
  readonly mass: Float64Array;
  /** 1/mass of each particle in 1/kg (0 if fixed). */
  readonly inverseMass: Float64Array;
  /** Start position of every particle in m (dim per particle). */
  readonly startPosition: Float64Array;
  /** Start velocity of every particle in m/s (dim per particle). */
  readonly startVelocity: Float64Array;
  /** First particle of each spring. */
  readonly springA: Int32Array;
  /** Second particle of each spring. */
  readonly springB: Int32Array;
  /** Rest length L of each spring in m. */
  readonly restLength: Float64Array;
  /** Stiffness k of each spring in N/m. */
  readonly stiffness: Float64Array;
  /** Damping c of each spring in N·s/m. */
  readonly damping: Float64Array;
  /** Packed spring ends: dim·a, dim·b per spring (offsets into x, v, a). */
  private readonly springIndex: Int32Array;
  /** Packed spring data: k, L, c, 1/m_a, 1/m_b per spring. */
  private readonly springData: Float64Array;
  /** The accelerations without springs: gravity on free particles, 0 on fixed (dim each). */
  private readonly gravityBase: Float64Array;
  private readonly u: Float64Array;
  private readonly w: Float64Array;
  /**
   * The WebAssembly kernel and its memory (2D models of at least {@link WASM_MIN_SPRINGS}
   * springs): created on the first {@link allocate}, undefined until then or where WebAssembly
   * cannot run, null for models that keep to JavaScript.
   */
  private kernels: SpringKernels | undefined | null;
  /** Byte offsets in the kernel's memory: constants, then the next free array. */
  private wasmBase = 0;
  private wasmIdx = 0;
  private wasmData = 0;
  private wasmNext = 0;
  private wasmEnd = 0;

  constructor(def: SpringModelDef) {
    const dim: number = def.dim ?? 2; // checked: callers from plain JS
    if (dim !== 1 && dim !== 2 && dim !== 3) {
      throw new RangeError(`SpringModel: dim must be 1, 2 or 3, got ${String(dim)}`);
    }
    const count = def.particles.length;
    if (count < 1) throw new RangeError('SpringModel: needs at least one particle');
    this.dim = dim;
    this.count = count;
    this.size = dim * count;
    this.gravity = new Float64Array(dim);
    if (def.gravity) {
      if (def.gravity.length !== dim) {
        throw new RangeError(
          `SpringModel: gravity needs ${dim} numbers, got ${def.gravity.length}`,
        );
      }
      for (let d = 0; d < dim; d++) this.gravity[d] = finite(def.gravity[d]!, 'gravity');
    }
    this.mass = new Float64Array(count);
    this.inverseMass = new Float64Array(count);
    this.startPosition = new Float64Array(this.size);
    this.startVelocity = new Float64Array(this.size);
    def.particles.forEach((p, i) => {
      if (p.position.length !== dim) {
        throw new RangeError(
          `SpringModel: particle ${i} position needs ${dim} numbers, got ${p.position.length}`,
        );
      }
      if (p.velocity && p.velocity.length !== dim) {
        throw new RangeError(
          `SpringModel: particle ${i} velocity needs ${dim} numbers, got ${p.velocity.length}`,
        );
      }
      for (let d = 0; d < dim; d++) {
        this.startPosition[i * dim + d] = finite(p.position[d]!, `particle ${i} position`);
        this.startVelocity[i * dim + d] = finite(p.velocity?.[d] ?? 0, `particle ${i} velocity`);
      }
      if (p.fixed) {
        this.mass[i] = Infinity;
        this.inverseMass[i] = 0;
      } else {
        const m = p.mass ?? 1;
        if (!(m > 0 && m < Infinity)) {
          throw new RangeError(`SpringModel: particle ${i} mass must be finite and > 0, got ${m}`);
        }
        this.mass[i] = m;
        this.inverseMass[i] = 1 / m;
      }
    });
    const springs = def.springs.length;
    this.springA = new Int32Array(springs);
    this.springB = new Int32Array(springs);
    this.restLength = new Float64Array(springs);
    this.stiffness = new Float64Array(springs);
    this.damping = new Float64Array(springs);
    let bandwidth = 0;
    let linear = true;
    def.springs.forEach((s, i) => {
      const ok = (j: number) => Number.isInteger(j) && j >= 0 && j < count;
      if (!ok(s.a) || !ok(s.b) || s.a === s.b) {
        throw new RangeError(
          `SpringModel: spring ${i} joins ${s.a} and ${s.b}: need two different particles of 0..${count - 1}`,
        );
      }
      const k = s.stiffness;
      const c = s.damping ?? 0;
      if (!(k >= 0 && k < Infinity) || !(c >= 0 && c < Infinity)) {
        throw new RangeError(
          `SpringModel: spring ${i} needs finite stiffness and damping ≥ 0, got ${k}, ${c}`,
        );
      }
      let rest = s.restLength;
      if (rest === undefined) {
        let d2 = 0;
        for (let d = 0; d < dim; d++) {
          const e = this.startPosition[s.a * dim + d]! - this.startPosition[s.b * dim + d]!;
          d2 += e * e;
        }
        rest = Math.sqrt(d2);
      }
      if (!(rest >= 0 && rest < Infinity)) {
        throw new RangeError(
          `SpringModel: spring ${i} rest length must be finite and ≥ 0, got ${rest}`,
        );
      }
      this.springA[i] = s.a;
      this.springB[i] = s.b;
      this.restLength[i] = rest;
      this.stiffness[i] = k;
      this.damping[i] = c;
      bandwidth = Math.max(bandwidth, dim * Math.abs(s.a - s.b) + dim - 1);
      if (dim > 1 && (rest !== 0 || c !== 0)) linear = false;
    });
    this.gravityBase = new Float64Array(this.size);
    for (let p = 0; p < count; p++) {
      const free = this.inverseMass[p]! > 0;
      for (let d = 0; d < dim; d++) this.gravityBase[p * dim + d] = free ? this.gravity[d]! : 0;
    }
    this.springIndex = new Int32Array(2 * springs);
    this.springData = new Float64Array(SPRING_DATA * springs);
    for (let i = 0; i < springs; i++) {
      const a = this.springA[i]!;
      const b = this.springB[i]!;
      const o = SPRING_DATA * i;
      this.springIndex[2 * i] = dim * a;
      this.springIndex[2 * i + 1] = dim * b;
      this.springData[o] = this.stiffness[i]!;
      this.springData[o + 1] = this.restLength[i]!;
      this.springData[o + 2] = this.damping[i]!;
      this.springData[o + 3] = this.inverseMass[a]!;
      this.springData[o + 4] = this.inverseMass[b]!;
    }
    this.bandwidth = Math.min(bandwidth, this.size - 1);
    this.linear = linear;
    this.u = new Float64Array(dim);
    this.w = new Float64Array(dim);
    this.kernels = dim === 2 && springs >= WASM_MIN_SPRINGS ? undefined : null;
  }

  /**
   * A zeroed array of `size` numbers. For a 2D model of at least {@link WASM_MIN_SPRINGS}
   * springs, a view of the memory of the model's WebAssembly kernel (up to
   * `WASM_ARRAYS` (12) of them; plain arrays after that, or where WebAssembly cannot run):
   * {@link accelerations} on three such arrays runs the kernel, on any others the JavaScript one,
   * with the same bits either way. SpringSystem and the integrators take their arrays from here.
   */
  allocate(size: number): Float64Array {
    if (size !== this.size || this.kernels === null) return new Float64Array(size);
    if (this.kernels === undefined) {
      const springs = this.springIndex.length >> 1;
      const bytes = 8 * this.size; // base
      this.wasmIdx = bytes;
      this.wasmData = this.wasmIdx + 8 * springs; // idx (two i32 per spring)
      this.wasmNext = this.wasmData + 8 * SPRING_DATA * springs;
      this.wasmEnd = this.wasmNext + WASM_ARRAYS * 8 * this.size;
      const k = springKernels(this.wasmEnd);
      if (k === undefined) {
        this.kernels = null;
        return new Float64Array(size);
      }
      const buf = k.memory.buffer;
      new Float64Array(buf, this.wasmBase, this.size).set(this.gravityBase);
      new Int32Array(buf, this.wasmIdx, 2 * springs).set(this.springIndex);
      new Float64Array(buf, this.wasmData, SPRING_DATA * springs).set(this.springData);
      this.kernels = k;
    }
    if (this.wasmNext >= this.wasmEnd) return new Float64Array(size);
    const view = new Float64Array(this.kernels.memory.buffer, this.wasmNext, size);
    this.wasmNext += 8 * size;
    return view;
  }

  /** Whether `x`, `v` and `out` are all arrays of this model's kernel memory (see {@link allocate}). */
  private inKernelMemory(x: Float64Array, v: Float64Array, out: Float64Array): boolean {
    const k = this.kernels;
    if (!k) return false;
    const buf = k.memory.buffer;
    return (
      x.buffer === buf &&
      v.buffer === buf &&
      out.buffer === buf &&
      x.length === this.size &&
      v.length === this.size &&
      out.length === this.size
    );
  }

  /**
   * `v += a·kick; x += v·drift`, element by element, in the kernel when all three arrays are
   * its memory's (returns true), else not at all (returns false: the caller does it).
   */
  kickDrift(
    x: Float64Array,
    v: Float64Array,
    a: Float64Array,
    kick: number,
    drift: number,
  ): boolean {
    if (!this.inKernelMemory(x, v, a)) return false;
    this.kernels!.kickDrift(this.size, x.byteOffset, v.byteOffset, a.byteOffset, kick, drift);
    return true;
  }

  /**
   * Gravity on free particles plus spring forces, divided by mass; 0 on fixed particles. x, v
   * and out must all have length {@link size} (a RangeError otherwise). Runs a kernel written
   * out for the model's dimension; every dimension does the same float operations in the same
   * order as a generic loop over the dimensions would.
   */
  accelerations(x: Float64Array, v: Float64Array, out: Float64Array): void {
    if (this.kernels && this.inKernelMemory(x, v, out)) {
      this.kernels.accelerations2(
        this.springIndex.length >> 1,
        this.size,
        x.byteOffset,
        v.byteOffset,
        out.byteOffset,
        this.wasmBase,
        this.wasmIdx,
        this.wasmData,
      );
      return;
    }
    const { gravityBase: base, springIndex: idx, springData: data } = this;
    if (this.dim === 2) accelerations2(x, v, out, base, idx, data);
    else if (this.dim === 3) accelerations3(x, v, out, base, idx, data);
    else accelerations1(x, v, out, base, idx, data);
  }

  /**
   * Adds sx·∂a/∂x + sv·∂a/∂v. Per spring, with P = I − u·uᵀ, w = v_a − v_b:
   * ∂F_a/∂x_a = −k·(u·uᵀ + (1 − L/ℓ)·P) − (c/ℓ)·(u·(P·w)ᵀ + (u·w)·P) and ∂F_a/∂v_a = −c·u·uᵀ;
   * the blocks of b are the same with the signs of x_b − x_a. Not symmetric with damping, and
   * indefinite for compressed springs — the band solver pivots.
   */
  addJacobian(x: Float64Array, v: Float64Array, sx: number, sv: number, m: BandMatrix): void {
    const { dim, springIndex: idx, springData: data, u, w } = this;
    const n = idx.length >> 1;
    for (let s = 0; s < n; s++) {
      const o = SPRING_DATA * s;
      const ma = data[o + 3]!;
      const mb = data[o + 4]!;
      if (ma === 0 && mb === 0) continue;
      const ia = idx[2 * s]!;
      const ib = idx[2 * s + 1]!;
      let len2 = 0;
      for (let d = 0; d < dim; d++) {
        const e = x[ia + d]! - x[ib + d]!;
        u[d] = e;
        len2 += e * e;
      }
      if (len2 === 0) continue;
      const len = Math.sqrt(len2);
      const inv = 1 / len;
      let uw = 0;
      for (let d = 0; d < dim; d++) {
        const ud = u[d]! * inv;
        u[d] = ud;
        const wd = v[ia + d]! - v[ib + d]!;
        w[d] = wd;
        uw += ud * wd;
      }
      const k = data[o]!;
      const c = data[o + 2]!;
      const geo = 1 - data[o + 1]! * inv;
      const cl = c * inv;
      for (let r = 0; r < dim; r++) {
        const ur = u[r]!;
        for (let q = 0; q < dim; q++) {
          const uq = u[q]!;
          const uu = ur * uq;
          const p = (r === q ? 1 : 0) - uu;
          const pw = w[q]! - uq * uw; // (P·w)_q
          const jx = -k * (uu + geo * p) - cl * (ur * pw + uw * p);
          const jv = -c * uu;
          const val = sx * jx + sv * jv;
          if (val === 0) continue;
          if (ma !== 0) {
            m.add(ia + r, ia + q, ma * val);
            m.add(ia + r, ib + q, -ma * val);
          }
          if (mb !== 0) {
            m.add(ib + r, ia + q, -mb * val);
            m.add(ib + r, ib + q, mb * val);
          }
        }
      }
    }
  }

  /**
   * Total mechanical energy in J: kinetic ½·m·|v|² and gravitational −m·g·x of free particles,
   * plus elastic ½·k·(ℓ − L)² of every spring. Damping only ever removes it.
   */
  energy(x: Float64Array, v: Float64Array): number {
    const { dim, count, gravity, mass, inverseMass: im } = this;
    let e = 0;
    for (let p = 0; p < count; p++) {
      if (im[p] === 0) continue;
      const m = mass[p]!;
      for (let d = 0; d < dim; d++) {
        const vd = v[p * dim + d]!;
        e += 0.5 * m * vd * vd - m * gravity[d]! * x[p * dim + d]!;
      }
    }
    const n = this.springA.length;
    for (let s = 0; s < n; s++) {
      const ia = this.springA[s]! * dim;
      const ib = this.springB[s]! * dim;
      let len2 = 0;
      for (let d = 0; d < dim; d++) {
        const e2 = x[ia + d]! - x[ib + d]!;
        len2 += e2 * e2;
      }
      const stretch = Math.sqrt(len2) - this.restLength[s]!;
      e += 0.5 * this.stiffness[s]! * stretch * stretch;
    }
    return e;
  }
}

const FORMAT_VERSION = 1;

/**
 * A spring scene as a deterministic {@link Simulation}: a {@link SpringModel}, a
 * {@link DynamicsState} and an {@link Integrator}, stepped at a fixed `dt`. Stepping allocates
 * nothing (backward Euler solves in preallocated band storage); `save`/`hash` write canonical
 * bytes. It has no inputs: `step` ignores them.
 *
 * Saved bytes (format 1, little-endian): u8 format, u8 dim, u8 method id (index in
 * `INTEGRATOR_METHODS`), u8 0, u32 particles, u32 springs, u32 hi + u32 lo of the FNV-1a 64 of
 * the configuration (dim, method, Newton iterations, dt, gravity, masses, springs), f64 tick,
 * then x and v (n f64 each), then `a` if the method keeps it and `xPrev` if it keeps it. A
 * snapshot loads only into a system of the same configuration.
 */
export class SpringSystem implements Simulation<unknown> {
  /** The forces. */
  readonly model: SpringModel;
  /** The method. */
  readonly integrator: Integrator;
  /** Positions, velocities and the method's memory. Call {@link restart} after editing x or v. */
  readonly state: DynamicsState;
  /** The fixed step in s. */
  readonly dt: number;
  /** Positions before the last step (m), for render interpolation; not part of the state. */
  readonly previous: Float64Array;
  private ticks = 0;
  private readonly methodId: number;
  private readonly configHi: number;
  private readonly configLo: number;
  private readonly writer: ByteWriter;

  constructor(def: SpringSystemDef) {
    if (!(def.dt > 0 && def.dt < Infinity)) {
      throw new RangeError(`SpringSystem: dt must be finite and > 0 seconds, got ${def.dt}`);
    }
    this.dt = def.dt;
    this.model = new SpringModel(def);
    const method = def.integrator ?? 'semi-implicit-euler';
    const newtonIterations = def.newtonIterations ?? 1;
    this.integrator = createIntegrator(method, this.model, { newtonIterations });
    this.methodId = INTEGRATOR_METHODS.indexOf(method);
    this.state = new DynamicsState(this.model.size, this.model);
    this.state.x.set(this.model.startPosition);
    this.state.v.set(this.model.startVelocity);
    this.previous = new Float64Array(this.model.size);
    this.writer = new ByteWriter(32 + 4 * 8 * this.model.size);
    const m = this.model;
    const cfg = new ByteWriter()
      .u8(m.dim)
      .u8(this.methodId)
      .u32(newtonIterations)
      .f64(this.dt)
      .f64s(m.gravity)
      .f64s(m.inverseMass)
      .ints(m.springA)
      .ints(m.springB)
      .f64s(m.restLength)
      .f64s(m.stiffness)
      .f64s(m.damping);
    const h = fnv1a64(cfg.peek());
    this.configHi = Number(h >> 32n);
    this.configLo = Number(h & 0xffffffffn);
    this.restart();
  }

  /** Ticks stepped so far. */
  get tick(): number {
    return this.ticks;
  }

  /** Simulated time in s: tick × dt (a product, never a running sum). */
  get time(): number {
    return this.ticks * this.dt;
  }

  /**
   * Re-prime the integrator from `state.x` and `state.v` (the Verlets' memory). Call after
   * editing positions or velocities from outside. Deterministic, but the result differs from
   * not calling it — so do it at the same tick on every peer.
   */
  restart(): void {
    this.integrator.start(this.state, this.dt);
    this.previous.set(this.state.x);
  }

  /** One fixed step of `dt`. Inputs are ignored (a spring scene has none). */
  step(): void {
    this.previous.set(this.state.x);
    this.integrator.step(this.state, this.dt);
    this.ticks++;
  }

  /** Positions interpolated between the previous and current step (alpha in [0, 1]) into `out`. */
  interpolate(alpha: number, out: Float64Array): Float64Array {
    const x = this.state.x;
    const p = this.previous;
    for (let i = 0; i < x.length; i++) out[i] = p[i]! + (x[i]! - p[i]!) * alpha;
    return out;
  }

  /** Total mechanical energy in J (see {@link SpringModel.energy}). */
  energy(): number {
    return this.model.energy(this.state.x, this.state.v);
  }

  private write(w: ByteWriter): ByteWriter {
    const { integrator: it, state, model } = this;
    w.u8(FORMAT_VERSION)
      .u8(model.dim)
      .u8(this.methodId)
      .u8(0)
      .u32(model.count)
      .u32(model.springA.length)
      .u32(this.configHi)
      .u32(this.configLo)
      .f64(this.ticks)
      .f64s(state.x)
      .f64s(state.v);
    if (it.keepsAcceleration) w.f64s(state.a);
    if (it.keepsPreviousPosition) w.f64s(state.xPrev);
    return w;
  }

  /** The state as canonical bytes (see the class comment for the layout). */
  save(): Uint8Array {
    return this.write(this.writer.reset()).finish();
  }

  /**
   * Restore a state from {@link save} of a system with the same configuration. Throws a
   * RangeError, before changing anything, on bytes of another format or configuration.
   */
  load(bytes: Uint8Array): void {
    const { integrator: it, state, model } = this;
    const arrays = 2 + (it.keepsAcceleration ? 1 : 0) + (it.keepsPreviousPosition ? 1 : 0);
    const expected = 4 + 16 + 8 + arrays * 8 * model.size;
    if (bytes.length !== expected) {
      throw new RangeError(`SpringSystem.load: expected ${expected} bytes, got ${bytes.length}`);
    }
    const r = new ByteReader(bytes);
    const version = r.u8();
    const dim = r.u8();
    const method = r.u8();
    r.u8();
    const count = r.u32();
    const springs = r.u32();
    const hi = r.u32();
    const lo = r.u32();
    if (version !== FORMAT_VERSION) {
      throw new RangeError(`SpringSystem.load: format ${version}, expected ${FORMAT_VERSION}`);
    }
    if (
      dim !== model.dim ||
      method !== this.methodId ||
      count !== model.count ||
      springs !== model.springA.length ||
      hi !== this.configHi ||
      lo !== this.configLo
    ) {
      throw new RangeError(
        `SpringSystem.load: snapshot of another configuration (dim ${dim}, method ${INTEGRATOR_METHODS[method] ?? method}, ${count} particles, ${springs} springs)`,
      );
    }
    const tick = r.f64();
    if (!(Number.isInteger(tick) && tick >= 0)) {
      throw new RangeError(`SpringSystem.load: bad tick ${tick}`);
    }
    this.ticks = tick;
    r.f64s(state.x);
    r.f64s(state.v);
    if (it.keepsAcceleration) r.f64s(state.a);
    if (it.keepsPreviousPosition) r.f64s(state.xPrev);
    r.end();
    this.previous.set(state.x);
  }

  /** FNV-1a 64 of the canonical state bytes. */
  hash(): bigint {
    return fnv1a64(this.write(this.writer.reset()).peek());
  }
}

/** Options of {@link springChain}. */
export interface SpringChainOptions {
  /** Particles along the chain, an integer ≥ 2. */
  count: number;
  /** Position of the first particle in m (1 to 3 numbers; their count sets the dimension). */
  from: readonly number[];
  /** Position of the last particle in m; the others are evenly spaced between. */
  to: readonly number[];
  /** Mass of each particle in kg. Default 0.1. */
  mass?: number;
  /** Stiffness of each link in N/m. Default 200. */
  stiffness?: number;
  /** Damping of each link in N·s/m. Default 0. */
  damping?: number;
  /** Rest length of each link in m. Default: the start spacing (straight and unstretched). */
  restLength?: number;
  /** Which ends are pinned. Default `'both'` (a rope hung between two points). */
  fixed?: 'both' | 'first' | 'none';
  /** Gravity in m/s². Default −9.81 on the second axis (y up), 0 in 1D. */
  gravity?: readonly number[];
  /** The fixed step in s. */
  dt: number;
  /** Integration method. Default `'semi-implicit-euler'`. */
  integrator?: IntegratorMethod;
  /** Backward Euler only: Newton iterations per step. Default 1. */
  newtonIterations?: number;
}

/**
 * A chain (rope) of `count` particles joined by `count − 1` springs, numbered along the chain
 * (so backward Euler's band is 2·dim − 1 wide on each side whatever the length).
 *
 * @example
 * const rope = new SpringSystem(springChain({ count: 20, from: [0, 0], to: [4, 0], dt: 1 / 60 }));
 */
export function springChain(o: SpringChainOptions): SpringSystemDef {
  const dim = o.from.length;
  if (dim !== 1 && dim !== 2 && dim !== 3) {
    throw new RangeError(`springChain: from needs 1 to 3 numbers, got ${dim}`);
  }
  if (o.to.length !== dim) {
    throw new RangeError(`springChain: to needs ${dim} numbers, got ${o.to.length}`);
  }
  if (!Number.isInteger(o.count) || o.count < 2) {
    throw new RangeError(`springChain: count must be an integer ≥ 2, got ${o.count}`);
  }
  const fixed = o.fixed ?? 'both';
  const particles: ParticleDef[] = [];
  for (let i = 0; i < o.count; i++) {
    const t = i / (o.count - 1);
    const position: number[] = [];
    for (let d = 0; d < dim; d++) position.push(o.from[d]! + (o.to[d]! - o.from[d]!) * t);
    const pinned = (i === 0 && fixed !== 'none') || (i === o.count - 1 && fixed === 'both');
    particles.push({ position, mass: o.mass ?? 0.1, fixed: pinned });
  }
  const springs: SpringDef[] = [];
  for (let i = 0; i + 1 < o.count; i++) {
    const s: SpringDef = {
      a: i,
      b: i + 1,
      stiffness: o.stiffness ?? 200,
      damping: o.damping ?? 0,
    };
    if (o.restLength !== undefined) s.restLength = o.restLength;
    springs.push(s);
  }
  const gravity = o.gravity ?? (dim === 1 ? [0] : dim === 2 ? [0, -9.81] : [0, -9.81, 0]);
  const def: SpringSystemDef = { dim, gravity, particles, springs, dt: o.dt };
  if (o.integrator !== undefined) def.integrator = o.integrator;
  if (o.newtonIterations !== undefined) def.newtonIterations = o.newtonIterations;
  return def;
}

/** Options of {@link springCloth}. */
export interface SpringClothOptions {
  /** Particles across and down, integers ≥ 2. */
  columns: number;
  rows: number;
  /** Distance between neighbours in m. Default 0.05. */
  spacing?: number;
  /** Mass of each particle in kg. Default 0.01. */
  mass?: number;
  /** Stiffness of each link in N/m. Default 20. */
  stiffness?: number;
  /** Damping of each link in N·s/m. Default 0.02. */
  damping?: number;
  /** Gravity in m/s². Default (0, −9.81). */
  gravity?: readonly number[];
  /** The fixed step in s. */
  dt: number;
  /** Integration method. Default `'semi-implicit-euler'`. */
  integrator?: IntegratorMethod;
}

/**
 * A 2D cloth: a `columns × rows` grid of particles `spacing` apart, its top row pinned, hanging
 * in −y from (0, 0). Structural springs only, numbered particle by particle (row by row): the
 * right neighbour, then the one below. At the defaults (10 g, 20 N/m: k/m = 2000 s⁻²) it is
 * stable at 1/60 s; with 64 springs or more it runs on SpringModel's WebAssembly kernel.
 */
export function springCloth(o: SpringClothOptions): SpringSystemDef {
  const { columns: w, rows: h } = o;
  if (!(Number.isInteger(w) && w >= 2 && Number.isInteger(h) && h >= 2)) {
    throw new RangeError(
      `springCloth: columns and rows must be integers ≥ 2, got ${String(w)} × ${String(h)}`,
    );
  }
  const spacing = o.spacing ?? 0.05;
  const particles: ParticleDef[] = [];
  const springs: SpringDef[] = [];
  for (let r = 0; r < h; r++) {
    for (let c = 0; c < w; c++) {
      particles.push({
        position: [c * spacing, -r * spacing],
        mass: o.mass ?? 0.01,
        fixed: r === 0,
      });
    }
  }
  const stiffness = o.stiffness ?? 20;
  const damping = o.damping ?? 0.02;
  for (let r = 0; r < h; r++) {
    for (let c = 0; c < w; c++) {
      const i = r * w + c;
      if (c + 1 < w) springs.push({ a: i, b: i + 1, stiffness, damping });
      if (r + 1 < h) springs.push({ a: i, b: i + w, stiffness, damping });
    }
  }
  const def: SpringSystemDef = {
    dim: 2,
    gravity: o.gravity ?? [0, -9.81],
    particles,
    springs,
    dt: o.dt,
  };
  if (o.integrator !== undefined) def.integrator = o.integrator;
  return def;
}
