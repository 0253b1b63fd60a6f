/**
 * The narrow phase (Box2D's `manifold.c`): for one pair of shapes that the broad phase found
 * close, the contact — if they overlap — as a unit normal and a separation.
 *
 * Shapes never rotate, so every test is closed-form: circle–circle along the centre line, box–box
 * and circle-inside-box out through the nearer face (the axis of least overlap), circle–box and
 * circle–segment from the closest point, box–segment over the separating axes x, y and the
 * segment's normal. One contact point per pair is enough without rotation: a contact's impulse
 * only ever moves the body's centre.
 *
 * The normal always points from the second shape to the first (`b` to `a`); a wall is
 * {@link staticRef}. Every function adds at most one contact.
 *
 * The functions take ids and read the shapes themselves: V8 boxes every double passed to a call it
 * does not inline (a heap number each), and the broad phase, with all of these in it, is past its
 * inlining budget — passing coordinates made 20 KB of garbage a step in a pile of boxes.
 */
import type { BodyStore } from './body.js';
import type { ContactList } from './contacts.js';
import type { WorldDef } from './def.js';
import { staticOf, staticRef, type StaticStore } from './statics.js';

/**
 * Circles `a` and `b`, `(dx, dy)` = centre a − centre b, radii summing to `radiusSum`. Centres on
 * top of each other part along +y. The one function here that takes coordinates: it is the hot
 * case, the broad phase has them already, and it is small enough that V8 always inlines it (the
 * benchmark's allocation check would show boxed doubles if it did not).
 */
export function circleCircle(
  contacts: ContactList,
  a: number,
  b: number,
  dx: number,
  dy: number,
  radiusSum: number,
): void {
  const d2 = dx * dx + dy * dy;
  if (d2 >= radiusSum * radiusSum) return;
  const d = Math.sqrt(d2);
  if (d > 0) contacts.add(a, b, dx / d, dy / d, d - radiusSum);
  else contacts.add(a, b, 0, 1, -radiusSum);
}

/**
 * Box `i` and box `b` (a body, or a static box as {@link staticRef}); the caller has seen that they
 * overlap on both axes. Out along the axis of least overlap; a tie goes to y.
 */
export function boxBox(
  contacts: ContactList,
  i: number,
  b: number,
  bodies: BodyStore,
  walls: StaticStore,
): void {
  let dx: number;
  let dy: number;
  let sumW: number;
  let sumH: number;
  if (b >= 0) {
    dx = bodies.x[i]! - bodies.x[b]!;
    dy = bodies.y[i]! - bodies.y[b]!;
    sumW = bodies.halfWidth[i]! + bodies.halfWidth[b]!;
    sumH = bodies.halfHeight[i]! + bodies.halfHeight[b]!;
  } else {
    const s = staticOf(b);
    dx = bodies.x[i]! - walls.centerX[s]!;
    dy = bodies.y[i]! - walls.centerY[s]!;
    sumW = bodies.halfWidth[i]! + walls.halfWidth[s]!;
    sumH = bodies.halfHeight[i]! + walls.halfHeight[s]!;
  }
  const overlapX = sumW - (dx < 0 ? -dx : dx);
  const overlapY = sumH - (dy < 0 ? -dy : dy);
  if (overlapX < overlapY) contacts.add(i, b, dx >= 0 ? 1 : -1, 0, -overlapX);
  else contacts.add(i, b, 0, dy >= 0 ? 1 : -1, -overlapY);
}

/**
 * Circle body `circle` against box `box` (a body, or a static box as {@link staticRef}): a contact
 * between `a` and `b` whose normal is `sign ×` (box → circle). A centre inside the box leaves
 * through the nearer face.
 */
export function circleBox(
  contacts: ContactList,
  a: number,
  b: number,
  circle: number,
  box: number,
  sign: number,
  bodies: BodyStore,
  walls: StaticStore,
): void {
  const cx = bodies.x[circle]!;
  const cy = bodies.y[circle]!;
  const r = bodies.halfWidth[circle]!;
  let bx: number;
  let by: number;
  let bw: number;
  let bh: number;
  if (box >= 0) {
    bx = bodies.x[box]!;
    by = bodies.y[box]!;
    bw = bodies.halfWidth[box]!;
    bh = bodies.halfHeight[box]!;
  } else {
    const s = staticOf(box);
    bx = walls.centerX[s]!;
    by = walls.centerY[s]!;
    bw = walls.halfWidth[s]!;
    bh = walls.halfHeight[s]!;
  }
  const lx = cx - bx;
  const ly = cy - by;
  const alx = lx < 0 ? -lx : lx;
  const aly = ly < 0 ? -ly : ly;
  if (alx <= bw && aly <= bh) {
    if (bw - alx <= bh - aly) contacts.add(a, b, lx >= 0 ? sign : -sign, 0, alx - bw - r);
    else contacts.add(a, b, 0, ly >= 0 ? sign : -sign, aly - bh - r);
    return;
  }
  // The closest point of the box, and the way from it to the centre.
  const qx = lx > bw ? bw : lx < -bw ? -bw : lx;
  const qy = ly > bh ? bh : ly < -bh ? -bh : ly;
  const ex = lx - qx;
  const ey = ly - qy;
  const d2 = ex * ex + ey * ey;
  if (d2 >= r * r) return;
  const d = Math.sqrt(d2);
  contacts.add(a, b, (sign * ex) / d, (sign * ey) / d, d - r);
}

