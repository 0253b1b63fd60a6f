/**
 * fetchWithRetry: a busy server's 503 and a rate limit's 429 are asked again after Retry-After
 * (or an exponential back-off), stretched by jitter; other answers come back at once. The waits are
 * recorded by an injected sleep, so no test waits on the clock.
 */
import http from 'node:http';
import type { AddressInfo } from 'node:net';
import { afterEach, describe, expect, it } from 'vitest';
import { fetchWithRetry, parseRetryAfter, type FetchRetry } from '../src/net/http-retry.js';

let server: http.Server | undefined;

/** Closes the server of the test, if it still runs. */
async function stop(): Promise<void> {
  const s = server;
  server = undefined;
  if (s)
    await new Promise<void>((resolve) =>
      s.close(() => {
        resolve();
      }),
    );
}
afterEach(stop);

/** A real HTTP server answering each request with the next of `answers` (the last repeats). */
async function serve(
  answers: { status: number; retryAfter?: string }[],
): Promise<{ url: string; bodies: string[] }> {
  const bodies: string[] = [];
  server = http.createServer((req, res) => {
    const chunks: Buffer[] = [];
    req.on('data', (c: Buffer) => chunks.push(c));
    req.on('end', () => {
      bodies.push(Buffer.concat(chunks).toString());
      const a = answers[Math.min(bodies.length - 1, answers.length - 1)]!;
      res.writeHead(a.status, a.retryAfter ? { 'Retry-After': a.retryAfter } : {});
      res.end(JSON.stringify({ n: bodies.length }));
    });
  });
  await new Promise<void>((resolve) => server!.listen(0, '127.0.0.1', resolve));
  return { url: `http://127.0.0.1:${(server.address() as AddressInfo).port}/`, bodies };
}

/** Records each wait instead of waiting. */
function recorder(): { sleep: (ms: number) => Promise<void>; waits: number[] } {
  const waits: number[] = [];
  return {
    waits,
    sleep: (ms) => {
      waits.push(ms);
      return Promise.resolve();
    },
  };
}

describe('fetchWithRetry', () => {
  it("asks again after the server's Retry-After (503 BUSY, 429), sending the same body, and returns the success", async () => {
    const { url, bodies } = await serve([
      { status: 503, retryAfter: '2' },
      { status: 429, retryAfter: '1' },
      { status: 201 },
    ]);
    const { sleep, waits } = recorder();
    const told: FetchRetry[] = [];
    const res = await fetchWithRetry(
      url,
      { method: 'POST', body: 'replay bytes' },
      { sleep, random: () => 0, onRetry: (r) => told.push(r) },
    );
    expect(res.status).toBe(201);
    expect(await res.json()).toEqual({ n: 3 });
    expect(bodies).toEqual(['replay bytes', 'replay bytes', 'replay bytes']);
    expect(waits).toEqual([2000, 1000]);
    expect(told).toEqual([
      { attempt: 2, delayMs: 2000, status: 503, retryAfterMs: 2000 },
      { attempt: 3, delayMs: 1000, status: 429, retryAfterMs: 1000 },
    ]);
  });

  it('backs off exponentially without a Retry-After, stretched by up to half by the jitter, capped', async () => {
    const { url } = await serve([{ status: 503 }]);
    const { sleep, waits } = recorder();
    const res = await fetchWithRetry(
      url,
      {},
      { sleep, random: () => 0.999, retries: 5, baseDelayMs: 100, maxDelayMs: 1000 },
    );
    expect(res.status).toBe(503); // out of retries: the last answer
    expect(waits).toEqual([150, 300, 600, 1200, 1500]);
  });

  it('spreads a burst: clients refused together wait different times', async () => {
    const { url } = await serve([{ status: 503, retryAfter: '5' }]);
    const { sleep, waits } = recorder();
    let seed = 1;
    const random = () => ((seed = (seed * 48271) % 2147483647) - 1) / 2147483646;
    await Promise.all(
      Array.from({ length: 10 }, () => fetchWithRetry(url, {}, { random, retries: 1, sleep })),
    );
    expect(waits).toHaveLength(10);
    expect(waits.every((w) => w >= 5000 && w < 7500)).toBe(true);
    expect(new Set(waits).size).toBe(10);
  });

  it('returns every other answer at once: a refusal is not retried', async () => {
    for (const status of [200, 201, 400, 401, 413, 422, 500]) {
      const { url, bodies } = await serve([{ status, retryAfter: '1' }]);
      const { sleep, waits } = recorder();
      expect((await fetchWithRetry(url, {}, { sleep })).status).toBe(status);
      expect(bodies).toHaveLength(1);
      expect(waits).toEqual([]);
      await stop();
    }
  });

  it('retries a server that cannot be reached, then throws its error', async () => {
    const { url } = await serve([{ status: 200 }]);
    await stop();
    const { sleep, waits } = recorder();
    const told: FetchRetry[] = [];
    await expect(
      fetchWithRetry(url, {}, { sleep, random: () => 0, retries: 2, onRetry: (r) => told.push(r) }),
    ).rejects.toThrow();
    expect(waits).toEqual([1000, 2000]);
    expect(told.map((r) => r.status)).toEqual([0, 0]);
  });

  it('stops waiting when the request is aborted', async () => {
    const { url } = await serve([{ status: 503, retryAfter: '30' }]);
    const controller = new AbortController();
    const pending = fetchWithRetry(
      url,
      { signal: controller.signal },
      {
        onRetry: () => {
          controller.abort(new Error('left the page'));
        },
      },
    );
    await expect(pending).rejects.toThrow('left the page');
  });

  it('refuses a bad retry count, and reads Retry-After as seconds only', async () => {
    await expect(fetchWithRetry('http://127.0.0.1:1/', {}, { retries: -1 })).rejects.toThrow(
      'retries must be a whole number',
    );
    expect(parseRetryAfter('5')).toBe(5000);
    expect(parseRetryAfter(' 0 ')).toBe(0);
    expect(parseRetryAfter('Wed, 21 Oct 2026 07:28:00 GMT')).toBeUndefined();
    expect(parseRetryAfter('-1')).toBeUndefined();
    expect(parseRetryAfter(null)).toBeUndefined();
  });
});
