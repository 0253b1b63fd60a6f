import { describe, expect, it } from 'vitest';
import { FixedLoop, packButtons } from 'fixedstep';
import {
  JumpMeter,
  JumperButtons,
  JumperScene,
  MOVEMENT_PERIOD_MS,
  SceneRig,
  movementScript,
  runMovement,
  type MovementLoop,
} from '@fixedstep/games';

const RATES = [30, 60, 144, 240];
const press = (b: number) => packButtons(1 << b, 1 << b);
const hold = (b: number) => packButtons(1 << b, 0);

function firstJumps(loop: MovementLoop, jitter = 0.2) {
  return RATES.map((hz) => {
    const run = runMovement({ loop, hz, jitter, durationMs: MOVEMENT_PERIOD_MS - 100 });
    const jump = run.meter.jumps[0];
    if (!jump) throw new Error(`no jump at ${hz} Hz`);
    return { hz, ...jump, hash: run.rig.scene.hash() };
  });
}

const spread = (xs: number[]) => Math.max(...xs) - Math.min(...xs);

describe('the movement scene: one run-and-jump at 30, 60, 144 and 240 Hz with ±20 % jitter', () => {
  it('fixed step: the same jump on every display, to the last bit', () => {
    const jumps = firstJumps('fixed');
    for (const j of jumps) {
      expect(j.apex).toBe(jumps[0]!.apex);
      expect(j.distance).toBe(jumps[0]!.distance);
      expect(j.takeoffX).toBe(jumps[0]!.takeoffX);
      expect(j.hash).toBe(jumps[0]!.hash);
    }
    expect(jumps[0]!.apex).toBeCloseTo(1.5456, 10);
    expect(jumps[0]!.distance).toBeCloseTo(3.24, 10);
    expect(spread(jumps.map((j) => j.apex))).toBe(0);
    expect(spread(jumps.map((j) => j.distance))).toBe(0);
  });

  it('variable Δt: every display jumps its own jump', () => {
    const jumps = firstJumps('variable');
    // 30 Hz: 1.5093 m / 3.1832 m … 240 Hz: 1.6027 m / 3.2976 m.
    expect(jumps[0]!.apex).toBeCloseTo(1.50925, 4);
    expect(jumps[3]!.apex).toBeCloseTo(1.60273, 4);
    expect(spread(jumps.map((j) => j.apex))).toBeGreaterThan(0.09);
    expect(spread(jumps.map((j) => j.distance))).toBeGreaterThan(0.16);
    expect(new Set(jumps.map((j) => j.hash)).size).toBe(4);
  });

  it('variable Δt still disagrees with no jitter at all: the rates differ', () => {
    const jumps = firstJumps('variable', 0);
    expect(spread(jumps.map((j) => j.apex))).toBeGreaterThan(0.05);
    expect(spread(jumps.map((j) => j.distance))).toBeGreaterThan(0.05);
    const fixed = firstJumps('fixed', 0);
    expect(spread(fixed.map((j) => j.apex))).toBe(0);
  });

  it('golden hash after 10 s of the script at a fixed step', () => {
    const run = runMovement({ loop: 'fixed', hz: 60, durationMs: 10_000 });
    const hash = run.rig.scene.hash();
    if (hash !== '28620860950a2e84') console.log(`movement golden hash is now ${hash}`);
    expect(hash).toBe('28620860950a2e84');
    expect(run.rig.updates).toBe(333);
    expect(run.meter.jumps).toHaveLength(4);
  });
});

