/**
 * The contact solver (Box2D's `contact_solver.c`): sequential impulses on velocities, then a
 * relaxation on positions.
 *
 * ## Velocities: sequential impulses
 *
 * Bodies do not rotate, so a contact between A and B with unit normal n (from B to A) only ever
 * sees the relative velocity of the two centres, `v = vA − vB`, and its normal part `vn = v · n`.
 * The contact may push (never pull): it applies an impulse `P = λ·n` to A and `−λ·n` to B with
 * `λ ≥ 0`, changing vn by `λ · (1/mA + 1/mB)`. The impulse that brings vn to zero is therefore
 *
 *     Δλ = −vn · mN,        mN = 1 / (1/mA + 1/mB)    ("normalMass"; 1/mB = 0 for a wall)
 *
 * Solving one contact disturbs its neighbours, so the solver sweeps over all contacts
 * `velocityIterations` times (Gauss–Seidel), each time applying the *change* of impulse. The
 * clamp is on the *accumulated* impulse, not on each change (Catto, "Iterative Dynamics with
 * Temporal Coherence", 2005):
 *
 *     λ' = max(0, λ − vn · mN);   apply λ' − λ;   λ = λ'
 *
 * so an iteration may take back part of what an earlier one pushed, but the total stays a push.
 *
 * **Friction** (Coulomb) is the same along the tangent t = (ny, −nx), relative tangential speed
 * `vt = v · t`, with the same effective mass (no rotation: the tangent sees the same masses), and
 * the accumulated friction impulse clamped to the friction cone of the *current* normal impulse:
 *
 *     τ' = clamp(τ − vt · mN, −μ·λ, μ·λ)
 *
 * **Warm starting**: a resting contact needs about the same impulse every step, so each contact
 * starts from the impulses the same pair needed last step (the {@link WarmStartCache}) and applies
 * them before iterating. A stack then holds after one step instead of sinking until the
 * iterations catch up.
 *
 * **Restitution**, as in Box2D, comes once after the iterations, only for contacts that were
 * approaching faster than `restitutionThreshold` when the step began (`approachSpeed`, measured
 * after gravity, before any impulse): their normal impulse grows until `vn = −e · approachSpeed`
 * (again clamped so the accumulated impulse stays ≥ 0). Below the threshold a contact does not
 * bounce, so resting bodies do not jitter.
 *
 * ## Positions: relaxation
 *
 * Velocities alone let overlap build up (gravity pulls a little further in each step). After
 * bodies have moved, each contact's separation is *predicted* without running the narrow phase
 * again — the separation when found plus how far the two bodies have moved along its normal
 * since: `s = s0 + (ΔA − ΔB) · n` — and any overlap deeper than `linearSlop` is removed, a
 * fraction `positionCorrection` (β) per iteration, split by inverse mass:
 *
 *     C = −(s + slop) · β / (1/mA + 1/mB);   A += C/mA · n;   B −= C/mB · n
 *
 * Walls come last in every iteration, so they have the final word. The slop leaves resting
 * contacts slightly overlapped, so they are found again next step and keep their warm start.
 */
import type { BodyStore } from './body.js';
import type { ContactList, WarmStartCache } from './contacts.js';
import type { WorldDef } from './def.js';

/**
 * Sequential impulses on this step's contacts (see the file comment): effective masses and
 * approach speeds, warm start from `cache`, `velocityIterations` sweeps over body–body contacts
 * then body–wall contacts, then restitution. Writes velocities; leaves the final impulses in
 * `contacts` for {@link WarmStartCache.store}.
 */
