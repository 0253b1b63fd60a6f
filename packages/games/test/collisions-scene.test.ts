import { describe, expect, it } from 'vitest';
import { hex64, runForHash, snapshotRoundTrip, tunnellingShare } from 'fixedstep';
import { ShotStatus, WallRange, WallRangeRig, wallRangeConfig, wallRule } from '@fixedstep/games';

const none = () => [];

/** Step a range at its nominal step until `shots` bodies have been resolved. */
function resolve(range: WallRange, shots: number): WallRange {
  while (range.through + range.bounced < shots) range.step();
  return range;
}

describe('WallRange: the firing range at a fixed step', () => {
  it('with CCD nothing goes through, even at 100 m/s against a 0.3 m wall', () => {
    const ccd = resolve(new WallRange({ speed: 100, wall: 0.3, ccd: true }), 300);
    expect(ccd.through).toBe(0);
    expect(ccd.bounced).toBe(300);
    // The same shots without CCD: v·dt = 3 m against 0.3 m, theory 1 − 0.5/6 ≈ 92 % through.
    const discrete = resolve(new WallRange({ speed: 100, wall: 0.3 }), 300);
    expect(discrete.share).toBeGreaterThan(0.85);
    expect(Math.abs(discrete.share - tunnellingShare(100, 0.3, 0.1, 0.03))).toBeLessThan(0.05);
  });

  it('matches the geometry: share through = max(0, 1 − (w + 2r)/(2·v·dt))', () => {
    // w = v·dt exactly (the talk's rule holds): every overlap is seen, still ~1/3 go through.
    const atRule = resolve(new WallRange({ speed: 60, wall: 1.8 }), 600);
    const theory = tunnellingShare(60, 1.8, 0.1, 0.03); // 1 − 2/3.6 = 0.444…
    expect(theory).toBeCloseTo(0.4444, 3);
    expect(Math.abs(atRule.share - theory)).toBeLessThan(0.05);
    // Just above the correct-bounce bound (v·dt ≤ w/2 + r): none.
    const safe = resolve(new WallRange({ speed: 60, wall: 3.5 }), 600);
    expect(wallRule(60, 3.5, 0.1, 0.03).theoryShare).toBe(0);
    expect(safe.through).toBe(0);
  });

  it('fires on a schedule: shot k at k × fireEvery, time = tick × step', () => {
    const r = new WallRange({ speed: 60, wall: 3.5 });
    for (let i = 0; i < 100; i++) r.step();
    expect(r.time).toBe(100 * 0.03);
    // Shots 0..29 left at 0, 0.1, …, 2.9 s; the 31st is due at 3.0 s, the start of step 101.
    expect(r.fired).toBe(30);
    expect(r.maxStep).toBe(0.03);
  });

  it('classifies and removes bodies: nothing left behind', () => {
    const r = new WallRange({ speed: 80, wall: 1 });
    for (let i = 0; i < 1000; i++) r.step();
    expect(r.through + r.bounced + r.pending).toBe(r.fired);
    expect(r.pending).toBeLessThanOrEqual(3);
    let live = 0;
    for (let id = 0; id < r.world.slotCount; id++) if (r.status[id] !== 0) live++;
    expect(live).toBe(r.world.bodyCount);
    expect(live).toBeLessThan(12);
    const throughXs: number[] = [];
    for (let id = 0; id < r.world.slotCount; id++) {
      if (r.status[id] === ShotStatus.through) throughXs.push(r.world.x[id]!);
    }
    expect(throughXs.every((x) => x > 0)).toBe(true);
  });

  it('golden hashes after 300 steps (print the actual value to re-bless)', () => {
    const discrete = runForHash(new WallRange({ speed: 100, wall: 1 }), 300, none);
    const ccd = runForHash(new WallRange({ speed: 100, wall: 1, ccd: true }), 300, none);
    if (discrete !== 'b622fca18862b893' || ccd !== 'c0786021fde2e23f') {
      console.log(`wall range golden is now: discrete ${discrete}, ccd ${ccd}`);
    }
    expect(discrete).toBe('b622fca18862b893');
    expect(ccd).toBe('c0786021fde2e23f');
  });

  it('survives a snapshot round trip, with and without CCD, at fixed and variable steps', () => {
    for (const ccd of [false, true]) {
      const r = snapshotRoundTrip(
        () => new WallRange({ speed: 90, wall: 0.8, ccd }),
        none,
        77,
        150,
      );
      expect(r.message).toBe('equal hashes for 150 ticks after the snapshot');
      expect(r.ok).toBe(true);
    }
    // Variable steps: load into a twin and keep stepping with the same Δts.
    const a = new WallRange({ speed: 90, wall: 0.8 });
    const dts = [0.02, 0.045, 0.031, 0.25, 0.017];
    for (let i = 0; i < 60; i++) a.stepBy(dts[i % dts.length]!);
    const b = new WallRange({ speed: 90, wall: 0.8 });
    b.load(a.save());
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
    for (let i = 0; i < 60; i++) {
      a.stepBy(dts[i % dts.length]!);
      b.stepBy(dts[i % dts.length]!);
    }
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
    expect(b.time).toBe(a.time);
    expect(() => {
      new WallRange({ speed: 90, wall: 0.9 }).load(a.save());
    }).toThrow(RangeError);
  });

  it('checks its options', () => {
    expect(wallRangeConfig({ speed: 10, wall: 1 })).toMatchObject({
      radius: 0.1,
      ccd: false,
      step: 0.03,
      fireEvery: 0.1,
      lanes: 18,
    });
    expect(() => new WallRange({ speed: 0, wall: 1 })).toThrow(RangeError);
    expect(() => new WallRange({ speed: 10, wall: 20 })).toThrow(RangeError);
    expect(() => new WallRange({ speed: 10, wall: 1, lanes: 40 })).toThrow(RangeError);
  });
});

