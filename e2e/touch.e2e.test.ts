/**
 * Touch play in chapter 9 on a phone (390 × 844, touch): the on-screen controls feed the same input
 * pipeline as the keyboard, so a tap lands on a tick exactly like a key. The runner is played past
 * its first block by a tap on Jump at the tick the bot would jump; a CTF round is played with the
 * stick and Fire, and its replay shows each tap on exactly one tick and verifies.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { CDPSession, Page } from 'playwright-core';
import { isDown, readReplay, verifyReplay, wasPressed } from 'fixedstep';
import { GAMES, RunnerButtons, RunnerGame, ShooterButtons, runnerBot } from '@fixedstep/games';
import { horizontalOverflow, num, phonePage, readouts, shots, skip, useGames } from './harness.js';

// The games chapter asks the highscore API for its table: serve the lab with it.
const games = useGames('touch');

async function tick(page: Page): Promise<number> {
  return num(await readouts(page), 'tick');
}

/** Step the paused game one tick at a time up to `target`. */
async function stepTo(page: Page, target: number): Promise<void> {
  for (let t = await tick(page); t < target; t++) {
    await page.getByTestId('control-step-tick').click();
    await expect.poll(() => tick(page)).toBe(t + 1);
  }
}

/** The tick at which the runner's bot first jumps with `seed`: the jump that clears the first block. */
function firstJump(seed: number): number {
  const game = new RunnerGame({ seed, players: 1 });
  for (let t = 0; t < 2000; t++) {
    const input = runnerBot(game, 0);
    if (isDown(input, RunnerButtons.jump)) return t;
    game.step([input]);
  }
  throw new Error('the bot never jumps');
}

/** A finger on the screen through the DevTools protocol (Playwright's touchscreen only taps). */
async function touch(cdp: CDPSession, type: 'touchStart' | 'touchMove' | 'touchEnd', x = 0, y = 0) {
  await cdp.send('Input.dispatchTouchEvent', {
    type,
    touchPoints: type === 'touchEnd' ? [] : [{ x, y, id: 1 }],
  });
}

describe('touch play on a phone', () => {
  it('shows thumb-sized controls on a touch screen and plays the runner past its first block', async () => {
    const { context, page, problems } = await phonePage(games.lab.browser);
    await games.open(page, 'game=runner&seed=3');
    const jump = page.getByTestId('touch-jump');
    await expect.poll(() => jump.isVisible()).toBe(true);
    const box = (await jump.boundingBox())!;
    expect(Math.min(box.width, box.height)).toBeGreaterThanOrEqual(44); // a thumb, not a fingertip
    await page.getByTestId('control-speed-0.25').click();
    await page.getByTestId('control-step-tick').click(); // starts the game, paused, at tick 1
    await expect.poll(() => tick(page)).toBe(1);
    // While paused, a tap lands on the next tick: be at the tick before the bot's jump, tap, step.
    const at = firstJump(3);
    await skip(page, 2); // 150 ticks at a quarter speed
    await stepTo(page, at);
    await jump.tap();
    await page.getByTestId('control-step-tick').click();
    await expect.poll(async () => num(await readouts(page), 'jumps')).toBe(1);
    await skip(page, 1); // 75 ticks on: over the block and landed
    const r = await readouts(page);
    expect(num(r, 'tick')).toBeGreaterThanOrEqual(at + 75);
    expect(num(r, 'highscore')).toBe(0); // no crash: a crash would have set a highscore
    expect(num(r, 'score')).toBeGreaterThan(0);
    await page.evaluate(() => {
      document.querySelector('[data-testid="canvas-game"]')!.scrollIntoView({ block: 'start' });
    });
    await page.screenshot({ path: path.join(shots, 'games-touch-runner.png') });
    expect(problems).toEqual([]);
    await context.close();
  });

  it('plays a CTF round with the stick and Fire; each tap is on exactly one tick of the replay, which verifies', async () => {
    const { context, page, problems } = await phonePage(games.lab.browser);
    const cdp = await context.newCDPSession(page);
    await games.open(page, 'game=ctf&seed=5');
    const stick = page.getByTestId('touch-stick');
    const fire = page.getByTestId('touch-fire');
    await expect.poll(() => stick.isVisible()).toBe(true);
    await page.getByTestId('control-step-tick').click(); // start, paused
    await expect.poll(() => tick(page)).toBe(1);
    await stick.scrollIntoViewIfNeeded();
    const s = (await stick.boundingBox())!;
    const cx = s.x + s.width / 2;
    const cy = s.y + s.height / 2;
    // Hold the stick right (and a little down), tap Fire three times, a few ticks apart.
    await touch(cdp, 'touchStart', cx + s.width * 0.45, cy + s.height * 0.1);
    const taps: number[] = [];
    for (let k = 0; k < 3; k++) {
      await stepTo(page, (await tick(page)) + 10);
      taps.push(await tick(page));
      await fire.tap();
    }
    await stepTo(page, (await tick(page)) + 20);
    await touch(cdp, 'touchEnd');
    await stepTo(page, (await tick(page)) + 5);
    await page.evaluate(() => {
      document.querySelector('[data-testid="canvas-game"]')!.scrollIntoView({ block: 'start' });
    });
    await page.screenshot({ path: path.join(shots, 'games-touch-ctf.png') });
    await page.getByTestId('control-end').click();
    await page.getByTestId('control-watch-replay').click();
    const b64 = await page.evaluate(() => {
      const text = sessionStorage.getItem('fixedstep.lastReplay');
      return text === null ? '' : (JSON.parse(text) as { b64: string }).b64;
    });
    const bytes = new Uint8Array(Buffer.from(b64, 'base64'));
    const replay = readReplay(bytes);
    const inputs = Array.from({ length: replay.tickCount }, (_, t) => replay.input(t, 0));
    // Each tap: pressed on exactly one tick, the tick after the one the game was paused at.
    const pressedAt = inputs.flatMap((x, t) => (wasPressed(x, ShooterButtons.fire) ? [t] : []));
    expect(pressedAt).toEqual(taps);
    // The stick held right the whole time (from the tick after it went down), never left or up.
    const right = inputs.filter((x) => isDown(x, ShooterButtons.right)).length;
    expect(right).toBeGreaterThanOrEqual(50);
    expect(inputs.some((x) => isDown(x, ShooterButtons.left) || isDown(x, ShooterButtons.up))).toBe(
      false,
    );
    expect(verifyReplay(bytes, GAMES).ok).toBe(true);
    expect(problems).toEqual([]);
    await context.close();
  });
});

