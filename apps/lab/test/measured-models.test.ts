import { describe, expect, it } from 'vitest';
import {
  MEASURED_MODELS_FORMAT,
  measuredModels,
  parseMeasuredModels,
} from '../src/chapters/network/measured-models.js';

describe('the three models measured by the bench over real transports', () => {
  it('the committed report has every model over real WebRTC and real TCP, with the render delay', () => {
    const m = measuredModels();
    expect(m.results.map((r) => r.transport)).toEqual([
      'WebRTC (werift, through TURN)',
      'WebSocket (kernel TCP, TUN link)',
    ]);
    for (const r of m.results) {
      expect(r.link).toEqual({ latencyMs: 100, jitterMs: 30, loss: 0.05 });
      expect(r.rows.map((x) => x.model)).toEqual(['statesync', 'lockstep', 'rollback']);
      const [state, lock, roll] = r.rows;
      // State sync shows the own input at once and the others a render delay late; lockstep
      // waits a round trip for its own; rollback shows it after its one tick of input delay.
      expect(state!.renderDelayMs).toBeGreaterThan(0);
      expect(state!.ownLatencyMs).toBeLessThan(lock!.ownLatencyMs);
      expect(roll!.ownLatencyMs).toBeLessThan(lock!.ownLatencyMs);
      expect(lock!.corrections).toBe(0);
      // The wire carries at least the messages.
      for (const x of r.rows) expect(x.wireUpBytesPerSecond).toBeGreaterThan(x.upBytesPerSecond);
    }
  });

  it('refuses another format and a missing number, naming the field', () => {
    const good = JSON.parse(JSON.stringify(measuredModels())) as Record<string, unknown>;
    expect(() => parseMeasuredModels({ ...good, format: 'other' })).toThrow(/format should be/);
    expect(parseMeasuredModels({ ...good, format: MEASURED_MODELS_FORMAT })).toEqual(good);
    const bad = JSON.parse(JSON.stringify({ ...good, format: MEASURED_MODELS_FORMAT })) as {
      results: { rows: Record<string, unknown>[] }[];
    };
    delete bad.results[0]!.rows[0]!.ownLatencyMs;
    expect(() => parseMeasuredModels(bad)).toThrow(/results\[0\]\.rows\[0\]\.ownLatencyMs/);
  });
});