describe('JumperScene', () => {
  it('runs, jumps higher when the button is held, lands and brakes to a stop', () => {
    const high = new JumperScene();
    const low = new JumperScene();
    high.update(1 / 60, press(JumperButtons.jump));
    low.update(1 / 60, press(JumperButtons.jump));
    let topHigh = 0;
    let topLow = 0;
    for (let i = 0; i < 60; i++) {
      high.update(1 / 60, hold(JumperButtons.jump));
      low.update(1 / 60, 0);
      topHigh = Math.max(topHigh, high.y);
      topLow = Math.max(topLow, low.y);
    }
    expect(topHigh).toBeGreaterThan(topLow * 1.5);
    expect(high.grounded).toBe(true);
    expect(high.jumps).toBe(1);

    const s = new JumperScene();
    for (let i = 0; i < 60; i++) s.update(1 / 60, hold(JumperButtons.right));
    expect(s.vx).toBe(6);
    for (let i = 0; i < 60; i++) s.update(1 / 60, 0);
    expect(s.vx).toBe(0);
    // No jump from the air: a second press mid-air does nothing.
    s.update(1 / 60, press(JumperButtons.jump));
    s.update(1 / 60, press(JumperButtons.jump));
    expect(s.jumps).toBe(1);
  });

  it('resets to the start line on the reset button, with nothing to interpolate', () => {
    const s = new JumperScene();
    for (let i = 0; i < 30; i++) s.update(1 / 60, hold(JumperButtons.right));
    s.update(1 / 60, press(JumperButtons.reset));
    expect(s.x).toBe(s.config.startX);
    expect(s.round).toBe(1);
    expect(s.renderX(0.5)).toBe(s.config.startX);
  });

  it('scores coins, which reappear at seeded places; the generator is part of the state', () => {
    const a = new JumperScene({ coins: 3, seed: 7, coinBottom: 1.2 });
    const before = [0, 1, 2].map((k) => [a.coinX(k), a.coinY(k)]);
    // Put a coin on the runner's path, as a saved state would.
    const bytes = a.save();
    const view = new Float64Array(bytes.buffer);
    view[12] = a.x + 1;
    view[13] = 0.45;
    a.load(bytes);
    for (let i = 0; i < 30 && a.score === 0; i++) a.update(1 / 60, hold(JumperButtons.right));
    expect(a.score).toBe(1);
    expect([a.coinX(0), a.coinY(0)]).not.toEqual(before[0]);
    // Snapshot round trip: a copy loaded from the bytes continues identically.
    const b = new JumperScene({ coins: 3, seed: 7, coinBottom: 1.2 });
    b.load(a.save());
    for (let i = 0; i < 240; i++) {
      const input = i % 50 < 30 ? hold(JumperButtons.right) : press(JumperButtons.jump);
      a.update(1 / 60, input);
      b.update(1 / 60, input);
      expect(b.hash()).toBe(a.hash());
    }
    expect(() => {
      b.load(new Uint8Array(3));
    }).toThrow(RangeError);
    expect(() => new JumperScene({ coins: 9 })).toThrow(RangeError);
  });
});

describe('JumpMeter', () => {
  it('measures take-off, apex and landing, and forgets a jump cut short by a reset', () => {
    const s = new JumperScene();
    const m = new JumpMeter();
    const step = (input: number) => {
      s.update(1 / 60, input);
      m.observe(s);
    };
    for (let i = 0; i < 20; i++) step(hold(JumperButtons.right));
    const takeoff = s.x;
    step(press(JumperButtons.jump) | hold(JumperButtons.right));
    while (!s.grounded) step(hold(JumperButtons.right) | hold(JumperButtons.jump));
    expect(m.jumps).toHaveLength(1);
    const j = m.jumps[0]!;
    expect(j.takeoffX).toBe(takeoff);
    expect(j.landingX).toBe(s.x);
    expect(j.distance).toBeCloseTo(s.x - takeoff, 12);
    expect(j.apex).toBeGreaterThan(1.5);
    step(press(JumperButtons.jump));
    expect(m.current).toBeDefined();
    step(press(JumperButtons.reset));
    expect(m.current).toBeUndefined();
    expect(m.jumps).toHaveLength(1);
  });
});

describe('SceneRig', () => {
  it('feeds scripted inputs to the tick that contains them, whatever the display', () => {
    const takeoffTicks = RATES.map((hz) => {
      let tick = 0;
      let at = -1;
      const rig = new SceneRig({
        loop: { kind: 'fixed', stepMs: 30 },
        display: { hz, jitter: 0.3, seed: hz },
        scene: new JumperScene(),
        script: movementScript(1000),
        onUpdate: (scene) => {
          tick++;
          if (at < 0 && scene.jumps === 1) at = tick;
        },
      });
      rig.runFor(1000);
      expect(rig.loop).toBeInstanceOf(FixedLoop);
      return at;
    });
    // The press at 450 ms belongs to the tick spanning 450–480 ms: tick 16.
    expect(takeoffTicks).toEqual([16, 16, 16, 16]);
  });

  it('waits for the work asked for, runs at most the guard, and counts the rest as owed', () => {
    const rig = new SceneRig({
      loop: { kind: 'fixed-naive', stepMs: 30 },
      display: { hz: 60, events: [{ kind: 'hitch', atMs: 100, durationMs: 3000 }] },
      scene: new JumperScene(),
      updateCostMs: 10,
      stallGuard: 50,
    });
    while (rig.lastSteps < 100) rig.frame();
    // The first frame after the hitch owes ~100 steps: 50 run, the rest owed, 1 s of work.
    expect(rig.lastSteps).toBe(rig.maxSteps);
    expect(rig.owed).toBe(rig.maxSteps - 50);
    expect(rig.updates).toBeLessThan(rig.maxSteps);
    expect(rig.longestFrameMs).toBeGreaterThan(3000);
    const before = rig.realMs;
    const asked = rig.lastSteps;
    rig.frame();
    expect(rig.realMs - before).toBeCloseTo(asked * 10, 6);
  });

  it('reads the clock it is given', () => {
    const seen: number[] = [];
    const rig = new SceneRig({
      loop: { kind: 'variable' },
      display: { hz: 10 },
      scene: new JumperScene(),
      clock: (t) => (t >= 300 ? t - 1000 : t),
      onUpdate: (_s, loop) => seen.push(loop.dt),
    });
    rig.runFor(500);
    expect(Math.min(...seen)).toBeCloseTo(-0.9, 9);
  });
});
