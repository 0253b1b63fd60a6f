import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  BandMatrix,
  createIntegrator,
  DynamicsState,
  INTEGRATOR_METHODS,
  runForHash,
  snapshotRoundTrip,
  springChain,
  SpringModel,
  SpringSystem,
  type IntegratorMethod,
  type SpringSystemDef,
} from 'fixedstep';

/**
 * Springs, spring systems and the backward-Euler machinery (band solver, Jacobians, Newton).
 */

/** The golden scene: a rope of 16 particles of 0.1 kg hung between (0, 0) and (3, 0) m. */
function chainScene(integrator: IntegratorMethod): SpringSystemDef {
  return springChain({
    count: 16,
    from: [0, 0],
    to: [3, 0],
    mass: 0.1,
    stiffness: 50,
    damping: 0.05,
    dt: 1 / 60,
    integrator,
  });
}

describe('BandMatrix: Gaussian elimination with partial pivoting', () => {
  it('solves a system that needs pivoting (zero diagonal)', () => {
    const m = new BandMatrix(3, 1);
    m.add(0, 1, 2);
    m.add(1, 0, 3);
    m.add(1, 2, 1);
    m.add(2, 1, 4);
    m.add(2, 2, 1);
    // [0 2 0; 3 0 1; 0 4 1]·[1 2 3] = [4 6 11]
    const rhs = Float64Array.of(4, 6, 11);
    m.solve(rhs);
    expect([...rhs]).toEqual([1, 2, 3]);
  });

  it('rejects entries outside the band and singular matrices with clear errors', () => {
    const m = new BandMatrix(4, 1);
    expect(() => {
      m.add(0, 2, 1);
    }).toThrow(/outside the 4×4 matrix of bandwidth 1/);
    expect(() => {
      m.solve(new Float64Array(4));
    }).toThrow(/singular/);
    expect(() => {
      m.solve(new Float64Array(3));
    }).toThrow(/rhs has length 3/);
  });

  it('solves random banded systems (dense when bandwidth = n − 1) to a small residual', () => {
    fc.assert(
      fc.property(
        fc.integer({ min: 1, max: 14 }),
        fc.integer({ min: 0, max: 14 }),
        fc.array(fc.double({ min: -10, max: 10, noNaN: true }), { minLength: 14 * 29 }),
        fc.array(fc.double({ min: -10, max: 10, noNaN: true }), { minLength: 14 }),
        (n, bw, entries, b) => {
          const band = Math.min(bw, n - 1);
          const m = new BandMatrix(n, band);
          const dense: number[][] = [];
          let k = 0;
          for (let i = 0; i < n; i++) {
            const row: number[] = [];
            for (let j = 0; j < n; j++) {
              let v = Math.abs(i - j) <= band ? entries[k++ % entries.length]! : 0;
              if (i === j) v += 25 * (band + 1); // keep it well conditioned
              if (v !== 0) m.add(i, j, v);
              row.push(v);
            }
            dense.push(row);
          }
          const rhs = Float64Array.from({ length: n }, (_, i) => b[i]!);
          m.solve(rhs);
          for (let i = 0; i < n; i++) {
            let s = 0;
            for (let j = 0; j < n; j++) s += dense[i]![j]! * rhs[j]!;
            expect(Math.abs(s - b[i]!)).toBeLessThan(1e-9);
          }
        },
      ),
    );
  });
});

