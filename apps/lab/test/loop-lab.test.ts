import { describe, expect, it } from 'vitest';
import { LoopRig } from '@fixedstep/games';
import { fnv1a64Hex } from 'fixedstep';
import {
  CHECKPOINT_TICK,
  ClockLab,
  LoopLab,
  PANELS,
  Ring,
  SCRIPT_PERIOD_MS,
  defaultSettings,
  labScript,
  type LoopLabSettings,
  type PanelReadouts,
} from '../src/chapters/loop/loop-lab.js';

function readouts(lab: { runs: { spec: { id: string }; readouts(): PanelReadouts }[] }) {
  return Object.fromEntries(lab.runs.map((r) => [r.spec.id, r.readouts()]));
}

function at(settings: Partial<LoopLabSettings>, ms: number) {
  const lab = new LoopLab({ ...defaultSettings(), ...settings });
  lab.advanceTo(ms);
  return readouts(lab);
}

const FIXED = ['fixed-naive', 'fixed-final', 'fixed'];

describe('LoopLab', () => {
  it('has the four loops of the talk and the production loop', () => {
    expect(PANELS.map((p) => p.kind)).toEqual([
      'frame-locked',
      'variable',
      'fixed-naive',
      'fixed-final',
      'fixed',
    ]);
  });

  it('shows the talk’s contrast between 60 and 144 Hz at 5 s', () => {
    const a = at({ hz: 60 }, 5000);
    const b = at({ hz: 144 }, 5000);
    // Frame-locked: 301 frames of 1/60 s in 4.983 s; 721 in 5 s.
    expect(a['frame-locked']!.ratio).toBeCloseTo(1.00334, 5);
    expect(b['frame-locked']!.ratio).toBeCloseTo(2.40333, 5);
    expect(a.variable!.ratio).toBeCloseTo(1, 9);
    expect(b.variable!.ratio).toBeCloseTo(1, 9);
    expect(b.variable!.checkpointHash).not.toBe(a.variable!.checkpointHash);
    for (const id of FIXED) {
      expect(a[id]!.updates).toBe(166);
      expect(b[id]!.updates).toBe(166);
      expect(a[id]!.checkpointHash).toBe('28013f3404c7a02c');
      expect(b[id]!.checkpointHash).toBe('28013f3404c7a02c');
      expect(b[id]!.hash).toBe(a[id]!.hash);
      expect(a[id]!.droppedMs).toBe(0);
    }
    expect(a['frame-locked']!.droppedMs).toBeUndefined();
  });

  it('runs a step a frame late in the slides’ loops when a frame lands exactly on a step boundary', () => {
    // At 144 Hz frame 108 is at exactly 750 ms = 25 steps of 30 ms. FixedLoop's integer
    // accumulator pays a step that is exactly due (acc >= step); the slides' `while (acc > STEP)`
    // waits for the next frame, 6.9 ms later. Then all three agree again, tick and hash.
    for (const boundary of [1500, 3000, 4500]) {
      const on = at({ hz: 144 }, boundary);
      const after = at({ hz: 144 }, boundary + 7);
      expect(on.fixed!.updates).toBe(boundary / 30);
      for (const id of ['fixed-naive', 'fixed-final']) {
        expect(on[id]!.updates).toBe(boundary / 30 - 1);
        expect(on[id]!.hash).not.toBe(on.fixed!.hash);
        expect(after[id]!.updates).toBe(after.fixed!.updates);
        expect(after[id]!.hash).toBe(after.fixed!.hash);
      }
    }
  });

  it('takes the checkpoint hash right after update 150, even inside a multi-step frame', () => {
    // At 30 Hz the fixed loops run 1 or 2 steps a frame; a plain rig traced per update agrees.
    const lab = new LoopLab({
      ...defaultSettings(),
      hz: 30,
      events: [{ kind: 'hitch', atMs: 4000, durationMs: 700 }],
    });
    lab.advanceTo(8000);
    const rig = new LoopRig({
      loop: { kind: 'fixed', stepMs: 30 },
      display: { hz: 30, events: [{ kind: 'hitch', atMs: 4000, durationMs: 700 }] },
      script: labScript([]),
      trace: true,
    });
    rig.runFor(8000);
    const state = Float64Array.from(
      rig.trace.slice((CHECKPOINT_TICK - 1) * 6, CHECKPOINT_TICK * 6),
    );
    expect(lab.runs[4]!.checkpointHash).toBe(fnv1a64Hex(new Uint8Array(state.buffer)));
    expect(lab.runs[4]!.readouts().maxSteps).toBeGreaterThan(1);
  });

  it('lands on the same numbers whether played frame by frame or skipped', () => {
    const live = new LoopLab({ ...defaultSettings(), hz: 144, jitter: 0.2 });
    for (let t = 0; t < 7000; t += 16.7) live.advanceBy(16.7);
    const skipped = new LoopLab({ ...defaultSettings(), hz: 144, jitter: 0.2 });
    skipped.advanceTo(live.timeMs);
    expect(readouts(skipped)).toEqual(readouts(live));
  });

  it('replays an event added mid-run exactly as if it had been scheduled from the start', () => {
    const live = new LoopLab();
    live.advanceTo(3000);
    live.addEvent('hitch', 2000);
    live.advanceTo(9000);
    const planned = new LoopLab({
      ...defaultSettings(),
      events: [{ kind: 'hitch', atMs: 3000, durationMs: 2000 }],
    });
    planned.advanceTo(9000);
    expect(readouts(live)).toEqual(readouts(planned));
    const r = readouts(live);
    expect(r['fixed-naive']!.maxSteps).toBe(67);
    expect(r['fixed-final']!.maxSteps).toBe(33);
    expect(r.fixed!.maxSteps).toBe(8);
    expect(r.fixed!.droppedMs).toBeCloseTo(1758.333, 3);
    expect(r['fixed-final']!.droppedMs).toBeCloseTo(1038.333, 3);
  });

  it('shows no frame during a hitch, and reports it as active', () => {
    const lab = new LoopLab();
    lab.advanceTo(3000);
    lab.addEvent('hitch', 2000);
    const before = readouts(lab);
    lab.advanceTo(4900);
    expect(lab.activeEvent()?.kind).toBe('hitch');
    expect(readouts(lab)).toEqual(before);
    lab.advanceTo(5100);
    expect(lab.activeEvent()).toBeUndefined();
    expect(readouts(lab).fixed!.realS).toBeGreaterThan(5);
  });

  it('pauses FixedLoop in a hidden tab and counts the time as dropped', () => {
    const r = at({ events: [{ kind: 'hidden', atMs: 3000, durationMs: 10_000 }] }, 15_000);
    expect(r.fixed!.droppedMs).toBeCloseTo(10_008.333, 3);
    expect(r.fixed!.maxSteps).toBe(1);
    expect(r['fixed-naive']!.maxSteps).toBe(334);
    expect(r['fixed-final']!.maxSteps).toBe(33);
  });

  it('lets the slides’ loop spiral into a stall on a slow machine, but not FixedLoop', () => {
    const r = at({ slow: true }, 30_000);
    expect(r['fixed-naive']!.stalled).toBe(true);
    expect(r['fixed-naive']!.owed).toBeGreaterThan(0);
    // Owed updates never ran, so they are not simulated time.
    expect(r['fixed-naive']!.simS).toBeLessThan(r['fixed-naive']!.realS);
    expect(r['fixed-final']!.stalled).toBe(false);
    expect(r['fixed-final']!.maxSteps).toBe(33);
    expect(r.fixed!.stalled).toBe(false);
    expect(r.fixed!.maxSteps).toBe(8);
    expect(r['frame-locked']!.ratio).toBeCloseTo(25 / 60, 2);
  });

  it('adds a throw at the current time and replays it in every panel', () => {
    const lab = new LoopLab();
    lab.advanceTo(5000);
    const before = readouts(lab);
    lab.addThrow();
    expect(readouts(lab)).toEqual(before);
    lab.advanceTo(5500);
    const plain = at({}, 5500);
    const thrown = readouts(lab);
    for (const id of FIXED) expect(thrown[id]!.hash).not.toBe(plain[id]!.hash);
    expect(thrown.fixed!.hash).toBe(thrown['fixed-naive']!.hash);
  });

  it('restarts at zero with no events, keeping the display', () => {
    const lab = new LoopLab({ ...defaultSettings(), hz: 240 });
    lab.advanceTo(4000);
    lab.addEvent('hidden', 1000);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.settings.events).toEqual([]);
    expect(lab.settings.hz).toBe(240);
    expect(readouts(lab).fixed!.realS).toBe(0);
  });
});

