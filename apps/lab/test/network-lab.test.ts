import { describe, expect, it } from 'vitest';
import { NetworkLab } from '../src/chapters/network-lab.js';

describe('NetworkLab', () => {
  it('20 s at 100 ± 30 ms and 5 % loss: both machines agree, lockstep and rollback', () => {
    const lab = new NetworkLab({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
    lab.advanceTo(20_000);
    const r = lab.readouts();
    for (const m of [r.lockstep, r.rollback]) {
      expect(m.equal).toBe(true);
      expect(m.hashes[0]).toMatch(/^[0-9a-f]{16}$/);
      expect(m.checkpoint).toBeGreaterThanOrEqual(1000);
      expect(m.desyncs).toBe(0);
      expect(m.lost).toBeGreaterThan(0);
    }
    expect(r.lockstep.inputDelay).toBeGreaterThanOrEqual(13);
    expect(r.rollback.rollbacks).toBeGreaterThan(0);
    expect(r.rollback.maxDepth).toBeGreaterThan(0);
  });

  it('repeats exactly: the same settings give the same numbers', () => {
    const run = () => {
      const lab = new NetworkLab();
      lab.advanceTo(6000);
      lab.setLink({ latencyMs: 150 });
      lab.advanceTo(9000);
      return lab.readouts();
    };
    expect(run()).toEqual(run());
  });

  it('restarts from zero', () => {
    const lab = new NetworkLab();
    lab.advanceTo(3000);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.readouts().lockstep.checkpoint).toBe(-1);
  });
});
