import { describe, expect, it } from 'vitest';
import { hex64 } from 'fixedstep';
import {
  ClockRanges,
  CollisionsLab,
  PANELS,
  defaultSettings,
  type CollisionsSettings,
  type RangeReadouts,
} from '../src/chapters/collisions-lab.js';

function readouts(lab: CollisionsLab): Record<string, RangeReadouts> {
  return Object.fromEntries(lab.runs.map((r) => [r.spec.id, r.readouts()]));
}

function at(settings: Partial<CollisionsSettings>, ms: number): Record<string, RangeReadouts> {
  const lab = new CollisionsLab({ ...defaultSettings(), ...settings });
  lab.advanceTo(ms);
  return readouts(lab);
}

describe('CollisionsLab', () => {
  it('has a variable-Δt panel and a fixed-step panel', () => {
    expect(PANELS.map((p) => p.id)).toEqual(['variable', 'fixed']);
  });

  it('shows the talk’s contrast at the default setting: tunnelled > 0 for variable Δt, 0 fixed, 0 with CCD', () => {
    const r = at({}, 5000);
    expect(r.variable!.fired).toBe(r.fixed!.fired);
    expect(r.variable!.fired).toBeGreaterThanOrEqual(49);
    expect(r.variable!.through).toBeGreaterThan(0);
    expect(r.fixed!.through).toBe(0);
    expect(r.variable!.ccdThrough).toBe(0);
    expect(r.fixed!.ccdThrough).toBe(0);
    expect(r.variable!.maxDtMs).toBeGreaterThan(40);
    expect(r.fixed!.maxDtMs).toBe(30);
  });

  it('at exactly the talk’s rule (w = v·dt) the fixed step still lets about 44 % through', () => {
    const lab = new CollisionsLab({ ...defaultSettings(), speed: 60, wall: 1.8 });
    lab.advanceTo(20_000);
    const fixed = readouts(lab).fixed!;
    expect(lab.rule.ruleHolds).toBe(true);
    expect(lab.rule.theoryShare).toBeCloseTo(0.4444, 3);
    expect(Math.abs(fixed.share - lab.rule.theoryShare)).toBeLessThan(0.06);
    expect(fixed.ccdThrough).toBe(0);
  });

  it('replays to the same numbers: a live run and a rebuilt one agree exactly', () => {
    const live = new CollisionsLab();
    for (let t = 0; t < 6000; t += 16.7) live.advanceTo(t);
    live.advanceTo(6000);
    const rebuilt = new CollisionsLab();
    rebuilt.advanceTo(6000);
    for (let i = 0; i < PANELS.length; i++) {
      const a = live.runs[i]!.rig;
      const b = rebuilt.runs[i]!.rig;
      expect(hex64(a.discrete.hash())).toBe(hex64(b.discrete.hash()));
      expect(hex64(a.continuous.hash())).toBe(hex64(b.continuous.hash()));
    }
    // A settings change replays from zero: back and forth lands on the same state.
    live.update({ speed: 80 });
    live.update({ speed: 60 });
    expect(hex64(live.runs[0]!.rig.discrete.hash())).toBe(
      hex64(rebuilt.runs[0]!.rig.discrete.hash()),
    );
  });

  it('a hitch makes the variable loop take one long step; the fixed loop does not notice', () => {
    const lab = new CollisionsLab();
    lab.advanceTo(3000);
    lab.addHitch();
    expect(lab.activeEvent()?.kind).toBe('hitch');
    lab.advanceTo(6000);
    const r = readouts(lab);
    expect(r.variable!.maxDtMs).toBeGreaterThan(250);
    expect(r.fixed!.maxDtMs).toBe(30);
    expect(r.fixed!.through).toBe(0);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.settings.events).toEqual([]);
  });

  it('remembers the result of each setting it leaves', () => {
    const lab = new CollisionsLab();
    lab.advanceTo(4000);
    const before = lab.result();
    lab.update({ wall: 1.8 });
    lab.update({ speed: 100 });
    expect(lab.history.map((h) => [h.speed, h.wall])).toEqual([
      [60, 3.5],
      [60, 1.8],
    ]);
    expect(lab.history[0]).toEqual(before);
    expect(lab.history[1]!.fixed.through).toBeGreaterThan(0);
    // Display changes replay the same setting: no new row.
    lab.update({ hz: 60 });
    expect(lab.history).toHaveLength(2);
  });

  it('runs on a real clock too', () => {
    const clock = new ClockRanges({ speed: 60, wall: 3.5 });
    for (let t = 0; t <= 2000; t += 16.7) clock.frameAt(t);
    const r = Object.fromEntries(clock.runs.map((p) => [p.spec.id, p.readouts()]));
    expect(r.fixed!.fired).toBeGreaterThanOrEqual(19);
    expect(r.variable!.lastDtMs).toBeCloseTo(16.7, 6);
    expect(clock.result().speed).toBe(60);
  });
});
