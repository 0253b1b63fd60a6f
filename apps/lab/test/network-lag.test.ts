import { describe, expect, it } from 'vitest';
import { lagRow } from '../src/chapters/network/network-lag.js';

describe('chapter 6: lag compensation', () => {
  it('at 150 ms the server confirms the on-screen hits when it judges them as seen, and few at its present', () => {
    const row = lagRow(150, 20);
    expect(row.compensated.screenHits).toBeGreaterThan(50);
    expect(row.compensated.confirmed / row.compensated.screenHits).toBeGreaterThanOrEqual(0.99);
    expect(row.plain.confirmed / row.plain.screenHits).toBeLessThan(0.2);
  });
});
