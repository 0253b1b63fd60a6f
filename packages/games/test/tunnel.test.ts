import { describe, expect, it } from 'vitest';
import { measureTunnelling } from '../src/scenes/tunnel.js';

describe('measureTunnelling (the `experiment tunnel` harness)', () => {
  it('lets nothing through where geometry says nothing goes through', () => {
    // Settings whose bodies land deep in the wall: before its ends reached past the lanes, the
    // outermost bodies were pushed out round the wall's end and counted as tunnelled (3 of 2000
    // at 30 m/s through 2 m).
    for (const [speed, wall, radius, dt] of [
      [30, 2, 0.05, 0.03],
      [30, 2, 0.02, 0.03],
      [15, 1, 0.02, 0.03],
      [50, 2, 0.05, 1 / 60],
      [5, 0.3, 0.05, 0.03],
    ] as const) {
      const r = measureTunnelling({ speed, wall, radius, dt, ccd: 'off' }, 2000, 1);
      expect({ speed, wall, radius, theory: r.theory, tunnelled: r.tunnelled }).toEqual({
        speed,
        wall,
        radius,
        theory: 0,
        tunnelled: 0,
      });
    }
  });

  it('measures the share geometry predicts where some go through', () => {
    for (const [speed, wall, radius] of [
      [10, 0.3, 0.02],
      [20, 0.1, 0.05],
      [50, 1, 0.05],
      [100, 0.3, 0.05],
    ] as const) {
      const r = measureTunnelling({ speed, wall, radius, dt: 0.03, ccd: 'off' }, 2000, 1);
      expect(r.theory).toBeGreaterThan(0);
      // Three standard deviations of a share over 2000 trials are at most 0.034.
      expect(Math.abs(r.share - r.theory), `${speed} m/s, ${wall} m`).toBeLessThan(0.034);
      expect(
        measureTunnelling({ speed, wall, radius, dt: 0.03, ccd: 'auto' }, 500, 1).tunnelled,
      ).toBe(0);
    }
  });

  it('refuses settings it cannot measure, naming them', () => {
    const ok = { speed: 10, wall: 0.3, radius: 0.05, dt: 0.03, ccd: 'off' } as const;
    expect(() => measureTunnelling({ ...ok, speed: 0 }, 10, 1)).toThrow(/must be positive/);
    expect(() => measureTunnelling(ok, 0, 1)).toThrow(/trials must be an integer/);
  });
});
