import { describe, expect, it } from 'vitest';
import type { DisplayEvent, LoopKind } from 'fixedstep';
import { LoopRig } from '@fixedstep/games';

/** The talk's claims about the loop, on the thrown-ball scene, at simulated 30/60/144/240 Hz. */
const DISPLAYS = [30, 60, 144, 240];
const HITCH: DisplayEvent[] = [{ kind: 'hitch', atMs: 3000, durationMs: 2000 }];
const STATE = 6; // numbers per state in a trace

function rig(kind: LoopKind, hz: number, jitter = 0.3, events = HITCH): LoopRig {
  const r = new LoopRig({
    loop: { kind },
    display: { hz, jitter, seed: hz * 7 + 1, events },
    trace: true,
  });
  r.runFor(9000);
  return r;
}

describe('the same inputs at 30, 60, 144 and 240 Hz with ±30% jitter and a 2 s hitch', () => {
  for (const kind of ['fixed-naive', 'fixed-final', 'fixed'] as const) {
    it(`${kind}: identical state at equal ticks on every display`, () => {
      const rigs = DISPLAYS.map((hz) => rig(kind, hz));
      const ticks = Math.min(...rigs.map((r) => r.trace.length / STATE));
      // The hitch drops a different amount of time per display, so the runs end on different
      // ticks; every tick they share must hold the same state, bit for bit.
      expect(ticks).toBeGreaterThan(150);
      const reference = rigs[0]!.trace;
      for (const r of rigs.slice(1)) {
        let firstDiff = -1;
        for (let i = 0; i < ticks * STATE; i++) {
          if (!Object.is(r.trace[i], reference[i])) {
            firstDiff = Math.floor(i / STATE);
            break;
          }
        }
        expect(firstDiff, `first differing tick at ${r.display.hz} Hz`).toBe(-1);
      }
      // Not a trivial scene: both throws landed and the ball bounced.
      expect(rigs[0]!.scene.state[5]).toBe(2);
      expect(rigs[0]!.scene.bounces).toBeGreaterThanOrEqual(4);
    });
  }

  it('variable Δt: a different state on every display', () => {
    const rigs = DISPLAYS.map((hz) => rig('variable', hz));
    const hashes = new Set(rigs.map((r) => r.scene.hash()));
    expect(hashes.size).toBe(DISPLAYS.length);
  });

  it('variable Δt: the same throw reaches a different height at 30 Hz and at 240 Hz', () => {
    const apex = (hz: number, kind: LoopKind) => {
      const r = new LoopRig({ loop: { kind }, display: { hz, jitter: 0.3, seed: 5 } });
      let top = 0;
      while (r.realMs < 1500) {
        r.frame();
        top = Math.max(top, r.scene.y);
      }
      return top;
    };
    const v30 = apex(30, 'variable');
    const v240 = apex(240, 'variable');
    const f30 = apex(30, 'fixed');
    const f240 = apex(240, 'fixed');
    expect(Math.abs(v30 - v240)).toBeGreaterThan(0.02);
    expect(f30).toBe(f240);
  });

  it('frame-locked: runs 2.4× faster at 144 Hz than at 60 Hz', () => {
    const speed = (hz: number) => {
      const r = new LoopRig({ loop: { kind: 'frame-locked' }, display: { hz } });
      r.runFor(10_000);
      return r.loop.simTime / (r.realMs / 1000);
    };
    const s60 = speed(60);
    const s144 = speed(144);
    expect(s60).toBeCloseTo(1, 2);
    expect(s144 / s60).toBeCloseTo(2.4, 2);
  });

  it('the fixed loops keep simulated time with real time (minus what the hitch dropped)', () => {
    for (const hz of DISPLAYS) {
      const r = rig('fixed', hz, 0.3, []);
      expect(Math.abs(r.loop.simTime - r.realMs / 1000)).toBeLessThan(0.02);
    }
  });
});

describe('the ball scene', () => {
  it('snapshot: save, load into a fresh scene, step both, equal bytes every step', () => {
    const a = rig('fixed', 60).scene;
    const b = new LoopRig({ loop: { kind: 'fixed' }, display: { hz: 60 } }).scene;
    b.load(a.save());
    for (let i = 0; i < 120; i++) {
      a.update(1 / 60, i === 10 ? 1 << 16 : 0);
      b.update(1 / 60, i === 10 ? 1 << 16 : 0);
      expect(b.hash()).toBe(a.hash());
    }
    expect(() => {
      b.load(new Uint8Array(3));
    }).toThrow(/expected 48 bytes/);
  });

  it('golden hash after 9 s at 60 Hz with the default script', () => {
    // Re-bless deliberately if the scene changes: the actual value is printed on mismatch.
    expect(rig('fixed', 60).scene.hash()).toBe('1624f89711c01d4e');
  });
});
