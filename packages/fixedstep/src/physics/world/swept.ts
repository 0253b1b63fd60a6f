/**
 * Swept tests (continuous collision detection): the time of impact of a moving shape against
 * another shape, as a ray against the Minkowski sum of the two shapes.
 *
 * Every function takes the mover's centre `p` and its displacement `d` over the interval, both
 * **relative to the other shape** (subtract the other shape's centre and displacement first).
 * The `hit*` functions return whether the shapes touch within the interval and, on a hit, write
 * the unit contact normal (pointing from the other shape towards the mover) to `out[0], out[1]`
 * and the fraction `u ∈ [0, 1]` of `d` at which they first touch to `out[2]`: `out` needs 3
 * numbers. The `toi*` functions are the same tests returning `u`, or `-1` for no hit, with the
 * normal in `out[0], out[1]`.
 *
 * Hot loops (the world's CCD, the games' walls and bots) call the `hit*` forms: a function that
 * V8 does not inline returns a fractional double boxed in a fresh heap object, so returning `u`
 * would allocate on every hit; a boolean never does.
 *
 * Shapes that already overlap at `u = 0` return `0` with the minimum-translation normal when the
 * mover is moving *into* the other shape (`d · n < 0`), and `-1` when it is moving out: the
 * discrete solver separates resting contacts, and a body pressed into a wall is stopped at once.
 *
 * Only `+ - * /` and `Math.sqrt` (correctly rounded in every engine), so results are bit-identical
 * everywhere.
 */

/** Scratch for the nearer of two candidate hits; never part of any state. */
const tmp = new Float64Array(3);
/** Scratch for the `toi*` forms. */
const hit = new Float64Array(3);

/** The `toi*` form of a `hit*` result in {@link hit}: `u` (normal copied to `out`), or -1. */
function toi(touched: boolean, out: Float64Array): number {
  if (!touched) return -1;
  out[0] = hit[0]!;
  out[1] = hit[1]!;
  return hit[2]!;
}

/**
 * A point moving from `(px, py)` by `(dx, dy)` against a circle of radius `radius` at the origin
 * (circle vs circle: `radius` = the sum of the radii). Solves `|p + u·d|² = R²` for the smaller root.
 */
export function hitPointCircle(
  px: number,
  py: number,
  dx: number,
  dy: number,
  radius: number,
  out: Float64Array,
): boolean {
  const c = px * px + py * py - radius * radius;
  const b = px * dx + py * dy;
  if (b >= 0) return false; // moving away (or not moving): no new contact
  if (c <= 0) {
    // Already touching: stop now, along the line of centres.
    const len = Math.sqrt(px * px + py * py);
    if (len > 0) {
      out[0] = px / len;
      out[1] = py / len;
    } else {
      const dl = Math.sqrt(dx * dx + dy * dy);
      out[0] = -dx / dl;
      out[1] = -dy / dl;
    }
    out[2] = 0;
    return true;
  }
  const a = dx * dx + dy * dy;
  const disc = b * b - a * c;
  if (disc < 0) return false;
  // (-b - √disc) / a, rationalised to avoid cancellation when the ray grazes.
  const u = c / (-b + Math.sqrt(disc));
  if (u > 1) return false;
  const hx = px + u * dx;
  const hy = py + u * dy;
  const hl = Math.sqrt(hx * hx + hy * hy);
  out[0] = hx / hl;
  out[1] = hy / hl;
  out[2] = u;
  return true;
}

/**
 * A point against an axis-aligned box of half extents `(hw, hh)` at the origin, rounded by
 * `radius` (circle vs box: the box's half extents and the circle's radius; box vs box: the sums of
 * the half extents and `radius = 0`). Slab test on the box grown by `radius`; an entry in a corner
 * square becomes a test against the corner circle (a miss there is a miss overall: the ray cannot
 * leave a corner square into a face region without passing within `radius` of the corner).
 */
