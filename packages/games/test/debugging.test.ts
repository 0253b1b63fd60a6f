import { describe, expect, it } from 'vitest';
import {
  InputRecorder,
  JumperButtons,
  TickHashes,
  demoRecording,
  recordingLength,
  runRecording,
} from '@fixedstep/games';

const RATES = [30, 60, 144, 240];

describe('the demo recording replayed at 30, 60, 144 and 240 Hz with ±20 % jitter', () => {
  it('fixed step: the same hash after every tick on every display', () => {
    const runs = RATES.map((hz) => runRecording({ loop: 'fixed', hz }));
    const ref = runs[0]!.hashes;
    expect(ref.length).toBe(323);
    for (const r of runs.slice(1)) {
      const n = Math.min(ref.length, r.hashes.length);
      let first = -1;
      for (let k = 0; k < n; k++) {
        if (r.hashes[k] !== ref[k]) {
          first = k + 1;
          break;
        }
      }
      expect(first, `first differing tick at ${r.rig.display.hz} Hz`).toBe(-1);
    }
    const golden = runs[0]!.rig.scene.hash();
    if (golden !== 'a737f453641f2d1e') console.log(`debugging golden hash is now ${golden}`);
    expect(golden).toBe('a737f453641f2d1e');
    // Not a trivial replay: the runner jumped six times and collected coins.
    expect(runs.map((r) => r.rig.scene.score)).toEqual([11, 11, 11, 11]);
    expect(runs[0]!.rig.scene.jumps).toBe(6);
  });

  it('variable Δt: a different final state on every display — even a different score', () => {
    const runs = RATES.map((hz) => runRecording({ loop: 'variable', hz }));
    const hashes = runs.map((r) => r.rig.scene.hash());
    expect(new Set(hashes).size).toBe(4);
    // At rest at the end, so the difference is not a matter of timing: 30 Hz scored 8, not 11.
    for (const r of runs) expect(r.rig.scene.vx).toBe(0);
    expect(runs.map((r) => r.rig.scene.score)).toEqual([8, 11, 11, 11]);
  });

  it('the demo recording is a well-formed session', () => {
    const rec = demoRecording();
    expect(recordingLength(rec)).toBe(8200);
    expect(rec).toHaveLength(22);
    for (let i = 1; i < rec.length; i++)
      expect(rec[i]!.timeMs).toBeGreaterThanOrEqual(rec[i - 1]!.timeMs);
  });
});

describe('InputRecorder', () => {
  it('records downs and ups in time order, skips repeats and lets go of held buttons', () => {
    const r = new InputRecorder();
    expect(r.push(100, JumperButtons.right, true)).toBeDefined();
    expect(r.push(120, JumperButtons.right, true)).toBeUndefined(); // key repeat
    expect(r.push(130, JumperButtons.left, false)).toBeUndefined(); // up with no down
    expect(r.push(90, JumperButtons.jump, true)?.timeMs).toBe(100); // never earlier than the last
    expect(r.finish(500)).toHaveLength(2);
    expect(r.events.map((e) => [e.timeMs, e.button, e.down])).toEqual([
      [100, JumperButtons.right, true],
      [100, JumperButtons.jump, true],
      [500, JumperButtons.right, false],
      [500, JumperButtons.jump, false],
    ]);
  });

  it('a recorded session replays into the same state on every display under a fixed step', () => {
    const r = new InputRecorder();
    r.push(200, JumperButtons.right, true);
    r.push(333.3, JumperButtons.jump, true);
    r.push(401.7, JumperButtons.jump, false);
    r.push(1500, JumperButtons.left, true);
    r.push(1520.25, JumperButtons.jump, true);
    r.finish(2600);
    const hashes = RATES.map((hz) =>
      runRecording({ loop: 'fixed', hz, recording: r.events, jitter: 0.3 }).rig.scene.hash(),
    );
    expect(new Set(hashes).size).toBe(1);
  });
});

describe('TickHashes', () => {
  it('keeps the hashes of the last ticks by tick number', () => {
    const t = new TickHashes(4);
    for (let k = 1; k <= 6; k++) t.push(`h${k}`);
    expect(t.latest).toBe(6);
    expect(t.at(6)).toBe('h6');
    expect(t.at(3)).toBe('h3');
    expect(t.at(2)).toBeUndefined();
    expect(t.at(7)).toBeUndefined();
    expect(t.at(0)).toBeUndefined();
  });
});