describe('WallRangeRig: variable Δt against a fixed step on one simulated display', () => {
  const rig = (loop: 'variable' | 'fixed', events: { atMs: number; durationMs: number }[] = []) => {
    const r = new WallRangeRig({
      loop,
      display: {
        hz: 30,
        jitter: 0.3,
        seed: 7,
        events: events.map((e) => ({ kind: 'hitch' as const, ...e })),
      },
      range: { speed: 60, wall: 3.5 },
    });
    r.runFor(10_000);
    return r;
  };

  it('the talk’s contrast: a wall safe for the fixed step lets variable-Δt bodies through; CCD none', () => {
    const variable = rig('variable');
    const fixed = rig('fixed');
    expect(variable.discrete.fired).toBeGreaterThanOrEqual(100);
    expect(variable.discrete.through).toBeGreaterThan(3);
    expect(variable.maxDt).toBeGreaterThan(0.04);
    expect(fixed.discrete.through).toBe(0);
    expect(fixed.maxDt).toBe(0.03);
    expect(variable.continuous.through).toBe(0);
    expect(fixed.continuous.through).toBe(0);
    // Both twins of a rig took exactly the same steps.
    expect(variable.continuous.time).toBe(variable.discrete.time);
  });

  it('a hitch is one long step for the variable loop and ordinary steps for the fixed one', () => {
    const variable = rig('variable', [{ atMs: 3000, durationMs: 250 }]);
    const fixed = rig('fixed', [{ atMs: 3000, durationMs: 250 }]);
    expect(variable.maxDt).toBeGreaterThan(0.25);
    expect(fixed.maxDt).toBe(0.03);
    expect(fixed.discrete.through).toBe(0);
    expect(variable.continuous.through).toBe(0);
  });

  it('repeats exactly', () => {
    expect(hex64(rig('variable').discrete.hash())).toBe(hex64(rig('variable').discrete.hash()));
  });
});
