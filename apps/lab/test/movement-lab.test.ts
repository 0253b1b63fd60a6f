import { describe, expect, it } from 'vitest';
import {
  LOOPS,
  MovementLab,
  RATES,
  STEP_MS,
  SWEEP_RATES,
  defaultMovementSettings,
  spread,
  sweep,
} from '../src/chapters/movement/movement-lab.js';

function at(ms: number, jitter = 0.2): MovementLab {
  const lab = new MovementLab({ ...defaultMovementSettings(), jitter });
  lab.advanceTo(ms);
  return lab;
}

describe('MovementLab', () => {
  it('shows the chapter’s contrast after 5 s: variable jumps spread, fixed ones coincide', () => {
    const lab = at(5000);
    const v = lab.readouts('variable');
    const f = lab.readouts('fixed');
    // Two rounds of 2.5 s: both loops show jump 2 on every display.
    expect(v.jumpIndex).toBe(1);
    expect(f.jumpIndex).toBe(1);
    expect(v.rows.map((r) => r.source)).toEqual([...RATES]);
    expect(v.apexSpread).toBeGreaterThan(0.01);
    expect(v.landingSpread).toBeGreaterThan(0.05);
    expect(f.apexSpread).toBe(0);
    expect(f.landingSpread).toBe(0);
    expect(f.rows[0]!.jump!.apex).toBeCloseTo(1.5456, 10);
    expect(f.rows[0]!.jump!.distance).toBeCloseTo(3.24, 10);
  });

  it('lands on the same numbers whether played frame by frame or skipped', () => {
    const skipped = at(7300);
    const played = new MovementLab();
    for (let t = 0; t <= 7300; t += 16.7) played.advanceTo(t);
    played.advanceTo(7300);
    for (const loop of LOOPS) {
      expect(played.readouts(loop.id)).toEqual(skipped.readouts(loop.id));
      const a = played.tracks(loop.id).map((t) => t.scene.hash());
      const b = skipped.tracks(loop.id).map((t) => t.scene.hash());
      expect(a).toEqual(b);
    }
  });

  it('draws every fixed-step runner at the same place, interpolated, at the common moment', () => {
    const lab = at(3333.3);
    const fixed = LOOPS.find((l) => l.fixed)!;
    const t = lab.drawTimeMs(fixed);
    expect(t).toBeLessThanOrEqual(3333.3 - STEP_MS);
    const pos = lab.tracks('fixed').map((tr) => tr.runnerAt(t, true));
    for (const p of pos) expect(p).toEqual(pos[0]);
    // Mid-jump at 3.3 s (the second round's jump), between two ticks.
    expect(pos[0]!.y).toBeGreaterThan(0.5);
    const variable = lab
      .tracks('variable')
      .map((tr) => tr.runnerAt(lab.drawTimeMs(LOOPS[0]!), true));
    expect(new Set(variable.map((p) => p.x)).size).toBe(4);
  });

  it('replays a jump pressed mid-run on every display, and restarts clean', () => {
    const lab = at(2000);
    const before = lab.tracks('fixed')[0]!.scene.jumps;
    lab.addJump(); // at 2.0 s the runner stands still: it jumps
    lab.advanceTo(3000);
    expect(lab.settings.jumps).toEqual([2000]);
    for (const t of lab.tracks('fixed')) expect(t.scene.jumps).toBe(before + 2);
    expect(lab.readouts('fixed').apexSpread).toBe(0);
    lab.update({ jitter: 0 });
    expect(lab.timeMs).toBe(3000);
    expect(lab.settings.jumps).toEqual([2000]);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.settings).toEqual({ jitter: 0, jumps: [] });
    expect(lab.readouts('fixed').jumpIndex).toBe(-1);
    expect(Number.isNaN(lab.readouts('fixed').apexSpread)).toBe(true);
  });

  it('runs a fifth run per loop on real frame times, and it jumps the fixed step’s jump', () => {
    const lab = new MovementLab(defaultMovementSettings(), true);
    // A rough 60 Hz page: frame times wobble by a few ms.
    let t = 0;
    for (let i = 0; i < 300; i++) {
      t += 16.7 + ((i * 7) % 5) - 2;
      lab.realFrame(t);
    }
    const f = lab.readouts('fixed');
    expect(f.rows.map((r) => r.source)).toEqual([...RATES, 'real']);
    expect(f.jumpIndex).toBe(1);
    expect(f.apexSpread).toBe(0);
    expect(f.landingSpread).toBe(0);
    expect(lab.readouts('variable').apexSpread).toBeGreaterThan(0);
  });

  it('sweeps the first jump over many display rates: one number under a fixed step', () => {
    const s = sweep(0.2);
    expect(s.hz).toEqual([...SWEEP_RATES]);
    expect(spread(s.apex.fixed)).toBe(0);
    expect(spread(s.landing.fixed)).toBe(0);
    expect(spread(s.apex.variable)).toBeGreaterThan(0.05);
    expect(spread(s.landing.variable)).toBeGreaterThan(0.1);
    expect(spread([])).toBeNaN();
    expect(spread([1, NaN])).toBeNaN();
  });
});
