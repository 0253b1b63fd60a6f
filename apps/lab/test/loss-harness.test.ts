import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import {
  LOSS_HARNESS_FORMAT,
  lossHarness,
  parseLossHarness,
} from '../src/chapters/network/loss-harness.js';

const file = new URL('../src/chapters/network/data/loss-harness.json', import.meta.url);
const raw = (): Record<string, unknown> =>
  JSON.parse(readFileSync(file, 'utf8')) as Record<string, unknown>;

describe('loss harness report', () => {
  it('loads the committed run: WebRTC and WebSocket at 100 ± 30 ms, 5 % loss', () => {
    const r = lossHarness();
    expect(r.format).toBe(LOSS_HARNESS_FORMAT);
    expect(r.link).toEqual({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
    expect(r.ticks).toBe(1800);
    const [rtc, ws] = r.rows;
    expect(rtc?.transport).toBe('WebRTC');
    expect(ws?.transport).toBe('WebSocket');
    expect(rtc?.hashesEqual && ws?.hashesEqual).toBe(true);
    // The recorded numbers (data/loss-harness.json).
    expect(rtc?.latencyP50).toBeCloseTo(127.7, 1);
    expect(rtc?.stalls).toBe(0);
    expect(ws?.stalls).toBe(11);
    expect(ws?.stallFrames).toBe(1572);
    expect(ws?.depths.get(30)).toBe(42);
    expect(rtc?.bytesPerSecond.map((b) => b.slot)).toEqual([0, 1]);
    // Depth counts add up to the rollbacks.
    for (const row of r.rows) {
      expect([...row.depths.values()].reduce((a, b) => a + b, 0)).toBe(row.rollbacks);
    }
    // What the panel says: TCP's retransmission timeouts show as stalls and a long tail.
    expect(ws!.latencyP99).toBeGreaterThan(rtc!.latencyP99 * 3);
    expect(ws!.stallFrames).toBeGreaterThan(rtc!.stallFrames * 100);
  });

  it('refuses another format, naming it', () => {
    expect(() => parseLossHarness({ ...raw(), format: 'fixedstep-netem/2' })).toThrow(
      /format "fixedstep-netem\/2" is not fixedstep-netem\/1/,
    );
    expect(() => parseLossHarness(null)).toThrow(/report should be an object/);
    expect(() => parseLossHarness([])).toThrow(/report should be an object/);
  });

  it('refuses a missing or bad field, naming it', () => {
    const noRows = raw();
    noRows.rows = [];
    expect(() => parseLossHarness(noRows)).toThrow(/report\.rows is empty/);
    const bad = raw();
    const rows = bad.rows as Record<string, unknown>[];
    rows[1] = { ...rows[1], latencyP99: 'slow' };
    expect(() => parseLossHarness(bad)).toThrow(/report\.rows\[1\]\.latencyP99 .* got "slow"/);
    rows[1] = { ...rows[1], latencyP99: 1, depths: { zero: 3 } };
    expect(() => parseLossHarness(bad)).toThrow(/report\.rows\[1\]\.depths has a bad depth "zero"/);
    const noLink = raw();
    delete noLink.link;
    expect(() => parseLossHarness(noLink)).toThrow(/report\.link should be an object/);
  });
});
