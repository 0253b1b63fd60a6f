import { describe, expect, it } from 'vitest';
import { JumperButtons, demoRecording, traceCatalogue } from '@fixedstep/games';
import {
  DebugLab,
  LOOPS,
  MAX_RECORDING_MS,
  RATES,
  defaultDebugSettings,
} from '../src/chapters/debugging/debugging-lab.js';
import { catalogueSize, guarantee, verdictText } from '../src/chapters/debugging/debugging-text.js';
import { count } from '../src/ui/format.js';

describe('DebugLab', () => {
  it('replays the demo: fixed-step hashes agree at the common tick, variable ones do not', () => {
    const lab = new DebugLab();
    lab.advanceTo(5000);
    const f = lab.readouts('fixed');
    const v = lab.readouts('variable');
    expect(f.rows.map((r) => r.source)).toEqual([...RATES]);
    expect(f.commonTick).toBeGreaterThanOrEqual(165);
    expect(f.commonTick).toBeLessThanOrEqual(166);
    expect(f.equal).toBe(true);
    expect(f.rows.every((r) => /^[0-9a-f]{16}$/.test(r.hash ?? ''))).toBe(true);
    expect(v.equal).toBe(false);
    expect(new Set(v.rows.map((r) => r.hash)).size).toBe(4);
    // The runners drift apart under a variable Δt; at equal ticks they never do.
    expect(f.divergence).toBe(0);
    expect(Math.max(...lab.samples.filter((_, i) => i % 3 === 2))).toBe(0);
    expect(Math.max(...lab.samples.filter((_, i) => i % 3 === 1))).toBeGreaterThan(0.05);
  });

  it('agrees tick for tick all the way through, whenever you look', () => {
    const lab = new DebugLab();
    for (let t = 0; t < 10_000; t += 97.3) {
      lab.advanceTo(t);
      expect(lab.readouts('fixed').equal, `at ${t} ms`).toBe(true);
    }
    expect(lab.readouts('fixed').rows.map((r) => r.score)).toEqual([11, 11, 11, 11]);
  });

  it('records the reader’s presses, then replays them on every display', () => {
    const lab = new DebugLab();
    lab.advanceTo(2000);
    lab.startRecording();
    expect(lab.mode).toBe('recording');
    expect(lab.timeMs).toBe(0);
    lab.advanceTo(300);
    expect(lab.press(JumperButtons.right, true, 4)).toBe(true);
    expect(lab.press(JumperButtons.right, true)).toBe(false); // a key repeat
    lab.advanceTo(800);
    lab.press(JumperButtons.jump, true, 7.5);
    lab.advanceTo(1000);
    lab.press(JumperButtons.jump, false);
    lab.advanceTo(1900);
    expect(lab.recordedInputs).toBe(3);
    expect(lab.recordingMs).toBe(1900);
    const live = lab.tracks('fixed').map((t) => t.scene.hash());
    expect(lab.readouts('fixed').equal).toBe(true);
    lab.stopRecording();
    expect(lab.mode).toBe('replay');
    expect(lab.demo).toBe(false);
    expect(lab.timeMs).toBe(0);
    // The right button was still held: stopping let it go.
    expect(lab.settings.recording.map((e) => [e.timeMs, e.button, e.down])).toEqual([
      [304, JumperButtons.right, true],
      [807.5, JumperButtons.jump, true],
      [1000, JumperButtons.jump, false],
      [1900, JumperButtons.right, false],
    ]);
    lab.advanceTo(1900);
    // The replay lands on the very state the live run reached.
    expect(lab.tracks('fixed').map((t) => t.scene.hash())).toEqual(live);
    expect(lab.readouts('fixed').equal).toBe(true);
    expect(lab.press(JumperButtons.left, true)).toBe(false); // not recording
  });

  it('stops a recording by itself after 30 s', () => {
    const lab = new DebugLab();
    lab.startRecording();
    lab.press(JumperButtons.left, true);
    lab.advanceTo(MAX_RECORDING_MS + 1000);
    expect(lab.mode).toBe('replay');
    expect(lab.recordingMs).toBe(MAX_RECORDING_MS);
  });

  it('replays from zero on a jitter change and on the demo button', () => {
    const lab = new DebugLab();
    lab.advanceTo(4000);
    const before = lab.readouts('fixed').rows[0]!.hash;
    lab.setJitter(0);
    expect(lab.timeMs).toBe(4000);
    expect(lab.readouts('fixed').rows[0]!.hash).toBe(before);
    lab.load(demoRecording(), true);
    expect(lab.timeMs).toBe(0);
    expect(lab.demo).toBe(true);
    expect(lab.settings.recording).toEqual(defaultDebugSettings().recording);
  });

  it('adds a fifth run per loop on real frame times, with the same hashes under a fixed step', () => {
    const lab = new DebugLab(defaultDebugSettings(), true);
    let t = 0;
    for (let i = 0; i < 400; i++) {
      t += 16.7 + ((i * 5) % 7) - 3;
      lab.realFrame(t);
    }
    const f = lab.readouts('fixed');
    expect(f.rows.map((r) => r.source)).toEqual([...RATES, 'real']);
    expect(f.equal).toBe(true);
    expect(lab.readouts('variable').equal).toBe(false);
  });
});

describe('what the debugging chapter says', () => {
  const variable = LOOPS.find((l) => !l.fixed)!;
  const fixed = LOOPS.find((l) => l.fixed)!;
  const cm = (m: number) => `${(m * 100).toFixed(1)} cm`;

  it('does not say "nothing has moved" of runs that moved and met again', () => {
    // Run left into the level's wall and jump: the four variable-Δt runs come to rest in the
    // same place, so their hashes agree again — after paths that did not.
    const L = JumperButtons.left;
    const J = JumperButtons.jump;
    const lab = new DebugLab({
      jitter: 0.2,
      recording: [
        { timeMs: 100, button: L, down: true },
        { timeMs: 600, button: J, down: true },
        { timeMs: 800, button: J, down: false },
        { timeMs: 3000, button: L, down: false },
      ],
    });
    lab.advanceTo(5000);
    const r = lab.readouts('variable');
    expect(r.equal).toBe(true);
    expect(r.moved).toBe(true);
    expect(r.maxDivergence).toBeGreaterThan(0.3);
    const text = verdictText(variable, r, cm);
    expect(text).not.toContain('nothing has moved');
    expect(text).toContain(`up to ${cm(r.maxDivergence)} apart`);
    expect(text).toContain(`at ${(r.maxDivergenceAtMs / 1000).toFixed(1)} s`);
    // Before anything happens, it says so; the fixed step's verdict is about its hashes.
    const start = new DebugLab();
    expect(verdictText(variable, start.readouts('variable'), cm)).toContain(
      'nothing has moved yet',
    );
    expect(verdictText(fixed, lab.readouts('fixed'), cm)).toContain('one hash at every tick');
  });

  it('states the determinism catalogue’s own size, not a number typed in', () => {
    const compared = traceCatalogue().filter((s) => s.informational !== true);
    const size = catalogueSize();
    expect(size.scenes).toBe(compared.length);
    expect(size.ticks).toBe(compared.reduce((n, s) => n + s.ticks, 0));
    const text = guarantee(size);
    expect(text).toContain(`${count(size.scenes)} scenes and games, ${count(size.ticks)} ticks`);
    expect(text).toContain('30, 59.94, 60, 144 and 240 Hz');
  });
});