describe('SpringModel', () => {
  it('computes Hooke + damping forces and the rope sags under gravity', () => {
    const model = new SpringModel({
      dim: 2,
      gravity: [0, -10],
      particles: [
        { position: [0, 0], fixed: true },
        { position: [2, 0], velocity: [0, 1], mass: 2 },
      ],
      springs: [{ a: 0, b: 1, stiffness: 10, damping: 3, restLength: 1.5 }],
    });
    const x = Float64Array.of(0, 0, 2, 0);
    const v = Float64Array.of(0, 0, 0, 1);
    const a = new Float64Array(4);
    model.accelerations(x, v, a);
    // stretch 0.5 m × 10 N/m = 5 N towards the anchor; damping sees no speed along the spring
    expect([...a]).toEqual([0, 0, -2.5, -10]);
    // energy: ½·2·1² + ½·10·0.5² − 2·(−10)·0 = 2.25 J
    expect(model.energy(x, v)).toBeCloseTo(2.25, 14);
  });

  it('gives Jacobians equal to central finite differences (2D, damped, stretched and compressed)', () => {
    const model = new SpringModel({
      dim: 2,
      gravity: [0, -9.81],
      particles: [
        { position: [0, 0], fixed: true },
        { position: [0.9, 0.2], mass: 0.5 },
        { position: [1.5, -0.4], mass: 0.7 },
        { position: [2.6, 0.1], mass: 0.3 },
      ],
      springs: [
        { a: 0, b: 1, stiffness: 40, damping: 0.8, restLength: 1.2 },
        { a: 1, b: 2, stiffness: 25, damping: 0.3, restLength: 0.5 },
        { a: 2, b: 3, stiffness: 60, damping: 1.1, restLength: 1.0 },
        { a: 1, b: 3, stiffness: 10, damping: 0.2 },
      ],
    });
    const n = model.size;
    const x = Float64Array.of(0, 0, 0.9, 0.2, 1.5, -0.4, 2.6, 0.1);
    const v = Float64Array.of(0, 0, 0.3, -0.7, -1.2, 0.4, 0.5, 0.9);
    for (const [sx, sv, arg] of [
      [1, 0, x],
      [0, 1, v],
    ] as const) {
      const J = new BandMatrix(n, model.bandwidth);
      model.addJacobian(x, v, sx, sv, J);
      const eps = 1e-6;
      const ap = new Float64Array(n);
      const am = new Float64Array(n);
      for (let j = 0; j < n; j++) {
        const keep = arg[j]!;
        arg[j] = keep + eps;
        model.accelerations(x, v, ap);
        arg[j] = keep - eps;
        model.accelerations(x, v, am);
        arg[j] = keep;
        for (let i = 0; i < n; i++) {
          const fd = (ap[i]! - am[i]!) / (2 * eps);
          expect(Math.abs(J.get(i, j) - fd), `∂a${i}/∂${sx ? 'x' : 'v'}${j}`).toBeLessThan(1e-6);
        }
      }
    }
    expect(model.bandwidth).toBe(5); // spring 1–3: dim·|a − b| + dim − 1 = 2·2 + 1
    expect(model.linear).toBe(false);
  });
});

/** Backward-Euler residual g = v₁ − v₀ − dt·a(x₀ + dt·v₁, v₁), its largest magnitude. */
function residual(
  model: SpringModel,
  x0: Float64Array,
  v0: Float64Array,
  v1: Float64Array,
  dt: number,
): number {
  const n = model.size;
  const x1 = x0.map((xi, i) => xi + dt * v1[i]!);
  const a = new Float64Array(n);
  model.accelerations(x1, v1, a);
  let worst = 0;
  for (let i = 0; i < n; i++) worst = Math.max(worst, Math.abs(v1[i]! - v0[i]! - dt * a[i]!));
  return worst;
}

