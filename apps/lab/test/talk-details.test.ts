import { describe, expect, it } from 'vitest';
import { slipSimulatedSeconds } from '../src/chapters/loop/loop-slip.js';
import {
  THROW,
  closedForm,
  slideStepAsWritten,
  taylorStep,
} from '../src/chapters/physics/physics-formulas.js';
import { cppMax, nanFrames, talkLoopTicks } from '../src/chapters/final-fixes/final-fixes-nan.js';
import { runnerHud } from '../src/games-view/games.js';

describe('the talk’s details, as the lab shows them', () => {
  it('the runner’s HUD reads as on the slide, without zero padding', () => {
    expect(runnerHud(0, 35730)).toBe('SCORE 0 / HIGHSCORE 35730');
    expect(runnerHud(42, 7)).toBe('SCORE 42 / HIGHSCORE 7');
  });

  it('the slide’s lastUpdate / lastUpdateTime slip: 1 s of a 60 Hz display simulates 30.5 s', () => {
    // Σ k/60 for k = 1…60 = 61/2 s: each frame's dt is the whole time since the start.
    expect(slipSimulatedSeconds(60, 1)).toBeCloseTo(30.5, 12);
    expect(slipSimulatedSeconds(30, 2)).toBeCloseTo(61, 12); // Σ k/30, k = 1…60
  });

  it('x_{t+1} = x_t + F(t)·t²/2 + C taken literally is no integrator; with Δt and v it is exact', () => {
    expect(closedForm(THROW.seconds)).toBeCloseTo(0.095, 12); // 5·1 − 9.81/2
    // Σ −9.81·(k/60)²/2 for k = 0…59 = −9.81 · 70210 / 7200.
    expect(slideStepAsWritten()).toBeCloseTo((-9.81 * 70210) / 7200, 9);
    expect(slideStepAsWritten()).toBeLessThan(-95);
    expect(taylorStep()).toBeCloseTo(closedForm(THROW.seconds), 9);
  });

  it('after a NaN frame the talk’s loop in JavaScript stops for good; the C++ max skips the frame', () => {
    expect(Math.max(0, Number.NaN)).toBeNaN();
    expect(cppMax(0, Number.NaN)).toBe(0);
    const frames = nanFrames();
    const js = talkLoopTicks(frames, Math.max);
    const cpp = talkLoopTicks(frames, cppMax);
    // Before the NaN (frames 0…9, 150 ms of 30 ms steps) both ran the same updates.
    expect(js.slice(0, 10)).toEqual(cpp.slice(0, 10));
    expect(js[9]).toBe(4);
    // JavaScript: not one update after it.
    expect(js.slice(10).every((n) => n === js[9])).toBe(true);
    // C++: the NaN frame and the one after it count as no time; the other 58/60 s run 32 steps.
    expect(cpp[60]).toBe(32);
  });
});
