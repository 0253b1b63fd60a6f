import { describe, expect, it } from 'vitest';
import { NetworkLab } from '../src/chapters/network/network-lab.js';
import { onlineOptions, roomLink } from '../src/chapters/network/network-online.js';

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

describe('NetworkLab on the real clock', () => {
  it('lets the page’s frames drive both machines, and they still agree', () => {
    const lab = new NetworkLab({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
    lab.advanceTo(2000);
    const before = lab.readouts();
    lab.setRealClock(true);
    expect(lab.realClock).toBe(true);
    // Simulated display frames no longer step the machines: 1 s of virtual time, no new ticks.
    lab.advanceTo(3000);
    expect(lab.readouts().lockstep.ticks).toEqual(before.lockstep.ticks);
    // A 144 Hz display with a hitch, from 3 s on.
    let t = 0;
    lab.realFrame(t); // the driver's first frame, at 0, pins the time line to now
    for (let i = 0; i < 144 * 8; i++) {
      t += i === 500 ? 400 : 1000 / 144;
      lab.realFrame(t);
    }
    expect(lab.timeMs).toBeCloseTo(3000 + t, 6);
    const r = lab.readouts();
    for (const m of [r.lockstep, r.rollback]) {
      expect(m.equal).toBe(true);
      expect(m.desyncs).toBe(0);
      expect(m.checkpoint).toBeGreaterThanOrEqual(600);
      expect(m.ticks[0]).toBeGreaterThan(before.lockstep.ticks[0] + 400);
    }
  });

  it('ignores real frames on the simulated displays, and restarts on either', () => {
    const lab = new NetworkLab();
    lab.realFrame(5000);
    expect(lab.timeMs).toBe(0);
    lab.setRealClock(true);
    lab.realFrame(1000);
    lab.realFrame(1500);
    expect(lab.timeMs).toBe(500);
    lab.restart();
    expect(lab.realClock).toBe(true);
    expect(lab.timeMs).toBe(0);
    lab.realFrame(100);
    lab.realFrame(350);
    expect(lab.timeMs).toBe(250);
  });
});

describe('the online panel’s address', () => {
  it('reads the room, the match length and join from the hash', () => {
    expect(onlineOptions('#/network')).toEqual({ room: undefined, ticks: 3600, join: false });
    expect(onlineOptions('#/network?room=abc&ticks=600&join=1')).toEqual({
      room: 'abc',
      ticks: 600,
      join: true,
    });
    // A bad room name is no room, and never joined; a match shorter than a checkpoint is refused.
    expect(onlineOptions('#/network?room=a%20b&join=1')).toEqual({
      room: undefined,
      ticks: 3600,
      join: false,
    });
    expect(onlineOptions('#/network?room=x&ticks=5').ticks).toBe(3600);
  });

  it('links a room for a second tab that joins it, and reads back', () => {
    expect(roomLink('room-1', 3600)).toBe('#/network?room=room-1&join=1');
    const link = roomLink('r.2_x', 600);
    expect(link).toBe('#/network?room=r.2_x&ticks=600&join=1');
    expect(onlineOptions(link)).toEqual({ room: 'r.2_x', ticks: 600, join: true });
  });
});
