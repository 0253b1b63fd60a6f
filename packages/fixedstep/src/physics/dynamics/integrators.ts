import { BandMatrix } from './band-matrix.js';
import {
  allocateFor,
  isImplicitModel,
  type DynamicsModel,
  type DynamicsState,
  type ImplicitModel,
} from './model.js';

/** The integration methods, by name. */
export type IntegratorMethod =
  | 'explicit-euler'
  | 'semi-implicit-euler'
  | 'backward-euler'
  | 'position-verlet'
  | 'velocity-verlet'
  | 'rk4';

/**
 * Every method, in a fixed order: a method's index here is its id in saved bytes (never
 * reorder; append new methods at the end).
 */
export const INTEGRATOR_METHODS: readonly IntegratorMethod[] = Object.freeze([
  'explicit-euler',
  'semi-implicit-euler',
  'backward-euler',
  'position-verlet',
  'velocity-verlet',
  'rk4',
]);

/** What a method promises, for docs, the lab and the tests. */
export interface IntegratorInfo {
  /** Human name. */
  readonly label: string;
  /** Global order of accuracy p: the error at a fixed end time shrinks like dtᵖ. */
  readonly order: number;
  /**
   * Largest ω·dt (dimensionless) at which the oscillator `x'' = −ω²x` stays bounded: 0 = it
   * grows at every step size, Infinity = it never grows.
   */
  readonly stabilityLimit: number;
  /** Symplectic: keeps a modified energy bounded for ever below its stability limit. */
  readonly symplectic: boolean;
  /** Solves a linear system per step (needs an {@link ImplicitModel}). */
  readonly implicit: boolean;
  /** Calls of `accelerations` per step (backward Euler: per Newton iteration). */
  readonly forceEvaluations: number;
}

/** Order, stability limit and cost of every method (see docs/integrators.md). */
export const INTEGRATOR_INFO: Readonly<Record<IntegratorMethod, IntegratorInfo>> = Object.freeze({
  'explicit-euler': {
    label: 'Explicit Euler',
    order: 1,
    stabilityLimit: 0,
    symplectic: false,
    implicit: false,
    forceEvaluations: 1,
  },
  'semi-implicit-euler': {
    label: 'Semi-implicit (symplectic) Euler',
    order: 1,
    stabilityLimit: 2,
    symplectic: true,
    implicit: false,
    forceEvaluations: 1,
  },
  'backward-euler': {
    label: 'Backward (implicit) Euler',
    order: 1,
    stabilityLimit: Infinity,
    symplectic: false,
    implicit: true,
    forceEvaluations: 1,
  },
  'position-verlet': {
    label: 'Position (Störmer) Verlet',
    order: 2,
    stabilityLimit: 2,
    symplectic: true,
    implicit: false,
    forceEvaluations: 1,
  },
  'velocity-verlet': {
    label: 'Velocity Verlet',
    order: 2,
    stabilityLimit: 2,
    symplectic: true,
    implicit: false,
    forceEvaluations: 1,
  },
  rk4: {
    label: 'Runge–Kutta 4',
    order: 4,
    stabilityLimit: Math.sqrt(8),
    symplectic: false,
    implicit: false,
    forceEvaluations: 4,
  },
});

/**
 * One interface for every method. An integrator is bound to one model (it owns scratch arrays
 * sized for it) and advances any {@link DynamicsState} of that size. `step` allocates nothing.
 *
 * Protocol: set `state.x` and `state.v`, call {@link start} once, then {@link step} with the
 * same `dt` every time. Call `start` again after editing x or v from outside (dragging a
 * particle, teleporting) or changing `dt` — the Verlet methods carry memory that would
 * otherwise be stale. Skipping it breaks no determinism, only accuracy.
 */
export interface Integrator {
  /** Which method. */
  readonly method: IntegratorMethod;
  /** Global order of accuracy (1, 2 or 4). */
  readonly order: number;
  /** The model it integrates. */
  readonly model: DynamicsModel;
  /** Whether `state.a` is memory carried between steps (the Verlets) rather than scratch. */
  readonly keepsAcceleration: boolean;
  /** Whether `state.xPrev` is memory carried between steps (position Verlet). */
  readonly keepsPreviousPosition: boolean;
  /**
   * Prepare the method's memory from `state.x`, `state.v` for steps of `dt` seconds (Verlet:
   * `a = a(x, v)`, position Verlet also its start-up `xPrev`). A no-op for the others.
   */
  start(state: DynamicsState, dt: number): void;
  /** Advance `state` by one step of `dt` seconds, in place. */
  step(state: DynamicsState, dt: number): void;
}

