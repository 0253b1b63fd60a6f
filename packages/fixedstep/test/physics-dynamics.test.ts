import { describe, expect, it } from 'vitest';
import {
  createIntegrator,
  HarmonicOscillator,
  INTEGRATOR_INFO,
  INTEGRATOR_METHODS,
  type IntegratorMethod,
} from 'fixedstep';

/**
 * The talk's §3 as numbers: each integrator on the harmonic oscillator x'' = −ω²x, against the
 * exact solution x = x₀·cos ωt + (v₀/ω)·sin ωt (tests may use Math.cos; the library may not).
 */

/** Run `steps` steps of `method` on x'' = −ω²x from (x0, v0); returns the final (x, v). */
function run(
  method: IntegratorMethod,
  omega: number,
  dt: number,
  steps: number,
  x0: number,
  v0: number,
  each?: (x: number, v: number) => void,
): [number, number] {
  const osc = new HarmonicOscillator(omega);
  const integrator = createIntegrator(method, osc);
  const s = osc.state(x0, v0);
  integrator.start(s, dt);
  for (let i = 0; i < steps; i++) {
    integrator.step(s, dt);
    each?.(s.x[0]!, s.v[0]!);
  }
  return [s.x[0]!, s.v[0]!];
}

describe('order of convergence on the oscillator (ω = 1 rad/s, x₀ = 1 m, v₀ = 0, T = 2 s)', () => {
  const T = 2;
  const stepsList = [40, 80, 160, 320]; // dt = 0.05, 0.025, 0.0125, 0.00625 s
  const expected: Record<IntegratorMethod, number> = {
    'explicit-euler': 1,
    'semi-implicit-euler': 1,
    'backward-euler': 1,
    'position-verlet': 2,
    'velocity-verlet': 2,
    rk4: 4,
  };
  // Measured (log2 of successive error ratios, dt 0.05 → 0.00625):
  //   explicit Euler       1.017 1.009 1.004
  //   semi-implicit Euler  1.006 1.003 1.002
  //   backward Euler       0.981 0.991 0.995
  //   position Verlet      2.000 2.000 2.000
  //   velocity Verlet      2.000 2.000 2.000
  //   RK4                  4.000 4.000 4.000
  it.each(INTEGRATOR_METHODS)('%s converges with its order', (method) => {
    const errors = stepsList.map((n) => {
      const [x, v] = run(method, 1, T / n, n, 1, 0);
      // error in the phase plane: position and velocity both count
      return Math.sqrt((x - Math.cos(T)) ** 2 + (v + Math.sin(T)) ** 2);
    });
    const orders = errors.slice(1).map((e, i) => Math.log2(errors[i]! / e));
    for (const p of orders) expect(Math.abs(p - expected[method])).toBeLessThanOrEqual(0.1);
    expect(INTEGRATOR_INFO[method].order).toBe(expected[method]);
  });
});

/** Theory: modulus of the eigenvalues of one step on x'' = −ω²x, as a function of h = ω·dt. */
function theoreticalModulus(method: IntegratorMethod, h: number): number {
  switch (method) {
    case 'explicit-euler':
      return Math.sqrt(1 + h * h);
    case 'backward-euler':
      return 1 / Math.sqrt(1 + h * h);
    case 'rk4': {
      // |R(ih)| with R(z) = 1 + z + z²/2 + z³/6 + z⁴/24
      const re = 1 - (h * h) / 2 + h ** 4 / 24;
      const im = h - h ** 3 / 6;
      return Math.sqrt(re * re + im * im);
    }
    default: {
      // symplectic Euler and both Verlets: det 1, trace 2 − h²
      const tr = 2 - h * h;
      return Math.abs(tr) <= 2 ? 1 : (Math.abs(tr) + Math.sqrt(tr * tr - 4)) / 2;
    }
  }
}

/**
 * The measured one-step map as a 2×2 matrix, from stepping the basis vectors: on (x, v), or for
 * position Verlet on its true state (x_n, x_{n−1}).
 */
