import { describe, expect, it } from 'vitest';
import { INTEGRATOR_METHODS, hex64 } from 'fixedstep';
import {
  ClockPhysics,
  EnergyHistory,
  HitchLab,
  PLOT_SAMPLES,
  PhysicsLab,
  defaultSettings,
  ropeOmegaDt,
  stabilityOf,
} from '../src/chapters/physics/physics-lab.js';
import { OscillatorRace } from '@fixedstep/games';

describe('PhysicsLab', () => {
  it('after 10 s at the talk’s 0.03 s step: explicit Euler’s energy > 10×, velocity Verlet within 1 %', () => {
    const lab = new PhysicsLab();
    lab.advanceTo(10_000);
    const run = lab.run;
    const ratio = (m: (typeof INTEGRATOR_METHODS)[number]) => run.race.energyRatio(run.lane(m));
    expect(run.race.tick).toBe(333);
    expect(run.omegaDt).toBeCloseTo(0.13416, 5);
    expect(ratio('explicit-euler')).toBeGreaterThan(10);
    expect(ratio('explicit-euler')).toBeCloseTo(380.198, 2);
    expect(Math.abs(ratio('velocity-verlet') - 1)).toBeLessThan(0.01);
    expect(run.lane('velocity-verlet').maxEnergyError).toBeLessThan(0.01);
    expect(ratio('backward-euler')).toBeLessThan(0.01);
    expect(run.rope.exploded).toBe(false);
    expect(run.rope.pokes).toBe(1); // the scripted poke at 1 s
  });

  it('past ω·dt = 2 the symplectic methods explode, RK4 and backward Euler hold', () => {
    const lab = new PhysicsLab({ ...defaultSettings(), stiffness: 5000 });
    lab.advanceTo(3000);
    const run = lab.run;
    expect(run.omegaDt).toBeCloseTo(2.1213, 4);
    const exploded = INTEGRATOR_METHODS.filter((m) => run.lane(m).exploded);
    expect(exploded).toEqual([
      'explicit-euler',
      'semi-implicit-euler',
      'position-verlet',
      'velocity-verlet',
    ]);
    expect(stabilityOf('semi-implicit-euler', run.omegaDt)).toBe('unstable');
    expect(stabilityOf('rk4', run.omegaDt)).toBe('stable');
    expect(stabilityOf('backward-euler', run.omegaDt)).toBe('damped');
    expect(stabilityOf('explicit-euler', 0.001)).toBe('grows');
  });

  it('a poke lands where a replay puts it: live and rebuilt runs agree exactly', () => {
    const live = new PhysicsLab();
    let t = 0;
    const frame = () => {
      t += 16.7;
      live.advanceTo(t);
    };
    while (t < 1500) frame();
    live.poke({ bead: 3, dvx: 2, dvy: 5 });
    while (t < 2500) frame();
    live.poke({ bead: 12, dvx: -3, dvy: 1 });
    live.poke({ bead: 12, dvx: 0, dvy: 2 });
    while (t < 4000) frame();
    expect(live.run.rope.pokes).toBe(4);
    const rebuilt = new PhysicsLab({ ...live.settings });
    rebuilt.advanceTo(live.timeMs);
    expect(hex64(rebuilt.run.rope.hash())).toBe(hex64(live.run.rope.hash()));
    expect(hex64(rebuilt.run.race.hash())).toBe(hex64(live.run.race.hash()));
    // Changing the rope's integrator replays the same pokes under the new method.
    live.update({ ropeMethod: 'backward-euler' });
    expect(live.run.rope.pokes).toBe(4);
    expect(live.run.rope.config.integrator).toBe('backward-euler');
  });

  it('explicit Euler shreds the rope within a second; stiff links leave only backward Euler', () => {
    const lab = new PhysicsLab({ ...defaultSettings(), ropeMethod: 'explicit-euler' });
    lab.advanceTo(3000);
    expect(lab.run.rope.exploded).toBe(true);
    expect(lab.run.rope.explodedAt * 0.03).toBeLessThan(2);
    expect(ropeOmegaDt(1000, 30)).toBeCloseTo(5.967, 2);
    const survivors = INTEGRATOR_METHODS.filter((m) => {
      const stiff = new PhysicsLab({ ...defaultSettings(), ropeStiffness: 1000, ropeMethod: m });
      stiff.advanceTo(3000);
      return !stiff.run.rope.exploded;
    });
    expect(survivors).toEqual(['backward-euler']);
  });

  it('restart goes back to zero and forgets the pokes', () => {
    const lab = new PhysicsLab();
    lab.advanceTo(2000);
    lab.poke({ bead: 4, dvx: 0, dvy: 3 });
    lab.advanceTo(2500);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.settings.pokes).toEqual([]);
    expect(lab.run.race.tick).toBe(0);
  });

  it('thins the energy history as it grows, keeping a regular grid', () => {
    const race = new OscillatorRace({ omega: 2, dt: 0.01 });
    const h = new EnergyHistory(INTEGRATOR_METHODS);
    h.record(race);
    for (let i = 0; i < 10_000; i++) {
      race.step();
      h.record(race);
    }
    expect(h.t.length).toBeLessThanOrEqual(PLOT_SAMPLES + 1);
    expect(h.t.length).toBeGreaterThan(PLOT_SAMPLES / 2);
    for (const s of h.series) expect(s).toHaveLength(h.t.length);
    const gaps = new Set(h.t.slice(1).map((t, i) => Math.round((t - h.t[i]!) / 0.01)));
    expect(gaps.size).toBe(1);
  });

  it('runs on a real clock too, with the scripted poke', () => {
    const clock = new ClockPhysics(defaultSettings());
    for (let t = 0; t <= 1500; t += 16.7) clock.frameAt(t);
    expect(clock.run.rope.pokes).toBe(1);
    expect(clock.run.race.tick).toBe(Math.floor(clock.timeMs / 30));
  });
});