export function hitPointRoundedBox(
  px: number,
  py: number,
  dx: number,
  dy: number,
  hw: number,
  hh: number,
  radius: number,
  out: Float64Array,
): boolean {
  const ex = hw + radius;
  const ey = hh + radius;
  const ax = px < 0 ? -px : px;
  const ay = py < 0 ? -py : py;
  if (ax < ex && ay < ey) {
    if (radius > 0 && ax > hw && ay > hh) {
      return hitPointCircle(
        px - (px > 0 ? hw : -hw),
        py - (py > 0 ? hh : -hh),
        dx,
        dy,
        radius,
        out,
      );
    }
    // Overlapping: the minimum-translation normal.
    let nx = 0;
    let ny = 0;
    if (ax > hw) nx = px >= 0 ? 1 : -1;
    else if (ay > hh) ny = py >= 0 ? 1 : -1;
    else if (ex - ax <= ey - ay) nx = px >= 0 ? 1 : -1;
    else ny = py >= 0 ? 1 : -1;
    if (nx * dx + ny * dy >= 0) return false;
    out[0] = nx;
    out[1] = ny;
    out[2] = 0;
    return true;
  }
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
      return hitPointCircle(
        px - (hx > 0 ? hw : -hw),
        py - (hy > 0 ? hh : -hh),
        dx,
        dy,
        radius,
        out,
      );
    }
  }
  if (axis === 1) {
    out[0] = dx > 0 ? -1 : 1;
    out[1] = 0;
  } else {
    out[0] = 0;
    out[1] = dy > 0 ? -1 : 1;
  }
  out[2] = tin;
  return true;
}

/**
 * A point against the segment `a → b` (absolute coordinates, like the point) rounded by `radius`
 * (a capsule): a circle of that radius against a static wall segment. `radius` must be positive.
 */
export function hitPointCapsule(
  px: number,
  py: number,
  dx: number,
  dy: number,
  ax: number,
  ay: number,
  bx: number,
  by: number,
  radius: number,
  out: Float64Array,
): boolean {
  const ex = bx - ax;
  const ey = by - ay;
  const len = Math.sqrt(ex * ex + ey * ey);
  if (len === 0) return hitPointCircle(px - ax, py - ay, dx, dy, radius, out);
  const tx = ex / len;
  const ty = ey / len;
  const nx = -ty;
  const ny = tx;
  const rx = px - ax;
  const ry = py - ay;
  const s = rx * nx + ry * ny; // signed distance from the segment's line
  const along = rx * tx + ry * ty;
  const ds = dx * nx + dy * ny;
  const as = s < 0 ? -s : s;
  if (as < radius) {
    if (along >= 0 && along <= len) {
      // Overlapping the flat part: push out on the side the centre is on.
      const side = s > 0 ? 1 : s < 0 ? -1 : ds > 0 ? -1 : 1;
      if (side * ds >= 0) return false;
      out[0] = side * nx;
      out[1] = side * ny;
      out[2] = 0;
      return true;
    }
    // Overlapping an end cap at the start: the nearest cap alone decides, as the flat part does
    // above (asking both caps, the far one's entry could be taken as a first contact although the
    // point never left the capsule).
    const cap = along < 0 ? 0 : len;
    const cx = rx - cap * tx;
    const cy = ry - cap * ty;
    if (cx * cx + cy * cy <= radius * radius) {
      return hitPointCircle(cx, cy, dx, dy, radius, out);
    }
  } else {
    const side = s > 0 ? 1 : -1;
    if (side * ds < 0) {
      const u = (side * radius - s) / ds;
      if (u > 1) return false;
      const al = along + u * (dx * tx + dy * ty);
      if (al >= 0 && al <= len) {
        out[0] = side * nx;
        out[1] = side * ny;
        out[2] = u;
        return true;
      }
    }
  }
  // The end caps.
  const ha = hitPointCircle(rx, ry, dx, dy, radius, out);
  const hb = hitPointCircle(px - bx, py - by, dx, dy, radius, tmp);
  if (hb && (!ha || tmp[2]! < out[2]!)) {
    out[0] = tmp[0]!;
    out[1] = tmp[1]!;
    out[2] = tmp[2]!;
    return true;
  }
  return ha;
}

/**
 * An axis-aligned box of half extents `(hw, hh)` with centre `p` moving by `d`, against the static
 * segment `a → b` (absolute coordinates). Their Minkowski sum is the intersection of three slabs —
 * along x, along y and along the segment's normal — so this clips the ray against the three
 * (Cyrus–Beck).
 */