function oneStepMatrix(method: IntegratorMethod, omega: number, dt: number): number[] {
  const osc = new HarmonicOscillator(omega);
  const integrator = createIntegrator(method, osc);
  const cols: number[][] = [];
  const basis: [number, number][] = [
    [1, 0],
    [0, 1],
  ];
  for (const [p, q] of basis) {
    const s = osc.state(0, 0);
    if (method === 'position-verlet') {
      s.x[0] = p;
      s.xPrev[0] = q;
      osc.accelerations(s.x, s.v, s.a); // the memory start() would leave
      integrator.step(s, dt);
      cols.push([s.x[0], s.xPrev[0]]);
    } else {
      s.x[0] = p;
      s.v[0] = q;
      integrator.start(s, dt);
      integrator.step(s, dt);
      cols.push([s.x[0], s.v[0]]);
    }
  }
  return [cols[0]![0]!, cols[1]![0]!, cols[0]![1]!, cols[1]![1]!]; // row-major [a b; c d]
}

function eigenModulus([a, b, c, d]: number[]): number {
  const tr = a! + d!;
  const det = a! * d! - b! * c!;
  const disc = tr * tr - 4 * det;
  if (disc < 0) return Math.sqrt(det); // complex pair: |λ|² = det
  const r = Math.sqrt(disc);
  return Math.max(Math.abs(tr + r), Math.abs(tr - r)) / 2;
}

describe('stability on x″ = −ω²x: eigenvalues of the measured one-step map vs theory', () => {
  const hs = [0.001, 0.03, 0.1, 0.5, 1, 1.5, 1.9, 1.99, 2.01, 2.1, 2.5, 2.8, 2.83, 3, 10];
  it.each(INTEGRATOR_METHODS)('%s: |λ| matches theory to 1e-9 for ω·dt from 0.001 to 10', (m) => {
    for (const h of hs) {
      // ω = 5 rad/s, so dt = h / 5: the modulus depends on ω·dt only
      const measured = eigenModulus(oneStepMatrix(m, 5, h / 5));
      const theory = theoreticalModulus(m, h);
      expect(Math.abs(measured - theory) / theory, `${m} at ω·dt = ${h}`).toBeLessThan(1e-9);
    }
  });

  it('the stability limits are 0 (explicit Euler), 2 (symplectic Euler, Verlets), 2√2 (RK4), ∞ (backward Euler)', () => {
    for (const m of INTEGRATOR_METHODS) {
      const limit = INTEGRATOR_INFO[m].stabilityLimit;
      for (const h of hs) {
        const measured = eigenModulus(oneStepMatrix(m, 1, h));
        const verdict = {
          method: m,
          h,
          bounded: measured <= 1 + 1e-12,
          grows: measured > 1 + 1e-9,
        };
        expect(verdict).toEqual({ method: m, h, bounded: h < limit, grows: h >= limit });
      }
    }
    expect(INTEGRATOR_INFO.rk4.stabilityLimit).toBe(2 * Math.SQRT2);
  });
});

