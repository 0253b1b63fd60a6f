/**
 * Chapter 9 in a real browser: the three games run with their bots, the keyboard plays the
 * runner, the variable-Δt switch lets bullets through walls that the fixed step keeps shut, and a
 * played game's replay is submitted to the highscore server (accepted with a rank; refused with a
 * faked score) and watched: the replay shows the live game's hash at the same tick.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import {
  expectFits,
  num,
  pause,
  phonePage,
  readouts,
  shoot,
  shots,
  useGames,
  value,
  watch,
} from './harness.js';

const games = useGames('games');

async function skip(page: Page, times: number): Promise<void> {
  const before = Number(await value(page, 'readout-clock'));
  for (let i = 0; i < times; i++) await page.getByTestId('control-skip').click();
  await expect
    .poll(async () => Number(await value(page, 'readout-clock')))
    .toBeGreaterThanOrEqual(before + 5000 * times);
}

/** Set a range input the way a drag does: its value, then `input` and `change`. */
async function setRange(page: Page, testId: string, v: number): Promise<void> {
  await page.getByTestId(testId).evaluate((el, x) => {
    const input = el as HTMLInputElement;
    input.value = String(x);
    input.dispatchEvent(new Event('input', { bubbles: true }));
    input.dispatchEvent(new Event('change', { bubbles: true }));
  }, v);
}

/** Scroll the controls to the top of the window, the game below them (for screenshots). */
async function showGame(page: Page): Promise<void> {
  await page.locator('.play').evaluate((el) => {
    el.scrollIntoView({ block: 'start' });
  });
}