/** Options of {@link createIntegrator}. */
export interface IntegratorOptions {
  /**
   * Backward Euler only: Newton iterations per step, an integer ≥ 1 (default 1). One is exact
   * for a linear model and the classic linearly-implicit (Baraff–Witkin) step otherwise; more
   * converge to the fully implicit step of a nonlinear model.
   */
  newtonIterations?: number;
}

/**
 * An integrator of `method` for `model`. Backward Euler needs an {@link ImplicitModel}
 * (Jacobians); the others only accelerations.
 */
export function createIntegrator(
  method: IntegratorMethod,
  model: DynamicsModel,
  options: IntegratorOptions = {},
): Integrator {
  if (!Number.isInteger(model.size) || model.size < 1) {
    throw new RangeError(`createIntegrator: model size must be an integer ≥ 1, got ${model.size}`);
  }
  switch (method) {
    case 'explicit-euler':
      return new ExplicitEuler(model);
    case 'semi-implicit-euler':
      return new SemiImplicitEuler(model);
    case 'backward-euler':
      return new BackwardEuler(model, options.newtonIterations ?? 1);
    case 'position-verlet':
      return new PositionVerlet(model);
    case 'velocity-verlet':
      return new VelocityVerlet(model);
    case 'rk4':
      return new RungeKutta4(model);
    default:
      throw new RangeError(`createIntegrator: unknown method ${String(method)}`);
  }
}

function checkSize(model: DynamicsModel, state: DynamicsState): void {
  if (state.size !== model.size) {
    throw new RangeError(`Integrator: state size ${state.size}, model size ${model.size}`);
  }
}

/*
 * The element-wise updates of the explicit methods, unrolled by four. Each element gets exactly
 * the operations of the plain loop (the elements are independent, and x, v and a are distinct
 * arrays), so the results are bit-identical to it. Why (V8): a loop that stores into typed arrays
 * reloads each array's length and data pointer on every iteration, so four elements per iteration
 * pay that once for four. The n mod 4 odd elements go first: a remainder loop after the main one
 * would never have run when V8 compiles the function on-stack during its first long loop, and
 * then every call would bail out of the optimized code there.
 */

/** x += v·dt; v += a·dt, element by element, both from the old values (explicit Euler). */
function driftKick(x: Float64Array, v: Float64Array, a: Float64Array, dt: number): void {
  const n = x.length;
  let i = 0;
  for (; i < (n & 3); i++) {
    x[i] = x[i]! + v[i]! * dt;
    v[i] = v[i]! + a[i]! * dt;
  }
  for (; i < n; i += 4) {
    x[i] = x[i]! + v[i]! * dt;
    x[i + 1] = x[i + 1]! + v[i + 1]! * dt;
    x[i + 2] = x[i + 2]! + v[i + 2]! * dt;
    x[i + 3] = x[i + 3]! + v[i + 3]! * dt;
    v[i] = v[i]! + a[i]! * dt;
    v[i + 1] = v[i + 1]! + a[i + 1]! * dt;
    v[i + 2] = v[i + 2]! + a[i + 2]! * dt;
    v[i + 3] = v[i + 3]! + a[i + 3]! * dt;
  }
}

/** v += a·kick, then x += v·drift with the new v, element by element. */
function kickDrift(
  x: Float64Array,
  v: Float64Array,
  a: Float64Array,
  kick: number,
  drift: number,
): void {
  const n = x.length;
  let i = 0;
  for (; i < (n & 3); i++) {
    const vi = v[i]! + a[i]! * kick;
    v[i] = vi;
    x[i] = x[i]! + vi * drift;
  }
  for (; i < n; i += 4) {
    const v0 = v[i]! + a[i]! * kick;
    const v1 = v[i + 1]! + a[i + 1]! * kick;
    const v2 = v[i + 2]! + a[i + 2]! * kick;
    const v3 = v[i + 3]! + a[i + 3]! * kick;
    v[i] = v0;
    v[i + 1] = v1;
    v[i + 2] = v2;
    v[i + 3] = v3;
    x[i] = x[i]! + v0 * drift;
    x[i + 1] = x[i + 1]! + v1 * drift;
    x[i + 2] = x[i + 2]! + v2 * drift;
    x[i + 3] = x[i + 3]! + v3 * drift;
  }
}

/** v += a·kick, element by element. */
function kickOnly(v: Float64Array, a: Float64Array, kick: number): void {
  const n = v.length;
  let i = 0;
  for (; i < (n & 3); i++) v[i] = v[i]! + a[i]! * kick;
  for (; i < n; i += 4) {
    v[i] = v[i]! + a[i]! * kick;
    v[i + 1] = v[i + 1]! + a[i + 1]! * kick;
    v[i + 2] = v[i + 2]! + a[i + 2]! * kick;
    v[i + 3] = v[i + 3]! + a[i + 3]! * kick;
  }
}

