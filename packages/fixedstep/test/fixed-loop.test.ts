import { describe, expect, it } from 'vitest';
import { FixedLoop, Timestep, type DropReason, type OverloadPolicy } from 'fixedstep';

/** A 10 ms loop that can take at most 4 steps a frame, overloaded as `overload` says. */
function overloaded(overload: OverloadPolicy): FixedLoop {
  return new FixedLoop({
    step: Timestep.fromMs(10),
    maxAccumulatorMs: 1000,
    maxStepsPerFrame: 4,
    overload,
  });
}

describe('Timestep', () => {
  it('holds 1/60 s exactly as a rational number of nanoseconds', () => {
    const s = Timestep.fromHz(60);
    expect(s.unitsPerStep / s.unitsPerNs).toBeCloseTo(1e9 / 60, 6);
    expect(s.unitsPerStep % 1).toBe(0);
    expect(s.seconds).toBe(1 / 60);
    expect(s.timeAt(60)).toBe(1);
  });
  it('takes the talk step of 30 ms', () => {
    const s = Timestep.fromMs(30);
    expect(s.seconds).toBe(0.03);
    expect(s.unitsPerStep).toBe(30_000_000);
  });
  it.each([0, -1, 1.5, NaN, Infinity, 200_000])('rejects tick rate %s with a clear error', (hz) => {
    expect(() => Timestep.fromHz(hz)).toThrow(/tick rate must be an integer/);
  });
  it.each([0, -5, NaN, 1e-7, 20_000, 0.0000005])('rejects step %s ms', (ms) => {
    expect(() => Timestep.fromMs(ms)).toThrow(/step must be/);
  });
});

