import { describe, expect, it } from 'vitest';
import { count, exact, hashHue, millis, plural, ratio, sci, seconds } from '../src/ui/format.js';
import { integerTicks } from '../src/ui/steps-chart.js';
import { routeOf } from '../src/chapters.js';

describe('format', () => {
  it('formats readouts', () => {
    expect(seconds(4.98)).toBe('4.980 s');
    expect(seconds(NaN)).toBe('—');
    expect(ratio(2.403333)).toBe('2.403×');
    expect(millis(undefined)).toBe('n/a');
    expect(millis(0)).toBe('0 ms');
    expect(millis(1e-9)).toBe('0 ms');
    expect(millis(12.34)).toBe('12.3 ms');
    expect(millis(1758.333)).toBe('1\u202f758 ms');
    expect(millis(-5)).toBe('−5 ms');
    expect(count(10008)).toBe('10\u202f008');
    expect(sci(4.02e-118)).toBe('4.02 × 10⁻¹¹⁸');
    expect(sci(1e9, 0)).toBe('10⁹');
    expect(sci(1.05e10)).toBe('1.05 × 10¹⁰');
    expect(sci(Infinity)).toBe('Infinity');
    expect(exact(0.1 + 0.2)).toBe('0.30000000000000004');
    expect(exact(NaN)).toBe('NaN');
    expect(exact(undefined)).toBe('');
    expect(hashHue('0acdb8691efc01d0')).toBe(0x0acdb8 % 360);
    expect(plural(1, 'point')).toBe('1 point');
    expect(plural(0, 'point')).toBe('0 points');
    expect(plural(1200, 'step')).toBe('1\u202f200 steps');
  });

  it('gives a steps-per-frame chart whole-step ticks above 0, at most four intervals', () => {
    expect(integerTicks(2)).toEqual([0, 1, 2]);
    expect(integerTicks(3)).toEqual([0, 1, 2, 3]);
    expect(integerTicks(9)).toEqual([0, 5]);
    expect(integerTicks(10)).toEqual([0, 5, 10]);
    expect(integerTicks(150)).toEqual([0, 50, 100, 150]);
    expect(integerTicks(0)).toEqual([0]);
  });
});

describe('routeOf', () => {
  it('reads the chapter id from the hash', () => {
    expect(routeOf('#/loop')).toBe('loop');
    expect(routeOf('#/final-fixes')).toBe('final-fixes');
    expect(routeOf('')).toBe('');
    expect(routeOf('#/')).toBe('');
    expect(routeOf('#main')).toBe('');
  });
});
