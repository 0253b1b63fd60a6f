/**
 * Chapter 10 in a real browser, at a laptop's 1440×900 and a phone's 390×844: Rapier's
 * WebAssembly loads from the page's own bundle (no request leaves the server), Fire knocks the
 * tower over (boxes turned, on the readouts and in the canvas's pixels), the replay's hash equals
 * the live run's at every tick, and the two network machines agree after rolling back. Driven by
 * Pause, Restart and Skip on the simulated display; every wait is on state, never on time.
 */
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import {
  expectFits,
  freshRun,
  num,
  readouts,
  realClockRuns,
  shoot,
  skip,
  useChapter,
  type Device,
} from './harness.js';

const chapter = useChapter(
  'rigid-bodies',
  '10. Rigid bodies — fixedstep lab',
  'readout-rapier-state',
);

/**
 * A watched page of `device` on the chapter once Rapier is loaded and the simulations run, paused
 * and restarted; and the requests it made that left the lab's own server (none are expected:
 * Rapier comes in the bundle).
 */
async function open(device?: Device): Promise<{ page: Page; problems: string[]; away: string[] }> {
  const { page, problems } = await chapter.newPage(device);
  const away: string[] = [];
  page.on('request', (req) => {
    if (!req.url().startsWith(chapter.lab.server.url) && !req.url().startsWith('data:')) {
      away.push(req.url());
    }
  });
  await chapter.goto(page);
  await expect
    .poll(() => page.getByTestId('readout-rapier-state').getAttribute('data-value'), {
      timeout: 60_000,
    })
    .toBe('ready');
  await freshRun(page);
  return { page, problems, away };
}

/** Pixels of `testId`'s canvas in the colour of a box turned past 10° (#fb7185). */
function turnedPixels(page: Page, testId: string): Promise<number> {
  return page.getByTestId(testId).evaluate((el) => {
    // Read a copy (one read per canvas: Chrome warns about a canvas read back again and again).
    const c = el as HTMLCanvasElement;
    const copy = document.createElement('canvas');
    copy.width = c.width;
    copy.height = c.height;
    const ctx = copy.getContext('2d')!;
    ctx.drawImage(c, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i]! - 232) < 24 && Math.abs(d[i + 1]! - 108) < 24 && d[i + 2]! > 100) n++;
    }
    return n;
  });
}

describe('chapter 10, rigid bodies', () => {
  it('fires, the tower falls, the replay matches every tick, both machines agree (1440×900)', async () => {
    const { page, problems, away } = await open();
    let r = await readouts(page);
    expect(num(r, 'knock-tick')).toBe(0);
    expect(num(r, 'knock-turned')).toBe(0);
    expect(await turnedPixels(page, 'canvas-live')).toBe(0);

    // Fire with the on-screen button (pointer down and up), then 5 s of the simulated display.
    await page.getByTestId('control-fire').click();
    await skip(page);
    r = await readouts(page);
    expect(num(r, 'knock-shots')).toBe(1);
    expect(num(r, 'knock-turned')).toBeGreaterThanOrEqual(5);
    expect(num(r, 'knock-top')).toBeLessThan(2);
    expect(await turnedPixels(page, 'canvas-live')).toBeGreaterThan(200);
    const recorded = num(r, 'knock-tick');
    expect(recorded).toBeGreaterThanOrEqual(290);

    // The F key fires too (the keyboard goes through the same sampler).
    await page.keyboard.press('KeyF');
    await skip(page);
    expect(num(await readouts(page), 'knock-shots')).toBe(2);

    // Replay the recording: its 10 s, re-simulated in the next 15; every tick's hash equal to the live run's.
    await page.getByTestId('control-replay').click();
    await skip(page, 3);
    await expect
      .poll(() => page.getByTestId('replay-verdict').getAttribute('data-value'))
      .toBe('true');
    r = await readouts(page);
    const ticks = num(r, 'replay-tick');
    expect(ticks).toBeGreaterThanOrEqual(recorded + 290);
    expect(num(r, 'replay-compared')).toBe(ticks + 1);
    expect(num(r, 'replay-different')).toBe(0);
    expect(r['readout-replay-hash']).toMatch(/^[0-9a-f]{16}$/);
    expect(r['readout-replay-hash']).toBe(r['readout-replay-live-hash']);
    expect(await turnedPixels(page, 'canvas-replay')).toBeGreaterThan(200);

    // The network, 20 s in: rollbacks happened and the confirmed hashes are equal.
    expect(num(r, 'net-checkpoint')).toBeGreaterThanOrEqual(1020);
    expect(r['readout-net-hash-1']).toMatch(/^[0-9a-f]{16}$/);
    expect(r['readout-net-hash-1']).toBe(r['readout-net-hash-2']);
    expect(r['readout-net-equal']).toBe('true');
    expect(num(r, 'net-1-rollbacks') + num(r, 'net-2-rollbacks')).toBeGreaterThan(0);
    expect(Math.max(num(r, 'net-1-max-depth'), num(r, 'net-2-max-depth'))).toBeGreaterThan(0);
    expect(await page.getByTestId('net-verdict').getAttribute('data-value')).toBe('true');

    // The two worlds: Rapier's boxes turned, the own world's cannot.
    expect(num(r, 'worlds-rapier-turned')).toBeGreaterThan(0);
    expect(num(r, 'worlds-own-turned')).toBe(0);
    expect(num(r, 'worlds-rapier-bytes-per-body')).toBeGreaterThan(
      10 * num(r, 'worlds-own-bytes-per-body'),
    );
    await page.getByTestId('control-scene-lean').click();
    await skip(page);
    r = await readouts(page);
    expect(num(r, 'worlds-rapier-top')).toBeLessThan(2);
    expect(num(r, 'worlds-own-top')).toBeGreaterThan(5.4);

    await shoot(page, 'rigid-bodies');
    expect(away).toEqual([]);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('on a phone (390×844): a tap fires, each machine fires from its side, the real clock runs', async () => {
    const { page, problems, away } = await open('phone');
    // A tap on the tower itself fires.
    await page.getByTestId('canvas-live').tap();
    // Player 2's machine fires from the right (the bots off, so only the taps fire).
    await page.getByTestId('control-bots').tap();
    await page.getByTestId('control-net-fire-2').tap();
    await skip(page);
    let r = await readouts(page);
    expect(num(r, 'knock-shots')).toBe(1);
    expect(num(r, 'knock-turned')).toBeGreaterThan(0);
    // Shots (player 1, player 2) as each machine counts them: the sum is 1 on both.
    expect(num(r, 'net-1-shots')).toBe(1);
    expect(num(r, 'net-2-shots')).toBe(1);
    // Player 1's machine heard of player 2's shot late: it rolled back.
    expect(num(r, 'net-1-rollbacks')).toBeGreaterThan(0);
    expect(r['readout-net-equal']).toBe('true');
    await expectFits(page, 'rigid-bodies-phone');

    // The real clock, from a restart: the page's own frames step everything.
    await freshRun(page);
    await realClockRuns(page, 600);
    r = await readouts(page);
    expect(num(r, 'knock-tick')).toBeGreaterThanOrEqual(36);
    expect(away).toEqual([]);
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