describe('ClockLab', () => {
  it('runs the same loops on real frame times', () => {
    const lab = new ClockLab();
    for (let i = 0; i <= 300; i++) lab.frameAt((i * 1000) / 60);
    const r = readouts(lab);
    expect(r['frame-locked']!.ratio).toBeCloseTo(301 / 300, 9);
    expect(r.fixed!.checkpointHash).toBe('28013f3404c7a02c');
    expect(r['fixed-naive']!.checkpointHash).toBe('28013f3404c7a02c');
  });

  it('pauses FixedLoop over a real hidden period', () => {
    const lab = new ClockLab();
    lab.frameAt(0);
    lab.frameAt(16);
    lab.markHidden();
    lab.frameAt(5016);
    expect(readouts(lab).fixed!.droppedMs).toBe(5000);
  });

  it('takes a throw at the last frame time', () => {
    const a = new ClockLab();
    const b = new ClockLab();
    for (let i = 0; i < 200; i++) {
      a.frameAt(i * 20);
      b.frameAt(i * 20);
      if (i === 150) a.addThrow();
    }
    expect(readouts(a).fixed!.hash).not.toBe(readouts(b).fixed!.hash);
  });
});

describe('labScript', () => {
  it('repeats the scripted throws and keeps events in time order', () => {
    const s = labScript([5000, 100]);
    for (let i = 1; i < s.length; i++)
      expect(s[i]!.timeMs).toBeGreaterThanOrEqual(s[i - 1]!.timeMs);
    expect(s.filter((e) => e.timeMs < SCRIPT_PERIOD_MS)).toHaveLength(6 + 4);
    expect(s.some((e) => e.timeMs === SCRIPT_PERIOD_MS + 400)).toBe(true);
  });
});

describe('Ring', () => {
  it('keeps the newest records, oldest first', () => {
    const r = new Ring(3, 2);
    for (let i = 0; i < 5; i++) r.push(i, i * 10);
    expect(r.size).toBe(3);
    expect([0, 1, 2].map((k) => r.get(k, 0))).toEqual([2, 3, 4]);
    expect(r.get(2, 1)).toBe(40);
    expect(() => new Ring(4, 6)).toThrow(/width/);
  });
});
