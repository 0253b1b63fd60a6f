import { describe, expect, it } from 'vitest';
import { LagHistory } from 'fixedstep';

describe('LagHistory', () => {
  it('blends between recorded ticks, and bounds how far back a shot is judged', () => {
    const h = new LagHistory({ entities: 2, fields: 2, maxRewindTicks: 10 });
    for (let t = 0; t <= 40; t++) h.record(t, [t, -t, 100 + 2 * t, 7]);
    expect(h.newest).toBe(40);
    expect(Array.from(h.sample(35.25, 0))).toEqual([35.25, -35.25]);
    expect(Array.from(h.sample(33, 1))).toEqual([166, 7]);
    // No further back than 10 ticks before the newest, no later than the newest.
    expect(h.judgedAt(5)).toBe(30);
    expect(h.judgedAt(Number.NaN)).toBe(30);
    expect(h.judgedAt(41.5)).toBe(40);
    expect(Array.from(h.sample(0, 0))).toEqual([30, -30]);
  });

  it('bridges a gap between recorded ticks, and starts over when a room rewinds', () => {
    const h = new LagHistory({ entities: 1, fields: 1, maxRewindTicks: 8 });
    h.record(10, [10]);
    h.record(14, [30]);
    expect(h.sample(12, 0)[0]).toBe(20);
    h.record(3, [5]);
    expect(h.newest).toBe(3);
    expect(h.sample(2, 0)[0]).toBe(5);
  });

  it('refuses what it cannot hold', () => {
    expect(() => new LagHistory({ entities: 0, fields: 1, maxRewindTicks: 4 })).toThrow(
      /entities must be an integer from 1/,
    );
    const h = new LagHistory({ entities: 2, fields: 1, maxRewindTicks: 4 });
    expect(() => h.sample(0, 0)).toThrow(/nothing recorded yet/);
    expect(() => {
      h.record(-1, [0, 0]);
    }).toThrow(/tick must be an integer/);
    expect(() => {
      h.record(0, [0]);
    }).toThrow(/1 values, 2 needed/);
    h.record(0, [1, 2]);
    expect(() => h.sample(0, 2)).toThrow(/entity 2 of 2/);
  });
});