describe('FixedLoop', () => {
  it('runs floor(elapsed / step) ticks for 1 s of 60 Hz frames, exactly, with no drift', () => {
    const loop = new FixedLoop({ step: 60 });
    for (let i = 0; i < 3600; i++) loop.advance(1000 / 60);
    expect(loop.tick).toBe(3600);
    expect(loop.simTime).toBe(60);
  });

  it('counts a negative, NaN or infinite frame as no time', () => {
    const loop = new FixedLoop({ step: 100 });
    expect(loop.advance(25)).toBe(2);
    expect(loop.advance(-1000)).toBe(0);
    expect(loop.advance(NaN)).toBe(0);
    expect(loop.advance(Infinity)).toBe(0);
    expect(loop.advance(-Infinity)).toBe(0);
    expect(loop.tick).toBe(2);
    expect(loop.accumulatorMs).toBeCloseTo(5, 9);
    expect(loop.backwardFrames).toBe(2);
    expect(loop.invalidFrames).toBe(2);
  });

  it('treats a clock that jumps back as no time and takes the new reading as the baseline', () => {
    const loop = new FixedLoop({ step: 100 });
    loop.frame(1000);
    expect(loop.frame(1025)).toBe(2);
    expect(loop.frame(500)).toBe(0); // jumped back
    expect(loop.frame(520)).toBe(2); // 20 ms after the new baseline
    expect(loop.backwardFrames).toBe(1);
  });

  it('quantises clock readings so deltas telescope: 10 000 jittered frames lose nothing', () => {
    const loop = new FixedLoop({ step: 60, maxStepsPerFrame: 1000 });
    let t = 12_345.678;
    loop.frame(t);
    for (let i = 0; i < 10_000; i++) {
      t += 16.6 + ((i * 7919) % 13) * 0.1234567;
      loop.frame(t);
    }
    const elapsedNs = Math.round(t * 1e6) - Math.round(12_345.678 * 1e6);
    expect(loop.tick).toBe(Math.floor((elapsedNs * 60) / 1e9));
  });

  it('clamps the accumulator and reports the dropped time', () => {
    const drops: [number, DropReason][] = [];
    const loop = new FixedLoop({
      step: 60,
      maxAccumulatorMs: 250,
      maxStepsPerFrame: 100,
      onDrop: (ms, r) => drops.push([ms, r]),
    });
    const n = loop.advance(2000); // a 2 s hitch
    expect(n).toBe(15); // 250 ms of 16.67 ms steps
    expect(loop.droppedMs('clamp')).toBeCloseTo(1750, 6);
    expect(drops).toHaveLength(1);
    expect(drops[0]![1]).toBe('clamp');
    expect(drops[0]![0]).toBeCloseTo(1750, 6);
  });

  it('defaults: 250 ms clamp, 8 steps per frame, catch-up', () => {
    const loop = new FixedLoop({ step: 60 });
    expect(loop.maxAccumulatorMs).toBe(250);
    expect(loop.maxStepsPerFrame).toBe(8);
    expect(loop.overload).toBe('catch-up');
    expect(loop.advance(2000)).toBe(8);
    expect(loop.advance(0)).toBe(7); // the rest of the 250 ms, one frame later
    expect(loop.advance(0)).toBe(0);
    expect(loop.tick).toBe(15);
  });

  it("overload 'drop' drops whole steps beyond the cap and keeps the fraction", () => {
    const loop = overloaded('drop');
    expect(loop.advance(95)).toBe(4);
    expect(loop.droppedMs('overload')).toBeCloseTo(50, 9);
    expect(loop.accumulatorMs).toBeCloseTo(5, 9);
    expect(loop.advance(5)).toBe(1);
  });

  it("overload 'reset' drops everything beyond the cap, fraction included", () => {
    const loop = overloaded('reset');
    expect(loop.advance(95)).toBe(4);
    expect(loop.droppedMs('overload')).toBeCloseTo(55, 9);
    expect(loop.accumulatorMs).toBe(0);
    expect(loop.alpha).toBe(0);
  });

  it('gives alpha as the fraction of a step owed', () => {
    const loop = new FixedLoop({ step: Timestep.fromMs(10) });
    loop.advance(12.5);
    expect(loop.alpha).toBeCloseTo(0.25, 12);
  });

  it('pauses, single-steps and resumes without simulating the paused time', () => {
    const loop = new FixedLoop({ step: Timestep.fromMs(10) });
    loop.advance(25);
    loop.pause();
    expect(loop.advance(100)).toBe(0);
    loop.singleStep();
    loop.singleStep();
    expect(loop.advance(16)).toBe(2);
    expect(loop.advance(16)).toBe(0);
    expect(loop.pausedMs).toBeCloseTo(132, 9);
    loop.resume();
    expect(loop.advance(5)).toBe(1); // 5 ms left before the pause + 5 ms
    expect(loop.tick).toBe(5);
  });

  it('scales time by running more or fewer steps, never by changing the step', () => {
    const half = new FixedLoop({ step: 60, timeScale: 0.5 });
    const double = new FixedLoop({ step: 60, timeScale: 2, maxStepsPerFrame: 16 });
    for (let i = 0; i < 600; i++) {
      half.advance(1000 / 60);
      double.advance(1000 / 60);
    }
    expect(half.tick).toBe(300);
    expect(double.tick).toBe(1200);
    expect(half.dt).toBe(1 / 60);
    expect(double.dt).toBe(1 / 60);
    expect(() => {
      half.setTimeScale(-1);
    }).toThrow(/time scale/);
    expect(() => {
      half.setTimeScale(NaN);
    }).toThrow(/time scale/);
  });

  it("drops the time a tab spends hidden under the 'pause' policy: no fast-forward on return", () => {
    const loop = new FixedLoop({ step: 60 });
    loop.frame(0);
    loop.frame(1000 / 60);
    const before = loop.tick;
    expect(before).toBe(1);
    loop.setHidden(true);
    loop.setHidden(false);
    const back = 1000 / 60 + 10_000;
    expect(loop.frame(back)).toBe(0); // the first frame back spans the 10 s hidden
    expect(loop.droppedMs('hidden')).toBeCloseTo(10_000, 6);
    expect(loop.frame(back + 20)).toBe(1); // then ordinary frames run ordinary steps
    expect(loop.tick).toBe(before + 1);
  });

  it("lets the clamp handle hidden time under the 'clamp' policy", () => {
    const loop = new FixedLoop({ step: 60, hidden: 'clamp', maxStepsPerFrame: 100 });
    loop.frame(0);
    loop.setHidden(true);
    loop.setHidden(false);
    expect(loop.frame(10_000)).toBe(15);
    expect(loop.droppedMs('clamp')).toBeCloseTo(9750, 6);
  });

  it('hysteresis stops 0/2-step alternation on a jittery display near the tick rate', () => {
    const pattern = (h: number) => {
      const loop = new FixedLoop({ step: 60, hysteresis: h });
      loop.advance(1000 / 60 - 0.5); // a phase where the accumulator sits just under a step
      const counts: number[] = [];
      for (let i = 0; i < 600; i++)
        counts.push(loop.advance(1000 / 60 + (i % 2 === 0 ? 0.9 : -0.9)));
      return counts.slice(10);
    };
    const plain = pattern(0);
    const damped = pattern(0.1);
    expect(plain.filter((n) => n === 0).length).toBeGreaterThan(100);
    expect(damped.every((n) => n === 1)).toBe(true);
  });

  it('rejects bad options with messages that name the option', () => {
    expect(() => new FixedLoop({ step: 60, maxAccumulatorMs: 5 })).toThrow(/maxAccumulatorMs/);
    expect(() => new FixedLoop({ step: 60, maxStepsPerFrame: 0 })).toThrow(/maxStepsPerFrame/);
    // @ts-expect-error: a policy that does not exist
    expect(() => new FixedLoop({ step: 60, overload: 'ignore' })).toThrow(
      /overload must be one of/,
    );
    expect(() => new FixedLoop({ step: 60, hysteresis: 0.7 })).toThrow(/hysteresis/);
  });
});
