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
 *
 * ## Visiting order
 *
 * The definition is a sweep over the contact list in order (body–body, then body–wall). Visiting
 * a contact reads and writes only its own two bodies, so two contacts with no body in common
 * commute, to the bit; what fixes the result is the order in which *each body* meets its
 * contacts. The solvers keep exactly that order but not the list's: {@link SolverSchedule} puts
 * each contact in a *wave* one later than the latest wave of an earlier contact of either body,
 * and the sweeps go wave by wave. Contacts in one wave share no body, so the processor overlaps
 * them instead of waiting for each body's previous update: in the settled 2,000-circle pile
 * (~3,500 contacts in ~176 waves) the WebAssembly sweep runs about 1.5× as fast in waves as in list
 * order, and faster again doing two visits side by side in SIMD lanes. A wall is a stand-in body
 * of its own per contact (velocity 0, inverse mass 0; for positions the wall contact's masses are
 * 1 and 0, so `C/(1 + 0)·1` is exactly the wall's `C`), which makes one loop serve both kinds.
 *
 * The visits are stored two by two, transposed (`kernel-layout.ts`): each field of a pair holds
 * the first visit's value, then the second's, so the WebAssembly sweeps load both into SIMD lanes
 * with one load and no shuffle. Two visits in a row of one wave share no body; the plan pairs the
 * last visit of a wave with the first of the next when they share none either, else puts a *pad*
 * beside it: a visit of zeros between the pad body (after the stand-ins, velocity and motion 0)
 * and itself, which changes nothing and is skipped where the JavaScript skips a visit (3 pads in
 * the 2,000-circle pile's ~3,500 visits). Before, a visit was a 64-byte record and the velocity
 * sweep paired two at run time (a test for a shared body, six shuffles and two lane stores a
 * pair); with the pairs, the position sweep and warm start two visits at a time too, and the
 * sweeps' clamps and skips done without selects (contact-solver.wat), an 8-tick rollback of that
 * pile takes 12–16 % less time (old and new in one process, interleaved, 300 rounds; the velocity
 * sweeps alone 0.67×, the position sweeps 0.66×).
 *
 * The sweeps run over one working memory in visiting order (velocities, positions, then the pairs
 * of visits), in WebAssembly (`contact-solver.wat`; the broad
 * phase's loops are in `broad-phase.wat`) where it can run, else in the JavaScript loops below:
 * the same IEEE-754 operations in the same order, so the same bits (a test runs both). Each
 * WebAssembly export has the name of the JavaScript function it twins (`warmStart`,
 * `iterateVelocities`, `iteratePositions`, `planVisits`, `preparePositions`, `velocitiesIn` …).
 */
import type { BodyStore } from './body.js';
import type { ContactList, WarmStartCache } from './contacts.js';
import type { WorldDef } from './def.js';
import * as layout from './kernel-layout.js';
import {
  materialUse,
  mixRestitution,
  restitutionOf,
  visitFrictions,
  type MaterialUse,
} from './material.js';
import { KernelMemory, type SolverKernels } from './solver-kernels.js';

// The working memory of one step's solvers (see "Visiting order" in the file comment and
// kernel-layout.ts): velocities (vx, vy per body, then per wall stand-in), positions (the motion
// since the contacts were found, movedX and movedY, then x, y), then the visits in visiting order.
// Copied into this module's own constants, which V8 folds into the hot loops (an imported binding
// is loaded on every use).
/** Bytes per pair of visits (two visits, transposed: see kernel-layout.ts). */
const VISIT_PAIR_BYTES = layout.VISIT_PAIR_BYTES;
/** f64 per pair of visits, and how many f64 the second visit of a pair is after the first. */
const PAIR = VISIT_PAIR_BYTES >>> 3;
const LANE = layout.VISIT_LANE_BYTES >>> 3;
/** A body id shifted by these is its velocity's, and its positions', byte offset. */
const VELOCITY_SHIFT = layout.VELOCITY_SHIFT;
const POSITION_SHIFT = layout.POSITION_SHIFT;
/** A velocity's byte offset shifted right by this is the f64 index of the body's positions. */
const VELOCITY_TO_POSITION = 3 - (POSITION_SHIFT - VELOCITY_SHIFT);
// f64 indices in a visit (from its first f64: its pair's, plus LANE for the second of the pair).
// For the position solver, SEPARATION replaces NORMAL_MASS and the inverse masses are read again
// (continuous detection may have woken bodies since).
const NORMAL_X = layout.VISIT_NORMAL_X >>> 3;
const NORMAL_Y = layout.VISIT_NORMAL_Y >>> 3;
const NORMAL_MASS = layout.VISIT_NORMAL_MASS >>> 3;
const SEPARATION = layout.VISIT_SEPARATION >>> 3;
const INVERSE_MASS_A = layout.VISIT_INVERSE_MASS_A >>> 3;
const INVERSE_MASS_B = layout.VISIT_INVERSE_MASS_B >>> 3;
const NORMAL_IMPULSE = layout.VISIT_NORMAL_IMPULSE >>> 3;
const TANGENT_IMPULSE = layout.VISIT_TANGENT_IMPULSE >>> 3;
// i32 indices in a visit (from twice its first f64's): the byte offsets of A's and B's velocities.
// The f64 index of visit s is first + PAIR·(s >> 1) + LANE·(s & 1); the JavaScript sweeps step
// through the visits in order, LANE and PAIR − LANE in turn.
const VELOCITY_A = layout.VISIT_VELOCITY_A >>> 2;
const VELOCITY_B = layout.VISIT_VELOCITY_B >>> 2;
/** Where x, y start in a body's positions, as an f64 index. */
const POSITION_XY = layout.POSITION_XY >>> 3;

/**
 * The order in which the solvers visit this step's contacts, over the world's kernel memory (see
 * the file comment, "Visiting order"; the broad phase uses the same memory before them).
 */
export class SolverSchedule extends KernelMemory {
  /** Contacts of this step, and how many of them are body–body. */
  count = 0;
  pairs = 0;
  /**
   * Body slots of this step; the wall contact `pairs + w` uses the stand-in body `slots + w`, and
   * the pads the one after the stand-ins.
   */
  slots = 0;
  /** Visits of this step: the contacts and the pads (an even number, two a pair). */
  visits = 0;
  /** The contact visited `s`-th (-1: a pad). */
  order = new Int32Array(0);
  /** Byte offsets of the position and visit regions in {@link memory}, and of the visits' end. */
  positionsAt = 0;
  visitsAt = 0;
  visitsEnd = 0;
  /**
   * By body: the wave of its last contact so far; by contact: its wave; by wave: where it starts,
   * its first contact and its last.
   */
  private lastWave = new Int32Array(0);
  private waveOf = new Int32Array(0);
  private waveStart = new Int32Array(0);
  private firstOf = new Int32Array(0);
  private lastOf = new Int32Array(0);
  /** What the world's materials ask of this step (see `material.ts`). */
  readonly materials: MaterialUse = { friction: false, maxRestitution: 0 };
  /** Each visit's friction, when the world has a body of its own friction. */
  private visitFriction = new Float64Array(0);

  /** {@link visitFriction} with room for `count` visits. */
  visitFrictionRoom(count: number): Float64Array {
    if (this.visitFriction.length < count)
      this.visitFriction = new Float64Array(Math.max(count, 2 * this.visitFriction.length));
    return this.visitFriction;
  }

  /**
   * Plans the visits of this step's contacts wave by wave: a contact's wave is one more than the
   * latest wave of an earlier contact of either of its bodies; waves are visited in order, the
   * contacts of a wave in list order. So every body meets its contacts in list order, and the
   * contacts of one wave share no body. The visits go two by two into pairs; where the last visit
   * of a wave would share a pair with the first of the next and they share a body, a pad takes its
   * place beside it (zeros, between the pad body and itself: it changes nothing). Fills each
   * visit's normal, inverse masses, offsets and — from `cache` — last step's impulses for the same
   * pair; with `restitution`, also the contacts' normal masses and approach speeds. Copies the
   * velocities in.
   */
  plan(
    contacts: ContactList,
    cache: WarmStartCache,
    bodies: BodyStore,
    restitution: boolean,
  ): void {
    const count = contacts.count;
    const pairs = contacts.bodyPairCount;
    const slots = bodies.slotCount;
    // The bodies, the walls' stand-ins, the pad body.
    const all = slots + count - pairs + 1;
    this.count = count;
    this.pairs = pairs;
    this.slots = slots;
    this.positionsAt = all << VELOCITY_SHIFT;
    this.visitsAt = this.positionsAt + (all << POSITION_SHIFT);
    // After the visits (at most a pair a contact, each with a pad), room for the WebAssembly plan's
    // inputs and scratch (see planVisitsInKernel), 48 bytes a contact, 16 a body and 28 a cache
    // entry; solveVelocities' and solvePositions' columns (at most 24 bytes a contact and 40 a
    // body, the order included) fit in the same room.
    const cached = cache.count;
    const scratch = 48 * count + 40 * slots + 28 * cached + 32;
    const kernels = this.reserve(this.visitsAt + VISIT_PAIR_BYTES * count + scratch, count);
    if (this.waveOf.length < count) {
      const room = Math.max(count, 2 * this.waveOf.length);
      this.order = new Int32Array(2 * room);
      this.waveOf = new Int32Array(room);
      this.waveStart = new Int32Array(room + 2);
      this.firstOf = new Int32Array(room + 2);
      this.lastOf = new Int32Array(room + 2);
    }
    if (this.lastWave.length < slots)
      this.lastWave = new Int32Array(Math.max(slots, 2 * this.lastWave.length));
    if (kernels && !restitution) this.planVisitsInKernel(kernels, contacts, cache, bodies);
    else this.planVisits(contacts, cache, bodies, restitution);
    this.visitsEnd = this.visitsAt + (VISIT_PAIR_BYTES >>> 1) * this.visits;
    const f64 = this.f64;
    const vx = bodies.vx;
    const vy = bodies.vy;
    if (kernels) {
      // Through columns after the visits (the plan is done with them).
      const vxAt = this.visitsEnd;
      const vyAt = vxAt + 8 * slots;
      f64.set(vx.subarray(0, slots), vxAt >>> 3);
      f64.set(vy.subarray(0, slots), vyAt >>> 3);
      kernels.velocitiesIn(slots, all - slots, vxAt, vyAt);
    } else velocitiesIn(f64, slots, all - slots, vx, vy);
  }

  /**
   * {@link planVisits} in WebAssembly (`planVisits` in contact-solver.wat, the same steps and
   * arithmetic): the
   * contacts' columns, the inverse masses and the cache copied in after the visits, the visiting
   * order copied back.
   */
  private planVisitsInKernel(
    kernels: SolverKernels,
    contacts: ContactList,
    cache: WarmStartCache,
    bodies: BodyStore,
  ): void {
    const count = this.count;
    const slots = this.slots;
    const cached = cache.count;
    const f64 = this.f64;
    const i32 = this.i32;
    // After the room the visits may take (the visits are written as the columns are read), f64
    // columns first (8-byte aligned: the visits' offset is a multiple of 16), then i32 ones.
    const nxAt = this.visitsAt + VISIT_PAIR_BYTES * count;
    const nyAt = nxAt + 8 * count;
    const imAt = nyAt + 8 * count;
    const cachedNAt = imAt + 8 * slots;
    const cachedTAt = cachedNAt + 8 * cached;
    const bodyAAt = cachedTAt + 8 * cached;
    const bodyBAt = bodyAAt + 4 * count;
    const headAt = bodyBAt + 4 * count;
    const nextAt = headAt + 4 * slots;
    const cachedAAt = nextAt + 4 * cached;
    const cachedBAt = cachedAAt + 4 * cached;
    const lastWaveAt = cachedBAt + 4 * cached;
    const waveOfAt = lastWaveAt + 4 * slots;
    const waveStartAt = waveOfAt + 4 * count;
    const firstOfAt = waveStartAt + 4 * (count + 2);
    const lastOfAt = firstOfAt + 4 * (count + 2);
    const orderAt = lastOfAt + 4 * (count + 2);
    f64.set(contacts.normalX.subarray(0, count), nxAt >>> 3);
    f64.set(contacts.normalY.subarray(0, count), nyAt >>> 3);
    f64.set(bodies.solverInverseMass.subarray(0, slots), imAt >>> 3);
    f64.set(cache.normalImpulse, cachedNAt >>> 3);
    f64.set(cache.tangentImpulse, cachedTAt >>> 3);
    i32.set(contacts.bodyA.subarray(0, count), bodyAAt >>> 2);
    i32.set(contacts.bodyB.subarray(0, count), bodyBAt >>> 2);
    i32.set(cache.bodyA, cachedAAt >>> 2);
    i32.set(cache.bodyB, cachedBAt >>> 2);
    this.visits = kernels.planVisits(
      count,
      this.pairs,
      slots,
      bodyAAt,
      bodyBAt,
      nxAt,
      nyAt,
      imAt,
      cached,
      headAt,
      nextAt,
      cachedAAt,
      cachedBAt,
      cachedNAt,
      cachedTAt,
      lastWaveAt,
      waveOfAt,
      waveStartAt,
      firstOfAt,
      lastOfAt,
      orderAt,
      this.visitsAt,
    );
    this.order.set(i32.subarray(orderAt >>> 2, (orderAt >>> 2) + this.visits));
  }

  /**
   * {@link plan}'s waves and visits in JavaScript (with `restitution`, also the normal masses and
   * approach speeds).
   */
  private planVisits(
    contacts: ContactList,
    cache: WarmStartCache,
    bodies: BodyStore,
    restitution: boolean,
  ): void {
    const count = this.count;
    const pairs = this.pairs;
    const slots = this.slots;
    const bodyA = contacts.bodyA;
    const bodyB = contacts.bodyB;
    const lastWave = this.lastWave;
    const waveOf = this.waveOf;
    const waveStart = this.waveStart;
    const firstOf = this.firstOf;
    const lastOf = this.lastOf;
    lastWave.fill(0, 0, slots);
    waveStart.fill(0, 0, count + 2);
    let waves = 0;
    for (let k = 0; k < count; k++) {
      const a = bodyA[k]!;
      let wave = lastWave[a]!;
      if (k < pairs) {
        const b = bodyB[k]!;
        const waveB = lastWave[b]!;
        if (waveB > wave) wave = waveB;
        lastWave[b] = wave + 1;
      }
      wave++;
      lastWave[a] = wave;
      waveOf[k] = wave;
      if (wave > waves) waves = wave;
      if (waveStart[wave + 1] === 0) firstOf[wave] = k;
      lastOf[wave] = k;
      waveStart[wave + 1]!++;
    }

    // Where each wave starts, in visits, with a pad after a wave that ends a pair's first visit
    // when the next wave's first visit shares a body with it (or there is none).
    const f64 = this.f64;
    const i32 = this.i32;
    const order = this.order;
    const first = this.visitsAt >>> 3;
    const padBody = (slots + count - pairs) << VELOCITY_SHIFT;
    let visits = 0;
    for (let w = 1; w <= waves; w++) {
      const size = waveStart[w + 1]!;
      waveStart[w] = visits;
      visits += size;
      if ((visits & 1) === 0) continue;
      if (w < waves) {
        // A's and B's velocity bodies of the two (a wall's B is its own stand-in).
        const k = lastOf[w]!;
        const a = bodyA[k]!;
        const b = k < pairs ? bodyB[k]! : slots + k - pairs;
        const k1 = firstOf[w + 1]!;
        const a1 = bodyA[k1]!;
        const b1 = k1 < pairs ? bodyB[k1]! : slots + k1 - pairs;
        if (a !== a1 && a !== b1 && b !== a1 && b !== b1) continue;
      }
      const o = first + PAIR * (visits >>> 1);
      f64.fill(0, o, o + (VELOCITY_A >>> 1)); // every f64 of the pair (its first visit comes later)
      i32[2 * (o + LANE) + VELOCITY_A] = padBody;
      i32[2 * (o + LANE) + VELOCITY_B] = padBody;
      order[visits++] = -1;
    }
    this.visits = visits;

    const normalX = contacts.normalX;
    const normalY = contacts.normalY;
    const normalMass = contacts.normalMass;
    const approachSpeed = contacts.approachSpeed;
    const vx = bodies.vx;
    const vy = bodies.vy;
    const inverseMass = bodies.solverInverseMass;
    const { head, next } = cache.chains(slots);
    const cachedB = cache.bodyB;
    const cachedNormal = cache.normalImpulse;
    const cachedTangent = cache.tangentImpulse;
    for (let k = 0; k < count; k++) {
      const s = waveStart[waveOf[k]!]!++;
      order[s] = k;
      const a = bodyA[k]!;
      const b = bodyB[k]!;
      const nx = normalX[k]!;
      const ny = normalY[k]!;
      const o = first + PAIR * (s >>> 1) + LANE * (s & 1);
      const ia = inverseMass[a]!;
      let mass: number;
      if (k < pairs) {
        const ib = inverseMass[b]!;
        mass = 1 / (ia + ib);
        f64[o + INVERSE_MASS_B] = ib;
        i32[2 * o + VELOCITY_B] = b << VELOCITY_SHIFT;
        if (restitution) approachSpeed[k] = (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
      } else {
        mass = 1 / ia;
        f64[o + INVERSE_MASS_B] = 0;
        i32[2 * o + VELOCITY_B] = (slots + k - pairs) << VELOCITY_SHIFT;
        if (restitution) approachSpeed[k] = vx[a]! * nx + vy[a]! * ny;
      }
      if (restitution) normalMass[k] = mass;
      let jn = 0;
      let jt = 0;
      for (let w = head[a]!; w !== -1; w = next[w]!) {
        if (cachedB[w] === b) {
          jn = cachedNormal[w]!;
          jt = cachedTangent[w]!;
          break;
        }
      }
      f64[o + NORMAL_X] = nx;
      f64[o + NORMAL_Y] = ny;
      f64[o + NORMAL_MASS] = mass;
      f64[o + INVERSE_MASS_A] = ia;
      f64[o + NORMAL_IMPULSE] = jn;
      f64[o + TANGENT_IMPULSE] = jt;
      i32[2 * o + VELOCITY_A] = a << VELOCITY_SHIFT;
    }
  }
}

/**
 * Velocities in: each body's (vx, vy) interleaved from byte 0, then the `standIns` wall stand-ins
 * at 0.
 */
function velocitiesIn(
  f64: Float64Array,
  slots: number,
  standIns: number,
  vx: Float64Array,
  vy: Float64Array,
): void {
  for (let i = 0; i < slots; i++) {
    f64[2 * i] = vx[i]!;
    f64[2 * i + 1] = vy[i]!;
  }
  f64.fill(0, 2 * slots, 2 * (slots + standIns));
}

/**
 * Velocities and impulses out: the velocities from byte 0 into `vx`, `vy` (by body); each of the
 * `count` visits' impulses into `normalImpulse`, `tangentImpulse` by contact (`order`: each
 * visit's; a pad's -1 is skipped), the tangent
 * one + 0: a friction impulse clamped to −(μ·0) is −0, stored +0 so the warm-start cache, which
 * copies it, is canonical as it is (the sign of a zero impulse changes no velocity).
 */
function velocitiesOut(
  f64: Float64Array,
  first: number,
  count: number,
  slots: number,
  order: Int32Array,
  vx: Float64Array,
  vy: Float64Array,
  normalImpulse: Float64Array,
  tangentImpulse: Float64Array,
): void {
  for (let i = 0; i < slots; i++) {
    vx[i] = f64[2 * i]!;
    vy[i] = f64[2 * i + 1]!;
  }
  for (let s = 0; s < count; s++) {
    const k = order[s]!;
    if (k < 0) continue;
    const o = first + PAIR * (s >>> 1) + LANE * (s & 1);
    normalImpulse[k] = f64[o + NORMAL_IMPULSE]!;
    tangentImpulse[k] = f64[o + TANGENT_IMPULSE]! + 0;
  }
}

/**
 * Warm start: the impulses of the `count` pairs of visits applied once, in visiting order (a visit
 * whose two impulses are zero is skipped: a pad's always are).
 */
function warmStart(f64: Float64Array, i32: Int32Array, first: number, count: number): void {
  const end = first + PAIR * count;
  for (let o = first, step = LANE; o < end; o += step, step = PAIR - step) {
    const jn = f64[o + NORMAL_IMPULSE]!;
    const jt = f64[o + TANGENT_IMPULSE]!;
    if (jn === 0 && jt === 0) continue;
    const a = i32[2 * o + VELOCITY_A]! >>> 3;
    const b = i32[2 * o + VELOCITY_B]! >>> 3;
    const nx = f64[o + NORMAL_X]!;
    const ny = f64[o + NORMAL_Y]!;
    const px = jn * nx - jt * ny;
    const py = jn * ny + jt * nx;
    const ia = f64[o + INVERSE_MASS_A]!;
    const ib = f64[o + INVERSE_MASS_B]!;
    f64[a] = f64[a]! + px * ia;
    f64[a + 1] = f64[a + 1]! + py * ia;
    f64[b] = f64[b]! - px * ib;
    f64[b + 1] = f64[b + 1]! - py * ib;
  }
}

/**
 * `iterations` sweeps of sequential impulses over the `count` pairs of visits (see the file
 * comment), in visiting order: each pair's first visit, then its second.
 */
function iterateVelocities(
  f64: Float64Array,
  i32: Int32Array,
  first: number,
  count: number,
  iterations: number,
  mu: number,
): void {
  const end = first + PAIR * count;
  for (let it = 0; it < iterations; it++) {
    for (let o = first, step = LANE; o < end; o += step, step = PAIR - step) {
      const a = i32[2 * o + VELOCITY_A]! >>> 3;
      const b = i32[2 * o + VELOCITY_B]! >>> 3;
      const nx = f64[o + NORMAL_X]!;
      const ny = f64[o + NORMAL_Y]!;
      const mass = f64[o + NORMAL_MASS]!;
      const vax = f64[a]!;
      const vay = f64[a + 1]!;
      const vbx = f64[b]!;
      const vby = f64[b + 1]!;
      const relativeVx = vax - vbx;
      const relativeVy = vay - vby;
      // Normal: λ' = max(0, λ − vn·mN).
      const oldNormal = f64[o + NORMAL_IMPULSE]!;
      let newNormal = oldNormal - (relativeVx * nx + relativeVy * ny) * mass;
      if (newNormal < 0) newNormal = 0;
      const deltaNormal = newNormal - oldNormal;
      f64[o + NORMAL_IMPULSE] = newNormal;
      // Friction: τ' = clamp(τ − vt·mN, ±μλ'), tangent (ny, −nx).
      const oldTangent = f64[o + TANGENT_IMPULSE]!;
      const maxFriction = mu * newNormal;
      let newTangent = oldTangent - (relativeVy * nx - relativeVx * ny) * mass;
      if (newTangent > maxFriction) newTangent = maxFriction;
      else if (newTangent < -maxFriction) newTangent = -maxFriction;
      const deltaTangent = newTangent - oldTangent;
      f64[o + TANGENT_IMPULSE] = newTangent;
      const px = deltaNormal * nx - deltaTangent * ny;
      const py = deltaNormal * ny + deltaTangent * nx;
      const ia = f64[o + INVERSE_MASS_A]!;
      const ib = f64[o + INVERSE_MASS_B]!;
      f64[a] = vax + px * ia;
      f64[a + 1] = vay + py * ia;
      f64[b] = vbx - px * ib;
      f64[b + 1] = vby - py * ib;
    }
  }
}

/**
 * {@link iterateVelocities}' twin for contacts of their own friction (`visitFriction`, by visit:
 * the world has a body with a friction of its own; see `material.ts`). JavaScript only: a visit
 * has no room for it in the kernels' layout.
 */
function iterateVelocitiesMixed(
  f64: Float64Array,
  i32: Int32Array,
  first: number,
  count: number,
  iterations: number,
  visitFriction: Float64Array,
): void {
  const end = first + PAIR * count;
  for (let it = 0; it < iterations; it++) {
    for (let o = first, s = 0, step = LANE; o < end; o += step, step = PAIR - step, s++) {
      const a = i32[2 * o + VELOCITY_A]! >>> 3;
      const b = i32[2 * o + VELOCITY_B]! >>> 3;
      const nx = f64[o + NORMAL_X]!;
      const ny = f64[o + NORMAL_Y]!;
      const mass = f64[o + NORMAL_MASS]!;
      const vax = f64[a]!;
      const vay = f64[a + 1]!;
      const vbx = f64[b]!;
      const vby = f64[b + 1]!;
      const relativeVx = vax - vbx;
      const relativeVy = vay - vby;
      // Normal: λ' = max(0, λ − vn·mN).
      const oldNormal = f64[o + NORMAL_IMPULSE]!;
      let newNormal = oldNormal - (relativeVx * nx + relativeVy * ny) * mass;
      if (newNormal < 0) newNormal = 0;
      const deltaNormal = newNormal - oldNormal;
      f64[o + NORMAL_IMPULSE] = newNormal;
      // Friction: τ' = clamp(τ − vt·mN, ±μλ'), tangent (ny, −nx).
      const oldTangent = f64[o + TANGENT_IMPULSE]!;
      const maxFriction = visitFriction[s]! * newNormal;
      let newTangent = oldTangent - (relativeVy * nx - relativeVx * ny) * mass;
      if (newTangent > maxFriction) newTangent = maxFriction;
      else if (newTangent < -maxFriction) newTangent = -maxFriction;
      const deltaTangent = newTangent - oldTangent;
      f64[o + TANGENT_IMPULSE] = newTangent;
      const px = deltaNormal * nx - deltaTangent * ny;
      const py = deltaNormal * ny + deltaTangent * nx;
      const ia = f64[o + INVERSE_MASS_A]!;
      const ib = f64[o + INVERSE_MASS_B]!;
      f64[a] = vax + px * ia;
      f64[a + 1] = vay + py * ia;
      f64[b] = vbx - px * ib;
      f64[b + 1] = vby - py * ib;
    }
  }
}

/**
 * `iterations` sweeps of the position relaxation over the `count` pairs of visits (see the file
 * comment), in visiting order.
 */
function iteratePositions(
  f64: Float64Array,
  i32: Int32Array,
  first: number,
  count: number,
  positions: number,
  iterations: number,
  slop: number,
  beta: number,
): void {
  const end = first + PAIR * count;
  for (let it = 0; it < iterations; it++) {
    for (let o = first, step = LANE; o < end; o += step, step = PAIR - step) {
      // movedX, movedY, x, y of A and B: 32 bytes a body, twice a velocity's 16.
      const a = positions + (i32[2 * o + VELOCITY_A]! >>> VELOCITY_TO_POSITION);
      const b = positions + (i32[2 * o + VELOCITY_B]! >>> VELOCITY_TO_POSITION);
      const nx = f64[o + NORMAL_X]!;
      const ny = f64[o + NORMAL_Y]!;
      const movedAx = f64[a]!;
      const movedAy = f64[a + 1]!;
      const movedBx = f64[b]!;
      const movedBy = f64[b + 1]!;
      const s = f64[o + SEPARATION]! + (movedAx - movedBx) * nx + (movedAy - movedBy) * ny;
      if (s >= -slop) continue;
      const ia = f64[o + INVERSE_MASS_A]!;
      const ib = f64[o + INVERSE_MASS_B]!;
      const correction = (-(s + slop) * beta) / (ia + ib);
      const pa = correction * ia;
      const pb = correction * ib;
      f64[a] = movedAx + pa * nx;
      f64[a + 1] = movedAy + pa * ny;
      f64[a + POSITION_XY] = f64[a + POSITION_XY]! + pa * nx;
      f64[a + POSITION_XY + 1] = f64[a + POSITION_XY + 1]! + pa * ny;
      f64[b] = movedBx - pb * nx;
      f64[b + 1] = movedBy - pb * ny;
      f64[b + POSITION_XY] = f64[b + POSITION_XY]! - pb * nx;
      f64[b + POSITION_XY + 1] = f64[b + POSITION_XY + 1]! - pb * ny;
    }
  }
}

/**
 * Sequential impulses on this step's contacts (see the file comment): effective masses and
 * approach speeds, warm start from `cache`, `velocityIterations` sweeps over the contacts in the
 * order `schedule` plans (every body meets its contacts in list order: body–body, then body–wall),
 * then restitution. Writes velocities; leaves the final impulses in `contacts` for
 * {@link WarmStartCache.store}.
 */
export function solveVelocities(
  contacts: ContactList,
  cache: WarmStartCache,
  bodies: BodyStore,
  def: Readonly<WorldDef>,
  schedule: SolverSchedule,
): void {
  const materials = schedule.materials;
  materialUse(bodies, def, materials);
  const e = materials.maxRestitution;
  schedule.plan(contacts, cache, bodies, e > 0);
  const count = contacts.count;
  const pairs = contacts.bodyPairCount;
  const visits = schedule.visits;
  const f64 = schedule.f64;
  const i32 = schedule.i32;
  const first = schedule.visitsAt >>> 3;
  // Friction per contact has no room in a visit (the kernels' layout): a world with a body of its
  // own friction sweeps in JavaScript, on the same memory, whichever path it is on.
  const kernels = materials.friction ? null : schedule.kernels;
  if (materials.friction) {
    const visitFriction = schedule.visitFrictionRoom(visits);
    visitFrictions(contacts, bodies, def, schedule.order, visits, visitFriction);
    warmStart(f64, i32, first, visits >>> 1);
    iterateVelocitiesMixed(f64, i32, first, visits >>> 1, def.velocityIterations, visitFriction);
  } else if (kernels) {
    kernels.warmStart(schedule.visitsAt, visits >>> 1);
    kernels.iterateVelocities(
      schedule.visitsAt,
      visits >>> 1,
      def.velocityIterations,
      def.friction,
    );
  } else {
    warmStart(f64, i32, first, visits >>> 1);
    iterateVelocities(f64, i32, first, visits >>> 1, def.velocityIterations, def.friction);
  }

  const n = bodies.slotCount;
  const vx = bodies.vx;
  const vy = bodies.vy;
  const order = schedule.order;
  const normalImpulse = contacts.normalImpulse;
  const tangentImpulse = contacts.tangentImpulse;
  if (kernels) {
    // Through columns after the visits, copied back whole.
    const orderAt = schedule.visitsEnd;
    const vxAt = orderAt + 4 * visits; // (visits is even)
    const vyAt = vxAt + 8 * n;
    const normalAt = vyAt + 8 * n;
    const tangentAt = normalAt + 8 * count;
    i32.set(order.subarray(0, visits), orderAt >>> 2);
    kernels.velocitiesOut(schedule.visitsAt, visits, n, orderAt, vxAt, vyAt, normalAt, tangentAt);
    vx.set(f64.subarray(vxAt >>> 3, (vxAt >>> 3) + n));
    vy.set(f64.subarray(vyAt >>> 3, (vyAt >>> 3) + n));
    normalImpulse.set(f64.subarray(normalAt >>> 3, (normalAt >>> 3) + count));
    tangentImpulse.set(f64.subarray(tangentAt >>> 3, (tangentAt >>> 3) + count));
  } else velocitiesOut(f64, first, visits, n, order, vx, vy, normalImpulse, tangentImpulse);
  if (!(e > 0)) return;

  // Restitution: once, for contacts that approached faster than the threshold.
  const bodyA = contacts.bodyA;
  const bodyB = contacts.bodyB;
  const normalX = contacts.normalX;
  const normalY = contacts.normalY;
  const normalMass = contacts.normalMass;
  const approachSpeed = contacts.approachSpeed;
  const inverseMass = bodies.solverInverseMass;
  const threshold = -def.restitutionThreshold;
  const mixed = bodies.materialCount > 0;
  for (let k = 0; k < count; k++) {
    const approach = approachSpeed[k]!;
    if (approach > threshold || normalImpulse[k] === 0) continue;
    const a = bodyA[k]!;
    const b = bodyB[k]!;
    const nx = normalX[k]!;
    const ny = normalY[k]!;
    const wall = k >= pairs;
    const vn = wall ? vx[a]! * nx + vy[a]! * ny : (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
    const oldNormal = normalImpulse[k]!;
    const bounce = mixed
      ? mixRestitution(
          restitutionOf(bodies, def, a),
          wall ? def.restitution : restitutionOf(bodies, def, b),
        )
      : e;
    let newNormal = oldNormal - (vn + bounce * approach) * normalMass[k]!;
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
 * Relaxation of positions (see the file comment): `positionIterations` sweeps over the contacts in
 * the order {@link solveVelocities} planned for this step (every body meets its contacts in list
 * order: body–body, then body–wall), pushing apart what overlaps deeper than the slop along the
 * contact normal, on separations predicted from how far each body has moved since its contacts
 * were found (`x − startX`, updated as it goes). Writes positions.
 */
export function solvePositions(
  contacts: ContactList,
  bodies: BodyStore,
  def: Readonly<WorldDef>,
  schedule: SolverSchedule,
): void {
  const count = contacts.count;
  const iterations = def.positionIterations;
  if (iterations === 0 || count === 0) return;
  const pairs = contacts.bodyPairCount;
  const n = bodies.slotCount;
  const visits = schedule.visits;
  // The bodies, the walls' stand-ins, the pad body.
  const all = n + count - pairs + 1;
  const separation = contacts.separation;
  const x = bodies.x;
  const y = bodies.y;
  const startX = bodies.startX;
  const startY = bodies.startY;
  const inverseMass = bodies.solverInverseMass;
  const f64 = schedule.f64;
  const i32 = schedule.i32;
  const order = schedule.order;
  const first = schedule.visitsAt >>> 3;
  const positions = schedule.positionsAt >>> 3;
  const kernels = schedule.kernels;
  // Columns after the visits for the WebAssembly preparation: separations, inverse masses, the
  // order, then x, y, startX, startY.
  const separationAt = schedule.visitsEnd;
  const inverseMassAt = separationAt + 8 * count;
  const orderAt = inverseMassAt + 8 * n;
  const xAt = orderAt + 4 * visits; // (visits is even)
  const yAt = xAt + 8 * n;
  const startXAt = yAt + 8 * n;
  const startYAt = startXAt + 8 * n;
  if (kernels) {
    f64.set(separation.subarray(0, count), separationAt >>> 3);
    f64.set(inverseMass.subarray(0, n), inverseMassAt >>> 3);
    i32.set(order.subarray(0, visits), orderAt >>> 2);
    f64.set(x.subarray(0, n), xAt >>> 3);
    f64.set(y.subarray(0, n), yAt >>> 3);
    f64.set(startX.subarray(0, n), startXAt >>> 3);
    f64.set(startY.subarray(0, n), startYAt >>> 3);
    kernels.positionsIn(n, all - n, schedule.positionsAt, xAt, yAt, startXAt, startYAt);
    kernels.preparePositions(
      schedule.visitsAt,
      visits,
      pairs,
      orderAt,
      separationAt,
      inverseMassAt,
    );
  } else {
    positionsIn(f64, n, all - n, positions, x, y, startX, startY);
    preparePositions(f64, i32, first, visits, pairs, order, separation, inverseMass);
  }
  if (kernels)
    kernels.iteratePositions(
      schedule.visitsAt,
      visits >>> 1,
      schedule.positionsAt,
      iterations,
      def.linearSlop,
      def.positionCorrection,
    );
  else
    iteratePositions(
      f64,
      i32,
      first,
      visits >>> 1,
      positions,
      iterations,
      def.linearSlop,
      def.positionCorrection,
    );
  if (kernels) {
    kernels.positionsOut(n, schedule.positionsAt, xAt, yAt);
    x.set(f64.subarray(xAt >>> 3, (xAt >>> 3) + n));
    y.set(f64.subarray(yAt >>> 3, (yAt >>> 3) + n));
    return;
  }
  positionsOut(f64, n, positions, x, y);
}

/**
 * Positions in: for each of the `slots` bodies from f64 index `at`, how far it has moved since its
 * contacts were found (x − startX, y − startY), then where it is; the `standIns` wall stand-ins
 * after them at 0 (a free slot's values are never read: it has no contact).
 */
function positionsIn(
  f64: Float64Array,
  slots: number,
  standIns: number,
  at: number,
  x: Float64Array,
  y: Float64Array,
  startX: Float64Array,
  startY: Float64Array,
): void {
  const stride = 1 << (POSITION_SHIFT - 3);
  for (let i = 0, p = at; i < slots; i++, p += stride) {
    const px = x[i]!;
    const py = y[i]!;
    f64[p] = px - startX[i]!;
    f64[p + 1] = py - startY[i]!;
    f64[p + POSITION_XY] = px;
    f64[p + POSITION_XY + 1] = py;
  }
  f64.fill(0, at + stride * slots, at + stride * (slots + standIns));
}

/**
 * The position solver's `count` visits: each visit's separation (by contact; `order` gives each
 * visit's, -1 for a pad, left as it is: zeros) and the inverse masses again — 1 and 0 for a wall,
 * whose correction is whole.
 */
function preparePositions(
  f64: Float64Array,
  i32: Int32Array,
  first: number,
  count: number,
  pairs: number,
  order: Int32Array,
  separation: Float64Array,
  inverseMass: Float64Array,
): void {
  for (let s = 0; s < count; s++) {
    const k = order[s]!;
    if (k < 0) continue;
    const o = first + PAIR * (s >>> 1) + LANE * (s & 1);
    f64[o + SEPARATION] = separation[k]!;
    if (k < pairs) {
      f64[o + INVERSE_MASS_A] = inverseMass[i32[2 * o + VELOCITY_A]! >>> VELOCITY_SHIFT]!;
      f64[o + INVERSE_MASS_B] = inverseMass[i32[2 * o + VELOCITY_B]! >>> VELOCITY_SHIFT]!;
    } else {
      // A wall takes the whole correction: (C / (1 + 0)) · 1 is C exactly.
      f64[o + INVERSE_MASS_A] = 1;
      f64[o + INVERSE_MASS_B] = 0;
    }
  }
}

/** Positions out: each body's x and y from its positions at f64 index `at` on into `x`, `y`. */
function positionsOut(
  f64: Float64Array,
  slots: number,
  at: number,
  x: Float64Array,
  y: Float64Array,
): void {
  const stride = 1 << (POSITION_SHIFT - 3);
  for (let i = 0, p = at; i < slots; i++, p += stride) {
    x[i] = f64[p + POSITION_XY]!;
    y[i] = f64[p + POSITION_XY + 1]!;
  }
}
