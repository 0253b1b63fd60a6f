import { describe, expect, it } from 'vitest';
import {
  INTEGRATOR_METHODS,
  runForHash,
  snapshotRoundTrip,
  type IntegratorMethod,
} from 'fixedstep';
import {
  OscillatorRace,
  Rope,
  SceneRig,
  TALK_INTEGRATOR_EXPERIMENT,
  TalkSpring,
  isStable,
  ropeConfig,
  ropeOmegaMax,
  ropeRestPositions,
  runIntegratorExperiment,
  type RopePoke,
} from '@fixedstep/games';

const none = () => [];

/** The talk's spring: k = 20 N/m on 1 kg at its 0.03 s step, 10 s. */
function talkRace(explodeAt?: number): OscillatorRace {
  const race = new OscillatorRace({ omega: Math.sqrt(20), dt: 0.03, explodeAt });
  for (let i = 0; i < 333; i++) race.step();
  return race;
}

describe('OscillatorRace: one spring, six integrators in lockstep', () => {
  it('explicit Euler explodes at dt 0.03 (energy ×380 in 10 s); velocity Verlet stays within 1 %', () => {
    const race = talkRace();
    const ratio = (m: IntegratorMethod) => race.energyRatio(race.lane(m));
    const h2 = 20 * 0.03 * 0.03;
    expect(race.time).toBeCloseTo(9.99, 12);
    expect(ratio('explicit-euler')).toBeGreaterThan(10);
    expect(ratio('explicit-euler') / (1 + h2) ** 333).toBeCloseTo(1, 9);
    expect(ratio('explicit-euler')).toBeCloseTo(380.198, 2);
    expect(race.lane('velocity-verlet').maxEnergyError).toBeLessThan(0.01);
    expect(Math.abs(ratio('velocity-verlet') - 1)).toBeLessThan(0.01);
    expect(ratio('position-verlet')).toBeCloseTo(ratio('velocity-verlet'), 10);
    // The talk's own code (semi-implicit Euler) wobbles but does not grow.
    expect(race.lane('semi-implicit-euler').maxEnergyError).toBeLessThan(0.08);
    // Backward Euler damps by exactly the factor explicit Euler gains.
    expect(ratio('backward-euler') * (1 + h2) ** 333).toBeCloseTo(1, 9);
    expect(race.lane('rk4').maxEnergyError).toBeLessThan(1e-4);
    expect(Math.abs(race.phaseError(race.lane('rk4')))).toBeLessThan(1e-3);
  });

  it('stops a lane at explodeAt and says when', () => {
    const race = new OscillatorRace({ omega: 100, dt: 0.03, explodeAt: 1e9 }); // ω·dt = 3
    for (let i = 0; i < 200; i++) race.step();
    const exploded = INTEGRATOR_METHODS.filter((m) => race.lane(m).exploded);
    expect(exploded).toEqual(INTEGRATOR_METHODS.filter((m) => m !== 'backward-euler'));
    expect(INTEGRATOR_METHODS.filter((m) => isStable(m, race.omegaDt))).toEqual(['backward-euler']);
    // A stopped lane stays just past the threshold, never at Infinity.
    const stopped = Math.max(...exploded.map((m) => race.energyRatio(race.lane(m))));
    expect(stopped).toBeLessThan(1e12);
    // Explicit Euler gains ×(1 + 9) per step at ω·dt = 3, RK4 only a little: it lasts longer.
    expect(race.lane('explicit-euler').explodedAt).toBeLessThan(race.lane('rk4').explodedAt);
    expect(isStable('rk4', 2.8)).toBe(true);
    expect(isStable('velocity-verlet', 1.99)).toBe(true);
    expect(isStable('backward-euler', 1e6)).toBe(true);
    expect(isStable('explicit-euler', 1e-6)).toBe(false);
  });

  it('is the CLI experiment: runIntegratorExperiment gives the same numbers', () => {
    const race = talkRace();
    const exp = runIntegratorExperiment({
      ...TALK_INTEGRATOR_EXPERIMENT,
      methods: INTEGRATOR_METHODS,
    });
    expect(exp.steps).toBe(333);
    for (const r of exp.results) {
      const lane = race.lane(r.method);
      expect(r.energyRatio).toBe(race.energyRatio(lane));
      expect(r.maxEnergyError).toBe(lane.maxEnergyError);
      expect(r.phaseError).toBe(race.phaseError(lane));
    }
  });

  it('golden hash after 10 s, and a snapshot round trip', () => {
    const h = runForHash(new OscillatorRace({ omega: Math.sqrt(20), dt: 0.03 }), 333, none);
    if (h !== 'b5ab567bfc7745cc') console.log(`oscillator race golden is now ${h}`);
    expect(h).toBe('b5ab567bfc7745cc');
    const rt = snapshotRoundTrip(
      () => new OscillatorRace({ omega: 30, dt: 0.03, explodeAt: 1e6 }),
      none,
      60,
      120,
    );
    expect(rt.message).toBe('equal hashes for 120 ticks after the snapshot');
  });
});

