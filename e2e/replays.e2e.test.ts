/**
 * Chapter 5 in a real browser: the chapter opens with a sample replay playing; a replay opened on
 * purpose (a bot game, "Watch replay" after a game) plays in view at 1440×900; a recorded bot game
 * plays back identically at 30 Hz and at 144 Hz (the same state hash at the same tick, equal to
 * the one in the file); the file downloads, reads back with `readReplay` and loads again; garbage
 * is refused with a message naming the problem.
 */
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { readReplay } from 'fixedstep';
import {
  expectFits,
  num,
  phonePage,
  readouts,
  shots,
  useHighscoreServer,
  value,
  watch,
} from './harness.js';

/** The lab with the highscore API (the replay view shows the game's table). */
const api = useHighscoreServer('replays');

async function openBotGame(page: Page, game: string): Promise<void> {
  await page.goto(`${api.url}#/replays`);
  await expect.poll(() => page.title()).toBe('5. Replays — fixedstep lab');
  await page.getByTestId(`control-bot-game-${game}`).click();
  await page.getByTestId('control-record-bot').click();
  await page.getByTestId('replay-view').waitFor();
  await expect.poll(() => value(page, 'replay-verified')).toBe('ok');
}

function playing(page: Page): Promise<string | null> {
  return page.getByTestId('control-play').getAttribute('aria-pressed');
}

/** Pause playback (a replay opens playing). */
async function pausePlayback(page: Page): Promise<void> {
  if ((await playing(page)) === 'true') await page.getByTestId('control-play').click();
  await expect.poll(() => playing(page)).toBe('false');
}

async function playAt(page: Page, hz: number, skips: number): Promise<void> {
  await pausePlayback(page);
  await page.getByTestId(`control-hz-${hz}`).click();
  await page.getByTestId('control-to-start').click();
  await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(0);
  await page.getByTestId('control-play').click();
  for (let i = 0; i < skips; i++) await page.getByTestId('control-skip').click();
  await pausePlayback(page);
}

/** The player — the game and its transport — lies inside the window, the transport right under the game. */
async function playerInView(page: Page): Promise<void> {
  const box = async (sel: string) => {
    const b = await page.locator(sel).boundingBox();
    if (!b) throw new Error(`${sel} has no box`);
    return b;
  };
  const viewport = page.viewportSize()!;
  const frame = await box('.replay-main > .game-frame');
  const transport = await box('.replay-main > .controls');
  expect(frame.y).toBeGreaterThanOrEqual(0);
  expect(transport.y + transport.height).toBeLessThanOrEqual(viewport.height);
  // No empty gap between the game and its controls.
  expect(transport.y - (frame.y + frame.height)).toBeLessThanOrEqual(16);
}

/** Playback runs: the tick moves on. */
async function ticking(page: Page): Promise<void> {
  expect(await playing(page)).toBe('true');
  const t0 = num(await readouts(page), 'replay-tick');
  await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBeGreaterThan(t0);
}