/**
 * Circle body `i` against segment wall `s`. A centre exactly on the segment goes back the way it
 * came: against its velocity, including the gravity this step is still to add to it if
 * `gravityPending`.
 */
export function circleSegment(
  contacts: ContactList,
  i: number,
  s: number,
  bodies: BodyStore,
  walls: StaticStore,
  gravityPending: boolean,
  def: Readonly<WorldDef>,
): void {
  const cx = bodies.x[i]!;
  const cy = bodies.y[i]!;
  const r = bodies.halfWidth[i]!;
  const ax = walls.ax[s]!;
  const ay = walls.ay[s]!;
  const nx = walls.normalX[s]!;
  const ny = walls.normalY[s]!;
  const len = walls.length[s]!;
  // The closest point of the segment: along the tangent (ny, −nx), clamped to [0, len].
  const rx = cx - ax;
  const ry = cy - ay;
  const along = rx * ny - ry * nx;
  let qx = ax;
  let qy = ay;
  if (along >= len) {
    qx = walls.bx[s]!;
    qy = walls.by[s]!;
  } else if (along > 0) {
    qx = ax + along * ny;
    qy = ay - along * nx;
  }
  const ex = cx - qx;
  const ey = cy - qy;
  const d2 = ex * ex + ey * ey;
  if (d2 >= r * r) return;
  const d = Math.sqrt(d2);
  if (d > 0) contacts.add(i, staticRef(s), ex / d, ey / d, d - r);
  else {
    const gx = gravityPending ? def.gravityX * def.timeStep : 0;
    const gy = gravityPending ? def.gravityY * def.timeStep : 0;
    const vx = bodies.vx[i]! + gx;
    const vy = bodies.vy[i]! + gy;
    const side = vx * nx + vy * ny > 0 ? -1 : 1;
    contacts.add(i, staticRef(s), side * nx, side * ny, -r);
  }
}

/**
 * Box body `i` against segment wall `s`: separating axes x, y and the segment's normal; the
 * smallest overlap wins (the normal on a tie).
 */
export function boxSegment(
  contacts: ContactList,
  i: number,
  s: number,
  bodies: BodyStore,
  walls: StaticStore,
): void {
  const cx = bodies.x[i]!;
  const cy = bodies.y[i]!;
  const w = bodies.halfWidth[i]!;
  const h = bodies.halfHeight[i]!;
  const ax = walls.ax[s]!;
  const ay = walls.ay[s]!;
  const bx = walls.bx[s]!;
  const by = walls.by[s]!;
  const nx = walls.normalX[s]!;
  const ny = walls.normalY[s]!;
  // Along the normal: the box's reach, the centre's signed distance, the overlap.
  const reach = w * (nx < 0 ? -nx : nx) + h * (ny < 0 ? -ny : ny);
  const distance = (cx - ax) * nx + (cy - ay) * ny;
  const overlapN = reach - (distance < 0 ? -distance : distance);
  if (overlapN <= 0) return;
  let best = overlapN;
  let bestX = distance >= 0 ? nx : -nx;
  let bestY = distance >= 0 ? ny : -ny;
  // Along x and y: the segment's extent grown by the box's half extents.
  const left = cx - ((ax < bx ? ax : bx) - w);
  const right = (ax < bx ? bx : ax) + w - cx;
  const below = cy - ((ay < by ? ay : by) - h);
  const above = (ay < by ? by : ay) + h - cy;
  if (left <= 0 || right <= 0 || below <= 0 || above <= 0) return;
  if (left < best) {
    best = left;
    bestX = -1;
    bestY = 0;
  }
  if (right < best) {
    best = right;
    bestX = 1;
    bestY = 0;
  }
  if (below < best) {
    best = below;
    bestX = 0;
    bestY = -1;
  }
  if (above < best) {
    best = above;
    bestX = 0;
    bestY = 1;
  }
  contacts.add(i, staticRef(s), bestX, bestY, -best);
}
