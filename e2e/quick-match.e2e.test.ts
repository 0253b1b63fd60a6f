/**
 * Chapter 6's "Quick match" in a real browser: two pages press it, the server's `/match` gives
 * both one fresh room, both join it through the relay and agree on the final hash.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import type { Browser } from 'playwright-core';
import { createServer, type FixedstepServer } from '@fixedstep/server';
import { dist, launchChromium, num, readoutsOnceHashed, watch } from './harness.js';

describe('chapter 6, quick match', () => {
  let server: FixedstepServer;
  let browser: Browser;
  beforeAll(async () => {
    // The relay and the queue of one server share its ticket secret. Both pages run on this
    // machine, and quick match never pairs an address with itself: they come "through a proxy"
    // (a loopback one, trusted for its `x-forwarded-for`) from two addresses.
    server = await createServer({
      port: 0,
      host: '127.0.0.1',
      root: dist,
      stateSync: false,
      signalling: false,
      trustProxy: 'x-forwarded-for',
    });
    browser = await launchChromium();
  });
  afterAll(async () => {
    await browser.close();
    await server.close();
  });

  it('two pages press Quick match, are put in one room and agree on the final hash', async () => {
    const ticks = 300;
    const pages = await Promise.all(
      ['198.51.100.1', '198.51.100.2'].map((address) =>
        browser.newPage({ extraHTTPHeaders: { 'x-forwarded-for': address } }),
      ),
    );
    const problems = pages.map((p) => watch(p));
    for (const p of pages) {
      await p.goto(`${server.url}#/network?ticks=${ticks}`);
      await p.getByTestId('control-quick-match').click();
    }
    const hashed = await readoutsOnceHashed(pages, 'readout-online-final-hash', 60_000);
    const finals = await Promise.all(
      pages.map(async (p, i) => ({
        r: hashed[i]!,
        room: await p.getByTestId('control-room').inputValue(),
        status: await p.getByTestId('quick-match-status').textContent(),
      })),
    );
    expect(finals[0]!.room).toMatch(/^qm-[A-Za-z0-9_-]{24}$/);
    expect(finals[1]!.room).toBe(finals[0]!.room);
    expect(finals.map((f) => f.status)).toEqual([
      'Matched with 1 other player(s): joining the room.',
      'Matched with 1 other player(s): joining the room.',
    ]);
    expect(new Set(finals.map((f) => f.r['readout-online-slot']))).toEqual(new Set(['1', '2']));
    expect(finals[0]!.r['readout-online-final-hash']).toBe(
      finals[1]!.r['readout-online-final-hash'],
    );
    for (const f of finals) expect(num(f.r, 'online-desyncs')).toBe(0);
    expect(server.matchmaking!.queue.size).toBe(0);
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });
});