describe('energy E = ½v² + ½ω²x² per step', () => {
  const osc = new HarmonicOscillator(1);
  const E = (x: number, v: number) => osc.energy(x, v);

  /** Every per-step ratio E_{n+1}/E_n over `steps` steps. */
  function ratios(method: IntegratorMethod, h: number, steps: number): number[] {
    const out: number[] = [];
    let prev = E(0.7, -0.4);
    run(method, 1, h, steps, 0.7, -0.4, (x, v) => {
      const e = E(x, v);
      out.push(e / prev);
      prev = e;
    });
    return out;
  }

  it.each([0.001, 0.01, 0.03, 0.134, 0.5, 1, 2, 3])(
    'explicit Euler multiplies it by exactly 1 + (ω·dt)² at every step (ω·dt = %s)',
    (h) => {
      for (const r of ratios('explicit-euler', h, 100)) {
        expect(Math.abs(r - (1 + h * h)) / (1 + h * h)).toBeLessThan(1e-9);
      }
    },
  );

  it.each([0.001, 0.03, 0.5, 1, 3, 30])(
    'backward Euler multiplies it by exactly 1/(1 + (ω·dt)²) at every step (ω·dt = %s)',
    (h) => {
      for (const r of ratios('backward-euler', h, 40)) {
        expect(Math.abs(r * (1 + h * h) - 1)).toBeLessThan(1e-9);
      }
    },
  );

  it.each([0.1, 1, 2, 2.8, 2.83])(
    'RK4 multiplies it by exactly |R(iω·dt)|² at every step (ω·dt = %s)',
    (h) => {
      const R2 = theoreticalModulus('rk4', h) ** 2;
      for (const r of ratios('rk4', h, 100)) expect(Math.abs(r - R2) / R2).toBeLessThan(1e-9);
    },
  );

  /** max E/E₀ over the first and the last 10 000 of `steps` steps (Infinity once non-finite). */
  function windows(method: IntegratorMethod, h: number, steps: number): [number, number] {
    const E0 = E(1, 0);
    let early = 0;
    let late = 0;
    let i = 0;
    run(method, 1, h, steps, 1, 0, (x, v) => {
      const r = Number.isFinite(x) && Number.isFinite(v) ? E(x, v) / E0 : Infinity;
      if (i < 10_000) early = Math.max(early, r);
      if (i >= steps - 10_000) late = Math.max(late, r);
      i++;
    });
    return [early, late];
  }

  it.each(['semi-implicit-euler', 'position-verlet', 'velocity-verlet'] as const)(
    '%s stays bounded for 1e5 steps up to ω·dt = 2 and blows up just above',
    (m) => {
      for (const h of [0.03, 0.5, 1, 1.5, 1.9, 1.99]) {
        const [early, late] = windows(m, h, 100_000);
        // no growth: the last 10 000 steps reach no higher than the first 10 000
        expect(late, `${m} at ω·dt = ${h}`).toBeLessThanOrEqual(early * (1 + 1e-6));
        expect(early, `${m} at ω·dt = ${h}`).toBeLessThan(1e3);
      }
      for (const h of [2.01, 2.1]) {
        const [, late] = windows(m, h, 100_000);
        expect(late, `${m} at ω·dt = ${h}`).toBeGreaterThan(1e100);
      }
    },
  );

  it('RK4 never gains energy up to ω·dt = 2√2 and blows up just above (1e5 steps)', () => {
    for (const h of [0.5, 2, 2.8, Math.sqrt(8)]) {
      const [early, late] = windows('rk4', h, 100_000);
      expect(Math.max(early, late), `ω·dt = ${h}`).toBeLessThanOrEqual(1 + 1e-9);
    }
    const [, late] = windows('rk4', 2.83, 100_000);
    expect(late).toBeGreaterThan(1e100);
  });

  it('backward Euler closed form: v₁ = (v₀ − dt·ω²·x₀)/(1 + ω²dt²), x₁ = x₀ + dt·v₁', () => {
    const omega = 7;
    const dt = 0.03;
    const [x, v] = run('backward-euler', omega, dt, 1, 0.8, 1.5);
    const v1 = (1.5 - dt * omega * omega * 0.8) / (1 + omega * omega * dt * dt);
    expect(v).toBeCloseTo(v1, 15);
    expect(x).toBeCloseTo(0.8 + dt * v1, 15);
  });
});

describe("the talk's exploding spring: k = 20 N/m, m = 1 kg (ω = 4.47 rad/s), dt = 0.03 s, 10 s", () => {
  const osc = HarmonicOscillator.fromSpring(20, 1);
  const dt = 0.03;
  const steps = Math.ceil(10 / dt); // 334 steps = 10.02 s
  const E0 = osc.energy(1, 0); // x₀ = 1 m, v₀ = 0: 10 J

  function energyTrace(method: IntegratorMethod): number[] {
    const out: number[] = [];
    run(method, osc.omega, dt, steps, 1, 0, (x, v) => out.push(osc.energy(x, v) / E0));
    return out;
  }

  it('explicit Euler: energy grows ×387 (> 10×) — (1 + (ω·dt)²)^334 = 1.018^334', () => {
    const trace = energyTrace('explicit-euler');
    const final = trace[trace.length - 1]!;
    expect(final).toBeGreaterThan(10);
    expect(final).toBeCloseTo((1 + 20 * dt * dt) ** steps, 6);
    expect(final).toBeCloseTo(387.04, 1);
  });

  it('velocity Verlet: energy stays within 1 % (max deviation 0.45 %)', () => {
    const dev = Math.max(...energyTrace('velocity-verlet').map((r) => Math.abs(r - 1)));
    expect(dev).toBeLessThan(0.01);
    expect(dev).toBeCloseTo(0.0045, 4);
  });

  it("the talk's own code (semi-implicit Euler) does not explode here: within 7.2 %", () => {
    const dev = Math.max(...energyTrace('semi-implicit-euler').map((r) => Math.abs(r - 1)));
    expect(dev).toBeLessThan(0.075);
  });
});
