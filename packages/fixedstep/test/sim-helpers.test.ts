import { describe, expect, it } from 'vitest';
import {
  BUTTON_WORD,
  FixedLoop,
  FrameStepper,
  InputSampler,
  InterpolationBuffer,
  ManualClock,
  defineGame,
  gameSetup,
  packButtons,
  type Simulation,
} from 'fixedstep';

describe('InterpolationBuffer', () => {
  it('blends previous and current by alpha, angles along the shorter arc', () => {
    const buf = new InterpolationBuffer({ fields: 3, capacity: 4, angleFields: [2] });
    buf.beginTick();
    buf.store(0, 0, 10, 3.0);
    buf.beginTick();
    buf.store(0, 2, 14, -3.0); // +0.28 rad the short way, not −6.0
    const out = buf.interpolate(0.25);
    expect(out[0]).toBe(0.5);
    expect(out[1]).toBe(11);
    expect(out[2]).toBeCloseTo(3.0 + 0.25 * (2 * Math.PI - 6.0), 12);
  });

  it('draws a body that just appeared (or was snapped) where it is, never blended from stale values', () => {
    const buf = new InterpolationBuffer({ fields: 2, capacity: 8 });
    buf.beginTick();
    buf.store(3, 100, 100);
    expect([...buf.interpolate(0.5).subarray(6, 8)]).toEqual([100, 100]); // first store
    buf.beginTick();
    buf.store(3, 110, 100);
    expect([...buf.interpolate(0.5).subarray(6, 8)]).toEqual([105, 100]);
    buf.beginTick(); // body 3 not stored this tick: it is gone
    expect(buf.isLive(3)).toBe(false);
    buf.beginTick();
    buf.store(3, -50, 0); // reused slot: a new body
    expect([...buf.interpolate(0.5).subarray(6, 8)]).toEqual([-50, 0]);
    buf.beginTick();
    buf.store(3, 500, 0);
    buf.snap(3); // teleported
    expect([...buf.interpolate(0.5).subarray(6, 8)]).toEqual([500, 0]);
  });

  it('grows with reserve and refuses bodies outside its capacity', () => {
    const buf = new InterpolationBuffer({ fields: 2, capacity: 1 });
    expect(() => {
      buf.store(1, 0, 0);
    }).toThrow(/outside the capacity 1/);
    buf.store(0, 1, 2);
    buf.reserve(100);
    expect(buf.capacity).toBe(100);
    buf.store(99, 3, 4);
    expect(buf.interpolate(0)[0]).toBe(1);
    expect(() => new InterpolationBuffer({ fields: 0, capacity: 1 })).toThrow(/fields/);
  });
});

describe('FixedLoop warns about the delta trap', () => {
  it('names the mistake when frame() is fed deltas, once', () => {
    const warnings: string[] = [];
    const loop = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 30; i++) loop.frame(16.6 + (i % 3) * 0.1); // deltas, not timestamps
    expect(warnings).toHaveLength(1);
    expect(warnings[0]).toMatch(
      /expects a clock reading.*ran back.*call loop\.advance\(deltaMs, nowMs\)/,
    );
    expect(loop.tick).toBeLessThan(2); // what the trap does: time stands still
  });

  it('names a constant delta fed as a timestamp, which freezes the loop, once', () => {
    const warnings: string[] = [];
    const loop = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 600; i++) loop.frame(1000 / 60); // the same delta every frame
    expect(loop.tick).toBe(0); // what the trap does: no tick, ever
    expect(warnings).toEqual([
      'FixedLoop.frame(nowMs) expects a clock reading in ms (a requestAnimationFrame timestamp, performance.now()), but the last 30 readings were all 16.666666666666668 ms: the clock does not advance, so no tick runs (tick 0). That is a constant frame delta, not a timestamp: call loop.advance(deltaMs, nowMs) instead.',
    ]);
    // The fix the message names: the same deltas through advance() run 60 ticks a second.
    const fixed = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 600; i++) fixed.advance(1000 / 60);
    expect(fixed.tick).toBeGreaterThanOrEqual(599);
    expect(warnings).toHaveLength(1);
  });

  it('stays quiet for a clock that stands still at 0, or past a second, or advances in between', () => {
    const warnings: string[] = [];
    const atZero = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) atZero.frame(0);
    const paused = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) paused.frame(4000); // a page clock paused at 4 s
    const stuttering = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    // Early in a page's life, a clock that stands still for 20 frames and then moves on.
    for (let i = 0; i < 60; i++) stuttering.frame(i < 20 ? 100 : 100 + (i - 19) * 16.7);
    const late = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) late.frame(16.7 + i * 16.7);
    for (let i = 0; i < 60; i++) late.frame(1000); // stands still after the first 60 frames
    expect(warnings).toEqual([]);
  });

  it('stays quiet for a real clock, duplicate frames, a paused clock, a clock set back once, and when told to', () => {
    const warnings: string[] = [];
    const loop = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) loop.frame(5000 + Math.floor(i / 2) * 16.7); // every frame twice
    const paused = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) paused.frame(0); // a simulated clock that does not run
    const setBack = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
    for (let i = 0; i < 60; i++) setBack.frame(i < 30 ? 2000 + i * 16.7 : 500 + i * 16.7);
    expect(warnings).toEqual([]);
    const silent = new FixedLoop({ step: 60, onWarning: null });
    for (let i = 0; i < 30; i++) silent.frame(16.6);
    expect(silent.frames).toBe(30);
  });

  it('warns when input events are on another time line, and advance(dt, now) fixes it', () => {
    const warnings: string[] = [];
    const run = (withNow: boolean) => {
      const loop = new FixedLoop({ step: 60, onWarning: (m) => warnings.push(m) });
      const sampler = new InputSampler(BUTTON_WORD);
      const clock = new ManualClock(90_000); // performance.now() of a page open for 90 s
      const inputs: number[] = [];
      for (let f = 0; f < 30; f++) {
        const now = clock.advance(1000 / 60);
        if (f === 10) sampler.push(now - 1, 0, true); // a key press at frame 10, stamped on the page clock
        const n = withNow ? loop.advance(1000 / 60, now) : loop.advance(1000 / 60);
        for (let j = 0; j < n; j++) inputs.push(sampler.sample(loop, j));
      }
      return inputs.findIndex((i) => i === packButtons(1, 1));
    };
    expect(run(false)).toBe(-1); // the press never reaches a tick: the trap
    expect(
      warnings.some((w) => /ahead of the loop's clock.*advance\(deltaMs, nowMs\)/.test(w)),
    ).toBe(true);
    warnings.length = 0;
    expect(run(true)).toBe(10); // frame 10's press on tick 10
    expect(warnings).toEqual([]);
  });
});

