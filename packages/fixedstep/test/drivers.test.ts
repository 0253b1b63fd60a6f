import { afterEach, describe, expect, it, vi } from 'vitest';
import {
  FixedLoop,
  FrameDriver,
  ManualClock,
  ManualScheduler,
  FrameStepper,
  timerScheduler,
  trackVisibility,
} from 'fixedstep';

afterEach(() => {
  vi.useRealTimers();
});

describe('drivers', () => {
  it('a manual scheduler and clock drive a runner frame by frame', () => {
    const clock = new ManualClock(1000);
    const scheduler = new ManualScheduler();
    const updates: number[] = [];
    const alphas: number[] = [];
    const runner = new FrameStepper({
      loop: new FixedLoop({ step: 50 }),
      update: (dt) => updates.push(dt),
      render: (a) => alphas.push(a),
    });
    const driver = new FrameDriver(scheduler, (now) => runner.frame(now));
    driver.start();
    expect(driver.running).toBe(true);
    for (let i = 0; i < 10; i++) scheduler.fire(clock.advance(25));
    // The first frame (1025 ms) sets the baseline; 225 ms later, 11 steps of 20 ms have run.
    expect(updates).toHaveLength(11);
    expect(updates.every((d) => d === 1 / 50)).toBe(true);
    expect(alphas.at(-1)).toBeCloseTo(0.25, 9);
    driver.stop();
    expect(scheduler.fire(clock.advance(25))).toBe(false);
  });

  it('two loops run at once without sharing anything', () => {
    const a = new FixedLoop({ step: 60 });
    const b = new FixedLoop({ step: 30 });
    for (let i = 0; i < 60; i++) {
      a.advance(1000 / 60);
      b.advance(1000 / 60);
    }
    a.pause();
    expect(a.tick).toBe(60);
    expect(b.tick).toBe(30);
    expect(b.isPaused).toBe(false);
  });

  it('the timer scheduler fires at its interval against the clock, without bursts after a stall', () => {
    vi.useFakeTimers();
    const clock = new ManualClock(0);
    const s = timerScheduler(10, clock);
    const seen: number[] = [];
    const driver = new FrameDriver(s, (now) => seen.push(now));
    driver.start();
    for (let i = 0; i < 5; i++) {
      clock.advance(10);
      vi.advanceTimersByTime(10);
    }
    expect(seen).toEqual([10, 20, 30, 40, 50]);
    clock.advance(1000); // the process stalled for a second
    vi.advanceTimersByTime(10);
    clock.advance(10);
    vi.advanceTimersByTime(10);
    expect(seen.length).toBeLessThanOrEqual(8);
    driver.stop();
    expect(() => timerScheduler(0)).toThrow(/interval/);
  });

  it('tracks page visibility into the loop', () => {
    const listeners: (() => void)[] = [];
    const doc = {
      hidden: false,
      addEventListener: (_: 'visibilitychange', l: () => void) => listeners.push(l),
      removeEventListener: () => listeners.pop(),
    };
    const loop = new FixedLoop({ step: 60 });
    const stop = trackVisibility(doc, loop);
    doc.hidden = true;
    listeners.forEach((l) => {
      l();
    });
    expect(loop.hidden).toBe(true);
    doc.hidden = false;
    listeners.forEach((l) => {
      l();
    });
    expect(loop.hidden).toBe(false);
    stop();
    expect(listeners).toHaveLength(0);
  });
});
