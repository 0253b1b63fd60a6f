import { describe, it } from 'vitest';
import fc from 'fast-check';
import { FixedLoop, Timestep, type OverloadPolicy } from 'fixedstep';

/** Frame deltas in ms, including the nasty ones. */
const frameDelta = fc.oneof(
  { weight: 6, arbitrary: fc.double({ min: 0, max: 100, noNaN: true }) },
  { weight: 1, arbitrary: fc.double({ min: -1e4, max: 0, noNaN: true }) },
  { weight: 1, arbitrary: fc.constantFrom(NaN, Infinity, -Infinity, 0, -0, 1000 / 60, 1000 / 144) },
  { weight: 1, arbitrary: fc.double({ min: 100, max: 1e5, noNaN: true }) },
);
const hugeDelta = fc.oneof(frameDelta, fc.double({ min: 1e5, max: 1e7, noNaN: true }));

const step = fc.oneof(
  fc.constantFrom(30, 60, 120, 144, 240, 50).map((hz) => Timestep.fromHz(hz)),
  fc.constantFrom(30, 10, 16, 33.333).map((ms) => Timestep.fromMs(ms)),
);

/** The loop's own accounting of a valid delta, in units, computed independently with BigInt. */
function unitsOf(dtMs: number, s: Timestep, scale = 1): bigint {
  const ns = Math.round(dtMs * 1e6);
  if (!(ns >= 0) || ns === Infinity) return 0n;
  const scaled = scale === 1 ? ns : Math.round(ns * scale);
  return BigInt(scaled) * BigInt(s.unitsPerNs);
}

/** A loop with step `s` that never reaches its caps in these runs (an hour, 100 000 steps a frame). */
function uncappedLoop(s: Timestep, options: { hysteresis?: number; timeScale?: number } = {}) {
  return new FixedLoop({
    step: s,
    ...options,
    maxAccumulatorMs: 3_600_000,
    maxStepsPerFrame: 100_000,
  });
}

describe('FixedLoop properties', () => {
  it('with no overload, ticks run = floor(elapsed / step) exactly after every frame', () => {
    fc.assert(
      fc.property(step, fc.array(frameDelta, { maxLength: 60 }), (s, deltas) => {
        const loop = uncappedLoop(s);
        let elapsed = 0n;
        const p = BigInt(s.unitsPerStep);
        for (const d of deltas) {
          loop.advance(d);
          elapsed += unitsOf(d, s);
          if (BigInt(loop.tick) !== elapsed / p) return false;
          if (BigInt(loop.accumulatorUnits) !== elapsed % p) return false;
          if (!(loop.alpha >= 0 && loop.alpha < 1)) return false;
          if (loop.droppedUnits() !== 0) return false;
        }
        return true;
      }),
      { numRuns: 500 },
    );
  });

  it('with hysteresis h, ticks run = floor(elapsed / step + h) exactly', () => {
    fc.assert(
      fc.property(
        step,
        fc.double({ min: 0, max: 0.5, noNaN: true }),
        fc.array(frameDelta, { maxLength: 60 }),
        (s, h, deltas) => {
          const loop = uncappedLoop(s, { hysteresis: h });
          const hu = BigInt(Math.round(h * s.unitsPerStep));
          let elapsed = 0n;
          for (const d of deltas) {
            loop.advance(d);
            elapsed += unitsOf(d, s);
            if (BigInt(loop.tick) !== (elapsed + hu) / BigInt(s.unitsPerStep)) return false;
            if (!(loop.alpha >= 0 && loop.alpha < 1)) return false;
          }
          return true;
        },
      ),
      { numRuns: 300 },
    );
  });

  it('under any clamp, cap and overload policy: steps ≤ cap, 0 ≤ alpha < 1, and elapsed = ticks·step + accumulator + dropped, exactly', () => {
    const policy = fc.constantFrom<OverloadPolicy>('catch-up', 'drop', 'reset');
    fc.assert(
      fc.property(
        step,
        policy,
        fc.integer({ min: 1, max: 20 }),
        fc.integer({ min: 1, max: 40 }),
        fc.double({ min: 0, max: 0.5, noNaN: true }),
        fc.array(hugeDelta, { maxLength: 60 }),
        (s, overload, cap, clampSteps, h, deltas) => {
          const drops: number[] = [];
          const loop = new FixedLoop({
            step: s,
            overload,
            maxStepsPerFrame: cap,
            maxAccumulatorMs: (clampSteps * s.unitsPerStep) / s.unitsPerNs / 1e6,
            hysteresis: h,
            onDrop: (ms) => drops.push(ms),
          });
          const p = BigInt(s.unitsPerStep);
          let elapsed = 0n;
          for (const d of deltas) {
            const n = loop.advance(d);
            elapsed += unitsOf(d, s);
            if (n > cap || n < 0) return false;
            if (!(loop.alpha >= 0 && loop.alpha < 1)) return false;
            const accounted =
              BigInt(loop.tick) * p + BigInt(loop.accumulatorUnits) + BigInt(loop.droppedUnits());
            if (accounted !== elapsed) return false;
            if (loop.accumulatorUnits > Math.round(loop.maxAccumulatorMs * 1e6) * s.unitsPerNs)
              return false;
          }
          const reported = drops.reduce((a, b) => a + b, 0);
          return Math.abs(reported - loop.droppedMs()) <= 1e-6 * Math.max(1, reported);
        },
      ),
      { numRuns: 500 },
    );
  });

  it('a time scale changes the number of steps, exactly as scaled time predicts', () => {
    fc.assert(
      fc.property(
        step,
        fc.constantFrom(0, 0.25, 0.5, 1, 1.5, 2, 3.7),
        fc.array(frameDelta, { maxLength: 40 }),
        (s, scale, deltas) => {
          const loop = uncappedLoop(s, { timeScale: scale });
          let elapsed = 0n;
          for (const d of deltas) {
            loop.advance(d);
            elapsed += unitsOf(d, s, scale);
            if (BigInt(loop.tick) !== elapsed / BigInt(s.unitsPerStep)) return false;
            if (loop.dt !== s.seconds) return false;
          }
          return true;
        },
      ),
      { numRuns: 300 },
    );
  });

  it('absurd deltas (1e300, MAX_VALUE) keep every counter finite and alpha in range', () => {
    fc.assert(
      fc.property(
        fc.array(fc.oneof(frameDelta, fc.constantFrom(1e300, Number.MAX_VALUE, 1e20)), {
          maxLength: 30,
        }),
        (deltas) => {
          const loop = new FixedLoop({ step: 60 });
          for (const d of deltas) {
            const n = loop.advance(d);
            if (!(n >= 0 && n <= 8)) return false;
            if (!(loop.alpha >= 0 && loop.alpha < 1)) return false;
            if (!Number.isFinite(loop.tick) || !Number.isFinite(loop.accumulatorMs)) return false;
          }
          return true;
        },
      ),
      { numRuns: 200 },
    );
  });
});
