import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  ButtonSampler,
  FixedLoop,
  NaiveFixedLoop,
  Random,
  isDown,
  packButtons,
  wasPressed,
} from 'fixedstep';

interface Tap {
  at: number;
  hold: number;
}

/** Drives a 60 Hz FixedLoop with frames at `frameTimes`, feeding taps, and returns each tick's input. */
function run(frameTimes: number[], taps: Tap[], button = 3, hysteresis = 0): number[] {
  const loop = new FixedLoop({
    step: 60,
    maxStepsPerFrame: 1000,
    maxAccumulatorMs: 3_600_000,
    hysteresis,
  });
  const sampler = new ButtonSampler();
  const events = taps
    .flatMap((t) => [
      { time: t.at, down: true },
      { time: t.at + t.hold, down: false },
    ])
    .sort((a, b) => a.time - b.time);
  const inputs: number[] = [];
  let e = 0;
  for (const f of frameTimes) {
    while (e < events.length && events[e]!.time <= f) {
      const ev = events[e++]!;
      sampler.push(ev.time, button, ev.down);
    }
    const n = loop.frame(f);
    for (let j = 0; j < n; j++) inputs.push(sampler.sample(loop, j));
  }
  return inputs;
}

function frames(hz: number, jitter: number, seed: number, untilMs: number): number[] {
  const rng = new Random(seed);
  const out = [0];
  let t = 0;
  while (t < untilMs) {
    t += (1000 / hz) * (1 + rng.range(-jitter, jitter));
    out.push(t);
  }
  return out;
}