describe('backward Euler on spring chains', () => {
  it('is exact in one linear solve for a 1D chain (linear forces): residual 6e-13 of Δv', () => {
    const def = springChain({
      count: 30,
      from: [0],
      to: [6],
      stiffness: 1e4,
      damping: 2,
      dt: 0.03,
    });
    const sys = new SpringSystem({ ...def, integrator: 'backward-euler', gravity: [0] });
    expect(sys.model.linear).toBe(true);
    expect(sys.model.bandwidth).toBe(1);
    sys.state.v[10] = 5; // a kick
    sys.restart();
    const x0 = sys.state.x.slice();
    const v0 = sys.state.v.slice();
    sys.step();
    const dv = Math.max(...sys.state.v.map((vi, i) => Math.abs(vi - v0[i]!)));
    expect(dv).toBeGreaterThan(1); // it did move
    // measured: 3e-12 m/s on a Δv of 5 m/s — the rounding of dt·a with a ≈ 1e5 m/s² per m
    expect(residual(sys.model, x0, v0, sys.state.v, sys.dt) / dv).toBeLessThan(1e-11);
  });

  it('converges quadratically with Newton iterations on a nonlinear 2D chain', () => {
    const res: number[] = [];
    for (const newtonIterations of [1, 2, 3, 4]) {
      const sys = new SpringSystem({
        ...springChain({
          count: 20,
          from: [0, 0],
          to: [3, 0],
          stiffness: 500,
          damping: 0.5,
          dt: 0.05,
        }),
        integrator: 'backward-euler',
        newtonIterations,
      });
      for (let i = 0; i < 5; i++) sys.step(); // let it fall and bend first
      const x0 = sys.state.x.slice();
      const v0 = sys.state.v.slice();
      sys.step();
      res.push(residual(sys.model, x0, v0, sys.state.v, sys.dt));
    }
    // measured: 6.0e-2, 6.1e-4, 1.2e-8, 1.2e-13 m/s (velocities about 3 m/s)
    expect(res[0]!).toBeGreaterThan(1e-4); // one step: linearly implicit, not exact
    expect(res[1]!).toBeLessThan(res[0]! * 1e-1);
    expect(res[2]!).toBeLessThan(1e-7);
    expect(res[3]!).toBeLessThan(1e-12);
  });

  it('stays stable on a stiff rope where the explicit methods explode (ω·dt ≈ 67)', () => {
    // 10 g beads on 1e4 N/m links: the fastest mode has ω ≈ 2·√(k/m) = 2000 rad/s
    const stiff = (integrator: IntegratorMethod) =>
      new SpringSystem(
        springChain({
          count: 10,
          from: [0, 0],
          to: [2, 0],
          mass: 0.01,
          stiffness: 1e4,
          dt: 1 / 30,
          integrator,
        }),
      );
    const be = stiff('backward-euler');
    const e0 = be.energy();
    let maxE = e0;
    for (let i = 0; i < 300; i++) {
      be.step();
      maxE = Math.max(maxE, be.energy());
    }
    expect(maxE).toBeLessThanOrEqual(e0 + 1e-9); // never gains energy
    expect(be.state.x[11]!).toBeLessThan(0); // a bead in the middle hangs below the line
    for (const m of ['semi-implicit-euler', 'velocity-verlet', 'rk4'] as const) {
      const sys = stiff(m);
      for (let i = 0; i < 300; i++) sys.step();
      expect(
        Number.isFinite(sys.energy()) ? Math.abs(sys.energy()) : Infinity,
        `${m} explodes`,
      ).toBeGreaterThan(1e6);
    }
  });

  it('refuses a model without Jacobians', () => {
    const model = {
      size: 1,
      accelerations: (_x: Float64Array, _v: Float64Array, out: Float64Array) => out.fill(0),
    };
    expect(() => createIntegrator('backward-euler', model)).toThrow(/needs a model with Jacobians/);
  });
});

