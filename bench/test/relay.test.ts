import { describe, expect, it } from 'vitest';
import { Random, decodeMessage, peekMessageType, type ConfirmedMessage } from 'fixedstep';
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
  const options = { rooms: 3, players: 2, seconds: 1, oneWayMs: 25, jitterMs: 5, seed: 9 };
  const trace = recordTrace({ ...options, stream: false });
  const stream = recordTrace({ ...options, stream: true });

  it('plays the match without drops or filled inputs, and the replay matches', () => {
    for (const t of [trace, stream]) {
      expect(t.dropped).toBe(0);
      expect(t.filledInputs).toBe(0);
      expect(t.closedTicks).toBeGreaterThanOrEqual(60);
      expect(timeRelay(t).bytesOut).toBe(t.bytesOutTotal);
      expect(timeCodec(t).ns).toBeGreaterThan(0);
    }
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

  it('over a stream each input goes once, each tick comes back once, XOR-coded, under 1 KB/s', () => {
    const inputs = stream.bytes
      .slice(stream.steadyFrom)
      .filter((b) => b !== undefined && peekMessageType(b) === 'input')
      .map((b) => decodeMessage(b!));
    expect(inputs.every((m) => m.type === 'input' && m.inputs.length === 1)).toBe(true);
    const confirmed = stream.sent.filter((m): m is ConfirmedMessage => m.type === 'confirmed');
    expect(confirmed.length).toBeGreaterThan(0);
    // After each member's first message, every one continues the previous: XOR-coded.
    expect(confirmed.filter((m) => !m.delta).length).toBeLessThanOrEqual(6);
    const perPlayerSecond = (x: number) => x / 6 / (stream.steadyMs / 1000);
    const down = perPlayerSecond(stream.bytesOut + 2 * stream.messagesOut);
    expect(down).toBeLessThan(1000);
    // Fewer bytes a message than over datagrams, which repeat unacknowledged ticks.
    expect(stream.bytesOut / stream.messagesOut).toBeLessThan(trace.bytesOut / trace.messagesOut);
    // One message a tick down: nothing waits for a group (datagrams group confirmed ticks).
    expect(perPlayerSecond(stream.messagesOut)).toBeCloseTo(60, -1);
    expect(stream.messagesOut).toBeGreaterThan(trace.messagesOut);
  });

  it('the client sees its inputs confirmed no later than without the stream', () => {
    const p50 = (t: typeof trace) => percentile(t.clientDelay, 50);
    const p99 = (t: typeof trace) => percentile(t.clientDelay, 99);
    expect(stream.clientDelay.length).toBeGreaterThan(300);
    // The round trip (50–60 ms) plus the wait for the other player's input.
    expect(p50(stream)).toBeGreaterThan(50);
    // No later than over datagrams, whose inputs go in groups of two ticks (relay protocol 6).
    expect(p50(stream)).toBeLessThan(p50(trace) + 2);
    expect(p99(stream)).toBeLessThan(p99(trace) + 5);
  });
});
