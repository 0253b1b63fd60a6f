/**
 * The lab's animation frames in a real browser: one write phase per frame — next to no forced
 * layout, counted in a DevTools trace of 60 frames (before it, the loop chapter forced about 5 a
 * frame and the physics chapter 4.5) — and a chapter whose demos are all off screen stands still
 * until one is back (counted in frames, not time).
 */
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { mainThreadWork } from '../bench/lib/main-thread.js';
import { animationFrames, traceFrames } from '../bench/lib/page-trace.js';
import { useLab, value, watch } from './harness.js';

const lab = useLab();

async function open(page: Page, route: string): Promise<void> {
  await page.goto(`${lab.server.url}#/${route}`);
  await page.getByTestId('readout-clock').waitFor();
  await page.evaluate(`document.querySelector('main canvas').scrollIntoView({ block: 'center' })`);
  await animationFrames(page, 10);
}

/** The main thread's work over `n` frames, from a DevTools trace. */
async function mainThreadOver(page: Page, n: number) {
  const cdp = await page.context().newCDPSession(page);
  const events = await traceFrames(page, cdp, n);
  await cdp.detach();
  return mainThreadWork(events);
}

describe('the lab’s frames', () => {
  it.each(['loop', 'physics', 'final-fixes'])(
    '%s: 60 running frames force (next to) no layout',
    async (route) => {
      const page = await lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
      const problems = watch(page);
      await open(page, route);
      const before = Number(await value(page, 'readout-clock'));
      const work = await mainThreadOver(page, 60);
      // It ran (the clock moved), laid the page out, and never inside script.
      expect(Number(await value(page, 'readout-clock'))).toBeGreaterThan(before);
      expect(work.layouts).toBeGreaterThan(0);
      // Before the write phase: about 300 (5 a frame in chapter 1). A stray one may come from a
      // chart being laid out for the first time inside its observer.
      expect(work.forcedLayouts).toBeLessThanOrEqual(2);
      expect(problems).toEqual([]);
      await page.close();
    },
  );

  it('stands still while every demo of the chapter is off screen, and goes on when one is back', async () => {
    // At 700 px high, the top of chapter 1 (its title and lede) is far enough from its demos.
    const page = await lab.browser.newPage({ viewport: { width: 1440, height: 700 } });
    await open(page, 'loop');
    const clock = async () => Number(await value(page, 'readout-clock'));
    await expect.poll(clock).toBeGreaterThan(0);
    // A place on the page with every canvas more than the observer's 200 px margin away.
    const y = await page.evaluate(`(() => {
      const spans = [...document.querySelectorAll('main canvas')].map((c) => {
        const r = c.getBoundingClientRect();
        return [r.top + scrollY, r.bottom + scrollY];
      });
      const max = document.documentElement.scrollHeight - innerHeight;
      for (let y = 0; y <= max; y += 50) {
        if (spans.every(([a, b]) => b < y - 250 || a > y + innerHeight + 250)) return y;
      }
      return -1;
    })()`);
    expect(y).toBeGreaterThanOrEqual(0);
    await page.evaluate(`window.scrollTo(0, ${String(y)})`);
    await animationFrames(page, 10); // the observers have spoken, the last write is out
    const stopped = await clock();
    await animationFrames(page, 30);
    expect(await clock()).toBe(stopped);
    expect(await page.getByTestId('control-pause').getAttribute('aria-pressed')).toBe('false');
    await page.evaluate(
      `document.querySelector('main canvas').scrollIntoView({ block: 'center' })`,
    );
    await expect.poll(clock).toBeGreaterThan(stopped);
    await page.close();
  });
});
