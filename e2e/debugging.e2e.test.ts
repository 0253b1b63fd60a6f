/**
 * Chapter 7 in a real browser: one recording replayed on four simulated displays; under a fixed
 * step every display shows the same state hash at the same tick. Also records a session of its own
 * from the keyboard and replays it.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import { expectFits, freshRun, num, readouts, shoot, shots, skip, useChapter } from './harness.js';

const RATES = [30, 60, 144, 240];
const chapter = useChapter(
  'debugging',
  '7. Debugging — fixedstep lab',
  'readout-fixed-hashes-equal',
);

function hashes(r: Record<string, string>, loop: string): string[] {
  return RATES.map((hz) => r[`readout-${loop}-${hz}-hash`] ?? '');
}

describe('chapter 7, debugging', () => {
  it('shows one hash per tick under a fixed step and four under a variable Δt', async () => {
    const { page, problems } = await chapter.open();
    expect(await page.getByTestId('guarantee').textContent()).toContain('every display rate');

    await freshRun(page);
    await skip(page);
    const r = await readouts(page);
    await shoot(page, 'debugging');
    expect(r['readout-fixed-hashes-equal']).toBe('true');
    expect(r['readout-variable-hashes-equal']).toBe('false');
    const fixed = hashes(r, 'fixed');
    expect(fixed[0]).toMatch(/^[0-9a-f]{16}$/);
    for (const h of fixed) expect(h).toBe(fixed[0]);
    expect(new Set(hashes(r, 'variable')).size).toBe(4);
    expect(num(r, 'fixed-common-tick')).toBeGreaterThanOrEqual(165);
    expect(num(r, 'fixed-divergence')).toBe(0);
    expect(num(r, 'variable-divergence')).toBeGreaterThan(0);
    expect(num(r, 'recording-inputs')).toBe(22);

    // Still equal, tick for tick, at the end of the demo.
    await skip(page);
    const end = await readouts(page);
    expect(end['readout-fixed-hashes-equal']).toBe('true');
    expect(RATES.map((hz) => num(end, `fixed-${hz}-score`))).toEqual([11, 11, 11, 11]);

    // The page's own animation frames add a fifth run per loop: under a fixed step it reaches the
    // same hash at the same tick as the four simulated displays.
    await page.getByTestId('control-real-clock').click();
    await page.getByTestId('control-pause').click(); // play
    await expect
      .poll(async () => num(await readouts(page), 'fixed-common-tick'), { timeout: 60_000 })
      .toBeGreaterThanOrEqual(40);
    await page.getByTestId('control-pause').click();
    const real = await readouts(page);
    expect(real['readout-fixed-real-hash']).toMatch(/^[0-9a-f]{16}$/);
    expect(real['readout-fixed-real-hash']).toBe(real['readout-fixed-30-hash']);
    expect(real['readout-fixed-hashes-equal']).toBe('true');

    expect(problems).toEqual([]);
    await page.close();
  });

  it('records inputs from the keyboard and replays them on every display', async () => {
    const { page, problems } = await chapter.open({ width: 1280, height: 860 });

    // R starts a recording (and plays); the pad buttons come alive.
    await page.keyboard.press('KeyR');
    await expect
      .poll(() => page.getByTestId('control-record').getAttribute('aria-pressed'))
      .toBe('true');
    expect(await page.getByTestId('control-jump').isEnabled()).toBe(true);
    // Between presses, wait for the chapter's clock to move on (state, not a sleep).
    const after = async (ms: number) => {
      const t0 = num(await readouts(page), 'clock');
      await expect
        .poll(async () => num(await readouts(page), 'clock'), { timeout: 60_000 })
        .toBeGreaterThanOrEqual(t0 + ms);
    };
    await page.keyboard.down('ArrowRight');
    await after(400);
    await page.keyboard.press('Space');
    await after(500);
    await page.keyboard.up('ArrowRight');
    await page.keyboard.down('ArrowLeft');
    await after(300);
    await page.keyboard.up('ArrowLeft');
    await after(200);
    await page.getByTestId('control-record').click(); // stop and replay
    await expect
      .poll(() => page.getByTestId('control-record').getAttribute('aria-pressed'))
      .toBe('false');
    const rec = await readouts(page);
    expect(num(rec, 'recording-inputs')).toBe(6);
    expect(num(rec, 'recording-length')).toBeGreaterThan(1000);

    // The replay, on the simulated displays, from zero.
    await freshRun(page);
    await skip(page);
    const r = await readouts(page);
    expect(r['readout-fixed-hashes-equal']).toBe('true');
    expect(r['readout-variable-hashes-equal']).toBe('false');
    await page.screenshot({ path: path.join(shots, 'debugging-recorded.png'), fullPage: false });

    // The demo comes back on its button.
    await page.getByTestId('control-demo').click();
    await expect.poll(async () => num(await readouts(page), 'recording-inputs')).toBe(22);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen', async () => {
    const { page, problems } = await chapter.openFresh('phone');
    await skip(page);
    await expectFits(page, 'debugging-phone');
    expect((await readouts(page))['readout-fixed-hashes-equal']).toBe('true');
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