export function solveVelocities(
  contacts: ContactList,
  cache: WarmStartCache,
  bodies: BodyStore,
  def: Readonly<WorldDef>,
): void {
  const count = contacts.count;
  const pairs = contacts.bodyPairCount;
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  const normalX = contacts.normalX;
  const normalY = contacts.normalY;
  const normalImpulse = contacts.normalImpulse;
  const tangentImpulse = contacts.tangentImpulse;
  const normalMass = contacts.normalMass;
  const approachSpeed = contacts.approachSpeed;
  const vx = bodies.vx;
  const vy = bodies.vy;
  const inverseMass = bodies.solverInverseMass;
  const mu = def.friction;

  // Effective masses, approach speeds, and last step's impulses for the same pair.
  const head = cache.head;
  const next = cache.next;
  const cachedB = cache.bodyB;
  const cachedNormal = cache.normalImpulse;
  const cachedTangent = cache.tangentImpulse;
  for (let k = 0; k < count; k++) {
    const a = bodyA[k]!;
    const b = bodyB[k]!;
    const nx = normalX[k]!;
    const ny = normalY[k]!;
    if (k < pairs) {
      normalMass[k] = 1 / (inverseMass[a]! + inverseMass[b]!);
      approachSpeed[k] = (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
    } else {
      normalMass[k] = 1 / inverseMass[a]!;
      approachSpeed[k] = vx[a]! * nx + vy[a]! * ny;
    }
    let jn = 0;
    let jt = 0;
    for (let w = head[a]!; w !== -1; w = next[w]!) {
      if (cachedB[w] === b) {
        jn = cachedNormal[w]!;
        jt = cachedTangent[w]!;
        break;
      }
    }
    normalImpulse[k] = jn;
    tangentImpulse[k] = jt;
  }

  // Warm start: apply those impulses before iterating.
  for (let k = 0; k < count; k++) {
    const jn = normalImpulse[k]!;
    const jt = tangentImpulse[k]!;
    if (jn === 0 && jt === 0) continue;
    const a = bodyA[k]!;
    const nx = normalX[k]!;
    const ny = normalY[k]!;
    const px = jn * nx - jt * ny;
    const py = jn * ny + jt * nx;
    const ia = inverseMass[a]!;
    vx[a] = vx[a]! + px * ia;
    vy[a] = vy[a]! + py * ia;
    if (k < pairs) {
      const b = bodyB[k]!;
      const ib = inverseMass[b]!;
      vx[b] = vx[b]! - px * ib;
      vy[b] = vy[b]! - py * ib;
    }
  }

  const iterations = def.velocityIterations;
  for (let it = 0; it < iterations; it++) {
    for (let k = 0; k < pairs; k++) {
      const a = bodyA[k]!;
      const b = bodyB[k]!;
      const nx = normalX[k]!;
      const ny = normalY[k]!;
      const mass = normalMass[k]!;
      const relativeVx = vx[a]! - vx[b]!;
      const relativeVy = vy[a]! - vy[b]!;
      // Normal: λ' = max(0, λ − vn·mN).
      const oldNormal = normalImpulse[k]!;
      let newNormal = oldNormal - (relativeVx * nx + relativeVy * ny) * mass;
      if (newNormal < 0) newNormal = 0;
      const deltaNormal = newNormal - oldNormal;
      normalImpulse[k] = newNormal;
      // Friction: τ' = clamp(τ − vt·mN, ±μλ'), tangent (ny, −nx).
      const oldTangent = tangentImpulse[k]!;
      const maxFriction = mu * newNormal;
      let newTangent = oldTangent - (relativeVy * nx - relativeVx * ny) * mass;
      if (newTangent > maxFriction) newTangent = maxFriction;
      else if (newTangent < -maxFriction) newTangent = -maxFriction;
      const deltaTangent = newTangent - oldTangent;
      tangentImpulse[k] = newTangent;
      const px = deltaNormal * nx - deltaTangent * ny;
      const py = deltaNormal * ny + deltaTangent * nx;
      const ia = inverseMass[a]!;
      const ib = inverseMass[b]!;
      vx[a] = vx[a]! + px * ia;
      vy[a] = vy[a]! + py * ia;
      vx[b] = vx[b]! - px * ib;
      vy[b] = vy[b]! - py * ib;
    }
    for (let k = pairs; k < count; k++) {
      // A wall: its velocity is zero and its inverse mass 0.
      const a = bodyA[k]!;
      const nx = normalX[k]!;
      const ny = normalY[k]!;
      const mass = normalMass[k]!;
      const relativeVx = vx[a]!;
      const relativeVy = vy[a]!;
      const oldNormal = normalImpulse[k]!;
      let newNormal = oldNormal - (relativeVx * nx + relativeVy * ny) * mass;
      if (newNormal < 0) newNormal = 0;
      const deltaNormal = newNormal - oldNormal;
      normalImpulse[k] = newNormal;
      const oldTangent = tangentImpulse[k]!;
      const maxFriction = mu * newNormal;
      let newTangent = oldTangent - (relativeVy * nx - relativeVx * ny) * mass;
      if (newTangent > maxFriction) newTangent = maxFriction;
      else if (newTangent < -maxFriction) newTangent = -maxFriction;
      const deltaTangent = newTangent - oldTangent;
      tangentImpulse[k] = newTangent;
      const ia = inverseMass[a]!;
      vx[a] = relativeVx + (deltaNormal * nx - deltaTangent * ny) * ia;
      vy[a] = relativeVy + (deltaNormal * ny + deltaTangent * nx) * ia;
    }
  }

  // Restitution: once, for contacts that approached faster than the threshold.
  const e = def.restitution;
  const threshold = -def.restitutionThreshold;
  for (let k = 0; e > 0 && k < count; k++) {
    const approach = approachSpeed[k]!;
    if (approach > threshold || normalImpulse[k] === 0) continue;
    const a = bodyA[k]!;
    const b = bodyB[k]!;
    const nx = normalX[k]!;
    const ny = normalY[k]!;
    const wall = k >= pairs;
    const vn = wall ? vx[a]! * nx + vy[a]! * ny : (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
    const oldNormal = normalImpulse[k]!;
    let newNormal = oldNormal - (vn + e * approach) * normalMass[k]!;
    if (newNormal < 0) newNormal = 0;
    const deltaNormal = newNormal - oldNormal;
    normalImpulse[k] = newNormal;
    const ia = inverseMass[a]!;
    vx[a] = vx[a]! + deltaNormal * nx * ia;
    vy[a] = vy[a]! + deltaNormal * ny * ia;
    if (!wall) {
      const ib = inverseMass[b]!;
      vx[b] = vx[b]! - deltaNormal * nx * ib;
      vy[b] = vy[b]! - deltaNormal * ny * ib;
    }
  }
}

/**
 * Relaxation of positions (see the file comment): `positionIterations` sweeps over body–body
 * contacts, then body–wall contacts, pushing apart what overlaps deeper than the slop along the
 * contact normal, on separations predicted from `bodies.movedX/Y` (how far each body has moved
 * since its contacts were found; updated as it goes). Writes positions.
 */
export function solvePositions(
  contacts: ContactList,
  bodies: BodyStore,
  def: Readonly<WorldDef>,
): void {
  const count = contacts.count;
  const pairs = contacts.bodyPairCount;
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  const normalX = contacts.normalX;
  const normalY = contacts.normalY;
  const separation = contacts.separation;
  const x = bodies.x;
  const y = bodies.y;
  const movedX = bodies.movedX;
  const movedY = bodies.movedY;
  const inverseMass = bodies.solverInverseMass;
  const slop = def.linearSlop;
  const beta = def.positionCorrection;
  const iterations = def.positionIterations;
  for (let it = 0; it < iterations; it++) {
    for (let k = 0; k < pairs; k++) {
      const a = bodyA[k]!;
      const b = bodyB[k]!;
      const nx = normalX[k]!;
      const ny = normalY[k]!;
      const s = separation[k]! + (movedX[a]! - movedX[b]!) * nx + (movedY[a]! - movedY[b]!) * ny;
      if (s >= -slop) continue;
      const ia = inverseMass[a]!;
      const ib = inverseMass[b]!;
      const correction = (-(s + slop) * beta) / (ia + ib);
      const pa = correction * ia;
      const pb = correction * ib;
      movedX[a] = movedX[a]! + pa * nx;
      movedY[a] = movedY[a]! + pa * ny;
      x[a] = x[a]! + pa * nx;
      y[a] = y[a]! + pa * ny;
      movedX[b] = movedX[b]! - pb * nx;
      movedY[b] = movedY[b]! - pb * ny;
      x[b] = x[b]! - pb * nx;
      y[b] = y[b]! - pb * ny;
    }
    for (let k = pairs; k < count; k++) {
      const a = bodyA[k]!;
      const nx = normalX[k]!;
      const ny = normalY[k]!;
      const s = separation[k]! + movedX[a]! * nx + movedY[a]! * ny;
      if (s >= -slop) continue;
      const correction = -(s + slop) * beta;
      movedX[a] = movedX[a]! + correction * nx;
      movedY[a] = movedY[a]! + correction * ny;
      x[a] = x[a]! + correction * nx;
      y[a] = y[a]! + correction * ny;
    }
  }
}