describe('ButtonSampler', () => {
  it('packs down and pressed bits', () => {
    const input = packButtons(0b101, 0b100);
    expect(isDown(input, 0)).toBe(true);
    expect(isDown(input, 1)).toBe(false);
    expect(wasPressed(input, 2)).toBe(true);
    expect(wasPressed(input, 0)).toBe(false);
    expect(packButtons(0xffff, 0xffff)).toBe(0xffffffff);
  });

  it('gives a tap between two ticks to exactly one tick, as down and pressed', () => {
    // 60 Hz ticks end at 16.67, 33.33 …; a 5 ms tap at 20 ms lies inside tick 1.
    const inputs = run(frames(30, 0, 1, 200), [{ at: 20, hold: 5 }]);
    const pressed = inputs.map((x) => wasPressed(x, 3));
    expect(pressed.filter(Boolean)).toHaveLength(1);
    expect(pressed.indexOf(true)).toBe(1);
    expect(isDown(inputs[1]!, 3)).toBe(true);
    expect(isDown(inputs[2]!, 3)).toBe(false);
  });

  it('never loses or doubles a press, and gives it to the same tick, at any display rate', () => {
    fc.assert(
      fc.property(
        fc.constantFrom(20, 30, 59.94, 60, 75, 144, 240, 360),
        fc.double({ min: 0, max: 0.5, noNaN: true }),
        fc.integer({ min: 1, max: 1e6 }),
        fc.array(
          fc.record({
            gap: fc.double({ min: 0.1, max: 80, noNaN: true }),
            hold: fc.double({ min: 0.01, max: 60, noNaN: true }),
          }),
          {
            minLength: 1,
            maxLength: 25,
          },
        ),
        (hz, jitter, seed, spec) => {
          const taps: Tap[] = [];
          let t = 5;
          for (const s of spec) {
            t += s.gap;
            taps.push({ at: t, hold: s.hold });
            t += s.hold;
          }
          const inputs = run(frames(hz, jitter, seed, t + 100), taps);
          const pressedTicks = inputs.flatMap((x, i) => (wasPressed(x, 3) ? [i] : []));
          // Each press goes to the tick whose span holds it, floor(at / step); two presses in one
          // tick show as one pressed tick. Nothing else may show a press.
          const expected = [...new Set(taps.map((tp) => Math.floor((tp.at * 60) / 1000)))];
          return JSON.stringify(pressedTicks) === JSON.stringify(expected);
        },
      ),
      { numRuns: 400 },
    );
  });

  it('with hysteresis, gives every press to tick floor(t / step + h) on every display', () => {
    // Regression: early steps once took presses in their last h of a step on some displays only.
    fc.assert(
      fc.property(
        fc.constantFrom(0.1, 0.25, 0.5),
        fc.constantFrom(30, 59.94, 60, 144, 240),
        fc.integer({ min: 1, max: 1e6 }),
        fc.array(fc.double({ min: 1, max: 3000, noNaN: true }), { minLength: 1, maxLength: 12 }),
        (h, hz, seed, times) => {
          const taps = [...new Set(times.map((t) => Math.round(t * 1000) / 1000))]
            .sort((a, b) => a - b)
            .map((at) => ({ at, hold: 0.001 }));
          const inputs = run(frames(hz, 0.3, seed, 3200), taps, 3, h);
          const pressedTicks = inputs.flatMap((x, i) => (wasPressed(x, 3) ? [i] : []));
          const hu = Math.round(h * 50_000_000); // units of 1/3 ns: a 60 Hz step is 5e7 units
          const expected = [
            ...new Set(
              taps.map((tp) => Math.floor((Math.round(tp.at * 1e6) * 3 + hu) / 50_000_000)),
            ),
          ];
          return JSON.stringify(pressedTicks) === JSON.stringify(expected);
        },
      ),
      { numRuns: 300 },
    );
  });

  it('keeps a held button down on every tick while it is held', () => {
    const inputs = run(frames(144, 0.3, 7, 600), [{ at: 100, hold: 250 }]);
    const downTicks = inputs.flatMap((x, i) => (isDown(x, 3) ? [i] : []));
    // Held from 100 ms to 350 ms: ticks 6 (100 ms is inside [100, 116.7)) to 21 (350 ms is inside [333.3, 350.0)).
    expect(downTicks[0]).toBe(6);
    expect(downTicks.at(-1)).toBe(21);
    expect(downTicks).toHaveLength(16);
  });

  it('an event exactly on a tick boundary goes to the later tick at every display rate (integer time)', () => {
    // 1000 ms is exactly the end of tick 59 at 60 Hz.
    for (const hz of [30, 60, 144, 240]) {
      const inputs = run(frames(hz, 0.3, 3, 1200), [{ at: 1000, hold: 1 }]);
      expect(inputs.findIndex((x) => wasPressed(x, 3))).toBe(60);
    }
  });

  it('while paused, a single step takes every event so far', () => {
    const loop = new FixedLoop({ step: 60 });
    const sampler = new ButtonSampler();
    loop.frame(0);
    loop.pause();
    sampler.push(500, 0, true);
    loop.singleStep();
    expect(loop.frame(600)).toBe(1);
    expect(wasPressed(sampler.sample(loop, 0), 0)).toBe(true);
  });

  it('works with the talk loops too (float accumulator)', () => {
    const loop = new NaiveFixedLoop(30);
    const sampler = new ButtonSampler();
    loop.frame(0);
    sampler.push(40, 1, true);
    sampler.push(41, 1, false);
    const n = loop.frame(100);
    expect(n).toBe(3);
    const got = [0, 1, 2].map((j) => wasPressed(sampler.sample(loop, j), 1));
    expect(got).toEqual([false, true, false]);
  });

  it('grows its queue without losing order, and rejects bad buttons', () => {
    const s = new ButtonSampler();
    for (let i = 0; i < 500; i++) s.push(i, i % 16, i % 2 === 0);
    expect(s.pending).toBe(500);
    expect(() => {
      s.push(1, 16, true);
    }).toThrow(/button must be an integer from 0 to 15/);
    expect(() => {
      s.push(1, -1, true);
    }).toThrow(/button/);
  });
});