describe('Rope: beads on springs between two pins', () => {
  const poke = (t: number): RopePoke[] => (t === 10 ? [{ bead: 5, dvx: 1.5, dvy: 4 }] : []);

  it('starts hanging at rest, symmetric, every link stretched', () => {
    const c = ropeConfig({ dt: 0.03 });
    const x = ropeRestPositions(c);
    const n = c.count;
    for (let i = 0; i < n; i++) {
      expect(x[2 * i]!).toBeCloseTo(-x[2 * (n - 1 - i)]!, 6);
      expect(x[2 * i + 1]!).toBeCloseTo(x[2 * (n - 1 - i) + 1]!, 6);
    }
    const rest = (c.span / (n - 1)) * c.restShare;
    for (let i = 0; i + 1 < n; i++) {
      const len = Math.hypot(x[2 * i + 2]! - x[2 * i]!, x[2 * i + 3]! - x[2 * i + 1]!);
      expect(len).toBeGreaterThan(rest);
    }
    expect(x[2 * 8 + 1]).toBeCloseTo(-2.161, 3); // the sag in the middle
    const rope = new Rope({ dt: 0.03, integrator: 'velocity-verlet' });
    for (let i = 0; i < 100; i++) rope.step();
    // Untouched, it stays where it hangs.
    for (let i = 0; i < rope.x.length; i++) expect(Math.abs(rope.x[i]! - x[i]!)).toBeLessThan(1e-6);
  });

  it('at the default 40 N/m and 30 ms (fastest ω·dt ≈ 1.19): explicit Euler shreds it, the rest hold', () => {
    expect(ropeOmegaMax({ stiffness: 40, mass: 0.1, count: 16 }) * 0.03).toBeCloseTo(1.1934, 3);
    const runs = INTEGRATOR_METHODS.map((m) => {
      const rope = new Rope({ dt: 0.03, integrator: m });
      for (let t = 0; t < 1000; t++) rope.step(poke(t));
      return { m, rope };
    });
    expect(runs.filter((r) => r.rope.exploded).map((r) => r.m)).toEqual(['explicit-euler']);
    expect(runs[0]!.rope.explodedAt).toBeLessThan(60);
    // The others keep their energy within 2.5 J of the start (the poke adds about 1 J).
    const drift = runs.slice(1).map((r) => Math.abs(r.rope.energy() - r.rope.energy0));
    expect(Math.max(...drift)).toBeLessThan(2.5);
    expect(runs.map((r) => r.rope.pokes)).toEqual(INTEGRATOR_METHODS.map(() => 1));
  });

  it('stiff links (1000 N/m, ω·dt ≈ 6): only backward Euler survives', () => {
    const survivors = INTEGRATOR_METHODS.filter((m) => {
      const rope = new Rope({ dt: 0.03, integrator: m, stiffness: 1000 });
      for (let t = 0; t < 300; t++) rope.step(poke(t));
      return !rope.exploded;
    });
    expect(survivors).toEqual(['backward-euler']);
  });

  it('ignores pokes at the pins or with bad numbers', () => {
    const rope = new Rope({ dt: 0.03 });
    rope.step([
      { bead: 0, dvx: 0, dvy: 5 },
      { bead: 15, dvx: 0, dvy: 5 },
      { bead: 3.5, dvx: 0, dvy: 5 },
      { bead: 4, dvx: Number.NaN, dvy: 5 },
    ]);
    expect(rope.pokes).toBe(0);
  });

  it('golden hashes after 300 steps with one poke, per integrator', () => {
    const golden: Record<IntegratorMethod, string> = {
      'explicit-euler': 'e176ad2b6d4525db',
      'semi-implicit-euler': '64bd9d6b5feb9caa',
      'backward-euler': 'ff38733e09b60cbc',
      'position-verlet': '5f49132ac23b2e5c',
      'velocity-verlet': '0fa8cef20d1dfb9e',
      rk4: '2501c69c276e9de5',
    };
    const actual = Object.fromEntries(
      INTEGRATOR_METHODS.map((m) => [
        m,
        runForHash(new Rope({ dt: 0.03, integrator: m }), 300, poke),
      ]),
    );
    if (JSON.stringify(actual) !== JSON.stringify(golden)) {
      console.log('rope golden is now', JSON.stringify(actual));
    }
    expect(actual).toEqual(golden);
  });

  it('survives a snapshot round trip under every integrator, pokes included', () => {
    const pokes = (t: number): RopePoke[] =>
      t % 37 === 5 ? [{ bead: 1 + (t % 14), dvx: 2, dvy: -1 }] : [];
    const messages = INTEGRATOR_METHODS.map(
      (m) => snapshotRoundTrip(() => new Rope({ dt: 0.03, integrator: m }), pokes, 60, 120).message,
    );
    expect(messages).toEqual(
      INTEGRATOR_METHODS.map(() => 'equal hashes for 120 ticks after the snapshot'),
    );
    // An exploded rope keeps its state (and its tick count) through a snapshot too.
    const rt = snapshotRoundTrip(
      () => new Rope({ dt: 0.03, integrator: 'explicit-euler' }),
      pokes,
      200,
      30,
    );
    expect(rt.ok).toBe(true);
  });
});