describe('the lab on a phone says what a phone can do', () => {
  it('the network chapter’s three-model table scrolls sideways on a phone and says so; on a laptop it fits', async () => {
    const { context, page, problems } = await phonePage(games.lab.browser);
    await page.goto(`${games.lab.server.url}#/network`);
    await page.getByTestId('readout-lockstep-hashes-equal').waitFor();
    const box = page.getByTestId('net-compare-box');
    await box.scrollIntoViewIfNeeded();
    await expect.poll(() => box.getAttribute('data-overflows')).toBe('true');
    expect(await page.getByTestId('net-compare-box-hint').isVisible()).toBe(true);
    const lastHead = page.getByTestId('net-compare').locator('thead th').last();
    // Cut off at the window's edge, and the box shows more to its right (not its left).
    expect((await lastHead.boundingBox())!.x).toBeGreaterThan(390);
    expect(await box.getAttribute('class')).toBe('scroll-box more-right');
    expect(await horizontalOverflow(page)).toBe(0); // the table scrolls, not the page
    await page.screenshot({ path: path.join(shots, 'network-phone-table.png') });
    // Scrolled to its end: the last column is in the window, the shadow has moved to the left.
    await box.locator('.scroll-box-view').evaluate((v) => {
      v.scrollLeft = v.scrollWidth;
    });
    await expect.poll(() => box.getAttribute('class')).toBe('scroll-box more-left');
    const head = (await lastHead.boundingBox())!;
    expect(head.x + head.width).toBeLessThanOrEqual(390);
    await page.screenshot({ path: path.join(shots, 'network-phone-table-end.png') });
    expect(problems).toEqual([]);
    await context.close();

    const wide = await games.lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    await wide.goto(`${games.lab.server.url}#/network`);
    await wide.getByTestId('readout-lockstep-hashes-equal').waitFor();
    const wideBox = wide.getByTestId('net-compare-box');
    await wideBox.scrollIntoViewIfNeeded();
    await expect.poll(() => wideBox.getAttribute('class')).toBe('scroll-box');
    expect(await wideBox.getAttribute('data-overflows')).toBe('false');
    expect(await wide.getByTestId('net-compare-box-hint').isVisible()).toBe(false);
    await wide.close();
  });

  it('the runner’s Play sits under the game on a phone, says tap, and the intro says touch; a laptop says keyboard', async () => {
    const { context, page, problems } = await phonePage(games.lab.browser);
    await games.open(page, 'game=runner&seed=3');
    const overlay = page.getByTestId('start-overlay');
    await expect.poll(() => overlay.isVisible()).toBe(true);
    const canvas = (await page.getByTestId('canvas-game').boundingBox())!;
    const play = (await overlay.boundingBox())!;
    // Under the canvas, so nothing of the game (its HUD: SCORE / HIGHSCORE) is covered.
    expect(play.y).toBeGreaterThanOrEqual(canvas.y + canvas.height - 0.5);
    const hint = (await overlay.textContent()) ?? '';
    expect(hint).toContain('tap Jump under the game');
    expect(hint).not.toContain('Space');
    const lede = (await page.locator('.lede').textContent()) ?? '';
    expect(lede).toContain('Play them with touch on any display');
    expect(lede).not.toContain('keyboard');
    await page.screenshot({ path: path.join(shots, 'games-phone-play.png') });
    // Tapping Jump starts the game, as the hint says.
    await page.getByTestId('touch-jump').tap();
    await expect.poll(() => overlay.isVisible()).toBe(false);
    await expect.poll(() => tick(page)).toBeGreaterThan(0);
    expect(problems).toEqual([]);
    await context.close();

    const wide = await games.lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    await games.open(wide, 'game=runner&seed=3');
    const wideOverlay = (await wide.getByTestId('start-overlay').boundingBox())!;
    const wideCanvas = (await wide.getByTestId('canvas-game').boundingBox())!;
    expect(wideOverlay.y).toBeLessThan(wideCanvas.y + wideCanvas.height); // over the big canvas
    expect(await wide.getByTestId('start-overlay').textContent()).toContain(
      'press Space with the game focused',
    );
    expect(await wide.locator('.lede').textContent()).toContain('Play them with the keyboard on');
    expect(await wide.getByTestId('touch-controls').isVisible()).toBe(false);
    await wide.close();
  });
});
