/**
 * Chapter 1 in a real browser: the built lab, served by `fixedstep serve`'s server, driven by
 * its own controls. The simulated display makes every number exact, so the assertions are on
 * numbers, never on timing.
 */
import { describe, expect, it } from 'vitest';
import {
  expectFits,
  freshRun,
  num,
  readouts,
  realClockRuns,
  shoot,
  skip,
  useChapter,
} from './harness.js';

const FIXED = ['fixed-naive', 'fixed-final', 'fixed'] as const;

const chapter = useChapter('loop', '1. The loop — fixedstep lab', 'readout-fixed-hash');

describe('chapter 1, the loop', () => {
  it('shows the talk’s contrasts in its numbers at 60 and 144 Hz', async () => {
    const { page, problems } = await chapter.open();
    await expect
      .poll(() => page.getByTestId('readout-fixed-hash').getAttribute('data-value'))
      .toMatch(/^[0-9a-f]{16}$/);

    await freshRun(page, 60);
    await skip(page);
    const at60 = await readouts(page);
    await shoot(page, 'loop-60hz');

    await freshRun(page, 144);
    await skip(page);
    const at144 = await readouts(page);
    await shoot(page, 'loop-144hz');

    // Both runs are at exactly 5 s of virtual time.
    expect(at60['readout-clock']).toBe('5000');
    expect(at144['readout-clock']).toBe('5000');

    // Frame-locked: time is the frame count. 1.0 at 60 Hz, 2.4 at 144 Hz.
    const fl60 = num(at60, 'frame-locked-ratio');
    const fl144 = num(at144, 'frame-locked-ratio');
    expect(fl60).toBeCloseTo(1.0, 1);
    expect(fl144).toBeCloseTo(2.4, 1);
    expect(Math.abs(fl144 / fl60 - 2.4)).toBeLessThan(0.05);

    // Variable Δt keeps time (ratio 1) but not the path: its state differs between rates.
    expect(num(at60, 'variable-ratio')).toBeCloseTo(1, 6);
    expect(num(at144, 'variable-ratio')).toBeCloseTo(1, 6);
    expect(at60['readout-variable-hash150']).toMatch(/^[0-9a-f]{16}$/);
    expect(at144['readout-variable-hash150']).not.toBe(at60['readout-variable-hash150']);
    expect(at144['readout-frame-locked-hash150']).not.toBe(at60['readout-frame-locked-hash150']);

    // The fixed loops keep time and path: same hash at tick 150 on both displays, all three alike.
    const golden = at60['readout-fixed-hash150'];
    expect(golden).toMatch(/^[0-9a-f]{16}$/);
    for (const id of FIXED) {
      expect(Math.abs(num(at60, `${id}-ratio`) - 1)).toBeLessThan(0.01);
      expect(Math.abs(num(at144, `${id}-ratio`) - 1)).toBeLessThan(0.01);
      expect(at60[`readout-${id}-hash150`]).toBe(golden);
      expect(at144[`readout-${id}-hash150`]).toBe(golden);
      // At 5 s both displays are at the same tick (166), so the current states agree too.
      expect(num(at60, `${id}-sim`)).toBe(num(at144, `${id}-sim`));
      expect(at144[`readout-${id}-hash`]).toBe(at60[`readout-${id}-hash`]);
      expect(num(at144, `${id}-dropped`)).toBe(0);
      expect(at144[`readout-${id}-stalled`]).toBe('false');
    }
    expect(num(at144, 'fixed-max-steps')).toBe(1);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('shows what a hitch, a hidden tab and a slow machine do to each loop', async () => {
    const { page, problems } = await chapter.open({ width: 1280, height: 800 });

    // A 2 s hitch at 5 s.
    await freshRun(page, 60);
    await skip(page); // t = 5 s
    await page.getByTestId('control-hitch').click();
    await skip(page); // t = 10 s
    const hitch = await readouts(page);
    // The slides' accumulator pays the whole 2 s at once; the clamp keeps 1 s (33 steps);
    // FixedLoop runs at most 8 steps and counts the rest as dropped.
    expect(num(hitch, 'fixed-naive-max-steps')).toBeGreaterThanOrEqual(66);
    expect(num(hitch, 'fixed-naive-dropped')).toBe(0);
    expect(num(hitch, 'fixed-final-max-steps')).toBe(33);
    expect(num(hitch, 'fixed-final-dropped')).toBeGreaterThan(900);
    expect(num(hitch, 'fixed-max-steps')).toBe(8);
    expect(num(hitch, 'fixed-dropped')).toBeGreaterThan(1700);
    expect(num(hitch, 'variable-ratio')).toBeCloseTo(1, 6);

    // A hidden tab: FixedLoop pauses and counts the 10 s as dropped.
    await page.getByTestId('control-restart').click();
    await skip(page);
    await page.getByTestId('control-hidden').click();
    await skip(page, 3); // t = 20 s
    const hidden = await readouts(page);
    expect(num(hidden, 'fixed-dropped')).toBeGreaterThanOrEqual(10_000);
    expect(num(hidden, 'fixed-max-steps')).toBe(1);
    expect(num(hidden, 'fixed-naive-max-steps')).toBeGreaterThanOrEqual(333);

    // A slow machine: the slides' loop spirals until the page stalls; FixedLoop stays capped.
    await page.getByTestId('control-restart').click();
    await page.getByTestId('control-slow').click();
    await skip(page, 6); // t = 30 s
    const slow = await readouts(page);
    expect(slow['readout-fixed-naive-stalled']).toBe('true');
    expect(slow['readout-fixed-stalled']).toBe('false');
    expect(num(slow, 'fixed-max-steps')).toBe(8);
    expect(num(slow, 'frame-locked-ratio')).toBeLessThan(0.5);
    expect(await page.getByTestId('readout-fixed-naive-stalled').isVisible()).toBe(true);
    await page.getByTestId('control-slow').click();

    // Interpolation off and the real clock: no errors, and the real clock moves.
    await page.getByTestId('control-interp').click();
    await realClockRuns(page);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('sets up each “Things to try” card afresh, in page order and after the others', async () => {
    const { page, problems } = await chapter.open();
    const cards = page.locator('.experiment-list button');
    expect(await cards.count()).toBe(5);
    const pressed = (id: string) => page.getByTestId(id).getAttribute('aria-pressed');
    // What each card's text says, from the moment it starts.
    const at144 = async () => {
      // 144 Hz: the frame-locked ball runs 2.4× too fast, variable Δt keeps time, the three
      // fixed loops agree on the hash after update 150 and on the ticks (the slides' `acc > STEP`
      // may be one step behind for the one frame that lands exactly on a step boundary, so "hash
      // now" is not compared at wherever the pause landed: loop-lab.test.ts pins that down); a
      // 30 ms step spans 4–5 frames, never 2 steps.
      const r = await readouts(page);
      expect(num(r, 'frame-locked-ratio')).toBeCloseTo(2.4, 1);
      expect(num(r, 'variable-ratio')).toBeCloseTo(1, 6);
      for (const id of FIXED) {
        expect(r[`readout-${id}-hash150`]).toBe(r['readout-fixed-hash150']);
        expect(Math.abs(num(r, `${id}-sim`) - num(r, 'fixed-sim'))).toBeLessThanOrEqual(0.030001);
        expect(num(r, `${id}-max-steps`)).toBe(1);
        expect(num(r, `${id}-dropped`)).toBe(0);
      }
      expect(r['readout-variable-hash150']).not.toBe(r['readout-fixed-hash150']);
    };
    const claims: (() => Promise<void>)[] = [
      at144,
      async () => {
        await skip(page);
        const r = await readouts(page);
        expect(num(r, 'fixed-naive-max-steps')).toBeGreaterThanOrEqual(66);
        expect(num(r, 'fixed-naive-dropped')).toBe(0);
        expect(num(r, 'fixed-final-max-steps')).toBe(33);
        expect(num(r, 'fixed-final-dropped')).toBeGreaterThan(900);
        expect(num(r, 'fixed-final-dropped')).toBeLessThan(1100);
        expect(num(r, 'fixed-max-steps')).toBe(8);
        expect(num(r, 'fixed-dropped')).toBeGreaterThan(1700);
      },
      async () => {
        await skip(page, 2);
        const r = await readouts(page);
        expect(num(r, 'fixed-naive-max-steps')).toBeGreaterThanOrEqual(333);
        expect(num(r, 'fixed-max-steps')).toBe(1);
        expect(num(r, 'fixed-dropped')).toBeGreaterThanOrEqual(10_000);
      },
      async () => {
        await skip(page, 6);
        const r = await readouts(page);
        expect(r['readout-fixed-naive-stalled']).toBe('true');
        expect(r['readout-fixed-stalled']).toBe('false');
        expect(num(r, 'fixed-max-steps')).toBe(8);
        expect(num(r, 'fixed-ratio')).toBeLessThan(1);
      },
      at144,
    ];
    // Each card plays; pause it where it starts (5 s in) and check what its text says.
    const check = async (i: number) => {
      await cards.nth(i).click();
      expect(await pressed('control-pause')).toBe('false');
      await page.getByTestId('control-pause').click();
      const t0 = num(await readouts(page), 'clock');
      expect(t0).toBeGreaterThanOrEqual(5000);
      expect(await pressed('control-interp')).toBe(i === 4 ? 'false' : 'true');
      expect(await pressed('control-slow')).toBe(i === 3 ? 'true' : 'false');
      expect(await page.locator('#jitter').inputValue()).toBe('0');
      const hz = i === 0 || i === 4 ? 144 : 60;
      expect(
        await page
          .getByTestId(`control-hz-${String(hz)}`)
          .locator('input')
          .isChecked(),
      ).toBe(true);
      await claims[i]!();
    };
    for (const i of [0, 1, 2, 3, 4, 3, 2, 1, 0]) await check(i);
    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen and works from the keyboard', async () => {
    const { page, problems } = await chapter.open('phone');
    await freshRun(page, 144);
    await skip(page);
    await expectFits(page, 'loop-phone');

    // The skip button works from the keyboard.
    await page.getByTestId('control-skip').focus();
    await page.keyboard.press('Enter');
    await expect
      .poll(() => page.getByTestId('readout-clock').getAttribute('data-value'))
      .toBe('10000');

    // Deep links reach other chapters; an unknown chapter says so instead of failing.
    await page.goto(`${chapter.lab.server.url}#/network`);
    await expect.poll(() => page.locator('main h1').textContent()).toBe('Network');
    expect(await page.locator('main .eyebrow').textContent()).toBe('Chapter 6');
    await page.goto(`${chapter.lab.server.url}#/no-such-chapter`);
    await expect.poll(() => page.locator('main h1').textContent()).toBe('No such chapter');
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
