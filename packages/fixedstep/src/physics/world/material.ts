/**
 * Materials (Box2D's `b2MixFriction`, `b2MixRestitution` in `contact.c`): how a contact's friction
 * and restitution come from its two bodies'. A body without its own value
 * ({@link WORLD_MATERIAL}) has the world's `def.friction` / `def.restitution`, and so does a wall.
 *
 * - friction: `sqrt(fa · fb)` — `Math.sqrt` is correctly rounded in every engine — or the common
 *   value when the two are equal, so a world whose bodies all have the world's friction steps
 *   exactly as it did before materials existed;
 * - restitution: the larger of the two.
 *
 * Linear damping is per body, not per contact: see `PhysicsWorld`'s velocity integration.
 */
import { WORLD_MATERIAL, type BodyStore } from './body.js';
import type { ContactList } from './contacts.js';
import type { WorldDef } from './def.js';

/** Box2D's `b2MixFriction`: `sqrt(fa · fb)`, exactly `fa` when the two are equal. */
export function mixFriction(fa: number, fb: number): number {
  return fa === fb ? fa : Math.sqrt(fa * fb);
}

/** Box2D's `b2MixRestitution`: the larger. */
export function mixRestitution(ea: number, eb: number): number {
  return ea > eb ? ea : eb;
}

/** A body's friction: its own or the world's. */
export function frictionOf(bodies: BodyStore, def: Readonly<WorldDef>, id: number): number {
  const f = bodies.friction[id]!;
  return f === WORLD_MATERIAL ? def.friction : f;
}

/** A body's restitution: its own or the world's. */
export function restitutionOf(bodies: BodyStore, def: Readonly<WorldDef>, id: number): number {
  const e = bodies.restitution[id]!;
  return e === WORLD_MATERIAL ? def.restitution : e;
}

/** What the materials of a world ask of this step's solver. */
export interface MaterialUse {
  /** Some live body has a friction of its own: contacts need their own friction. */
  friction: boolean;
  /** The largest restitution any contact can have (the world's or a body's). */
  maxRestitution: number;
}

/** {@link MaterialUse} of the world now (a scan of the bodies, only when some have a material). */
export function materialUse(bodies: BodyStore, def: Readonly<WorldDef>, out: MaterialUse): void {
  out.friction = false;
  out.maxRestitution = def.restitution;
  if (bodies.materialCount === 0) return;
  const flags = bodies.flags;
  const friction = bodies.friction;
  const restitution = bodies.restitution;
  for (let i = 0; i < bodies.slotCount; i++) {
    if (flags[i] === 0) continue;
    if (friction[i] !== WORLD_MATERIAL) out.friction = true;
    const e = restitution[i]!;
    if (e > out.maxRestitution) out.maxRestitution = e;
  }
}

/**
 * Each of the `visits` visits' mixed friction into `out` (by visit: `order` gives each visit's
 * contact; a pad, -1, gets 0). A body–wall contact's wall has the world's friction.
 */
export function visitFrictions(
  contacts: ContactList,
  bodies: BodyStore,
  def: Readonly<WorldDef>,
  order: Int32Array,
  visits: number,
  out: Float64Array,
): void {
  const pairs = contacts.bodyPairCount;
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  for (let s = 0; s < visits; s++) {
    const k = order[s]!;
    if (k < 0) {
      out[s] = 0; // a pad
      continue;
    }
    const fa = frictionOf(bodies, def, bodyA[k]!);
    const fb = k < pairs ? frictionOf(bodies, def, bodyB[k]!) : def.friction;
    out[s] = mixFriction(fa, fb);
  }
}
