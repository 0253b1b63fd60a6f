/**
 * The library's swept tests `hitPointRoundedBox` and `hitPointCircle`, written out operation for
 * operation on numbers read from an array of registers instead of passed as arguments.
 *
 * Why a copy: the library's forms take eight numbers; called from a loop that V8 does not inline
 * them into (the walls' queries, the bullets' targets), every fractional one is boxed in a fresh
 * heap object — an allocation per argument per call, every tick. Reading them from an array costs
 * nothing. The arithmetic is the library's, in the same order, so the answers are bit for bit the
 * same (`packages/games/test/swept.test.ts` compares the two on random and edge-case moves); only
 * the contact normal, which no arena query uses, is left out.
 */

/** Register indices of {@link pointRoundedBox} and {@link pointCircle}. */
export const SWEPT = {
  /** The mover's centre relative to the box's (or circle's) centre, arena units. */
  px: 0,
  py: 1,
  /** Its displacement over the move. */
  dx: 2,
  dy: 3,
  /** The box's half extents ({@link pointRoundedBox} only). */
  hw: 4,
  hh: 5,
  /** The rounding radius (the mover's radius; for a circle, the sum of the radii). */
  radius: 6,
  /** Out: the fraction `u ∈ [0, 1]` of the move at which they first touch, on a hit. */
  u: 7,
} as const;

/** Registers for {@link pointRoundedBox} and {@link pointCircle} (indexed by {@link SWEPT}). */
export function sweptRegisters(): Float64Array {
  return new Float64Array(8);
}

/**
 * `hitPointRoundedBox(px, py, dx, dy, hw, hh, radius)` of the library on registers `reg`: whether
 * the moving point touches the box grown by `radius` (rounded corners) during the move — `u` to
 * `reg[SWEPT.u]` on a hit (0 when already overlapping and moving in).
 */
export function pointRoundedBox(reg: Float64Array): boolean {
  const px = reg[0]!;
  const py = reg[1]!;
  const dx = reg[2]!;
  const dy = reg[3]!;
  const hw = reg[4]!;
  const hh = reg[5]!;
  const radius = reg[6]!;
  const ex = hw + radius;
  const ey = hh + radius;
  const ax = px < 0 ? -px : px;
  const ay = py < 0 ? -py : py;
  if (ax < ex && ay < ey) return startsInside(reg);
  let tin = 0;
  let tout = 1;
  let axis = 0; // 1: entered through an x face, 2: through a y face
  if (dx === 0) {
    if (ax >= ex) return false;
  } else {
    let t1 = (-ex - px) / dx;
    let t2 = (ex - px) / dx;
    if (t1 > t2) {
      const s = t1;
      t1 = t2;
      t2 = s;
    }
    if (t1 >= tin) {
      tin = t1;
      axis = 1;
    }
    if (t2 < tout) tout = t2;
  }
  if (dy === 0) {
    if (ay >= ey) return false;
  } else {
    let t1 = (-ey - py) / dy;
    let t2 = (ey - py) / dy;
    if (t1 > t2) {
      const s = t1;
      t1 = t2;
      t2 = s;
    }
    if (t1 >= tin) {
      tin = t1;
      axis = 2;
    }
    if (t2 < tout) tout = t2;
  }
  if (tin > tout || axis === 0) return false;
  if (radius > 0) {
    const hx = px + tin * dx;
    const hy = py + tin * dy;
    if ((hx > hw || hx < -hw) && (hy > hh || hy < -hh)) {
      reg[0] = px - (hx > 0 ? hw : -hw);
      reg[1] = py - (hy > 0 ? hh : -hh);
      return pointCircle(reg);
    }
  }
  reg[7] = tin;
  return true;
}

/**
 * {@link pointRoundedBox} when the point starts inside the grown box (its square corners
 * included): the rare case, apart so that the common one is small enough for V8 to inline.
 */
function startsInside(reg: Float64Array): boolean {
  const px = reg[0]!;
  const py = reg[1]!;
  const dx = reg[2]!;
  const dy = reg[3]!;
  const hw = reg[4]!;
  const hh = reg[5]!;
  const radius = reg[6]!;
  const ex = hw + radius;
  const ey = hh + radius;
  const ax = px < 0 ? -px : px;
  const ay = py < 0 ? -py : py;
  if (radius > 0 && ax > hw && ay > hh) {
    reg[0] = px - (px > 0 ? hw : -hw);
    reg[1] = py - (py > 0 ? hh : -hh);
    return pointCircle(reg);
  }
  // Overlapping: the minimum-translation normal; a hit at once unless moving out.
  let nx = 0;
  let ny = 0;
  if (ax > hw) nx = px >= 0 ? 1 : -1;
  else if (ay > hh) ny = py >= 0 ? 1 : -1;
  else if (ex - ax <= ey - ay) nx = px >= 0 ? 1 : -1;
  else ny = py >= 0 ? 1 : -1;
  if (nx * dx + ny * dy >= 0) return false;
  reg[7] = 0;
  return true;
}

/**
 * `hitPointCircle(px, py, dx, dy, radius)` of the library on registers `reg`: whether the moving
 * point comes within `radius` of the origin during the move — `u` to `reg[SWEPT.u]` on a hit (0
 * when already touching and moving in). Ignores the half extents.
 */
export function pointCircle(reg: Float64Array): boolean {
  const px = reg[0]!;
  const py = reg[1]!;
  const dx = reg[2]!;
  const dy = reg[3]!;
  const radius = reg[6]!;
  const c = px * px + py * py - radius * radius;
  const b = px * dx + py * dy;
  if (b >= 0) return false; // moving away (or not moving): no new contact
  if (c <= 0) {
    reg[7] = 0; // already touching
    return true;
  }
  const a = dx * dx + dy * dy;
  const disc = b * b - a * c;
  if (disc < 0) return false;
  // (-b - √disc) / a, rationalised to avoid cancellation when the ray grazes.
  const u = c / (-b + Math.sqrt(disc));
  if (u > 1) return false;
  reg[7] = u;
  return true;
}