describe('HitchLab: the talk’s spring code under a variable Δt and a fixed step', () => {
  it('jitter alone is harmless; a hitch pushes the variable loop past ω·Δt = 2, the fixed step never', () => {
    const lab = new HitchLab();
    lab.advanceTo(2000);
    const v = () => lab.run('variable').rig.scene;
    const f = () => lab.run('fixed').rig.scene;
    expect(v().maxRatio).toBeLessThan(1.6);
    expect(v().omega * v().maxDt).toBeLessThan(0.5);
    lab.addHitch();
    expect(lab.hitches).toEqual([2000]);
    lab.advanceTo(6000);
    expect(v().maxDt * 1000).toBeGreaterThan(250);
    expect(v().omega * v().maxDt).toBeGreaterThan(2);
    expect(v().maxRatio).toBeGreaterThan(10);
    expect(f().maxDt).toBe(0.03);
    expect(f().maxRatio).toBeLessThan(1.2);
    // The traces hold the last few seconds of x(t), in time order.
    const { t } = lab.run('variable').trace;
    expect(t.at(-1)!).toBeGreaterThan(5.9);
    expect(t.every((x, i) => i === 0 || x > t[i - 1]!)).toBe(true);
  });

  it('replays: the same hitches give the same numbers; restart forgets them', () => {
    const a = new HitchLab();
    a.advanceTo(2000);
    a.addHitch();
    a.advanceTo(5000);
    const b = new HitchLab();
    b.advanceTo(2000);
    b.addHitch();
    for (let t = 2000; t <= 5000; t += 16.7) b.advanceTo(t);
    b.advanceTo(5000);
    expect(b.run('variable').rig.scene.x).toBe(a.run('variable').rig.scene.x);
    a.restart();
    expect(a.hitches).toEqual([]);
    expect(a.timeMs).toBe(0);
  });
});
