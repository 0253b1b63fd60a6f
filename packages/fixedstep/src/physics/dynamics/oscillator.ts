import type { BandMatrix } from './band-matrix.js';
import { DynamicsState } from './model.js';
import type { ImplicitModel } from './model.js';

/**
 * The harmonic oscillator `x'' = −ω²·x` — a mass m on a spring of stiffness k has
 * ω = √(k/m) — as a one-degree-of-freedom {@link ImplicitModel}. It is linear, so backward
 * Euler solves it in closed form: v₁ = (v₀ − dt·ω²·x₀) / (1 + ω²dt²), x₁ = x₀ + dt·v₁.
 *
 * Exact solution, for checking: x(t) = x₀·cos ωt + (v₀/ω)·sin ωt.
 */
export class HarmonicOscillator implements ImplicitModel {
  readonly size = 1;
  readonly bandwidth = 0;
  readonly linear = true;
  /** Angular frequency ω in rad/s. */
  readonly omega: number;
  /** ω² in 1/s² (= k/m). */
  readonly omegaSquared: number;

  /** @param omega — angular frequency ω in rad/s, finite and ≥ 0. */
  constructor(omega: number) {
    if (!(omega >= 0 && omega < Infinity)) {
      throw new RangeError(`HarmonicOscillator: omega must be finite and ≥ 0, got ${omega}`);
    }
    this.omega = omega;
    this.omegaSquared = omega * omega;
  }

  /** The oscillator of a mass `mass` kg on a spring of stiffness `stiffness` N/m: ω = √(k/m). */
  static fromSpring(stiffness: number, mass: number): HarmonicOscillator {
    if (!(stiffness >= 0 && mass > 0)) {
      throw new RangeError(
        `HarmonicOscillator.fromSpring: need stiffness ≥ 0 and mass > 0, got ${stiffness}, ${mass}`,
      );
    }
    return new HarmonicOscillator(Math.sqrt(stiffness / mass));
  }

  /** a = −ω²·x, in m/s² for x in m. */
  accelerations(x: Float64Array, _v: Float64Array, out: Float64Array): void {
    out[0] = -this.omegaSquared * x[0]!;
  }

  /** ∂a/∂x = −ω², ∂a/∂v = 0. */
  addJacobian(_x: Float64Array, _v: Float64Array, sx: number, _sv: number, m: BandMatrix): void {
    m.add(0, 0, -sx * this.omegaSquared);
  }

  /**
   * Energy per unit mass, `E = ½v² + ½ω²x²` in J/kg (m²/s²). Constant along the exact motion;
   * multiply by the mass for joules.
   */
  energy(x: number, v: number): number {
    return 0.5 * v * v + 0.5 * this.omegaSquared * x * x;
  }

  /** A fresh one-degree-of-freedom state at position `x0` (m) and velocity `v0` (m/s). */
  state(x0: number, v0 = 0): DynamicsState {
    const s = new DynamicsState(1);
    s.x[0] = x0;
    s.v[0] = v0;
    return s;
  }
}
