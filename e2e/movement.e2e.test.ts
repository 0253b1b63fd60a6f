/**
 * Chapter 2 in a real browser: the same jump on four simulated displays, under a variable Δt and
 * under a fixed step. The simulated displays make every number exact.
 */
import { describe, expect, it } from 'vitest';
import { expectFits, num, readouts, shoot, skip, useChapter } from './harness.js';

const RATES = [30, 60, 144, 240];
const chapter = useChapter('movement', '2. Movement — fixedstep lab', 'readout-fixed-apex-spread');

describe('chapter 2, movement', () => {
  it('fans the variable-Δt jumps out and lays the fixed-step jumps on top of each other', async () => {
    const { page, problems } = await chapter.openFresh();
    await skip(page);
    const r = await readouts(page);
    await shoot(page, 'movement');

    // The second jump (two 2.5 s rounds) is shown under both loops.
    expect(num(r, 'variable-jump')).toBe(2);
    expect(num(r, 'fixed-jump')).toBe(2);
    expect(num(r, 'variable-apex-spread')).toBeGreaterThan(0.01);
    expect(num(r, 'variable-landing-spread')).toBeGreaterThan(0.05);
    expect(num(r, 'fixed-apex-spread')).toBe(0);
    expect(num(r, 'fixed-landing-spread')).toBe(0);
    for (const hz of RATES) {
      expect(num(r, `fixed-${hz}-apex`)).toBeCloseTo(1.5456, 10);
      expect(num(r, `fixed-${hz}-landing`)).toBeCloseTo(3.24, 10);
    }
    expect(await page.getByTestId('verdict-fixed').textContent()).toContain('one jump');

    // Less jitter replays from zero: the fixed-step jump does not move at all.
    await page.getByTestId('control-jitter').focus();
    for (let i = 0; i < 20; i++) await page.keyboard.press('ArrowLeft');
    await expect.poll(() => page.locator('#movement-jitter-out').textContent()).toBe('±0 %');
    await expect
      .poll(async () => (await page.getByTestId('readout-clock').getAttribute('data-value')) ?? '')
      .toBe('5000');
    const calm = await readouts(page);
    expect(num(calm, 'fixed-apex-spread')).toBe(0);
    expect(num(calm, 'fixed-30-apex')).toBe(num(r, 'fixed-30-apex'));
    expect(num(calm, 'variable-apex-spread')).toBeGreaterThan(0);
    expect(num(calm, 'variable-30-apex')).not.toBe(num(r, 'variable-30-apex'));

    // A jump of the reader's, then the real clock: the page's own frames trace the same jump.
    await page.getByTestId('control-jump').click();
    await page.getByTestId('control-real-clock').click();
    await page.getByTestId('control-pause').click();
    await expect
      .poll(
        async () =>
          (await page.getByTestId('readout-fixed-real-apex').getAttribute('data-value')) ?? '',
        {
          timeout: 60_000,
        },
      )
      .not.toBe('');
    const real = await readouts(page);
    expect(num(real, 'fixed-real-apex')).toBe(num(real, 'fixed-30-apex'));
    expect(num(real, 'fixed-apex-spread')).toBe(0);
    expect(num(real, 'fixed-landing-spread')).toBe(0);
    await page.getByTestId('control-real-clock').click();

    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen and works from the keyboard', async () => {
    const { page, problems } = await chapter.openFresh('phone');
    await page.getByTestId('control-skip').focus();
    await page.keyboard.press('Enter');
    await expect
      .poll(() => page.getByTestId('readout-clock').getAttribute('data-value'))
      .toBe('5000');
    await expectFits(page, 'movement-phone');
    const r = await readouts(page);
    expect(num(r, 'fixed-landing-spread')).toBe(0);
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
