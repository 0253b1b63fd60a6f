import { describe, expect, it } from 'vitest';
import { Random, decodeMessage, peekMessageType } from 'fixedstep';
import {
  HeldButtons,
  inputDelayTicks,
  percentile,
  playersPerCore,
  recordTrace,
  timeCodec,
  timeRelay,
} from '../suites/relay.js';

describe('relay suite helpers', () => {
  it('percentile is nearest-rank', () => {
    const v = Array.from({ length: 100 }, (_, i) => 100 - i);
    expect(percentile(v, 99)).toBe(99);
    expect(percentile(v, 50)).toBe(50);
    expect(percentile(v, 100)).toBe(100);
    expect(percentile([7], 99)).toBe(7);
    expect(() => percentile([], 50)).toThrow(RangeError);
  });

  it('players per core scales the measured cost to one second of CPU', () => {
    expect(playersPerCore(400, 0.1e9)).toBe(4000);
    expect(() => playersPerCore(400, 0)).toThrow(RangeError);
  });

  it('input delay follows the lockstep session rule', () => {
    expect(inputDelayTicks(60, 1000 / 60)).toBe(6);
    expect(inputDelayTicks(0, 1000 / 60)).toBe(2);
  });

  it('held buttons set a pressed bit only on the tick a button goes down', () => {
    const b = new HeldButtons(new Random(3), 2);
    let held = 0;
    for (let t = 0; t < 1000; t++) {
      const x = b.next();
      const nowHeld = x & 0xffff;
      expect(x >>> 16).toBe(nowHeld & ~held & 0xffff);
      held = nowHeld;
    }
  });
});

describe('relay suite trace', () => {
  const trace = recordTrace({
    rooms: 3,
    players: 2,
    seconds: 1,
    oneWayMs: 25,
    jitterMs: 5,
    seed: 9,
  });

  it('plays the match without drops or filled inputs, and the replay matches', () => {
    expect(trace.dropped).toBe(0);
    expect(trace.filledInputs).toBe(0);
    expect(trace.closedTicks).toBeGreaterThanOrEqual(60);
    expect(timeRelay(trace).bytesOut).toBe(trace.bytesOutTotal);
    expect(timeCodec(trace).ns).toBeGreaterThan(0);
  });

  it('clients send one input message a tick, plus hashes and pings', () => {
    const counts: Record<string, number> = {};
    for (let i = trace.steadyFrom; i < trace.at.length; i++) {
      const b = trace.bytes[i];
      if (b === undefined) continue;
      const k = peekMessageType(b) ?? '?';
      counts[k] = (counts[k] ?? 0) + 1;
    }
    const perPlayerSecond = (k: string) => (counts[k] ?? 0) / 6 / (trace.steadyMs / 1000);
    expect(perPlayerSecond('input')).toBeCloseTo(60, -1);
    expect(perPlayerSecond('ping')).toBeCloseTo(4, 0);
    expect(perPlayerSecond('hash')).toBeCloseTo(2, 0);
    const inputs = trace.bytes.filter((b) => b !== undefined && peekMessageType(b) === 'input');
    const m = decodeMessage(inputs[inputs.length - 1]!);
    // The relay's counters cover the same window: 66 messages a player-second up.
    expect(trace.messagesIn / 6 / (trace.steadyMs / 1000)).toBeCloseTo(66, -1);
    expect(m.type === 'input' && m.inputs.length).toBeLessThanOrEqual(8);
  });
});
