import type { BandMatrix } from './band-matrix.js';

/**
 * A second-order system `x'' = a(x, v)` with n degrees of freedom, on flat arrays: n = 2·N for
 * N particles in 2D (x0, y0, x1, y1, …), n = 1 for a single oscillator. Units are the caller's;
 * the library's scenes use metres, seconds, kilograms, so x in m, v in m/s, a in m/s².
 */
export interface DynamicsModel {
  /** Degrees of freedom n: the length of every x, v and a array. */
  readonly size: number;
  /**
   * Write the accelerations at positions `x` and velocities `v` into `out` (all of length n).
   * Must overwrite every element of `out` (never read it first), must not keep or modify `x`
   * and `v`, must not allocate, and must use only deterministic math (see `Simulation`).
   */
  accelerations(x: Float64Array, v: Float64Array, out: Float64Array): void;
  /**
   * Optional: a zeroed array of `size` numbers that {@link accelerations} computes on fastest
   * (e.g. a view of the memory of a WebAssembly kernel). States and integrators take their arrays
   * from here when it exists; any Float64Array still works, only slower.
   */
  allocate?(size: number): Float64Array;
  /**
   * Optional: `v += a·kick`, then `x += v·drift` (with the new v), element by element, exactly
   * so, if the model can do it faster for these arrays (returns true), else nothing (false, and
   * the integrator does it).
   */
  kickDrift?(
    x: Float64Array,
    v: Float64Array,
    a: Float64Array,
    kick: number,
    drift: number,
  ): boolean;
}

/** `model.allocate(size)` where the model has it, else a plain zeroed Float64Array. */
export function allocateFor(model: DynamicsModel | undefined, size: number): Float64Array {
  return model?.allocate?.(size) ?? new Float64Array(size);
}

/**
 * A {@link DynamicsModel} that also gives its Jacobians, which backward Euler needs.
 */
export interface ImplicitModel extends DynamicsModel {
  /**
   * Half-bandwidth of `∂a/∂x` and `∂a/∂v`: entries with `|i − j|` above it are always zero.
   * `size − 1` (or more) means dense. The backward-Euler solve costs about `2·n·bandwidth²`.
   */
  readonly bandwidth: number;
  /**
   * True when `a` is affine in x and v (Hooke springs along a line, zero-rest-length springs
   * without damping, the harmonic oscillator, plus constant forces): then one Newton iteration
   * of backward Euler is its exact solution (up to rounding).
   */
  readonly linear: boolean;
  /**
   * Add `sx·∂a/∂x + sv·∂a/∂v`, evaluated at (x, v), into `m` (an n×n {@link BandMatrix} of the
   * declared bandwidth). Backward Euler calls it with `sx = −dt²`, `sv = −dt` on an identity.
   * Must not allocate.
   */
  addJacobian(x: Float64Array, v: Float64Array, sx: number, sv: number, m: BandMatrix): void;
}

/** Whether `model` provides Jacobians (an {@link ImplicitModel}). */
export function isImplicitModel(model: DynamicsModel): model is ImplicitModel {
  return (
    typeof (model as Partial<ImplicitModel>).addJacobian === 'function' &&
    typeof (model as Partial<ImplicitModel>).bandwidth === 'number'
  );
}

/**
 * The state an integrator advances, in four preallocated arrays of length n. `x` and `v` are
 * the state proper; `a` and `xPrev` are the memory of the methods that carry it from step to
 * step (see {@link Integrator.keepsAcceleration} and {@link Integrator.keepsPreviousPosition}),
 * scratch or unused for the others. The arrays are never replaced, so views of them stay valid.
 */
export class DynamicsState {
  /** Degrees of freedom n. */
  readonly size: number;
  /** Positions, e.g. m. */
  readonly x: Float64Array;
  /** Velocities, e.g. m/s. For position Verlet, derived from positions (central difference). */
  readonly v: Float64Array;
  /** Accelerations a(x, v) at the current state, e.g. m/s² (Verlet methods keep it). */
  readonly a: Float64Array;
  /** Positions one step back (position Verlet's memory), e.g. m. */
  readonly xPrev: Float64Array;

  /**
   * A zero state of `size` degrees of freedom (an integer ≥ 1). With a `model` that has
   * {@link DynamicsModel.allocate}, the arrays come from it (see SpringModel: the WebAssembly
   * kernel's memory).
   */
  constructor(size: number, model?: DynamicsModel) {
    if (!Number.isInteger(size) || size < 1) {
      throw new RangeError(`DynamicsState: size must be an integer ≥ 1, got ${size}`);
    }
    this.size = size;
    this.x = allocateFor(model, size);
    this.v = allocateFor(model, size);
    this.a = allocateFor(model, size);
    this.xPrev = allocateFor(model, size);
  }

  /** Copy every array of `other` (of the same size) into this state. */
  copyFrom(other: DynamicsState): void {
    if (other.size !== this.size) {
      throw new RangeError(`DynamicsState.copyFrom: size ${other.size}, expected ${this.size}`);
    }
    this.x.set(other.x);
    this.v.set(other.v);
    this.a.set(other.a);
    this.xPrev.set(other.xPrev);
  }
}
