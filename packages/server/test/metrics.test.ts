/**
 * /metrics carries the event loop's delay (issue: "event-loop delay is not in /metrics"): Node's
 * own histogram (perf_hooks.monitorEventLoopDelay, through prom-client), under the server's prefix.
 */
import { describe, expect, it } from 'vitest';
import { ServerMetrics } from '../src/http/metrics.js';

describe('ServerMetrics', () => {
  it("names the event loop's delay: now, p50, p99 and max, in seconds", async () => {
    const metrics = new ServerMetrics();
    const text = await metrics.registry.metrics();
    const names = ['lag_seconds', 'lag_p50_seconds', 'lag_p99_seconds', 'lag_max_seconds'];
    const values = names.map((name) => {
      const line = text
        .split('\n')
        .find((l) => l.startsWith(`fixedstep_nodejs_eventloop_${name} `));
      return Number(line?.split(' ')[1]);
    });
    // Each present, a number of seconds (a missing line reads NaN and fails).
    expect(values.map((v) => v >= 0)).toEqual(names.map(() => true));
  });
});
