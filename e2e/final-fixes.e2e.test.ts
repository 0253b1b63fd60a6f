/**
 * Chapter 8 in a real browser: a hitch on a slow machine without the clamp (the spiral of death,
 * on a simulated display), with it and with FixedLoop; and a clock that jumps backwards.
 */
import { describe, expect, it } from 'vitest';
import { expectFits, num, readouts, realClockRuns, shoot, skip, useChapter } from './harness.js';

const chapter = useChapter(
  'final-fixes',
  '8. Final fixes — fixedstep lab',
  'readout-noclamp-max-steps',
);

describe('chapter 8, final fixes', () => {
  it('spirals without the clamp, stays bounded with it, and shrugs off a clock set back', async () => {
    const { page, problems } = await chapter.openFresh();
    await skip(page, 3); // t = 15 s
    const r = await readouts(page);
    await shoot(page, 'final-fixes');

    // The slides' loop: each frame owes more than the last, until a frame would hang the page.
    expect(num(r, 'noclamp-max-steps')).toBeGreaterThan(num(r, 'clamp-max-steps'));
    expect(num(r, 'noclamp-max-steps')).toBeGreaterThanOrEqual(125);
    expect(r['readout-noclamp-stalled']).toBe('true');
    expect(num(r, 'noclamp-owed')).toBeGreaterThan(0);
    expect(await page.getByTestId('readout-noclamp-stalled').isVisible()).toBe(true);
    // The clamp bounds the debt at 1 s: 33 steps; FixedLoop caps a frame at 8.
    expect(num(r, 'clamp-max-steps')).toBe(33);
    expect(r['readout-clamp-stalled']).toBe('false');
    expect(num(r, 'fixed-max-steps')).toBe(8);
    expect(r['readout-fixed-stalled']).toBe('false');
    expect(num(r, 'fixed-fps')).toBeGreaterThan(num(r, 'clamp-fps'));

    // The clock set back by 1.5 s at 3 s.
    expect(r['readout-backwards-variable-reversed']).toBe('true');
    expect(num(r, 'backwards-variable-lag')).toBeCloseTo(1500, 3);
    expect(r['readout-backwards-naive-reversed']).toBe('false');
    expect(num(r, 'backwards-naive-frozen')).toBeGreaterThan(1400);
    for (const id of ['final', 'fixed']) {
      expect(r[`readout-backwards-${id}-reversed`]).toBe('false');
      expect(num(r, `backwards-${id}-frozen`)).toBeLessThan(100);
      expect(num(r, `backwards-${id}-lag`)).toBeLessThan(100);
    }
    expect(num(r, 'backwards-fixed-backward-frames')).toBe(1);
    expect(num(r, 'backwards-clock')).toBe(13_500);

    // A fast machine: the hitch is paid off and nobody stalls (replayed to the same moment).
    await page.getByTestId('control-machine-10').click();
    await expect.poll(async () => (await readouts(page))['readout-noclamp-stalled']).toBe('false');
    const fast = await readouts(page);
    expect(num(fast, 'noclamp-max-steps')).toBe(33);
    expect(fast['readout-clock']).toBe('15000');

    // A 10 s breakpoint: without the clamp the page owes all of it at once.
    await page.getByTestId('control-breakpoint').click();
    await skip(page, 3);
    const bp = await readouts(page);
    expect(num(bp, 'noclamp-max-steps')).toBeGreaterThanOrEqual(333);
    expect(num(bp, 'clamp-max-steps')).toBe(33);
    expect(num(bp, 'fixed-max-steps')).toBe(8);

    // Setting the clock back again: FixedLoop counts a second backward reading.
    await page.getByTestId('control-jump-back').click();
    await skip(page);
    expect(num(await readouts(page), 'backwards-fixed-backward-frames')).toBe(2);

    // The real clock runs both benches on the page's frames.
    await realClockRuns(page, 500);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen', async () => {
    const { page, problems } = await chapter.openFresh('phone');
    await skip(page, 3);
    await expectFits(page, 'final-fixes-phone');
    expect((await readouts(page))['readout-noclamp-stalled']).toBe('true');
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