describe('chapter 9, games', () => {
  const HUD: Record<string, string[]> = {
    runner: ['score', 'highscore', 'jumps'],
    ctf: ['kills', 'flags', 'deaths', 'through-walls'],
    survival: ['kills', 'lives', 'wave', 'enemies', 'through-walls'],
  };

  const GOALS: Record<string, (r: Record<string, string>) => Record<string, boolean>> = {
    runner: (r) => ({
      'score > 1000': num(r, 'score') > 1000,
      jumped: num(r, 'jumps') > 0,
      'apex 1.9333 m': Math.abs(num(r, 'jump-apex') - 1.9333) < 0.001,
    }),
    ctf: (r) => ({
      'kills or deaths': num(r, 'kills') + num(r, 'deaths') > 0,
      'nothing through walls': num(r, 'through-walls') === 0,
    }),
    survival: (r) => ({
      'kills > 5': num(r, 'kills') > 5,
      'all 15 lives': num(r, 'lives') === 15,
      'wave ≥ 2': num(r, 'wave') >= 2,
      'nothing through walls': num(r, 'through-walls') === 0,
    }),
  };

  for (const id of ['runner', 'ctf', 'survival']) {
    it(`${id}: runs with the bot, the HUD numbers move, no console problems`, async () => {
      const page = await games.lab.browser.newPage({ viewport: { width: 1440, height: 1000 } });
      const problems = watch(page);
      await games.open(page, `game=${id}&seed=7`);
      expect(await page.getByTestId('start-overlay').isVisible()).toBe(true);
      const start = await readouts(page);
      expect(num(start, 'tick')).toBe(0);
      expect(Object.keys(start)).toEqual(
        expect.arrayContaining(HUD[id]!.map((k) => `readout-${k}`)),
      );

      await page.getByTestId('control-bot').click();
      await skip(page, 3);
      await pause(page);
      const r = await readouts(page);
      expect(num(r, 'tick')).toBeGreaterThanOrEqual(900);
      expect(r['readout-hash']).toMatch(/^[0-9a-f]{16}$/);
      expect(r['readout-hash']).not.toBe(start['readout-hash']);
      // What 15 s of the bot must have done, per game (every entry must hold).
      const goals = GOALS[id]!(r);
      expect(Object.entries(goals).filter(([, ok]) => !ok)).toEqual([]);
      expect(num(r, 'replay-bytes')).toBeGreaterThan(0);
      // For the picture: a moment when most of capture the flag's players are alive.
      if (id === 'ctf') await skip(page, 1);
      if (id === 'survival') {
        // For the picture: nobody shoots for a moment, so the next wave closes in.
        await page.getByTestId('control-bot').click();
        await page.getByTestId('control-pause').click();
        await page.waitForFunction(
          () =>
            Number(
              document.querySelector('[data-testid="readout-enemies"]')?.getAttribute('data-value'),
            ) >= 6,
          undefined,
          { timeout: 60_000 },
        );
        await pause(page);
      }
      await showGame(page);
      await page.screenshot({ path: path.join(shots, `games-${id}.png`) });
      expect(problems).toEqual([]);
      await page.close();
    });
  }

  it('the variable-Δt switch lets bullets through walls at 30 Hz; the fixed step lets none', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1440, height: 1000 } });
    const problems = watch(page);
    await games.open(page, 'game=ctf&seed=7&loop=variable');
    await page.getByTestId('control-hz-30').click();
    await setRange(page, 'control-jitter', 30);
    await page.getByTestId('control-bot').click();
    await skip(page, 2);
    await pause(page);
    const naive = await readouts(page);
    await showGame(page);
    await page.screenshot({ path: path.join(shots, 'games-ctf-variable.png') });
    expect(num(naive, 'through-walls')).toBeGreaterThan(0);
    expect(num(naive, 'max-dt')).toBeGreaterThan(34);

    // Same seed, same display, the fixed step.
    await page.getByTestId('control-loop-fixed').click();
    await expect.poll(async () => num(await readouts(page), 'tick')).toBeLessThan(60);
    await skip(page, 2);
    await pause(page);
    const fixed = await readouts(page);
    expect(num(fixed, 'tick')).toBeGreaterThanOrEqual(600);
    expect(num(fixed, 'through-walls')).toBe(0);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('under a variable Δt at 30 Hz the runner’s jumps are lower than the fixed step’s', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await games.open(page, 'game=runner&seed=1&loop=variable');
    await page.getByTestId('control-hz-30').click();
    await page.getByTestId('control-bot').click();
    await skip(page, 2);
    await pause(page);
    const r = await readouts(page);
    expect(num(r, 'jumps')).toBeGreaterThan(0);
    expect(num(r, 'jump-apex')).toBeLessThan(1.9333 - 0.05);
    expect(await page.getByTestId('readout-jump-apex').getAttribute('class')).toContain('warn');
    expect(await page.getByTestId('readout-replay-bytes').textContent()).toBe('not recorded');
    expect(problems).toEqual([]);
    await page.close();
  });

  it('slows time down and steps one tick at a time under the fixed step', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await games.open(page, 'game=ctf&seed=3');
    await page.getByTestId('control-hz-60').click();
    await page.getByTestId('control-bot').click();
    await pause(page);
    const start = num(await readouts(page), 'tick');
    await page.getByTestId('control-speed-0.25').click();
    await skip(page, 1);
    const slow = num(await readouts(page), 'tick');
    // 5 s of display at a quarter speed: 75 ticks of 1/60 s (a frame or so either way).
    expect(slow - start).toBeGreaterThanOrEqual(74);
    expect(slow - start).toBeLessThanOrEqual(76);
    for (let i = 1; i <= 3; i++) {
      await page.getByTestId('control-step-tick').click();
      await expect.poll(async () => num(await readouts(page), 'tick')).toBe(slow + i);
    }
    // Back to 1×: the next 5 s run 300 ticks.
    await page.getByTestId('control-speed-1').click();
    await skip(page, 1);
    const normal = num(await readouts(page), 'tick') - (slow + 3);
    expect(normal).toBeGreaterThanOrEqual(298);
    expect(normal).toBeLessThanOrEqual(301);
    // A variable Δt has no time scale: the controls say so by being off.
    await page.getByTestId('control-loop-variable').click();
    expect(await page.getByTestId('control-step-tick').isDisabled()).toBe(true);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('plays the runner from the keyboard, with a visible focus ring', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await games.open(page, 'game=runner&seed=3');
    const canvas = page.getByTestId('canvas-game');
    await showGame(page);
    await page.screenshot({ path: path.join(shots, 'games-start.png') });
    // The clock stands still except when Skip moves it: key presses land on exact ticks, however
    // fast this machine is. A quarter speed makes one Skip 75 ticks (1.25 s of the game).
    await page.getByTestId('control-speed-0.25').click();
    await page.getByTestId('control-step-tick').click(); // starts the game, paused, at tick 1
    await expect.poll(async () => num(await readouts(page), 'tick')).toBe(1);
    await canvas.focus();
    await page.keyboard.press('Space');
    await skip(page, 1);
    const first = await readouts(page);
    expect(num(first, 'tick')).toBeGreaterThanOrEqual(74);
    expect(num(first, 'jumps')).toBe(1);
    await canvas.focus();
    await page.keyboard.press('ArrowUp');
    await skip(page, 1);
    await canvas.focus();
    const r = await readouts(page);
    expect(num(r, 'tick')).toBeGreaterThanOrEqual(148);
    expect(num(r, 'jumps')).toBe(2);
    expect(Math.abs(num(r, 'jump-apex') - 1.9333)).toBeLessThan(0.001);
    const outline = await canvas.evaluate((el) => getComputedStyle(el).outlineStyle);
    expect(outline).toBe('solid');
    await showGame(page);
    await page.screenshot({ path: path.join(shots, 'games-keyboard.png') });
    expect(problems).toEqual([]);
    await page.close();
  });

  it('starts the game with its first key', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await games.open(page, 'game=runner&seed=3');
    expect(await page.getByTestId('start-overlay').isVisible()).toBe(true);
    await page.getByTestId('canvas-game').focus();
    await page.keyboard.press('Space');
    await expect.poll(async () => num(await readouts(page), 'tick')).toBeGreaterThan(0);
    expect(await page.getByTestId('start-overlay').isHidden()).toBe(true);
    await pause(page);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('submits the best run under the name typed after the game, refuses a faked score, and replays the same states', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1440, height: 1000 } });
    const problems = watch(page);
    await games.open(page, 'game=runner&seed=11');
    await page.getByTestId('control-bot').click();
    await skip(page, 2);
    await pause(page);
    const live = await readouts(page);
    const tick = num(live, 'tick');
    const hash = live['readout-hash']!;
    // The best run of the session: the highscore of the runs that crashed, or this one if better.
    const best = Math.max(num(live, 'score'), num(live, 'highscore'));

    await page.getByTestId('control-end').click();
    await page.getByTestId('after-game').waitFor();
    expect(await page.getByTestId('control-claimed-score').inputValue()).toBe(String(best));
    expect(await page.getByTestId('after-text').textContent()).toMatch(
      /The replay is [\d\u202f]+ bytes: the inputs of [\d\u202f]+ ticks in [\d\u202f]+ B/,
    );
    // The name is typed after the game: it still goes to the table.
    await page.getByTestId('control-name').fill('e2e after');
    await page.getByTestId('control-name').dispatchEvent('change');

    // A faked score first: the server re-simulates and refuses it.
    await page.getByTestId('control-claimed-score').fill(String(best + 5000));
    await page.getByTestId('control-submit-score').click();
    const result = page.getByTestId('submit-result');
    await expect.poll(() => result.getAttribute('data-value')).toBe('refused');
    expect(await result.getAttribute('data-code')).toBe('SCORE_MISMATCH');
    expect(await result.textContent()).toContain(
      `claimed ${best + 5000}, the replay scores ${best}`,
    );

    // The honest one.
    await page.getByTestId('control-claimed-score').fill(String(best));
    await page.getByTestId('control-submit-score').click();
    await expect.poll(() => result.getAttribute('data-value')).toBe('accepted');
    expect(await result.getAttribute('data-rank')).toBe('1');
    await expect
      .poll(() => page.locator('.hs-table tbody tr').first().textContent())
      .toContain('e2e after');
    await shoot(page, 'games-after');

    // The replay of the whole game, at the live game's tick, has the live game's hash.
    await page.getByTestId('control-watch-replay').click();
    await expect.poll(() => page.title()).toBe('5. Replays — fixedstep lab');
    await expect.poll(() => value(page, 'replay-verified')).toBe('ok');
    expect(num(await readouts(page), 'replay-ticks')).toBe(tick);
    await expect
      .poll(() => page.getByTestId('control-play').getAttribute('aria-pressed'))
      .toBe('true');
    await page.getByTestId('control-play').click(); // it opened playing: pause it
    await setRange(page, 'replay-timeline', tick - 100);
    await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(tick - 100);
    await setRange(page, 'replay-timeline', tick);
    await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(tick);
    expect(await value(page, 'readout-replay-hash')).toBe(hash);
    expect(num(await readouts(page), 'replay-hud-score')).toBe(num(live, 'score'));
    // The browser logs the refused submission's 422 itself; nothing else may appear.
    expect(problems).toEqual([
      'console.error: Failed to load resource: the server responded with a status of 422 (Unprocessable Entity)',
    ]);
    await page.close();
  });

  it('runs on the real clock too (the page’s own animation frames)', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await games.open(page, 'game=ctf&seed=2');
    await page.getByTestId('control-real-clock').click();
    await page.getByTestId('control-bot').click();
    expect(await page.getByTestId('control-skip').isDisabled()).toBe(true);
    await expect
      .poll(async () => num(await readouts(page), 'tick'), { timeout: 60_000 })
      .toBeGreaterThan(30);
    await pause(page);
    const r = await readouts(page);
    expect(num(r, 'through-walls')).toBe(0);
    expect(await page.locator('.play .status .mode').textContent()).toContain('real clock');
    expect(problems).toEqual([]);
    await page.close();
  });

  it('says so gracefully when the page has no highscore server', async () => {
    const page = await games.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems: string[] = [];
    page.on('pageerror', (e) => problems.push(e.message));
    await page.goto(`${games.lab.server.url}#/games?game=runner&seed=1`);
    await expect
      .poll(() => page.getByTestId('highscores-note').textContent())
      .toContain('no highscore server');
    expect(await page.getByTestId('highscores').getAttribute('data-state')).toBe('unavailable');
    expect(await page.getByTestId('control-submit-score').isDisabled()).toBe(true);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen', async () => {
    const { context, page, problems } = await phonePage(games.lab.browser);
    await page.goto(`${games.url}#/games?game=survival&seed=7`);
    await page.getByTestId('readout-tick').waitFor();
    await page.getByTestId('control-bot').click();
    await skip(page, 1);
    await pause(page);
    await expectFits(page, 'games-phone');
    expect(problems).toEqual([]);
    await context.close();
  });
});
