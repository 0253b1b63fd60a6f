import { describe, expect, it } from 'vitest';
import { FinalFixedLoop, FrameLockedLoop, NaiveFixedLoop, VariableLoop } from 'fixedstep';

describe("the talk's loops, as on the slides", () => {
  it('frame-locked: one update per frame with the design Δt, so time runs with the frame rate', () => {
    const at60 = new FrameLockedLoop(60);
    const at144 = new FrameLockedLoop(60);
    // One second of frames on each display.
    for (let i = 0; i < 60; i++) at60.frame((i * 1000) / 60);
    for (let i = 0; i < 144; i++) at144.frame((i * 1000) / 144);
    expect(at60.updates).toBe(60);
    expect(at60.dt).toBe(1 / 60);
    expect(at144.simTime / at60.simTime).toBeCloseTo(2.4, 10);
  });

  it('variable Δt: one update with the raw frame time, even a negative one', () => {
    const loop = new VariableLoop();
    loop.frame(0);
    expect(loop.frame(16)).toBe(1);
    expect(loop.dt).toBeCloseTo(0.016, 12);
    loop.frame(10); // the clock jumped back
    expect(loop.dt).toBeCloseTo(-0.006, 12);
    expect(loop.simTime).toBeCloseTo(0.01, 12);
  });

  it('naive accumulator: a 2 s hitch runs every owed step in one frame (no clamp, no cap)', () => {
    const loop = new NaiveFixedLoop(30);
    loop.frame(0);
    expect(loop.frame(2000)).toBe(66);
    expect(loop.accumulator).toBeCloseTo(20, 9);
  });

  it('naive accumulator: a clock that jumps back freezes it until the debt is repaid', () => {
    const loop = new NaiveFixedLoop(30);
    loop.frame(1000);
    loop.frame(0); // -1000 ms
    let t = 0;
    let steps = 0;
    while (t < 1000) steps += loop.frame((t += 10));
    expect(steps).toBe(0);
    expect(loop.frame(1100)).toBe(3);
  });

  it('naive accumulator: one NaN reading stops it for good', () => {
    const loop = new NaiveFixedLoop(30);
    loop.frame(0);
    loop.advance(NaN);
    expect(loop.frame(5000)).toBe(0);
    expect(Number.isNaN(loop.accumulator)).toBe(true);
  });

  it('final fixes: negative Δt counts as 0 and the accumulator is clamped to 1 s', () => {
    const loop = new FinalFixedLoop(30, 1000);
    loop.frame(0);
    expect(loop.frame(-500)).toBe(0);
    expect(loop.accumulator).toBe(0);
    expect(loop.frame(4500)).toBe(33); // 5 s owed, clamped to 1 s = 33 steps of 30 ms
    expect(loop.accumulator).toBeCloseTo(10, 9);
  });

  it('uses strict > as on the slides: exactly one step of time runs no step', () => {
    const loop = new NaiveFixedLoop(30);
    loop.frame(0);
    expect(loop.frame(30)).toBe(0);
    expect(loop.frame(30.5)).toBe(1);
  });
});
