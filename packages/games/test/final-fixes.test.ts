import { describe, expect, it } from 'vitest';
import { FixedLoop } from 'fixedstep';
import {
  STALL_WORK_MS,
  backwardsRig,
  jumpingClock,
  spiralRig,
  type BackwardsLoop,
  type SpiralLoop,
} from '@fixedstep/games';

const HITCH = [{ kind: 'hitch' as const, atMs: 1000, durationMs: 1000 }];

function spiral(loop: SpiralLoop, costMs: number, ms = 20_000) {
  const rig = spiralRig({ loop, updateCostMs: costMs, events: HITCH });
  const steps: number[] = [];
  rig.advanceTo(ms, () => steps.push(rig.lastSteps));
  return { rig, steps };
}

describe('a 1 s hitch on a machine where an update costs 40 ms (more than the 30 ms step)', () => {
  it('no clamp: the steps per frame climb until the page would stall', () => {
    const { rig, steps } = spiral('noclamp', 40);
    // After the hitch: 40, 54, 72, 96, 128, 170 — each frame owes a third more than the last.
    const after = steps.filter((s) => s >= 33);
    for (let i = 1; i < after.length; i++) expect(after[i]!).toBeGreaterThan(after[i - 1]!);
    expect(after.slice(0, 6)).toEqual([40, 54, 72, 96, 128, 170]);
    expect(rig.maxSteps * 40).toBeGreaterThan(STALL_WORK_MS);
    expect(rig.stalled).toBe(true);
    expect(rig.owed).toBe(3 + 45); // 128 − 125 and 170 − 125
    expect(rig.longestFrameMs).toBeGreaterThan(5000);
  });

  it('clamp at 1 s: never more than 33 steps a frame, never a stall — but ~1 frame a second', () => {
    const { rig } = spiral('clamp', 40);
    expect(rig.maxSteps).toBe(33);
    expect(rig.stalled).toBe(false);
    expect(rig.longestFrameMs).toBeCloseTo(1320, 6);
  });

  it('FixedLoop: at most 8 steps a frame, ~3 frames a second, the rest dropped and counted', () => {
    const { rig } = spiral('fixed', 40);
    expect(rig.maxSteps).toBe(8);
    expect(rig.stalled).toBe(false);
    expect(rig.longestFrameMs).toBeLessThan(1300);
    const loop = rig.loop;
    expect(loop).toBeInstanceOf(FixedLoop);
    expect(loop instanceof FixedLoop && loop.droppedMs()).toBeGreaterThan(3000);
  });

  it('on a fast machine (10 ms) nobody stalls and the no-clamp loop recovers', () => {
    const { rig, steps } = spiral('noclamp', 10, 8000);
    expect(rig.stalled).toBe(false);
    expect(rig.maxSteps).toBe(33);
    expect(Math.max(...steps.slice(-60))).toBeLessThanOrEqual(1);
  });
});

describe('a wall clock set back by 1.5 s at t = 3 s, on a 60 Hz display', () => {
  function run(loop: BackwardsLoop) {
    const rig = backwardsRig({ loop, jumpsAtMs: [3000], backMs: 1500 });
    const sims: [number, number][] = [];
    rig.advanceTo(8000, () => sims.push([rig.realMs, rig.loop.simTime]));
    let reversed = false;
    let frozen = 0;
    let progressAt = 0;
    for (let i = 1; i < sims.length; i++) {
      const [t, sim] = sims[i]!;
      const prev = sims[i - 1]![1];
      if (sim < prev) reversed = true;
      if (sim > prev) {
        frozen = Math.max(frozen, t - progressAt);
        progressAt = t;
      }
    }
    return { rig, reversed, frozen, lag: rig.realMs - rig.loop.simTime * 1000 };
  }

  it('variable Δt: one negative step — simulated time runs backwards by 1.5 s', () => {
    const r = run('variable');
    expect(r.reversed).toBe(true);
    expect(r.lag).toBeCloseTo(1500, 6);
  });

  it('the slides’ accumulator: no step for 1.5 s while the debt is paid, then 1.5 s behind', () => {
    const r = run('naive');
    expect(r.reversed).toBe(false);
    expect(r.frozen).toBeGreaterThan(1500);
    expect(r.frozen).toBeLessThan(1600);
    expect(r.lag).toBeGreaterThan(1490);
  });

  it('max(0, Δt) and FixedLoop: nothing happens', () => {
    for (const loop of ['final', 'fixed'] as const) {
      const r = run(loop);
      expect(r.reversed).toBe(false);
      expect(r.frozen).toBeLessThanOrEqual(50);
      expect(r.lag).toBeLessThan(50);
    }
    const fixed = run('fixed').rig.loop;
    expect(fixed instanceof FixedLoop && fixed.backwardFrames).toBe(1);
  });

  it('jumpingClock sets the clock back at each jump', () => {
    const c = jumpingClock([3000, 1000], 500);
    expect([c(999), c(1000), c(2999), c(3000)]).toEqual([999, 500, 2499, 2000]);
  });
});