/** x += v·dt; v += a(x₀, v₀)·dt — both from the old state. Energy grows at every dt. */
class ExplicitEuler implements Integrator {
  readonly method = 'explicit-euler';
  readonly order = 1;
  readonly keepsAcceleration = false;
  readonly keepsPreviousPosition = false;
  constructor(readonly model: DynamicsModel) {}

  start(state: DynamicsState): void {
    checkSize(this.model, state);
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a } = state;
    this.model.accelerations(x, v, a);
    driftKick(x, v, a, dt);
  }
}

/** v += a(x, v)·dt; x += v_new·dt — the talk's code. Symplectic. */
class SemiImplicitEuler implements Integrator {
  readonly method = 'semi-implicit-euler';
  readonly order = 1;
  readonly keepsAcceleration = false;
  readonly keepsPreviousPosition = false;
  constructor(readonly model: DynamicsModel) {}

  start(state: DynamicsState): void {
    checkSize(this.model, state);
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a } = state;
    this.model.accelerations(x, v, a);
    if (this.model.kickDrift?.(x, v, a, dt, dt) !== true) kickDrift(x, v, a, dt, dt);
  }
}

/**
 * Backward Euler: find v₁ with v₁ = v₀ + dt·a(x₀ + dt·v₁, v₁), then x₁ = x₀ + dt·v₁, by Newton's
 * method on g(v) = v − v₀ − dt·a(x₀ + dt·v, v) from v = v₀. Each iteration solves
 * (I − dt·∂a/∂v − dt²·∂a/∂x)·δ = −g(v) with the Jacobians at (x₀ + dt·v, v) — for the first
 * iteration, the right side dt·a(x₀ + dt·v₀, v₀) equals dt·(a₀ + dt·∂a/∂x·v₀) exactly when `a`
 * is affine, so one iteration is the exact implicit step of a linear system.
 */
class BackwardEuler implements Integrator {
  readonly method = 'backward-euler';
  readonly order = 1;
  readonly keepsAcceleration = false;
  readonly keepsPreviousPosition = false;
  readonly model: ImplicitModel;
  private readonly matrix: BandMatrix;
  private readonly v0: Float64Array;
  private readonly xt: Float64Array;
  private readonly rhs: Float64Array;

  constructor(
    model: DynamicsModel,
    readonly newtonIterations: number,
  ) {
    if (!isImplicitModel(model)) {
      throw new TypeError(
        'createIntegrator: backward Euler needs a model with Jacobians (ImplicitModel: bandwidth, linear, addJacobian)',
      );
    }
    if (!Number.isInteger(newtonIterations) || newtonIterations < 1) {
      throw new RangeError(
        `createIntegrator: newtonIterations must be an integer ≥ 1, got ${newtonIterations}`,
      );
    }
    this.model = model;
    const n = model.size;
    this.matrix = new BandMatrix(n, Math.min(n - 1, Math.max(0, model.bandwidth)));
    this.v0 = allocateFor(model, n);
    this.xt = allocateFor(model, n);
    this.rhs = allocateFor(model, n);
  }

  start(state: DynamicsState): void {
    checkSize(this.model, state);
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a } = state;
    const { v0, xt, rhs, matrix, model } = this;
    const n = x.length;
    v0.set(v);
    for (let it = 0; it < this.newtonIterations; it++) {
      for (let i = 0; i < n; i++) xt[i] = x[i]! + dt * v[i]!;
      model.accelerations(xt, v, a);
      for (let i = 0; i < n; i++) rhs[i] = v0[i]! - v[i]! + dt * a[i]!;
      matrix.setIdentity();
      model.addJacobian(xt, v, -dt * dt, -dt, matrix);
      matrix.solve(rhs);
      for (let i = 0; i < n; i++) v[i] = v[i]! + rhs[i]!;
    }
    for (let i = 0; i < n; i++) x[i] = x[i]! + dt * v[i]!;
  }
}

/**
 * Störmer–Verlet on positions: x₊ = 2x − x₋ + a(x)·dt². Memory: `xPrev` (x₋) and `a` (a at x).
 * Start-up (in {@link Integrator.start}): x₋ = x₀ − v₀·dt + ½a₀·dt², so the first step lands
 * on the Taylor step x₁ = x₀ + v₀·dt + ½a₀·dt². The velocity it reports is the central
 * difference v_n = (x_{n+1} − x_{n−1}) / 2dt, computed with the x_{n+1} the recurrence will
 * give: v_n = (x_n − x_{n−1})/dt + ½a_n·dt. With forces that depend on velocity, `a` is
 * evaluated with the backward difference (x_n − x_{n−1})/dt as velocity (first order in them).
 */
