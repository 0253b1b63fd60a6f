/**
 * Lag compensation in state sync: bots shoot at what their screens show over a 150 ms round trip;
 * judged at the time the shooter saw, the server agrees with their screens; judged at its present,
 * it does not.
 */
import { describe, expect, it } from 'vitest';
import { runGalleryMatch } from '@fixedstep/games';

describe('lag compensation (the shooting gallery)', () => {
  it('at 150 ms round trip, ≥ 99 % of the shots that hit on screen hit on the server — against few without', () => {
    const compensated = runGalleryMatch({ compensate: true, rttMs: 150, seconds: 30 });
    const plain = runGalleryMatch({ compensate: false, rttMs: 150, seconds: 30 });
    // The same shots, aimed the same way (the bots see the same screens in both runs).
    expect(compensated.screenHits).toBe(plain.screenHits);
    expect(compensated.screenHits).toBeGreaterThan(80);
    expect(compensated.confirmed / compensated.screenHits).toBeGreaterThanOrEqual(0.99);
    expect(plain.confirmed / plain.screenHits).toBeLessThan(0.2);
    // A shot that missed on screen rarely hits on the server (only near a bounce).
    expect(compensated.phantom).toBeLessThanOrEqual(compensated.shots / 50);
    // Its screen was a snapshot interval and a one-way trip (and the lead) behind: ~15 ticks.
    expect(compensated.meanRewind).toBeGreaterThan(8);
    expect(compensated.meanRewind).toBeLessThan(25);
  });
});
