/**
 * Every chapter in the registry (`CHAPTERS` of apps/lab/src/chapters.ts), at a laptop's 1440×900
 * and a phone's 390×844: it opens under its own title, runs its animation frames, and leaves no
 * console error or warning, no page error, no failed request and no sideways scrolling — also when
 * the reader goes on to the next chapter (each one is torn down). A chapter is tested here the
 * moment it is registered.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { CHAPTERS } from '../apps/lab/src/chapters.js';
import { horizontalOverflow, phonePage, shots, useHighscoreServer, watch } from './harness.js';

/** The lab as `fixedstep serve` serves it: with the highscore API the game chapters read. */
const api = useHighscoreServer('chapters');

/** Open `id`'s chapter and wait until it has drawn a few animation frames. */
async function open(page: Page, id: string, title: string): Promise<void> {
  await page.goto(`${api.url}#/${id}`);
  await expect.poll(() => page.locator('main h1').textContent()).toBe(title);
  // Frames, not a sleep: three animation frames after the chapter mounted.
  await page.evaluate(
    () =>
      new Promise<void>((resolve) => {
        let n = 0;
        const tick = () => {
          if (++n === 3) resolve();
          else requestAnimationFrame(tick);
        };
        requestAnimationFrame(tick);
      }),
  );
}

/**
 * Every chapter in turn on `page` (whose problems `problems` collects): it opens, passes `check`,
 * does not scroll sideways, is photographed as `chapter-<id>-<device>`, and has left no problem.
 */
async function expectEachOpens(
  page: Page,
  problems: readonly string[],
  device: string,
  check: (c: (typeof CHAPTERS)[number]) => Promise<void> = () => Promise.resolve(),
): Promise<void> {
  for (const c of CHAPTERS) {
    await open(page, c.id, c.title);
    await check(c);
    expect({ chapter: c.id, overflow: await horizontalOverflow(page) }).toEqual({
      chapter: c.id,
      overflow: 0,
    });
    await page.screenshot({ path: path.join(shots, `chapter-${c.id}-${device}.png`) });
    expect({ chapter: c.id, problems }).toEqual({ chapter: c.id, problems: [] });
  }
}

describe('every registered chapter', () => {
  it('has a unique id, a number in order and a title', () => {
    expect(new Set(CHAPTERS.map((c) => c.id)).size).toBe(CHAPTERS.length);
    expect(CHAPTERS.map((c) => c.number)).toEqual(CHAPTERS.map((_, i) => i + 1));
    for (const c of CHAPTERS) expect(c.id).toMatch(/^[a-z0-9-]+$/);
  });

  it('opens cleanly at 1440×900, one after another', async () => {
    const page = await api.lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    await expectEachOpens(page, watch(page), 'desktop', async (c) => {
      expect(await page.title()).toBe(`${c.number}. ${c.title} — fixedstep lab`);
      expect(await page.locator('main .eyebrow').textContent()).toBe(`Chapter ${c.number}`);
    });
    await page.close();
  });

  it('opens cleanly on a phone (390×844), one after another', async () => {
    const { context, page, problems } = await phonePage(api.lab.browser);
    await expectEachOpens(page, problems, 'phone');
    await context.close();
  });
});
