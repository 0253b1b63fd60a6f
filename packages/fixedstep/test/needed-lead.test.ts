/**
 * The two pieces `lead: 'auto'` of a state-sync session is made of: NeededLead (the largest lead
 * late inputs asked for over a window) and LeadTicks (how the lead follows what is wanted).
 * The whole behaviour over a lossy stream is held by packages/games/test/state-schemas.test.ts.
 */
import { describe, expect, it } from 'vitest';
import { LeadTicks } from '../src/net/clock-sync.js';
import { NeededLead } from '../src/net/sessions/needed-lead.js';

describe('NeededLead', () => {
  it('keeps the largest need of the window and forgets it a second at a time', () => {
    const n = new NeededLead(5000);
    expect(n.value(0)).toBe(-1);
    n.note(100, 12);
    n.note(900, 40); // a stall, in the same second: the larger stays
    n.note(950, 20);
    n.note(2_500, 15);
    expect(n.value(2_600)).toBe(40);
    expect(n.value(4_999)).toBe(40); // seconds 0–4
    expect(n.value(5_000)).toBe(15); // second 0 has left the window
    expect(n.value(6_999)).toBe(15);
    expect(n.value(7_000)).toBe(-1); // second 2 has left too
  });

  it('a slot reused a window later starts from the new need, not the old one', () => {
    const n = new NeededLead(3000);
    n.note(1_200, 50);
    n.note(4_100, 9); // second 4 reuses second 1's slot
    expect(n.value(4_100)).toBe(9);
  });
});

describe('LeadTicks', () => {
  it('takes the first lead at once, then rises every riseEveryMs and falls every 250 ms', () => {
    const l = new LeadTicks(-1, 50);
    l.follow(10, 0);
    expect(l.ticks).toBe(10);
    for (let t = 50; t <= 500; t += 50) l.follow(30, t);
    expect(l.ticks).toBe(20); // ten rises in 500 ms
    for (let t = 550; t <= 1_500; t += 50) l.follow(0, t);
    expect(l.ticks).toBe(16); // four falls in the next second (at 750, 1000, 1250, 1500)
  });
});
