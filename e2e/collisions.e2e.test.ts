/**
 * Chapter 3 in a real browser: the built lab, driven by its own controls on the simulated
 * display, so every number is exact. The talk's claim: with a variable Δt bodies go through a
 * wall that a fixed step keeps them out of, and continuous detection lets none through.
 */
import { describe, expect, it } from 'vitest';
import { expectFits, num, readouts, realClockRuns, shoot, skip, useChapter } from './harness.js';

const chapter = useChapter('collisions', '3. Collisions — fixedstep lab', 'readout-variable-fired');

describe('chapter 3, collisions', () => {
  it('tunnels under variable Δt, not under a fixed step, never with CCD', async () => {
    const { page, problems } = await chapter.openFresh();
    await skip(page, 2);
    const r = await readouts(page);
    expect(r['readout-clock']).toBe('10000');
    expect(num(r, 'variable-fired')).toBeGreaterThanOrEqual(99);
    expect(num(r, 'variable-tunnelled')).toBeGreaterThan(0);
    expect(num(r, 'variable-ccd-tunnelled')).toBe(0);
    expect(num(r, 'fixed-tunnelled')).toBe(0);
    expect(num(r, 'fixed-ccd-tunnelled')).toBe(0);
    expect(num(r, 'ccd-tunnelled')).toBe(0);
    expect(num(r, 'variable-max-dt')).toBeGreaterThan(40);
    expect(num(r, 'fixed-max-dt')).toBe(30);
    expect(num(r, 'min-wall')).toBeCloseTo(1.8, 9);
    expect(num(r, 'theory-share')).toBe(0);

    // CCD switches the drawing to the continuous twins; the counts stay what they are.
    await page.getByTestId('control-ccd').click();
    expect(await page.getByTestId('control-ccd').getAttribute('aria-pressed')).toBe('true');
    const withCcd = await readouts(page);
    expect(num(withCcd, 'variable-ccd-tunnelled')).toBe(0);
    expect(withCcd['readout-variable-tunnelled']).toBe(r['readout-variable-tunnelled']);
    await page.getByTestId('control-ccd').click();
    await shoot(page, 'collisions');

    // The talk's rule exactly (w = v·dt = 1.8 m): detected, yet ~44 % pushed through.
    await page.getByTestId('control-wall').fill('1.8');
    await expect.poll(async () => num(await readouts(page), 'theory-share')).toBeGreaterThan(0.4);
    await skip(page, 2);
    const atRule = await readouts(page);
    expect(num(atRule, 'theory-share')).toBeCloseTo(0.4444, 3);
    expect(num(atRule, 'fixed-tunnelled')).toBeGreaterThan(50);
    expect(Math.abs(num(atRule, 'measured-share') - 0.4444)).toBeLessThan(0.08);
    expect(num(atRule, 'ccd-tunnelled')).toBe(0);
    // The setting left behind is a row of the per-setting table, with the display it ran on.
    const rows = page.locator('[data-testid="results-table"] tbody tr');
    await expect.poll(() => rows.count()).toBe(2);
    expect(await rows.nth(1).locator('td.col-display').textContent()).toBe('30 Hz ±30 %');

    // A hitch: one 250 ms step for the variable loop, ordinary steps for the fixed one.
    await page.getByTestId('control-hitch').click();
    await skip(page);
    const hitch = await readouts(page);
    expect(num(hitch, 'variable-max-dt')).toBeGreaterThan(250);
    expect(num(hitch, 'fixed-max-dt')).toBe(30);

    // The real clock runs.
    await realClockRuns(page);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('takes every click on the chart, and each experiment does what it says', async () => {
    const { page, problems } = await chapter.openFresh();
    await skip(page);

    // Four clicks in turn, the mouse moving between them inside the chart: each picks its
    // setting, although every new setting adds a row to the results table (uPlot measures the
    // chart only when the mouse enters it or the page scrolls).
    const over = page.locator('[data-testid="chart-walls"] .u-over');
    const setting = async () => {
      const r = await readouts(page);
      return {
        speed: Number(await page.getByTestId('control-speed').inputValue()),
        wall: Number(await page.getByTestId('control-wall').inputValue()),
        step: num(r, 'step-distance'),
        safe: num(r, 'max-safe-speed'),
      };
    };
    const points = [
      [0.2, 0.93],
      [0.7, 0.3],
      [0.45, 0.96],
      [0.9, 0.6],
    ] as const;
    await over.scrollIntoViewIfNeeded();
    let taken = 0;
    for (const [fx, fy] of points) {
      const before = await setting();
      const box = await over.boundingBox();
      if (!box) throw new Error('no chart');
      await page.mouse.move(box.x + box.width * fx, box.y + box.height * fy, { steps: 8 });
      await page.mouse.down();
      await page.mouse.up();
      await expect.poll(async () => (await setting()).speed).not.toBe(before.speed);
      const after = await setting();
      // The scales run 5 % past the sliders' ends (150 m/s, 8 m), so a dot there is whole.
      expect(after.speed).toBeCloseTo(157.5 * fx, -0.5);
      expect(after.wall).toBeCloseTo(8.4 * (1 - fy), 0);
      expect(after.step).toBeCloseTo(after.speed * 0.03, 9);
      expect(after.wall).not.toBe(before.wall);
      expect(after.safe).not.toBe(before.safe);
      taken++;
    }
    expect(taken).toBe(points.length);

    // The experiments, in page order: each one's claim holds whatever came before.
    const run = async (n: number) => {
      await page.getByTestId(`experiment-${n}`).click();
      await page.getByTestId('control-pause').click();
      await skip(page, 2);
      return readouts(page);
    };
    const rule = await run(1);
    expect(await page.getByTestId('control-wall').inputValue()).toBe('1.8');
    expect(num(rule, 'theory-share')).toBeCloseTo(0.4444, 3);
    expect(Math.abs(num(rule, 'measured-share') - 0.4444)).toBeLessThan(0.08);
    expect(num(rule, 'ccd-tunnelled')).toBe(0);

    const hitch = await run(2);
    expect(await page.getByTestId('control-speed').inputValue()).toBe('60');
    expect(await page.getByTestId('control-wall').inputValue()).toBe('3.5');
    expect(await page.getByTestId('control-jitter').inputValue()).toBe('0');
    expect(await page.getByTestId('control-hz-60').locator('input').isChecked()).toBe(true);
    expect(num(hitch, 'variable-max-dt')).toBeGreaterThanOrEqual(250);
    expect(num(hitch, 'variable-tunnelled')).toBeGreaterThan(0);
    expect(num(hitch, 'fixed-max-dt')).toBe(30);
    expect(num(hitch, 'fixed-tunnelled')).toBe(0);

    const smooth = await run(3);
    expect(await page.getByTestId('control-hz-144').locator('input').isChecked()).toBe(true);
    expect(num(smooth, 'variable-max-dt')).toBeLessThan(7.5);
    expect(num(smooth, 'variable-tunnelled')).toBe(0);
    expect(num(smooth, 'fixed-tunnelled')).toBe(0);

    const bullets = await run(4);
    expect(await page.getByTestId('control-ccd').getAttribute('aria-pressed')).toBe('true');
    expect(num(bullets, 'variable-share')).toBeGreaterThan(0.5);
    expect(num(bullets, 'fixed-share')).toBeGreaterThan(0.5);
    expect(num(bullets, 'ccd-tunnelled')).toBe(0);

    // Again from the end: the rule's experiment draws the discrete twins and lets ~44 % through.
    const again = await run(1);
    expect(await page.getByTestId('control-ccd').getAttribute('aria-pressed')).toBe('false');
    expect(await page.getByTestId('control-hz-30').locator('input').isChecked()).toBe(true);
    expect(Math.abs(num(again, 'measured-share') - 0.4444)).toBeLessThan(0.08);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen and works from the keyboard', async () => {
    const { page, problems } = await chapter.openFresh('phone');
    await skip(page);
    await expectFits(page, 'collisions-phone');

    // A slider moves with the arrow keys: 60 → 61 m/s, one step is then 1.83 m.
    await page.getByTestId('control-speed').focus();
    await page.keyboard.press('ArrowRight');
    await expect.poll(async () => num(await readouts(page), 'step-distance')).toBeCloseTo(1.83, 9);
    await page.getByTestId('control-skip').focus();
    await page.keyboard.press('Enter');
    await expect
      .poll(() => page.getByTestId('readout-clock').getAttribute('data-value'))
      .toBe('10000');
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
