/**
 * Chapter 6's "Quick match" in a real browser: two pages press it, the server's `/match` gives
 * both one fresh room, both join it through the relay and agree on the final hash.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { chromium, type Browser } from 'playwright-core';
import { startServer, type RunningServer } from '@fixedstep/server';
import { attachRelay, type RelayEndpoint } from '../packages/server/src/relay/endpoint.js';
import { attachMatchmaking, type MatchEndpoint } from '../packages/server/src/match/index.js';
import { CHROMIUM_ARGS, dist, num, readouts, watch } from './harness.js';

describe('chapter 6, quick match', () => {
  let server: RunningServer;
  let relay: RelayEndpoint;
  let matchmaking: MatchEndpoint;
  let browser: Browser;
  beforeAll(async () => {
    server = await startServer({ port: 0, host: '127.0.0.1', root: dist });
    relay = attachRelay(server.server);
    matchmaking = attachMatchmaking(server.server);
    browser = await chromium.launch({
      executablePath: process.env.CHROMIUM_PATH ?? '/usr/bin/chromium',
      args: CHROMIUM_ARGS,
    });
  });
  afterAll(async () => {
    await browser.close();
    await matchmaking.close();
    await relay.close();
    await server.close();
  });

  it('two pages press Quick match, are put in one room and agree on the final hash', async () => {
    const ticks = 300;
    const pages = await Promise.all([0, 1].map(() => browser.newPage()));
    const problems = pages.map((p) => watch(p));
    for (const p of pages) {
      await p.goto(`${server.url}#/network?ticks=${ticks}`);
      await p.getByTestId('control-quick-match').click();
    }
    const finals = await Promise.all(
      pages.map(async (p) => {
        await expect
          .poll(() => p.getByTestId('readout-online-final-hash').getAttribute('data-value'), {
            timeout: 60_000,
          })
          .toMatch(/^[0-9a-f]{16}$/);
        return {
          r: await readouts(p),
          room: await p.getByTestId('control-room').inputValue(),
          status: await p.getByTestId('quick-match-status').textContent(),
        };
      }),
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
    expect(matchmaking.queue.size).toBe(0);
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });
});