describe('SpringSystem as a Simulation', () => {
  // Golden hashes after 600 ticks (10 s at 60 Hz). Explicit Euler's rope has blown up by then
  // (energy ×1e100 or so) — its hash still pins the arithmetic down.
  const GOLDEN: Record<IntegratorMethod, string> = {
    'explicit-euler': 'f2be552604177a24',
    'semi-implicit-euler': 'c733e9947e30749c',
    'backward-euler': '597f4c2c377a8ab0',
    'position-verlet': 'be3bb0d910588b79',
    'velocity-verlet': 'ff414192dc59d827',
    rk4: '21f978ccfc601372',
  };

  it.each(INTEGRATOR_METHODS)('%s: golden hash of the rope after 600 ticks', (m) => {
    const actual = runForHash(new SpringSystem(chainScene(m)), 600, () => []);
    expect(actual, `golden hash changed for ${m}: actual ${actual}`).toBe(GOLDEN[m]);
  });

  it.each(INTEGRATOR_METHODS)('%s: snapshot round trip (save at 60, 120 equal ticks)', (m) => {
    const r = snapshotRoundTrip(
      () => new SpringSystem(chainScene(m)),
      () => [],
    );
    expect(r).toMatchObject({ ok: true, firstMismatch: -1 }); // prints the message if not
  });

  it('keeps the pinned ends exactly in place and time as tick × dt', () => {
    const sys = new SpringSystem(chainScene('velocity-verlet'));
    for (let i = 0; i < 600; i++) sys.step();
    const x = sys.state.x;
    expect([x[0], x[1], x[30], x[31]]).toEqual([0, 0, 3, 0]);
    expect(sys.tick).toBe(600);
    expect(sys.time).toBe(600 * (1 / 60));
    expect(x[15]!).toBeLessThan(-0.1); // the middle sags
  });

  it('velocity Verlet on a taut undamped rope: energy error 7.9 mJ of 3.75 J over 60 s, ×¼ per dt/2', () => {
    // Links of rest length 0.1 m spaced 0.2 m: pre-tensioned, so no link folds through zero
    // length (where a Hooke spring's force flips direction and no integrator keeps energy).
    const devs = [60, 120, 240].map((hz) => {
      const sys = new SpringSystem(
        springChain({
          count: 16,
          from: [0, 0],
          to: [3, 0],
          mass: 0.1,
          stiffness: 50,
          restLength: 0.1,
          dt: 1 / hz,
          integrator: 'velocity-verlet',
        }),
      );
      const e0 = sys.energy();
      let dev = 0;
      for (let i = 0; i < 60 * hz; i++) {
        sys.step();
        dev = Math.max(dev, Math.abs(sys.energy() - e0));
      }
      return dev / e0;
    });
    // measured: 2.1e-3, 5.1e-4, 1.3e-4 of E₀ = 3.75 J
    expect(devs[0]!).toBeLessThan(0.003);
    expect(Math.log2(devs[0]! / devs[1]!)).toBeCloseTo(2, 0);
    expect(Math.log2(devs[1]! / devs[2]!)).toBeCloseTo(2, 0);
  });

  it('rejects snapshots of another configuration before touching its state', () => {
    const a = new SpringSystem(chainScene('rk4'));
    const b = new SpringSystem({ ...chainScene('rk4'), gravity: [0, -9.8] });
    const c = new SpringSystem(chainScene('velocity-verlet'));
    const before = b.save();
    expect(() => {
      b.load(a.save());
    }).toThrow(/another configuration/);
    expect(() => {
      c.load(a.save());
    }).toThrow(/expected \d+ bytes/);
    expect(b.save()).toEqual(before);
  });

  it('allocates no typed arrays while stepping and never replaces its state arrays', () => {
    const systems = INTEGRATOR_METHODS.map((m) => new SpringSystem(chainScene(m)));
    const arrays = systems.map((s) => [s.state.x, s.state.v, s.state.a, s.state.xPrev]);
    const original = globalThis.Float64Array;
    let created = 0;
    class Counting extends original {
      constructor(...args: ConstructorParameters<typeof Float64Array>) {
        super(...args);
        created++;
      }
    }
    globalThis.Float64Array = Counting;
    try {
      for (const s of systems) for (let i = 0; i < 200; i++) s.step();
    } finally {
      globalThis.Float64Array = original;
    }
    expect(created).toBe(0);
    // the counter does count: one construction outside the loop
    globalThis.Float64Array = Counting;
    try {
      new DynamicsState(1);
    } finally {
      globalThis.Float64Array = original;
    }
    expect(created).toBe(4);
    systems.forEach((s, i) => {
      const [x, v, a, xPrev] = arrays[i]!;
      expect(s.state.x).toBe(x);
      expect(s.state.v).toBe(v);
      expect(s.state.a).toBe(a);
      expect(s.state.xPrev).toBe(xPrev);
    });
  });
});