class PositionVerlet implements Integrator {
  readonly method = 'position-verlet';
  readonly order = 2;
  readonly keepsAcceleration = true;
  readonly keepsPreviousPosition = true;
  constructor(readonly model: DynamicsModel) {}

  start(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a, xPrev } = state;
    this.model.accelerations(x, v, a);
    const h2 = 0.5 * dt * dt;
    const n = x.length;
    for (let i = 0; i < n; i++) xPrev[i] = x[i]! - v[i]! * dt + a[i]! * h2;
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a, xPrev } = state;
    const dt2 = dt * dt;
    const inv = 1 / dt;
    const n = x.length;
    for (let i = 0; i < n; i++) {
      const xi = x[i]!;
      const next = 2 * xi - xPrev[i]! + a[i]! * dt2;
      xPrev[i] = xi;
      x[i] = next;
      v[i] = (next - xi) * inv; // backward difference, the velocity forces see
    }
    this.model.accelerations(x, v, a);
    kickOnly(v, a, 0.5 * dt);
  }
}

/**
 * Velocity Verlet (kick–drift–kick): v½ = v + ½a·dt; x += v½·dt; a = a(x, v½); v = v½ + ½a·dt.
 * Memory: `a` (a at the current state). Velocity-dependent forces see the half-step velocity
 * v½ (first order in them).
 */
class VelocityVerlet implements Integrator {
  readonly method = 'velocity-verlet';
  readonly order = 2;
  readonly keepsAcceleration = true;
  readonly keepsPreviousPosition = false;
  constructor(readonly model: DynamicsModel) {}

  start(state: DynamicsState): void {
    checkSize(this.model, state);
    this.model.accelerations(state.x, state.v, state.a);
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v, a } = state;
    const half = 0.5 * dt;
    // v½ = v + ½a·dt; x += v½·dt
    if (this.model.kickDrift?.(x, v, a, half, dt) !== true) kickDrift(x, v, a, half, dt);
    this.model.accelerations(x, v, a);
    kickOnly(v, a, half);
  }
}

/**
 * Classic fourth-order Runge–Kutta on (x, v). With k1..k4 the stage accelerations, the
 * position update x += dt·(k1x + 2k2x + 2k3x + k4x)/6 is written out as
 * x += dt·v + dt²·(k1 + k2 + k3)/6 (the stage velocities are v + (dt/2)·k1, v + (dt/2)·k2,
 * v + dt·k3).
 */
class RungeKutta4 implements Integrator {
  readonly method = 'rk4';
  readonly order = 4;
  readonly keepsAcceleration = false;
  readonly keepsPreviousPosition = false;
  private readonly k1: Float64Array;
  private readonly k2: Float64Array;
  private readonly k3: Float64Array;
  private readonly k4: Float64Array;
  private readonly xt: Float64Array;
  private readonly vt: Float64Array;

  constructor(readonly model: DynamicsModel) {
    const n = model.size;
    this.k1 = allocateFor(model, n);
    this.k2 = allocateFor(model, n);
    this.k3 = allocateFor(model, n);
    this.k4 = allocateFor(model, n);
    this.xt = allocateFor(model, n);
    this.vt = allocateFor(model, n);
  }

  start(state: DynamicsState): void {
    checkSize(this.model, state);
  }

  step(state: DynamicsState, dt: number): void {
    checkSize(this.model, state);
    const { x, v } = state;
    const { k1, k2, k3, k4, xt, vt, model } = this;
    const n = x.length;
    const half = 0.5 * dt;
    model.accelerations(x, v, k1);
    for (let i = 0; i < n; i++) {
      xt[i] = x[i]! + half * v[i]!;
      vt[i] = v[i]! + half * k1[i]!;
    }
    model.accelerations(xt, vt, k2);
    for (let i = 0; i < n; i++) {
      xt[i] = x[i]! + half * (v[i]! + half * k1[i]!);
      vt[i] = v[i]! + half * k2[i]!;
    }
    model.accelerations(xt, vt, k3);
    for (let i = 0; i < n; i++) {
      xt[i] = x[i]! + dt * (v[i]! + half * k2[i]!);
      vt[i] = v[i]! + dt * k3[i]!;
    }
    model.accelerations(xt, vt, k4);
    const c = dt / 6;
    for (let i = 0; i < n; i++) {
      const a1 = k1[i]!;
      const a2 = k2[i]!;
      const a3 = k3[i]!;
      x[i] = x[i]! + dt * v[i]! + dt * c * (a1 + a2 + a3);
      v[i] = v[i]! + c * (a1 + 2 * a2 + 2 * a3 + k4[i]!);
    }
  }
}
