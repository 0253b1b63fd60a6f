/**
 * The talk's details where the lab shows them: the slides' lastUpdate / lastUpdateTime slip in
 * chapter 1, the two formulas beside the integrators in chapter 4, and the talk's final loop after
 * a NaN frame in chapter 8 — each with the numbers its function computes (unit-tested in
 * apps/lab/test/talk-details.test.ts).
 */
import { describe, expect, it } from 'vitest';
import type { Page } from 'playwright-core';
import { useLab, watch } from './harness.js';

const lab = useLab();

async function section(
  route: string,
  testId: string,
): Promise<{ page: Page; text: string; value: string }> {
  const page = await lab.browser.newPage({ viewport: { width: 1440, height: 900 } });
  await page.goto(`${lab.server.url}#/${route}`);
  const el = page.getByTestId(testId);
  await el.scrollIntoViewIfNeeded();
  expect(await el.isVisible()).toBe(true);
  return {
    page,
    text: (await el.textContent()) ?? '',
    value: (await el.getAttribute('data-value')) ?? '',
  };
}

describe('the talk’s details', () => {
  it('chapter 1 shows the slide’s lastUpdate / lastUpdateTime slip and what it does', async () => {
    const { page, text, value } = await section('loop', 'slip-text');
    const problems = watch(page);
    expect(Number(value)).toBeCloseTo(30.5, 9);
    expect(text).toContain('adds up to 30.5 s of simulated time');
    const slip = page.locator('.slip');
    expect(await slip.textContent()).toContain('lastUpdate += dt;');
    expect(await slip.textContent()).toContain('lastUpdateTime += dt;');
    expect(problems).toEqual([]);
    await page.close();
  });

  it('chapter 4 shows the slides’ formulas beside the integrators and why the step is none', async () => {
    const { page, text, value } = await section('physics', 'formulas-text');
    expect(value).toBe('0.0950 -95.66 0.0950');
    const formulas = (await page.locator('.formulas').textContent()) ?? '';
    expect(formulas).toContain('x(t) = a·t²/2 + v·t + C');
    expect(formulas).toContain('x_{t+1} = x_t + F(t)·t²/2 + C');
    expect(text).toContain('is not an integrator as written');
    expect(text).toContain('at -95.66 m after one second');
    await page.close();
  });

  it('chapter 8 explains the talk’s final loop after a NaN frame in JavaScript', async () => {
    const { page, text, value } = await section('final-fixes', 'nan-text');
    expect(value).toBe('4 32');
    expect(text).toContain('Math.max(0, NaN) is NaN');
    expect(text).toContain('the loop runs 4 updates, all before the bad frame, and never another');
    expect(text).toContain('ends at 32 updates');
    await page.close();
  });
});
