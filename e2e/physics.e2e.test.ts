/**
 * Chapter 4 in a real browser: the built lab, driven by its own controls on the simulated
 * display, so every number is exact. The talk's claim: at a 0.03 s step Euler's spring explodes;
 * the alternatives do not.
 */
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  expectFits,
  num,
  pause,
  readouts,
  realClockRuns,
  shots,
  shoot,
  skip,
  useChapter,
} from './harness.js';

const chapter = useChapter(
  'physics',
  '4. Physics — fixedstep lab',
  'readout-explicit-euler-energy-ratio',
);

describe('chapter 4, physics', () => {
  it('explodes explicit Euler’s spring at 0.03 s while velocity Verlet keeps its energy', async () => {
    const { page, problems } = await chapter.openFresh();
    await skip(page, 2);
    const r = await readouts(page);
    expect(r['readout-clock']).toBe('10000');
    expect(num(r, 'ticks')).toBe(333);
    expect(num(r, 'omega-dt')).toBeCloseTo(0.13416, 5);
    expect(num(r, 'explicit-euler-energy-ratio')).toBeGreaterThan(10);
    expect(num(r, 'explicit-euler-energy-ratio')).toBeCloseTo(380.198, 2);
    expect(Math.abs(num(r, 'velocity-verlet-energy-ratio') - 1)).toBeLessThan(0.01);
    expect(num(r, 'velocity-verlet-max-error')).toBeLessThan(0.01);
    expect(num(r, 'semi-implicit-euler-max-error')).toBeLessThan(0.08);
    expect(num(r, 'backward-euler-energy-ratio')).toBeLessThan(0.01);
    expect(Math.abs(num(r, 'rk4-energy-ratio') - 1)).toBeLessThan(1e-4);
    expect(r['readout-explicit-euler-state']).toBe('grows');
    expect(r['readout-velocity-verlet-state']).toBe('stable');
    expect(r['readout-backward-euler-state']).toBe('damped');
    expect(r['readout-rope-state']).toBe('swinging');
    expect(num(r, 'rope-pokes')).toBe(1);
    await shoot(page, 'physics');

    // Past ω·dt = 2 (k = 5000 N/m): the symplectic methods explode; RK4 (inside its 2√2) and
    // backward Euler stay bounded but drain the motion, so both read "damped".
    await page.getByTestId('control-stiffness').fill('13');
    await expect.poll(async () => num(await readouts(page), 'omega-dt')).toBeCloseTo(2.1213, 4);
    const stiff = await readouts(page);
    const states = [
      'explicit-euler',
      'semi-implicit-euler',
      'position-verlet',
      'velocity-verlet',
    ].map((m) => stiff[`readout-${m}-state`]);
    expect(states).toEqual(['exploded', 'exploded', 'exploded', 'exploded']);
    expect(stiff['readout-rk4-state']).toBe('damped');
    expect(num(stiff, 'rk4-energy-ratio')).toBeLessThan(1e-3);
    expect(stiff['readout-backward-euler-state']).toBe('damped');

    // The rope: a click pokes it, the arrow keys poke it, explicit Euler shreds it.
    const rope = page.getByTestId('canvas-rope');
    await rope.scrollIntoViewIfNeeded();
    const box = (await rope.boundingBox())!;
    await rope.click({ position: { x: box.width / 2, y: box.height * 0.75 } });
    await expect.poll(async () => num(await readouts(page), 'rope-pokes')).toBe(2);
    await pause(page);
    await rope.focus();
    await page.keyboard.press('ArrowUp');
    await page.keyboard.press('Period');
    await page.keyboard.press('ArrowLeft');
    await expect.poll(async () => num(await readouts(page), 'rope-pokes')).toBe(4);
    await pause(page);
    await page.getByTestId('control-rope-explicit-euler').click();
    await skip(page);
    const shredded = await readouts(page);
    expect(shredded['readout-rope-state']).toBe('exploded');
    expect(num(shredded, 'rope-pokes')).toBeGreaterThanOrEqual(1);
    await page.getByTestId('control-rope-backward-euler').click();
    await expect.poll(async () => (await readouts(page))['readout-rope-state']).toBe('swinging');

    // The real clock runs.
    await realClockRuns(page);

    expect(problems).toEqual([]);
    await page.close();
  });

  it('each "Things to try" does what its text says, in any order', async () => {
    const { page, problems } = await chapter.openFresh({ width: 1280, height: 900 });
    const tryIt = async (name: string) => {
      await page.getByRole('button', { name, exact: true }).click();
    };
    // In page order, each starting from what the one before left.
    // The page writes its readouts once a frame (write-phase.ts): wait for the frame after a click.
    await tryIt('Run 10 s');
    await expect
      .poll(async () => num(await readouts(page), 'explicit-euler-energy-ratio'))
      .toBeCloseTo(380.198, 2);
    let r = await readouts(page);
    expect(Math.abs(num(r, 'velocity-verlet-energy-ratio') - 1)).toBeLessThan(0.01);

    await tryIt('k = 5000 N/m');
    await pause(page);
    await skip(page);
    r = await readouts(page);
    expect(num(r, 'omega-dt')).toBeCloseTo(2.1213, 4);
    expect(
      ['semi-implicit-euler', 'position-verlet', 'velocity-verlet'].map(
        (m) => r[`readout-${m}-state`],
      ),
    ).toEqual(['exploded', 'exploded', 'exploded']);
    expect(r['readout-rk4-state']).not.toBe('exploded');

    await tryIt('Step 15 ms');
    await expect.poll(async () => num(await readouts(page), 'omega-dt')).toBeCloseTo(0.0671, 4); // k back to 20
    r = await readouts(page);
    expect(num(r, 'explicit-euler-energy-ratio')).toBeGreaterThan(15);
    expect(num(r, 'explicit-euler-energy-ratio')).toBeLessThan(25);

    await tryIt('Stiff rope');
    await pause(page);
    await skip(page);
    r = await readouts(page);
    expect(num(r, 'omega-dt')).toBeCloseTo(0.1342, 4); // the step back to 30 ms
    expect(r['readout-rope-state']).toBe('swinging');
    expect(await page.getByTestId('control-rope-backward-euler').isChecked()).toBe(true);
    // The same rope under RK4 shreds.
    await page.getByTestId('control-rope-rk4').click();
    await expect.poll(async () => (await readouts(page))['readout-rope-state']).toBe('exploded');
    expect(problems).toEqual([]);
    await page.close();
  });

  it('a hitch breaks the talk’s spring under a variable Δt, not under the fixed step', async () => {
    const { page, problems } = await chapter.openFresh({ width: 1280, height: 900 });
    await skip(page);
    let r = await readouts(page);
    expect(num(r, 'hitch-variable-omega-dt')).toBeLessThan(0.5);
    expect(num(r, 'hitch-variable-max-energy')).toBeLessThan(1.6);
    await page.getByTestId('control-spring-hitch').click();
    await expect.poll(async () => num(await readouts(page), 'hitch-count')).toBe(1);
    await skip(page);
    r = await readouts(page);
    expect(num(r, 'hitch-variable-omega-dt')).toBeGreaterThan(2);
    expect(num(r, 'hitch-variable-max-dt')).toBeGreaterThan(250);
    expect(num(r, 'hitch-fixed-omega-dt')).toBeCloseTo(0.3, 9);
    expect(num(r, 'hitch-fixed-max-energy')).toBeLessThan(1.2);
    await page.getByTestId('canvas-hitch-variable').scrollIntoViewIfNeeded();
    await page
      .locator('.hitch-section')
      .screenshot({ path: path.join(shots, 'physics-hitch.png') });
    expect(problems).toEqual([]);
    await page.close();
  });

  it('fits a phone screen', async () => {
    const { page, problems } = await chapter.openFresh('phone');
    await skip(page, 2);
    await expectFits(page, 'physics-phone');
    // A tap on the rope pokes it.
    const rope = page.getByTestId('canvas-rope');
    await rope.scrollIntoViewIfNeeded();
    await rope.tap();
    await expect.poll(async () => num(await readouts(page), 'rope-pokes')).toBe(2);
    expect(problems).toEqual([]);
    await page.context().close();
  });
});
