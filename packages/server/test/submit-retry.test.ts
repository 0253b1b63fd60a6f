/**
 * Honest bursts (issue: "136 of 200 parallel honest submissions got 503 BUSY; the lab never
 * retries"): clients that submit through `fetchWithRetry` — as the lab does — all get their scores
 * ranked when the verification queue was full at first. The `gate` game holds the one verifier
 * until the test opens it; each client's wait lasts until the gate is open and the queue is empty
 * (state, not time), so the burst is the same on any machine.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { fetchWithRetry, type AnyGameDefinition, type FetchRetry } from 'fixedstep';
import type { FixedstepServer } from '../src/app.js';
import { gaugeOf, recordRun, startGatedServer, type GatedServer } from './verify-runs.js';

const CLIENTS = 12;
let gated: GatedServer;
let server: FixedstepServer;
let games: readonly AnyGameDefinition[];
beforeAll(async () => {
  gated = await startGatedServer('retry', {
    // Each client is a player of its own address (X-Forwarded-For), as a real burst is.
    trustProxy: 'x-forwarded-for',
  });
  ({ server, games } = gated);
}, 120_000);
afterAll(() => gated.close());

const run = (seed: number) => recordRun(games, 'gate', seed, `p${seed}`);

const url = (p: string) => `http://127.0.0.1:${server.port}${p}`;

const gauge = (name: string) => gaugeOf(server.port, name);

describe('a burst of honest submissions while the verifier is busy', () => {
  it(`${CLIENTS} clients that retry BUSY all get ranked; each was told its score is queued`, async () => {
    let open!: () => void;
    const opened = new Promise<void>((resolve) => (open = resolve));
    // A client's wait: until the gate is open and nothing waits in the queue.
    const sleep = async () => {
      await opened;
      await expect
        .poll(() => gauge('fixedstep_verification_queue_length'), { interval: 5 })
        .toBe(0);
    };
    const retries: FetchRetry[][] = Array.from({ length: CLIENTS }, () => []);
    const answers = Array.from({ length: CLIENTS }, (_, i) => {
      const { bytes, score } = run(i + 1);
      return fetchWithRetry(
        url(`/api/highscores?score=${score}`),
        {
          method: 'POST',
          body: Buffer.from(bytes),
          headers: { 'X-Forwarded-For': `203.0.113.${i + 1}` },
        },
        { retries: 2 * CLIENTS, sleep, onRetry: (r) => retries[i]!.push(r) },
      );
    });
    // One verifies (held at the gate), one waits in the queue, the rest were told BUSY.
    await expect
      .poll(() => retries.filter((r) => r.length > 0).length, { timeout: 30_000 })
      .toBe(CLIENTS - 2);
    for (const r of retries.flat()) {
      expect(r.status).toBe(503);
      expect(r.retryAfterMs).toBeGreaterThan(0);
    }
    gated.openGate();
    open();
    const statuses = await Promise.all(answers.map(async (a) => (await a).status));
    expect(statuses).toEqual(Array.from({ length: CLIENTS }, () => 201));
    const table = (await (
      await fetch(url(`/api/highscores?game=gate&limit=${CLIENTS}`))
    ).json()) as {
      entries: unknown[];
    };
    expect(table.entries).toHaveLength(CLIENTS);
  });
});
