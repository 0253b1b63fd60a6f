import { beforeAll, describe, expect, it } from 'vitest';
import { NetworkLab } from '../src/chapters/network/network-lab.js';
import { onlineOptions, roomLink } from '../src/chapters/network/network-online.js';
import { stateOnlineOptions, stateRoomLink } from '../src/chapters/network/network-state-online.js';
import {
  NEEDS,
  WHEN_TO_USE,
  correctionText,
  latencyText,
  verdictText,
} from '../src/chapters/network/network-text.js';

describe('NetworkLab', () => {
  // One 20 s run at 100 ± 30 ms and 5 % loss, shared by the tests that read it.
  let lossy: NetworkLab;
  beforeAll(() => {
    lossy = new NetworkLab({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
    lossy.advanceTo(20_000);
  });

  it('20 s at 100 ± 30 ms and 5 % loss: both machines agree, in all three models', () => {
    const lab = lossy;
    const r = lab.readouts();
    for (const m of [r.statesync, r.lockstep, r.rollback]) {
      expect(m.equal).toBe(true);
      expect(m.hashes[0]).toMatch(/^[0-9a-f]{16}$/);
      expect(m.checkpoint).toBeGreaterThanOrEqual(1000);
      expect(m.desyncs).toBe(0);
      expect(m.lost).toBeGreaterThan(0);
    }
    expect(r.lockstep.inputDelay).toBeGreaterThanOrEqual(13);
    expect(r.rollback.rollbacks).toBeGreaterThan(0);
    expect(r.rollback.maxDepth).toBeGreaterThan(0);
    // State sync: both machines hold the server's world at the checkpoint (its hash); the render
    // delay covers a snapshot interval plus the measured lateness, the lead half a round trip.
    expect(r.statesync.snapshots).toBeGreaterThan(2 * 300);
    expect(r.statesync.renderDelayMs).toBeGreaterThan(50 + 100);
    expect(r.statesync.renderDelayMs).toBeLessThan(50 + 100 + 2 * 30 + 20);
    expect(r.statesync.lead).toBeGreaterThanOrEqual(Math.ceil(100 / (1000 / 60)));
  });

  it('measures the three models the same way: bytes, input to screen, corrections', () => {
    const [state, lock, roll] = lossy.compare();
    expect([state!.mode, lock!.mode, roll!.mode]).toEqual(['statesync', 'lockstep', 'rollback']);
    // Your own input: at once with state sync (predicted the frame it is sampled), one tick of
    // input delay with rollback, a round trip and the jitter buffer with lockstep.
    expect(state!.ownLatencyMs).toBeLessThan(1000 / 60);
    expect(roll!.ownLatencyMs).toBeGreaterThanOrEqual(1000 / 60 - 1);
    expect(roll!.ownLatencyMs).toBeLessThan(3 * (1000 / 60));
    expect(lock!.ownLatencyMs).toBeGreaterThan(200);
    // On the other screen: one way up, one way down and the render delay for state sync; the
    // same order of time for the input-sync models.
    for (const m of [state!, lock!, roll!]) {
      expect(m.otherLatencyMs).toBeGreaterThan(150);
      expect(m.otherLatencyMs).toBeLessThan(600);
    }
    // Bytes: the world costs more than the inputs on the way down; up, everyone sends buttons —
    // the input-sync models in groups of two ticks with a bounded window (relay protocol 6), state
    // sync a tick at a time.
    expect(state!.downBytesPerSecond).toBeGreaterThan(2 * lock!.downBytesPerSecond);
    for (const m of [state!, lock!, roll!]) {
      expect(m.upBytesPerSecond).toBeGreaterThan(500);
      expect(m.upBytesPerSecond).toBeLessThan(2500);
    }
    expect(lock!.upBytesPerSecond).toBeLessThan(0.7 * state!.upBytesPerSecond);
    // Corrections: lockstep never guesses; rollback corrects other players (jumps), state sync
    // only the own player (glides), and less often.
    expect(lock!.corrections).toBe(0);
    expect(roll!.corrections).toBeGreaterThan(10);
    expect(state!.corrections).toBeLessThan(roll!.corrections);
    expect(state!.smoothed).toBe(true);
    expect(roll!.smoothed).toBe(false);
    for (const m of [state!, roll!]) expect(m.largestCorrection).toBeLessThanOrEqual(40);
  });

  it('repeats exactly: the same settings give the same numbers', () => {
    const run = () => {
      const lab = new NetworkLab();
      lab.advanceTo(6000);
      lab.setLink({ latencyMs: 150 });
      lab.advanceTo(9000);
      return lab.readouts();
    };
    expect(run()).toEqual(run());
  });

  it('restarts from zero', () => {
    const lab = new NetworkLab();
    lab.advanceTo(3000);
    lab.restart();
    expect(lab.timeMs).toBe(0);
    expect(lab.readouts().lockstep.checkpoint).toBe(-1);
  });
});

describe('NetworkLab on the real clock', () => {
  it('lets the page’s frames drive both machines, and they still agree', () => {
    const lab = new NetworkLab({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
    lab.advanceTo(2000);
    const before = lab.readouts();
    lab.setRealClock(true);
    expect(lab.realClock).toBe(true);
    // Simulated display frames no longer step the machines: 1 s of virtual time, no new ticks.
    lab.advanceTo(3000);
    expect(lab.readouts().lockstep.ticks).toEqual(before.lockstep.ticks);
    expect(lab.readouts().statesync.ticks).toEqual(before.statesync.ticks);
    // A 144 Hz display with a hitch, from 3 s on.
    let t = 0;
    lab.realFrame(t); // the driver's first frame, at 0, pins the time line to now
    for (let i = 0; i < 144 * 8; i++) {
      t += i === 500 ? 400 : 1000 / 144;
      lab.realFrame(t);
    }
    expect(lab.timeMs).toBeCloseTo(3000 + t, 6);
    const r = lab.readouts();
    for (const m of [r.statesync, r.lockstep, r.rollback]) {
      expect(m.equal).toBe(true);
      expect(m.desyncs).toBe(0);
      expect(m.checkpoint).toBeGreaterThanOrEqual(600);
      expect(m.ticks[0]).toBeGreaterThan(before.lockstep.ticks[0] + 400);
    }
  });

  it('ignores real frames on the simulated displays, and restarts on either', () => {
    const lab = new NetworkLab();
    lab.realFrame(5000);
    expect(lab.timeMs).toBe(0);
    lab.setRealClock(true);
    lab.realFrame(1000);
    lab.realFrame(1500);
    expect(lab.timeMs).toBe(500);
    lab.restart();
    expect(lab.realClock).toBe(true);
    expect(lab.timeMs).toBe(0);
    lab.realFrame(100);
    lab.realFrame(350);
    expect(lab.timeMs).toBe(250);
  });
});

describe('each machine’s screen is its own player’s', () => {
  it('the two machines of every model draw their own slot (one is player 1, the other player 2)', () => {
    const lab = new NetworkLab();
    lab.advanceTo(3000);
    for (const mode of ['statesync', 'lockstep', 'rollback'] as const) {
      const m = lab.match(mode);
      const slots = [m.view(0)?.slot, m.view(1)?.slot];
      expect({ mode, slots: new Set(slots) }).toEqual({ mode, slots: new Set([0, 1]) });
    }
  });
});

describe('the online panel’s address', () => {
  it('reads the room, the match length and join from the hash', () => {
    // No ticks: the match lasts until the game ends it.
    expect(onlineOptions('#/network')).toEqual({
      room: undefined,
      ticks: undefined,
      join: false,
      p2p: false,
    });
    expect(onlineOptions('#/network?room=abc&ticks=600&join=1')).toEqual({
      room: 'abc',
      ticks: 600,
      join: true,
      p2p: false,
    });
    // A bad room name is no room, and never joined; a match shorter than a checkpoint is refused.
    expect(onlineOptions('#/network?room=a%20b&join=1')).toEqual({
      room: undefined,
      ticks: undefined,
      join: false,
      p2p: false,
    });
    expect(onlineOptions('#/network?room=x&ticks=5').ticks).toBe(undefined);
  });

  it('links a room for a second tab that joins it, and reads back', () => {
    expect(roomLink('room-1', undefined)).toBe('#/network?room=room-1&join=1');
    const link = roomLink('r.2_x', 600);
    expect(link).toBe('#/network?room=r.2_x&ticks=600&join=1');
    expect(onlineOptions(link)).toEqual({ room: 'r.2_x', ticks: 600, join: true, p2p: false });
    // Peer to peer: the second tab joins the same way.
    const p2p = roomLink('r3', undefined, true);
    expect(p2p).toBe('#/network?room=r3&p2p=1&join=1');
    expect(onlineOptions(p2p)).toEqual({ room: 'r3', ticks: undefined, join: true, p2p: true });
  });
});

describe('the state-sync online panel’s address', () => {
  it('joins the room named in the hash, and reports the server world at a checkpoint tick', () => {
    expect(stateOnlineOptions('#/network')).toEqual({ room: undefined, at: 600 });
    expect(stateOnlineOptions('#/network?state=abc&at=300')).toEqual({ room: 'abc', at: 300 });
    // A bad room name is no room; a tick that is not a checkpoint is the default.
    expect(stateOnlineOptions('#/network?state=a%20b&at=301')).toEqual({
      room: undefined,
      at: 600,
    });
    const link = stateRoomLink('r-1', 300);
    expect(link).toBe('#/network?state=r-1&at=300');
    expect(stateOnlineOptions(link)).toEqual({ room: 'r-1', at: 300 });
    expect(stateRoomLink('r-1', 600)).toBe('#/network?state=r-1');
  });
});

describe('what the chapter says', () => {
  it('a verdict per model, and the comparison’s cells', () => {
    expect(verdictText('statesync', { checkpoint: 120, equal: true, desyncs: 0 })).toBe(
      'Both machines got the server’s world of tick 120, byte for byte.',
    );
    expect(verdictText('lockstep', { checkpoint: 120, equal: true, desyncs: 0 })).toBe(
      'Both machines computed the same world at tick 120.',
    );
    expect(verdictText('rollback', { checkpoint: -1, equal: false, desyncs: 0 })).toBe(
      'Connecting and syncing clocks…',
    );
    expect(latencyText(NaN)).toBe('—');
    expect(latencyText(16.6)).toBe('17 ms');
    const base = {
      upBytesPerSecond: 0,
      downBytesPerSecond: 0,
      ownLatencyMs: 0,
      otherLatencyMs: 0,
    };
    expect(
      correctionText({
        ...base,
        mode: 'lockstep',
        corrections: 0,
        largestCorrection: 0,
        smoothed: false,
      }),
    ).toBe('none (nothing is guessed)');
    expect(
      correctionText({
        ...base,
        mode: 'statesync',
        corrections: 3,
        largestCorrection: 2.25,
        smoothed: true,
      }),
    ).toBe('3, up to 2.3 units (glide)');
    expect(
      correctionText({
        ...base,
        mode: 'rollback',
        corrections: 12,
        largestCorrection: 8,
        smoothed: false,
      }),
    ).toBe('12, up to 8.0 units (jump)');
    // Every model says what it needs and when to use it.
    expect(Object.keys(NEEDS).sort()).toEqual(['lockstep', 'rollback', 'statesync']);
    expect(WHEN_TO_USE.map((w) => w.mode)).toEqual(['statesync', 'lockstep', 'rollback']);
    expect(NEEDS.statesync).toMatch(/need not be deterministic/);
  });
});
