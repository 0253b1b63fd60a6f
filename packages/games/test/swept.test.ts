/**
 * The arena's register forms of the swept tests (`arena/swept.ts`) against the library's
 * `hitPointRoundedBox` and `hitPointCircle`: the same answer and the same `u`, bit for bit, on
 * random moves and on the edge cases (corners, faces grazed, starts inside, moves out, no move).
 */
import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import { hitPointCircle, hitPointRoundedBox } from 'fixedstep';
import { SWEPT, pointCircle, pointRoundedBox, sweptRegisters } from '../src/games/arena/swept.js';

interface Move {
  px: number;
  py: number;
  dx: number;
  dy: number;
  hw: number;
  hh: number;
  radius: number;
}

/** Both forms on one move: the library's (hit, u) and the copy's, to compare with `toEqual`. */
function both(m: Move, circle: boolean): { library: [boolean, number]; copy: [boolean, number] } {
  const out = new Float64Array(3);
  const hit = circle
    ? hitPointCircle(m.px, m.py, m.dx, m.dy, m.radius, out)
    : hitPointRoundedBox(m.px, m.py, m.dx, m.dy, m.hw, m.hh, m.radius, out);
  const reg = sweptRegisters();
  reg[SWEPT.px] = m.px;
  reg[SWEPT.py] = m.py;
  reg[SWEPT.dx] = m.dx;
  reg[SWEPT.dy] = m.dy;
  reg[SWEPT.hw] = m.hw;
  reg[SWEPT.hh] = m.hh;
  reg[SWEPT.radius] = m.radius;
  const copy = circle ? pointCircle(reg) : pointRoundedBox(reg);
  // u only means something on a hit (both leave it alone otherwise).
  return { library: [hit, hit ? out[2]! : -1], copy: [copy, copy ? reg[SWEPT.u]! : -1] };
}

/** Coordinates that land on edges and corners often: small integers and halves, and any double. */
const coordinate = fc.oneof(
  fc.integer({ min: -40, max: 40 }),
  fc.integer({ min: -80, max: 80 }).map((n) => n / 2),
  fc.double({ min: -60, max: 60, noNaN: true }),
);
const extent = fc.oneof(
  fc.integer({ min: 1, max: 30 }),
  fc.double({ min: 0.25, max: 30, noNaN: true }),
);
const radius = fc.oneof(
  fc.constantFrom(0, 2, 6, 9, 10, 12),
  fc.double({ min: 0, max: 16, noNaN: true }),
);
const moves = fc.record({
  px: coordinate,
  py: coordinate,
  dx: coordinate,
  dy: coordinate,
  hw: extent,
  hh: extent,
  radius,
});

/** Moves built to hit the special cases: along faces, through corners, from inside, none at all. */
function edgeCases(): Move[] {
  const cases: Move[] = [];
  const hw = 8;
  const hh = 3;
  for (const radius of [0, 2, 10]) {
    const ex = hw + radius;
    const ey = hh + radius;
    const starts = [-ex - 5, -ex, -hw, 0, hw, ex, ex + 5];
    const startsY = [-ey - 5, -ey, -hh, 0, hh, ey, ey + 5];
    const steps = [-20, -ex, -1, 0, 1, ex, 20];
    for (const px of starts) {
      for (const py of startsY) {
        for (const dx of steps) {
          for (const dy of steps) cases.push({ px, py, dx, dy, hw, hh, radius });
        }
      }
    }
  }
  return cases;
}

describe('the arena swept tests, written out on registers', () => {
  it('answer as the library’s hitPointRoundedBox on the edge cases', () => {
    const cases = edgeCases();
    expect(cases.length).toBeGreaterThan(5000);
    let hits = 0;
    for (const m of cases) {
      const r = both(m, false);
      expect({ m, answer: r.copy }).toEqual({ m, answer: r.library });
      if (r.library[0]) hits++;
    }
    // Both outcomes are well represented.
    expect(hits).toBeGreaterThan(cases.length / 10);
    expect(hits).toBeLessThan(cases.length - cases.length / 10);
  });

  it('answer as the library’s hitPointCircle on the edge cases', () => {
    for (const m of edgeCases()) {
      const r = both(m, true);
      expect({ m, answer: r.copy }).toEqual({ m, answer: r.library });
    }
  });

  it('answer as the library on random moves, bit for bit', () => {
    fc.assert(
      fc.property(moves, (m) => {
        const box = both(m, false);
        const circle = both(m, true);
        return (
          box.copy[0] === box.library[0] &&
          Object.is(box.copy[1], box.library[1]) &&
          circle.copy[0] === circle.library[0] &&
          Object.is(circle.copy[1], circle.library[1])
        );
      }),
      { numRuns: 20000, seed: 1 },
    );
  });
});