describe('chapter 5, replays', () => {
  it('opens with a sample playing; a replay opened on purpose plays in view', async () => {
    const page = await api.lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
    const problems = watch(page);
    await page.goto(`${api.url}#/replays`);
    await page.getByTestId('replay-view').waitFor();
    expect(await page.locator('#view-title').textContent()).toBe('Replay — Runner');
    await expect.poll(() => value(page, 'replay-verified')).toBe('ok');
    await ticking(page);
    // What the file holds, from its own sections.
    const facts = await readouts(page);
    const contents = (await page.getByTestId('replay-contents').textContent()) ?? '';
    const bytes = (n: number) => String(n).replace(/\B(?=(\d{3})+(?!\d))/g, '\u202f');
    expect(contents).toContain(`is ${bytes(num(facts, 'replay-size'))} bytes`);
    expect(contents).toContain(`in ${bytes(num(facts, 'replay-inputs'))} B`);

    await page.getByTestId('control-bot-game-ctf').click();
    await page.getByTestId('control-record-bot').click();
    await expect
      .poll(() => page.locator('#view-title').textContent())
      .toBe('Replay — Capture the flag');
    await playerInView(page);
    await ticking(page);
    await page.screenshot({ path: path.join(shots, 'replays-open.png') });

    // "Watch replay" after a game: the replays chapter opens with it playing, in view.
    await page.goto(`${api.url}#/games?game=survival&seed=4&bot=1`);
    await page.getByTestId('readout-tick').waitFor();
    await page.getByTestId('control-skip').click();
    await page.getByTestId('control-end').click();
    await page.getByTestId('control-watch-replay').click();
    await expect.poll(() => page.title()).toBe('5. Replays — fixedstep lab');
    await expect.poll(() => page.locator('#view-title').textContent()).toBe('Replay — Survival');
    await playerInView(page);
    await ticking(page);
    await page.screenshot({ path: path.join(shots, 'replays-watch.png') });
    expect(problems).toEqual([]);
    await page.close();
  });

  it('plays a replay identically at 30 Hz and at 144 Hz', async () => {
    const page = await api.lab.browser.newPage({ viewport: { width: 1440, height: 1000 } });
    const problems = watch(page);
    await openBotGame(page, 'ctf');
    const facts = await readouts(page);
    expect(num(facts, 'replay-ticks')).toBe(3600);
    expect(num(facts, 'replay-size')).toBeGreaterThan(1000);
    expect(num(facts, 'replay-bpm')).toBe(num(facts, 'replay-size'));
    expect(num(facts, 'replay-keyframes')).toBe(0); // inputs, seed and hashes only
    // A minute of the CTF bot: its inputs and a hash every 10 s.
    expect(num(facts, 'replay-size')).toBeLessThan(4096);
    expect(await page.getByTestId('replay-verified').textContent()).toContain(
      'reproduced every stored hash',
    );

    // Past the first stored hash after tick 0 (every 10 s) on each display.
    await playAt(page, 30, 3);
    const at30 = await readouts(page);
    expect(num(at30, 'replay-tick')).toBeGreaterThan(600);
    await playAt(page, 144, 3);
    const r = await readouts(page);
    const tick = num(r, 'replay-common-tick');
    expect(tick).toBeGreaterThanOrEqual(600);
    expect(tick % 600).toBe(0);
    expect(r['readout-replay-hash-30']).toMatch(/^[0-9a-f]{16}$/);
    expect(r['readout-replay-hash-144']).toBe(r['readout-replay-hash-30']);
    expect(r['readout-replay-hash-file']).toBe(r['readout-replay-hash-30']);
    expect(r['readout-replay-displays-equal']).toBe('true');

    // Seeking lands on the very state playing reached.
    await pausePlayback(page);
    await page.getByTestId('replay-timeline').evaluate((el, t) => {
      const input = el as HTMLInputElement;
      input.value = String(t);
      input.dispatchEvent(new Event('input', { bubbles: true }));
      input.dispatchEvent(new Event('change', { bubbles: true }));
    }, tick);
    await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(tick);
    expect(await value(page, 'readout-replay-hash')).toBe(r['readout-replay-hash-30']);
    // A tick back and forth again.
    await page.getByTestId('control-step-back').click();
    await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(tick - 1);
    await page.getByTestId('control-step-forward').click();
    await expect.poll(async () => num(await readouts(page), 'replay-tick')).toBe(tick);
    expect(await value(page, 'readout-replay-hash')).toBe(r['readout-replay-hash-30']);

    await page.locator('.replay-view').evaluate((el) => {
      el.scrollIntoView({ block: 'start' });
    });
    await page.screenshot({ path: path.join(shots, 'replays.png') });

    // On the page's real animation frames (16×, so it is quick) the replay reaches the same states.
    await page.getByTestId('control-real-clock').click();
    await page.getByTestId('control-speed-16').click();
    await page.getByTestId('control-to-start').click();
    await page.getByTestId('control-play').click();
    await expect
      .poll(async () => num(await readouts(page), 'replay-tick'), { timeout: 60_000 })
      .toBeGreaterThan(tick + 120);
    await pausePlayback(page);
    const real = await readouts(page);
    expect(num(real, 'replay-common-tick')).toBeGreaterThanOrEqual(tick);
    expect(real['readout-replay-hash-real']).toMatch(/^[0-9a-f]{16}$/);
    expect(real['readout-replay-hash-real']).toBe(real['readout-replay-hash-30']);
    expect(real['readout-replay-hash-real']).toBe(real['readout-replay-hash-144']);
    expect(real['readout-replay-displays-equal']).toBe('true');
    expect(problems).toEqual([]);
    await page.close();
  });

  it('downloads a file that reads back, and loads it again', async () => {
    const context = await api.lab.browser.newContext({
      viewport: { width: 1280, height: 900 },
      acceptDownloads: true,
    });
    const page = await context.newPage();
    const problems = watch(page);
    await openBotGame(page, 'survival');
    const ticks = num(await readouts(page), 'replay-ticks');
    const [download] = await Promise.all([
      page.waitForEvent('download'),
      page.getByTestId('control-download-replay').click(),
    ]);
    expect(download.suggestedFilename()).toMatch(/^survival-seed-\d+-[\dT-]+\.fsr$/);
    const file = await download.path();
    const bytes = new Uint8Array(readFileSync(file));
    const replay = readReplay(bytes, { gameId: 'survival' });
    expect(replay.tickCount).toBe(ticks);
    expect(replay.byteLength).toBe(num(await readouts(page), 'replay-size'));

    // Back in through the file input.
    await page.getByTestId('control-load-file').setInputFiles({
      name: 'mine.fsr',
      mimeType: 'application/octet-stream',
      buffer: Buffer.from(bytes),
    });
    await expect
      .poll(() => page.locator('.replay-view .section-intro').first().textContent())
      .toContain('the file mine.fsr');
    await expect.poll(() => value(page, 'replay-verified')).toBe('ok');
    expect(num(await readouts(page), 'replay-ticks')).toBe(ticks);
    expect(await page.getByTestId('replay-error').isHidden()).toBe(true);
    expect(problems).toEqual([]);
    await context.close();
  });

  it('refuses garbage with a message that names the problem', async () => {
    const page = await api.lab.browser.newPage({ viewport: { width: 1280, height: 900 } });
    const problems = watch(page);
    await page.goto(`${api.url}#/replays`);
    await page.getByTestId('control-load-file').waitFor();
    await page.getByTestId('control-load-file').setInputFiles({
      name: 'holiday.jpg',
      mimeType: 'image/jpeg',
      buffer: Buffer.from('\xff\xd8\xff\xe0 not a replay at all, just some bytes', 'latin1'),
    });
    const error = page.getByTestId('replay-error');
    await error.waitFor();
    expect(await error.getAttribute('data-code')).toBe('BAD_MAGIC');
    const text = (await error.textContent()) ?? '';
    expect(text).toContain('not a fixedstep replay file');
    expect(text).toContain('BAD_MAGIC');

    // A real replay with one byte changed: the checksum catches it.
    await page.getByTestId('control-record-bot').click();
    await expect.poll(() => value(page, 'replay-verified')).toBe('ok');
    expect(await error.isHidden()).toBe(true);
    await pausePlayback(page);
    const [download] = await Promise.all([
      page.waitForEvent('download'),
      page.getByTestId('control-download-replay').click(),
    ]);
    const damaged = Buffer.from(readFileSync(await download.path()));
    damaged[50] = damaged[50]! ^ 0x01;
    await page.getByTestId('control-load-file').setInputFiles({
      name: 'damaged.fsr',
      mimeType: 'application/octet-stream',
      buffer: damaged,
    });
    await expect.poll(() => error.getAttribute('data-code')).toBe('BAD_CHECKSUM');
    expect(await error.textContent()).toContain('damaged');
    await page.screenshot({ path: path.join(shots, 'replays-error.png') });
    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen', async () => {
    const { context, page, problems } = await phonePage(api.lab.browser);
    await openBotGame(page, 'runner');
    await ticking(page);
    await expectFits(page, 'replays-phone');
    expect(problems).toEqual([]);
    await context.close();
  });
});