describe('FrameStepper', () => {
  it('runs each due step with its own tick’s input, then renders with alpha', () => {
    const seen: number[] = [];
    const alphas: number[] = [];
    const sampler = new InputSampler();
    const stepper = new FrameStepper({
      loop: new FixedLoop({ step: 60 }),
      input: sampler,
      update: (dt, input) => {
        expect(dt).toBe(1 / 60);
        seen.push(input);
      },
      render: (a) => alphas.push(a),
    });
    stepper.frame(1000);
    sampler.push(1020, 2, true);
    expect(stepper.frame(1050)).toBe(3);
    expect(seen).toEqual([0, packButtons(4, 4), packButtons(4, 0)]);
    expect(alphas).toHaveLength(2);
    expect(alphas[1]).toBeCloseTo(0, 6);
  });

  it('steps two local players, one sampler each, each press on its own tick and player', () => {
    const left = new InputSampler();
    const right = new InputSampler();
    const steps: number[][] = [];
    const firsts: number[] = [];
    const stepper = new FrameStepper({
      loop: new FixedLoop({ step: 60 }),
      inputs: [left, right],
      update: (_dt, first, inputs) => {
        firsts.push(first);
        steps.push([...inputs]);
      },
    });
    stepper.frame(1000);
    left.push(1005, 0, true); // tick 0 (1000–1016.7 ms): player 0 presses button 0
    right.push(1030, 1, true); // tick 1 (1016.7–1033.3 ms): player 1 presses button 1
    right.push(1040, 1, false); // released during tick 2: down in it, not pressed
    expect(stepper.frame(1050)).toBe(3);
    expect(steps).toEqual([
      [packButtons(1, 1), 0],
      [packButtons(1, 0), packButtons(2, 2)],
      [packButtons(1, 0), packButtons(2, 0)],
    ]);
    expect(stepper.frame(1070)).toBe(1);
    expect(steps[3]).toEqual([packButtons(1, 0), 0]); // tick 3: player 1 let go
    expect(firsts).toEqual(steps.map((s) => s[0]));
  });

  it('keeps one source as before: inputs is [input]; refuses both or none', () => {
    const seen: number[][] = [];
    const stepper = new FrameStepper({
      loop: new FixedLoop({ step: 60 }),
      neutral: 7,
      update: (_dt, input, inputs) => seen.push([input, ...inputs]),
    });
    stepper.frame(0);
    stepper.frame(20);
    expect(seen).toEqual([[7, 7]]);
    const loop = new FixedLoop({ step: 60 });
    const update = () => undefined;
    expect(() => new FrameStepper({ loop, update, input: new InputSampler(), inputs: [] })).toThrow(
      new RangeError('FrameStepper: pass input (one player) or inputs (several), not both'),
    );
    expect(() => new FrameStepper({ loop, update, inputs: [] })).toThrow(
      new RangeError('FrameStepper: inputs needs at least one sampler, got none'),
    );
  });
});

describe('defineGame', () => {
  const counter = (): Simulation => {
    let tick = 0;
    return {
      get tick() {
        return tick;
      },
      step: () => {
        tick++;
      },
      save: () => Uint8Array.of(tick),
      load: (b) => {
        tick = b[0]!;
      },
      hash: () => BigInt(tick),
    };
  };
  const base = {
    id: 'counter',
    version: 1,
    tickRate: 60,
    input: BUTTON_WORD,
    minPlayers: 1,
    maxPlayers: 2,
    create: counter,
  };

  it('freezes a valid definition; the loop reads its tick rate', () => {
    const game = defineGame(base);
    expect(Object.isFrozen(game)).toBe(true);
    expect(new FixedLoop({ step: game }).dt).toBe(1 / 60);
    expect(gameSetup(game, 2, 7)).toEqual({ seed: 7, players: 2, options: new Uint8Array(0) });
    expect(() => gameSetup(game, 3, 7)).toThrow(/players must be from 1 to 2, got 3/);
    expect(() => gameSetup(game, 1, -1)).toThrow(/seed must be a u32/);
  });

  it('names the first wrong field', () => {
    expect(() => defineGame({ ...base, id: 'no spaces' })).toThrow(/id must be/);
    expect(() => defineGame({ ...base, version: 1.5 })).toThrow(/version must be an integer/);
    expect(() => defineGame({ ...base, tickRate: 0 })).toThrow(/tickRate must be/);
    expect(() => defineGame({ ...base, minPlayers: 3 })).toThrow(/minPlayers ≤ maxPlayers/);
    expect(() => defineGame({ ...base, input: {} as typeof BUTTON_WORD })).toThrow(/input schema/);
  });
});
