import { describe, expect, it } from 'vitest';
import { hex64 } from 'fixedstep';
import {
  ClockRanges,
  CollisionsLab,
  EXPERIMENT_HITCH_AT_MS,
  EXPERIMENTS,
  PANELS,
  defaultSettings,
  type CollisionsSettings,
  type RangeReadouts,
} from '../src/chapters/collisions/collisions-lab.js';

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

  it('keeps the CCD twins’ own resolved count in a setting’s result', () => {
    const lab = new CollisionsLab({ ...defaultSettings(), speed: 150, wall: 0.5 });
    lab.advanceTo(6000);
    const r = lab.result();
    const live = readouts(lab);
    expect(r.variable.ccdResolved).toBe(live.variable!.ccdResolved);
    expect(r.fixed.ccdResolved).toBe(live.fixed!.ccdResolved);
    expect(r.fixed.ccdResolved).toBeGreaterThan(0);
  });
});

/**
 * Runs an experiment as its button does and checks what its text says; returns the claims that
 * do not hold (empty: the text is true).
 */
function experimentFails(lab: CollisionsLab, index: number): string[] {
  const exp = EXPERIMENTS[index]!;
  lab.startOver(exp.settings);
  const claims: [string, boolean][] = [
    ['starts from zero', lab.timeMs === 0],
    ['with exactly its settings', JSON.stringify(lab.settings) === JSON.stringify(exp.settings)],
  ];
  const claim = (what: string, ok: boolean) => claims.push([`${exp.action}: ${what}`, ok]);
  switch (exp.action) {
    case 'Wall = v·dt': {
      lab.advanceTo(20_000);
      const r = readouts(lab);
      claim('the wall is one step', Math.abs(lab.rule.stepDistance - 1.8) < 1e-9);
      claim('the text says about 44 %', /about 44\s% of the bodies, almost half/.test(exp.text));
      claim('theory 44.4 %', Math.abs(lab.rule.theoryShare - 0.4444) < 0.001);
      claim('about 44 % through, fixed', Math.abs(r.fixed!.share - 0.444) < 0.06);
      claim('none through with CCD', r.fixed!.ccdThrough + r.variable!.ccdThrough === 0);
      claim('draws the discrete twins', !exp.ccd);
      break;
    }
    case 'Drop a hitch': {
      lab.advanceTo(EXPERIMENT_HITCH_AT_MS - 1);
      const before = readouts(lab);
      claim('resolved before the hitch', before.variable!.resolved > 0);
      claim('none through before the hitch', before.variable!.through === 0);
      claim('17 ms steps before the hitch', before.variable!.maxDtMs < 17);
      lab.advanceTo(10_000);
      const after = readouts(lab);
      claim('a step of at least 250 ms', after.variable!.maxDtMs >= 250);
      claim('bodies through, variable', after.variable!.through > 0);
      claim('fixed steps stay 30 ms', after.fixed!.maxDtMs === 30);
      claim('none through, fixed', after.fixed!.through === 0);
      break;
    }
    case '144 Hz, no jitter': {
      lab.advanceTo(20_000);
      const r = readouts(lab);
      claim('resolved', r.variable!.resolved > 150);
      claim('none through, variable', r.variable!.through === 0);
      claim('none through, fixed', r.fixed!.through === 0);
      claim('7 ms steps', r.variable!.maxDtMs < 7.5);
      break;
    }
    case 'Fire bullets': {
      lab.advanceTo(10_000);
      const r = readouts(lab);
      claim('4.5 m per step', Math.abs(lab.rule.stepDistance - 4.5) < 1e-9);
      claim('most through, variable', r.variable!.share > 0.5);
      claim('most through, fixed', r.fixed!.share > 0.5);
      claim('CCD resolved', r.variable!.ccdResolved > 50 && r.fixed!.ccdResolved > 50);
      claim('none through with CCD', r.variable!.ccdThrough + r.fixed!.ccdThrough === 0);
      claim('draws the CCD twins', exp.ccd);
      break;
    }
    default:
      claim('has a check', false);
  }
  return claims.filter(([, ok]) => !ok).map(([what]) => what);
}

describe('Things to try', () => {
  it('each experiment’s claim holds, run in page order on one lab', () => {
    const lab = new CollisionsLab();
    lab.advanceTo(3000);
    const fails = EXPERIMENTS.flatMap((_, i) => experimentFails(lab, i));
    expect(fails).toEqual([]);
  });

  it('and in any other order, after any other setting', () => {
    const lab = new CollisionsLab();
    const fails: string[] = [];
    for (const i of [3, 1, 2, 0, 1, 3, 2]) {
      lab.update({ speed: 33, wall: 6.1, jitter: 0.5, hz: 30 });
      lab.advanceTo(lab.timeMs + 1500);
      lab.addHitch();
      fails.push(...experimentFails(lab, i));
    }
    expect(fails).toEqual([]);
  });
});
