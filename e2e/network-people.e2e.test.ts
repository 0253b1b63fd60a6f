/**
 * Chapter 6, "Play online", played by people: two pages join one room through the server's
 * relay, each person moves their own player (keys on one page; on a phone, the on-screen stick),
 * each screen marks its own player "YOU", and the match ends with the same final hash on both.
 * Every wait is on the pages' state, never on a fixed time.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { attachRelay } from '../packages/server/src/relay/endpoint.js';
import { attachSignalling } from '../packages/server/src/signalling/endpoint.js';
import {
  horizontalOverflow,
  phonePage,
  readoutsOnceHashed,
  shots,
  useLabWith,
  watch,
} from './harness.js';

/** The x of this page's own player (the one its screen marks "YOU"), CTF units. */
async function youX(page: Page): Promise<number> {
  return Number(await page.getByTestId('canvas-online').getAttribute('data-you-x'));
}

async function state(page: Page): Promise<string | null> {
  return page.getByTestId('readout-online-state').getAttribute('data-value');
}

/** Wait for both pages' final hash and return their readouts. */
function finals(pages: Page[]): Promise<Record<string, string>[]> {
  return readoutsOnceHashed(pages, 'readout-online-final-hash', 90_000);
}

describe('chapter 6, people play people online', () => {
  const online = useLabWith((s) => [attachRelay(s.server), attachSignalling(s.server)]);

  it('two people play by keyboard; each screen is its own player’s; the end is the same on both', async () => {
    const ticks = 600;
    const pages = await Promise.all([0, 1].map(() => online.browser.newPage()));
    const problems = pages.map((p) => watch(p));
    const [one, two] = pages as [Page, Page];
    await one.goto(`${online.server.url}#/network?room=people-keys&ticks=${ticks}`);
    // The keys are on the page, not in a tooltip; no bot unless asked.
    await expect
      .poll(() => one.getByTestId('online-keys').innerText())
      .toContain('Fire: Space / J');
    expect(await one.getByTestId('control-online-bot').getAttribute('aria-pressed')).toBe('false');
    await one.getByTestId('control-join').click();
    await expect.poll(() => state(one)).toBe('waiting for the other player');
    const link = await one.getByTestId('link-room-tab').getAttribute('href');
    await two.goto(`${online.server.url}${link}`);
    for (const p of pages) await expect.poll(() => state(p), { timeout: 30_000 }).toBe('running');
    // Page 1 is player 1 (red, left base), page 2 player 2 (blue, right base); each screen marks
    // its own player YOU.
    for (const [i, p] of pages.entries()) {
      expect(await p.getByTestId('readout-online-slot').getAttribute('data-value')).toBe(
        String(i + 1),
      );
      expect(await p.getByTestId('canvas-online').getAttribute('data-you')).toBe(String(i + 1));
    }
    // Each person walks toward the middle: player 1 right (D), player 2 left (←) — held until
    // their own player has moved 60 units on their own screen.
    const start = [await youX(one), await youX(two)];
    await one.getByTestId('canvas-online').click();
    await one.keyboard.down('KeyD');
    await two.getByTestId('canvas-online').click();
    await two.keyboard.down('ArrowLeft');
    await expect.poll(() => youX(one), { timeout: 30_000 }).toBeGreaterThan(start[0]! + 60);
    await expect.poll(() => youX(two), { timeout: 30_000 }).toBeLessThan(start[1]! - 60);
    await one.keyboard.up('KeyD');
    await two.keyboard.up('ArrowLeft');
    await two.keyboard.press('Space');
    const got = await finals(pages);
    const [r1, r2] = got as [Record<string, string>, Record<string, string>];
    expect(r1['readout-online-final-hash']).toBe(r2['readout-online-final-hash']);
    expect(r1['readout-online-end']).toBe(String(ticks));
    expect(r2['readout-online-end']).toBe(String(ticks));
    for (const r of got) {
      expect(r['readout-online-state']).toBe('finished');
      expect(r['readout-online-desyncs']).toBe('0');
    }
    // The final screens show that one state, each with its own player marked.
    expect(await one.getByTestId('canvas-online').getAttribute('data-you')).toBe('1');
    expect(await two.getByTestId('canvas-online').getAttribute('data-you')).toBe('2');
    // The online panel of each page.
    await one
      .locator('[aria-labelledby="net-online-title"]')
      .screenshot({ path: path.join(shots, 'network-people-1.png') });
    await two
      .locator('[aria-labelledby="net-online-title"]')
      .screenshot({ path: path.join(shots, 'network-people-2.png') });
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });

  it('on a phone (390 × 844, touch) the panel fits and the on-screen stick plays', async () => {
    const ticks = 600;
    const { context, page: phone, problems } = await phonePage(online.browser);
    const desk = await online.browser.newPage();
    const deskProblems = watch(desk);
    await phone.goto(`${online.server.url}#/network?room=people-touch&ticks=${ticks}`);
    const stick = phone.getByTestId('touch-stick');
    await stick.waitFor();
    expect(await phone.getByTestId('touch-fire').isVisible()).toBe(true);
    expect(await phone.getByTestId('online-keys').isVisible()).toBe(true);
    expect(await horizontalOverflow(phone)).toBe(0);
    // Nothing of the panel is cut at the right edge.
    const cut = await phone.evaluate(() => {
      const panel = document.querySelector('[aria-labelledby="net-online-title"]')!;
      const out: string[] = [];
      for (const el of panel.querySelectorAll('*')) {
        const r = el.getBoundingClientRect();
        if (r.width > 0 && r.right > window.innerWidth + 0.5) out.push(el.outerHTML.slice(0, 80));
      }
      return out;
    });
    expect(cut).toEqual([]);
    await phone.getByTestId('control-join').tap();
    await expect.poll(() => state(phone)).toBe('waiting for the other player');
    await desk.goto(
      `${online.server.url}${await phone.getByTestId('link-room-tab').getAttribute('href')}`,
    );
    for (const p of [phone, desk]) {
      await expect.poll(() => state(p), { timeout: 30_000 }).toBe('running');
    }
    expect(await phone.getByTestId('canvas-online').getAttribute('data-you')).toBe('1');
    expect(await desk.getByTestId('canvas-online').getAttribute('data-you')).toBe('2');
    // A thumb on the stick's right edge (a real touch: touch → pointer events → the sampler),
    // held until the phone's own player has moved 60 units right.
    await stick.scrollIntoViewIfNeeded();
    const box = (await stick.boundingBox())!;
    const cdp = await context.newCDPSession(phone);
    const at = { x: box.x + box.width * 0.95, y: box.y + box.height / 2, id: 1 };
    const x0 = await youX(phone);
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [at] });
    await expect.poll(() => youX(phone), { timeout: 30_000 }).toBeGreaterThan(x0 + 60);
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    await phone.getByTestId('touch-fire').tap();
    const got = await finals([phone, desk]);
    expect(got[0]!['readout-online-final-hash']).toBe(got[1]!['readout-online-final-hash']);
    // The game and its controls, as the phone's screen shows them.
    await phone.getByTestId('canvas-online').scrollIntoViewIfNeeded();
    await phone.screenshot({ path: path.join(shots, 'network-people-phone.png') });
    expect(await horizontalOverflow(phone)).toBe(0);
    expect(problems).toEqual([]);
    expect(deskProblems).toEqual([]);
    await desk.close();
    await context.close();
  });

  it('peer to peer (WebRTC): page 1 hosts the relay, page 2 joins it; the same end on both', async () => {
    const ticks = 600;
    const pages = await Promise.all([0, 1].map(() => online.browser.newPage()));
    const problems = pages.map((p) => watch(p));
    const [one, two] = pages as [Page, Page];
    await one.goto(`${online.server.url}#/network?room=people-p2p&ticks=${ticks}&p2p=1`);
    expect(await one.getByTestId('control-online-p2p').getAttribute('aria-pressed')).toBe('true');
    await one.getByTestId('control-join').click();
    await expect.poll(() => state(one)).toBe('waiting for the other player');
    expect(await one.getByTestId('readout-online-via').getAttribute('data-value')).toBe(
      'WebRTC, hosting',
    );
    // The second tab's link carries the room's invite: nobody joins the host without it.
    const link = await one.getByTestId('link-room-tab').getAttribute('href');
    expect(link).toMatch(
      new RegExp(`^#/network\\?room=people-p2p&ticks=${ticks}&p2p=1&invite=[0-9a-f]{32}&join=1$`),
    );
    await two.goto(`${online.server.url}${link}`);
    for (const p of pages) await expect.poll(() => state(p), { timeout: 40_000 }).toBe('running');
    const via = await two.getByTestId('readout-online-via').getAttribute('data-value');
    for (const [i, p] of pages.entries()) {
      expect(await p.getByTestId('canvas-online').getAttribute('data-you')).toBe(String(i + 1));
    }
    const start = await youX(two);
    await two.getByTestId('canvas-online').click();
    await two.keyboard.down('KeyA');
    await expect.poll(() => youX(two), { timeout: 30_000 }).toBeLessThan(start - 60);
    await two.keyboard.up('KeyA');
    const got = await finals(pages);
    expect(got[0]!['readout-online-final-hash']).toBe(got[1]!['readout-online-final-hash']);
    for (const r of got) expect(r['readout-online-desyncs']).toBe('0');
    expect(via).toBe('WebRTC, direct');
    expect(problems).toEqual([[], []]);
    for (const p of pages) await p.close();
  });
});
