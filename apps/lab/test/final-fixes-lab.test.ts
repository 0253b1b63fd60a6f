import { describe, expect, it } from 'vitest';
import {
  BACKWARDS_LOOPS,
  FinalLab,
  SPIRAL_LOOPS,
  defaultFinalSettings,
  spiralOutlook,
} from '../src/chapters/final-fixes/final-fixes-lab.js';
import { backwardsIntro, spiralIntro } from '../src/chapters/final-fixes/final-fixes-text.js';

function byId<T extends { spec: { id: string } }>(runs: T[], id: string): T {
  const r = runs.find((x) => x.spec.id === id);
  if (!r) throw new Error(id);
  return r;
}

describe('FinalLab', () => {
  it('has the three spiral loops and the four clock loops', () => {
    expect(SPIRAL_LOOPS.map((l) => l.id)).toEqual(['noclamp', 'clamp', 'fixed']);
    expect(BACKWARDS_LOOPS.map((l) => l.id)).toEqual(['variable', 'naive', 'final', 'fixed']);
  });

  it('after 15 s: no clamp spirals into a stall; the clamp and FixedLoop stay bounded', () => {
    const lab = new FinalLab();
    lab.advanceTo(15_000);
    const r = (id: string) => lab.spiralReadouts(byId(lab.spiral, id));
    expect(r('noclamp').maxSteps).toBe(128);
    expect(r('noclamp').stalled).toBe(true);
    expect(r('noclamp').owed).toBe(3);
    expect(r('noclamp').fps).toBe(0);
    expect(r('clamp').maxSteps).toBe(33);
    expect(r('clamp').stalled).toBe(false);
    expect(r('fixed').maxSteps).toBe(8);
    expect(r('fixed').stalled).toBe(false);
    expect(r('fixed').fps).toBeGreaterThanOrEqual(3);
    expect(r('noclamp').maxSteps).toBeGreaterThan(r('clamp').maxSteps);
  });

  it('after 5 s: the clock set back at 3 s reversed one loop, froze another, left two alone', () => {
    const lab = new FinalLab();
    lab.advanceTo(5000);
    const r = (id: string) => lab.backwardsReadouts(byId(lab.backwards, id));
    expect(r('variable').reversed).toBe(true);
    expect(r('variable').lagMs).toBeCloseTo(1500, 6);
    expect(r('naive').reversed).toBe(false);
    expect(r('naive').frozenMs).toBeGreaterThan(1500);
    for (const id of ['final', 'fixed']) {
      expect(r(id).reversed).toBe(false);
      expect(r(id).frozenMs).toBeLessThanOrEqual(50);
      expect(r(id).lagMs).toBeLessThan(50);
    }
    expect(r('fixed').backwardFrames).toBe(1);
    expect(r('final').backwardFrames).toBeUndefined();
    expect(lab.clockReading).toBe(3500);
  });

  it('replays added hitches and clock jumps from zero, and restarts with the defaults', () => {
    const lab = new FinalLab({ ...defaultFinalSettings(), costMs: 10 });
    lab.advanceTo(6000);
    lab.addHitch(10_000);
    lab.jumpBack();
    expect(lab.activeHitch()?.durationMs).toBe(10_000);
    lab.advanceTo(20_000);
    // A fast machine after a 10 s breakpoint: no clamp owes 333 steps at once (a 3.3 s frame).
    const noclamp = lab.spiralReadouts(byId(lab.spiral, 'noclamp'));
    expect(noclamp.maxSteps).toBeGreaterThanOrEqual(333);
    expect(noclamp.longestFrameMs).toBeGreaterThan(10_000);
    expect(lab.spiralReadouts(byId(lab.spiral, 'clamp')).maxSteps).toBe(33);
    expect(lab.backwardsReadouts(byId(lab.backwards, 'fixed')).backwardFrames).toBe(2);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.settings.hitches).toEqual(defaultFinalSettings().hitches);
    expect(lab.settings.backJumps).toEqual([3000]);
    expect(lab.settings.costMs).toBe(10);
  });

  it('lets each overload policy bound FixedLoop the same way', () => {
    for (const overload of ['catch-up', 'drop', 'reset'] as const) {
      const lab = new FinalLab({ ...defaultFinalSettings(), overload });
      lab.advanceTo(10_000);
      const r = lab.spiralReadouts(byId(lab.spiral, 'fixed'));
      expect(r.maxSteps).toBe(8);
      expect(r.stalled).toBe(false);
    }
  });

  it('runs on real frame times: the slow machine delays its own frames', () => {
    const lab = new FinalLab(defaultFinalSettings(), true);
    for (let t = 0; t <= 6000; t += 16.7) lab.realFrame(t);
    const noclamp = lab.spiralReadouts(byId(lab.spiral, 'noclamp'));
    expect(noclamp.maxSteps).toBeGreaterThan(33);
    expect(lab.spiralReadouts(byId(lab.spiral, 'fixed')).maxSteps).toBe(8);
    expect(lab.backwardsReadouts(byId(lab.backwards, 'variable')).reversed).toBe(true);
    expect(lab.backwardsReadouts(byId(lab.backwards, 'fixed')).reversed).toBe(false);
  });
});

describe('what the final-fixes chapter says', () => {
  it('sets the clock back by the amount selected, at the time it happens', () => {
    const s = { ...defaultFinalSettings(), backMs: 5000 };
    const text = backwardsIntro(s);
    expect(text).toContain('At t = 3.000 s the clock is set back by 5.000 s');
    expect(text).not.toContain('1.5');
    expect(backwardsIntro({ backJumps: [3000, 7250], backMs: 500 })).toContain(
      'At t = 3.000 s (and again at 7.250 s) the clock is set back by 0.500 s',
    );
  });

  it('states the spiral the no-clamp panel will show, read from its own rig', () => {
    const hitch = defaultFinalSettings().hitches[0]!;
    for (const costMs of [10, 25, 40]) {
      const o = spiralOutlook(costMs, hitch);
      // The panel's rig, run to the end of the hitch and a few frames past it.
      const lab = new FinalLab({ ...defaultFinalSettings(), costMs });
      const noclamp = byId(lab.spiral, 'noclamp');
      const steps: number[] = [];
      const end = hitch.atMs + hitch.durationMs;
      for (let t = end; steps.length < 5 && !noclamp.rig.stalled; t += 250) {
        lab.advanceTo(t);
        const f = noclamp.frames;
        steps.length = 0;
        for (let k = 0; k < f.length && steps.length < 5; k += 4)
          if (f[k]! >= end) steps.push(f[k + 1]!);
      }
      expect(o.steps, `cost ${costMs} ms`).toEqual(steps.slice(0, o.steps.length));
      const text = spiralIntro(o);
      expect(text).toContain(`owes ${o.steps[0]} steps`);
      expect(text).toContain(`one update costs ${costMs} ms`);
      expect(text.includes('each frame owes more than the last')).toBe(costMs > 30);
    }
    expect(spiralOutlook(40, hitch).steps).toEqual([40, 54, 72, 96, 128]);
    expect(spiralOutlook(10, hitch).steps).toEqual([33, 11, 4, 1, 1]);
  });
});