describe('TalkSpring: the talk’s spring code under a fixed step and under a variable Δt', () => {
  const rig = (kind: 'variable' | 'fixed', hitches: number[]) => {
    const r = new SceneRig({
      loop: kind === 'fixed' ? { kind: 'fixed', stepMs: 30 } : { kind: 'variable' },
      display: {
        hz: 30,
        jitter: 0.3,
        seed: 11,
        events: hitches.map((atMs) => ({ kind: 'hitch' as const, atMs, durationMs: 250 })),
      },
      scene: new TalkSpring(10),
    });
    r.runFor(8000);
    return r.scene;
  };

  it('a jittery display alone is harmless to both (ω·dt ≤ 0.45 < 2)', () => {
    const v = rig('variable', []);
    const f = rig('fixed', []);
    expect(v.maxDt).toBeLessThan(0.045);
    expect(f.maxDt).toBe(0.03);
    expect(v.maxRatio).toBeLessThan(1.6);
    expect(f.maxRatio).toBeLessThan(1.2);
  });

  it('one 250 ms hitch is one update of ω·dt ≈ 2.8 for the variable loop: its energy jumps; the fixed step does not notice', () => {
    const v = rig('variable', [2000]);
    const f = rig('fixed', [2000]);
    expect(v.maxDt).toBeGreaterThan(0.25);
    expect(v.omega * v.maxDt).toBeGreaterThan(2);
    expect(v.maxRatio).toBeGreaterThan(10);
    expect(f.maxDt).toBe(0.03);
    expect(f.maxRatio).toBeLessThan(1.2);
    // How much one such step multiplies the energy depends on where in its swing the spring is
    // (×1.3 to ×80 here); hitch after hitch, it grows.
    expect(rig('variable', [3000]).maxRatio).toBeLessThan(2);
    expect(rig('variable', [2000, 4000, 6000]).maxRatio).toBeGreaterThan(v.maxRatio);
  });

  it('is deterministic and refuses a bad ω', () => {
    expect(rig('variable', [2000]).x).toBe(rig('variable', [2000]).x);
    expect(() => new TalkSpring(0)).toThrow(RangeError);
  });
});