export function hitBoxSegment(
  px: number,
  py: number,
  dx: number,
  dy: number,
  hw: number,
  hh: number,
  ax: number,
  ay: number,
  bx: number,
  by: number,
  out: Float64Array,
): boolean {
  const ex = bx - ax;
  const ey = by - ay;
  const len = Math.sqrt(ex * ex + ey * ey);
  const nx = len > 0 ? -ey / len : 0;
  const ny = len > 0 ? ex / len : 1;
  const rn = hw * (nx < 0 ? -nx : nx) + hh * (ny < 0 ? -ny : ny);
  let tin = -Infinity;
  let tout = Infinity;
  let inX = 0;
  let inY = 0;
  // Penetration bookkeeping for the already-overlapping case.
  let minPen = Infinity;
  let penX = 0;
  let penY = 0;
  for (let k = 0; k < 3; k++) {
    let lo: number;
    let hi: number;
    let val: number;
    let rate: number;
    let axX: number;
    let axY: number;
    if (k === 0) {
      lo = (ax < bx ? ax : bx) - hw;
      hi = (ax < bx ? bx : ax) + hw;
      val = px;
      rate = dx;
      axX = 1;
      axY = 0;
    } else if (k === 1) {
      lo = (ay < by ? ay : by) - hh;
      hi = (ay < by ? by : ay) + hh;
      val = py;
      rate = dy;
      axX = 0;
      axY = 1;
    } else {
      lo = -rn;
      hi = rn;
      val = (px - ax) * nx + (py - ay) * ny;
      rate = dx * nx + dy * ny;
      axX = nx;
      axY = ny;
    }
    if (val - lo < minPen) {
      minPen = val - lo;
      penX = -axX;
      penY = -axY;
    }
    if (hi - val < minPen) {
      minPen = hi - val;
      penX = axX;
      penY = axY;
    }
    if (rate === 0) {
      if (val <= lo || val >= hi) return false;
      continue;
    }
    let t1 = (lo - val) / rate;
    let t2 = (hi - val) / rate;
    let sx = -axX;
    let sy = -axY;
    if (t1 > t2) {
      const s = t1;
      t1 = t2;
      t2 = s;
      sx = axX;
      sy = axY;
    }
    if (t1 > tin) {
      tin = t1;
      inX = sx;
      inY = sy;
    }
    if (t2 < tout) tout = t2;
  }
  if (tin > tout || tout <= 0) return false;
  if (tin < 0) {
    // Inside all three slabs: overlapping now.
    if (minPen <= 0) return false;
    if (penX * dx + penY * dy >= 0) return false;
    out[0] = penX;
    out[1] = penY;
    out[2] = 0;
    return true;
  }
  if (tin > 1) return false;
  out[0] = inX;
  out[1] = inY;
  out[2] = tin;
  return true;
}

/** {@link hitPointCircle}, returning `u` or -1; the normal goes to `out[0], out[1]`. */
export function toiPointCircle(
  px: number,
  py: number,
  dx: number,
  dy: number,
  radius: number,
  out: Float64Array,
): number {
  return toi(hitPointCircle(px, py, dx, dy, radius, hit), out);
}

/** {@link hitPointRoundedBox}, returning `u` or -1; the normal goes to `out[0], out[1]`. */
export function toiPointRoundedBox(
  px: number,
  py: number,
  dx: number,
  dy: number,
  hw: number,
  hh: number,
  radius: number,
  out: Float64Array,
): number {
  return toi(hitPointRoundedBox(px, py, dx, dy, hw, hh, radius, hit), out);
}

/** {@link hitPointCapsule}, returning `u` or -1; the normal goes to `out[0], out[1]`. */
export function toiPointCapsule(
  px: number,
  py: number,
  dx: number,
  dy: number,
  ax: number,
  ay: number,
  bx: number,
  by: number,
  radius: number,
  out: Float64Array,
): number {
  return toi(hitPointCapsule(px, py, dx, dy, ax, ay, bx, by, radius, hit), out);
}

/** {@link hitBoxSegment}, returning `u` or -1; the normal goes to `out[0], out[1]`. */
export function toiBoxSegment(
  px: number,
  py: number,
  dx: number,
  dy: number,
  hw: number,
  hh: number,
  ax: number,
  ay: number,
  bx: number,
  by: number,
  out: Float64Array,
): number {
  return toi(hitBoxSegment(px, py, dx, dy, hw, hh, ax, ay, bx, by, hit), out);
}
