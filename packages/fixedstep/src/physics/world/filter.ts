/**
 * Collision filtering and sensors (Box2D's `b2Filter`, `b2ShouldShapesCollide`, `isSensor`).
 *
 * Every body has a category (bits), a mask (the categories it collides with) and a group. Two
 * bodies collide when they share a non-zero group and it is positive (a negative shared group
 * never collides), else when each one's category is in the other's mask — Box2D's rule, 32 bits
 * wide. Static walls have the default filter (category 1, every mask bit, group 0), as a Box2D
 * static shape made with `b2DefaultShapeDef()` does: a body whose mask lacks bit 1 passes
 * through walls. A sensor collides with nothing (bodies or walls); it only overlaps.
 *
 * The filter is applied where the step makes pairs, *after* the broad phase: {@link filterContacts}
 * drops the contacts a filter or a sensor excludes from the list the broad phase made — in
 * JavaScript or in WebAssembly, the same list to the bit — so the broad phase, the kernels and the
 * solvers are unchanged, and a world with no filter and no sensor runs exactly the code it ran
 * before. Continuous detection asks {@link bodiesCollide} and {@link collidesWithWalls} directly.
 */
import { BodyFlag, DEFAULT_CATEGORY_BITS, DEFAULT_MASK_BITS, type BodyStore } from './body.js';
import type { ContactList } from './contacts.js';
import { show } from './validate.js';

const { SENSOR } = BodyFlag;

/** A body's collision filter (Box2D's `b2Filter`, 32-bit categories). */
export interface BodyFilter {
  /**
   * The categories the body is in: an integer from 0 to 0xFFFFFFFF, usually one bit. Default
   * 0x0001 (`DEFAULT_CATEGORY_BITS`).
   */
  categoryBits: number;
  /**
   * The categories it collides with: an integer from 0 to 0xFFFFFFFF. Default 0xFFFFFFFF (all).
   * Keep bit 1 to collide with static walls.
   */
  maskBits: number;
  /**
   * Bodies with the same non-zero group always collide (positive) or never (negative), whatever
   * the bits. An integer from −2^31 to 2^31 − 1. Default 0 (no group).
   */
  groupIndex: number;
}

/** The default filter (a fresh object): category 1, every mask bit, group 0. */
export function defaultFilter(): BodyFilter {
  return { categoryBits: DEFAULT_CATEGORY_BITS, maskBits: DEFAULT_MASK_BITS, groupIndex: 0 };
}

/** Box2D's `b2ShouldShapesCollide` on two filters' values. */
export function shouldCollide(
  categoryA: number,
  maskA: number,
  groupA: number,
  categoryB: number,
  maskB: number,
  groupB: number,
): boolean {
  if (groupA === groupB && groupA !== 0) return groupA > 0;
  return (maskA & categoryB) !== 0 && (categoryA & maskB) !== 0;
}

/** Whether live bodies `a` and `b` may touch: neither is a sensor and their filters agree. */
export function bodiesCollide(bodies: BodyStore, a: number, b: number): boolean {
  const flags = bodies.flags;
  if (((flags[a]! | flags[b]!) & SENSOR) !== 0) return false;
  const ga = bodies.groupIndex[a]!;
  if (ga === bodies.groupIndex[b] && ga !== 0) return ga > 0;
  return (
    (bodies.maskBits[a]! & bodies.categoryBits[b]!) !== 0 &&
    (bodies.categoryBits[a]! & bodies.maskBits[b]!) !== 0
  );
}

/** Whether live body `i` may touch a static wall (which has the default filter). */
export function collidesWithWalls(bodies: BodyStore, i: number): boolean {
  return (
    (bodies.flags[i]! & SENSOR) === 0 &&
    (bodies.maskBits[i]! & DEFAULT_CATEGORY_BITS) !== 0 &&
    bodies.categoryBits[i] !== 0
  );
}

/**
 * Drops from `contacts` (as the broad phase left them, before any solver field is set) every
 * contact that a filter or a sensor excludes, keeping the order of the rest and
 * `bodyPairCount`. Call it only when the world has a filter or a sensor
 * (`filteredCount + sensorCount > 0`).
 */
export function filterContacts(contacts: ContactList, bodies: BodyStore): void {
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  const normalX = contacts.normalX;
  const normalY = contacts.normalY;
  const separation = contacts.separation;
  const pairs = contacts.bodyPairCount;
  const n = contacts.count;
  let kept = 0;
  let keptPairs = 0;
  for (let k = 0; k < n; k++) {
    const a = bodyA[k]!;
    const b = bodyB[k]!;
    if (b >= 0 ? !bodiesCollide(bodies, a, b) : !collidesWithWalls(bodies, a)) continue;
    if (kept !== k) {
      bodyA[kept] = a;
      bodyB[kept] = b;
      normalX[kept] = normalX[k]!;
      normalY[kept] = normalY[k]!;
      separation[kept] = separation[k]!;
    }
    kept++;
    if (k < pairs) keptPairs = kept;
  }
  contacts.count = kept;
  contacts.bodyPairCount = keptPairs;
}

/** The fields of a {@link BodyFilter}. */
const FILTER_KEYS: ReadonlySet<string> = new Set(['categoryBits', 'maskBits', 'groupIndex']);

/**
 * Checks a (partial) filter given to `method` for body `id` and returns it whole (missing fields
 * from `base`). Throws a TypeError for an unknown field or a value that is not a number, a
 * RangeError naming the field for a number out of range.
 */
export function checkFilter(
  method: string,
  id: number,
  filter: unknown,
  base: Readonly<BodyFilter>,
): BodyFilter {
  const where = `PhysicsWorld.${method}: body ${id}`;
  if (typeof filter !== 'object' || filter === null)
    throw new TypeError(`${where}: filter must be an object, got ${show(filter)}`);
  for (const key in filter) {
    if (!FILTER_KEYS.has(key))
      throw new TypeError(
        `${where}: unknown filter field "${key}"; the fields are categoryBits, maskBits, groupIndex`,
      );
  }
  const f = filter as Partial<Record<keyof BodyFilter, unknown>>;
  const categoryBits = f.categoryBits ?? base.categoryBits;
  const maskBits = f.maskBits ?? base.maskBits;
  const groupIndex = f.groupIndex ?? base.groupIndex;
  checkBits(where, 'categoryBits', categoryBits);
  checkBits(where, 'maskBits', maskBits);
  if (!(
    typeof groupIndex === 'number' &&
    Number.isInteger(groupIndex) &&
    groupIndex >= -0x80000000 &&
    groupIndex <= 0x7fffffff
  ))
    fieldFail(where, 'groupIndex', 'an integer from -2147483648 to 2147483647', groupIndex);
  return { categoryBits, maskBits, groupIndex: groupIndex + 0 };
}

/** A 32-bit mask: an integer from 0 to 0xFFFFFFFF. */
export function checkBits(where: string, field: string, v: unknown): asserts v is number {
  if (typeof v === 'number' && Number.isInteger(v) && v >= 0 && v <= 0xffffffff) return;
  fieldFail(where, field, 'an integer from 0 to 0xFFFFFFFF (4294967295)', v);
}

function fieldFail(where: string, field: string, rule: string, v: unknown): never {
  const text = `${where}: ${field} must be ${rule}, got ${show(v)}`;
  throw typeof v === 'number' ? new RangeError(text) : new TypeError(text);
}
