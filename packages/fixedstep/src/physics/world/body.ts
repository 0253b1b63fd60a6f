/**
 * Body storage (Box2D's `body.c`): every body is a slot in a structure of typed arrays, indexed by
 * body id. The *state* columns are what a snapshot holds; the *per-step* columns are scratch that
 * every step rewrites before it reads them.
 *
 * A freed slot is cleared to zeros and the next body takes the lowest free slot, so the state
 * after any history of creations and removals depends only on which slots hold what.
 */
import { BODY_ASLEEP, BODY_KINEMATIC } from './kernel-layout.js';

/**
 * Flag bits of {@link BodyStore.flags}; a slot whose flags are 0 is free.
 *
 * Files whose hot loops test flags copy the bits they need into module constants
 * (`const { BOX } = BodyFlag;`): V8 folds a module's own constants into optimised code but
 * loads an imported binding on every use, which cost 4 % of a step. The WebAssembly kernels test
 * KINEMATIC and ASLEEP too: their values come from `kernel-layout.ts`.
 */
export const BodyFlag = Object.freeze({
  /** A live body. */
  ALIVE: 1,
  /** An axis-aligned box; otherwise a circle (whose half width and half height are its radius). */
  BOX: 2,
  /** Always swept with continuous detection (unless the world's ccd is `'off'`). */
  BULLET: 4,
  /** Infinite mass: moves with its velocity, pushes dynamic bodies, ignores walls and gravity. */
  KINEMATIC: BODY_KINEMATIC,
  /** Sleeping: not moved, and pairs of sleeping bodies are not even looked at. */
  ASLEEP: BODY_ASLEEP,
  /**
   * A sensor (Box2D's `isSensor`): found by overlaps, never touched — no contact, no sweep hit,
   * no push-out, with bodies or walls. Its overlaps make sensor events (`events.ts`).
   */
  SENSOR: 32,
});
/** Every flag a version 1 snapshot may hold. */
export const KNOWN_FLAGS = 31;
/** Every flag a version 2 snapshot may hold (version 1's and {@link BodyFlag.SENSOR}). */
export const KNOWN_FLAGS_V2 = 63;

/** Box2D's `B2_DEFAULT_CATEGORY_BITS`: a body's category unless it is given one. */
export const DEFAULT_CATEGORY_BITS = 0x0001;
/** Box2D's `B2_DEFAULT_MASK_BITS` (32 bits here): a body collides with every category. */
export const DEFAULT_MASK_BITS = 0xffffffff;

/**
 * What a body's {@link BodyStore.friction} or {@link BodyStore.restitution} holds when it has none
 * of its own: the world's (`def.friction`, `def.restitution`), whatever that is at the step.
 */
export const WORLD_MATERIAL = -1;

const { SENSOR } = BodyFlag;

/**
 * The bodies, a structure of typed arrays by body id (see the file comment). The world checks
 * every value before it reaches here; the store only keeps them and its counts and extents.
 */
export class BodyStore {
  /** Slots the arrays have room for. */
  capacity = 0;
  /** Slots in use: one past the highest live id. */
  slotCount = 0;
  /** Live bodies. */
  liveCount = 0;
  /** Sleeping bodies. */
  sleepingCount = 0;
  /** The largest half extent of any live body (0 with none): the grid's cell is twice this. */
  largestHalfExtent = 0;
  /** The smallest half extent of any live body (Infinity with none): CCD's thinnest feature. */
  thinnestHalfExtent = Infinity;

  // State (saved), by body id.
  flags = new Uint8Array(0);
  x = new Float64Array(0);
  y = new Float64Array(0);
  vx = new Float64Array(0);
  vy = new Float64Array(0);
  halfWidth = new Float64Array(0);
  halfHeight = new Float64Array(0);
  /** 1/kg; 0 for kinematic bodies. */
  inverseMass = new Float64Array(0);
  /** Seconds each body has been slower than `def.sleepSpeed`. */
  restTime = new Float64Array(0);
  /** The island a sleeping body fell asleep with: its lowest body id (0 while awake). */
  island = new Int32Array(0);
  // Collision filter (Box2D's `b2Filter`; see `filter.ts`): state, saved by a version 2 snapshot.
  // A free slot holds zeros; a new body gets the defaults.
  /** Which categories the body is in (bits). */
  categoryBits = new Uint32Array(0);
  /** Which categories it collides with (bits). */
  maskBits = new Uint32Array(0);
  /** Same non-zero group: positive always collides, negative never (overrides the bits). */
  groupIndex = new Int32Array(0);
  /** Live bodies whose filter is not the default one. */
  filteredCount = 0;
  // Material (Box2D's `friction`, `restitution`, `linearDamping`): state, saved by a version 3
  // snapshot. A free slot holds zeros; a new body gets the defaults.
  /** Coulomb friction coefficient, ≥ 0, or {@link WORLD_MATERIAL} (the world's). */
  friction = new Float64Array(0);
  /** Coefficient of restitution in [0, 1], or {@link WORLD_MATERIAL} (the world's). */
  restitution = new Float64Array(0);
  /** Linear damping, 1/s, ≥ 0 (0: none). */
  linearDamping = new Float64Array(0);
  /** Live bodies with a material other than the default (own friction, restitution or damping). */
  materialCount = 0;
  /** Live sensors. */
  sensorCount = 0;

  // Per step (scratch, never saved).
  /** Where each body was at the start of the step (where the grid put it). */
  startX = new Float64Array(0);
  startY = new Float64Array(0);
  /** Each body's velocity before gravity: put back if the step throws. */
  startVx = new Float64Array(0);
  startVy = new Float64Array(0);
  /**
   * The start of each body's straight path over the step: its position at fraction `s` of the step
   * is `pathStart + s · (x − pathStart)`. Continuous detection keeps it consistent.
   */
  pathStartX = new Float64Array(0);
  pathStartY = new Float64Array(0);
  /** Inverse mass as the solvers see it this step: 0 for kinematic and sleeping bodies. */
  solverInverseMass = new Float64Array(0);

  /** The lowest free slot: the id the next body gets. */
  nextId(): number {
    if (this.liveCount === this.slotCount) return this.slotCount;
    let id = 0;
    while (this.flags[id] !== 0) id++;
    return id;
  }

  /**
   * Puts a body in slot `id` (from {@link nextId}); the caller has checked every value and made
   * room ({@link grow}).
   */
  create(
    id: number,
    flags: number,
    x: number,
    y: number,
    vx: number,
    vy: number,
    halfWidth: number,
    halfHeight: number,
    inverseMass: number,
  ): void {
    if (id === this.slotCount) this.slotCount++;
    this.flags[id] = flags;
    this.x[id] = x;
    this.y[id] = y;
    this.vx[id] = vx;
    this.vy[id] = vy;
    this.halfWidth[id] = halfWidth;
    this.halfHeight[id] = halfHeight;
    this.inverseMass[id] = inverseMass;
    this.categoryBits[id] = DEFAULT_CATEGORY_BITS;
    this.maskBits[id] = DEFAULT_MASK_BITS;
    this.groupIndex[id] = 0;
    this.friction[id] = WORLD_MATERIAL;
    this.restitution[id] = WORLD_MATERIAL;
    this.linearDamping[id] = 0;
    if ((flags & SENSOR) !== 0) this.sensorCount++;
    this.liveCount++;
    const large = halfWidth > halfHeight ? halfWidth : halfHeight;
    const small = halfWidth < halfHeight ? halfWidth : halfHeight;
    if (large > this.largestHalfExtent) this.largestHalfExtent = large;
    if (small < this.thinnestHalfExtent) this.thinnestHalfExtent = small;
  }

  /** Clears a live, awake slot to zeros and trims free slots off the end. */
  destroy(id: number): void {
    const w = this.halfWidth[id]!;
    const h = this.halfHeight[id]!;
    const wasExtreme =
      Math.max(w, h) >= this.largestHalfExtent || Math.min(w, h) <= this.thinnestHalfExtent;
    if ((this.flags[id]! & SENSOR) !== 0) this.sensorCount--;
    if (!this.hasDefaultFilter(id)) this.filteredCount--;
    if (!this.hasDefaultMaterial(id)) this.materialCount--;
    this.friction[id] = 0;
    this.restitution[id] = 0;
    this.linearDamping[id] = 0;
    this.categoryBits[id] = 0;
    this.maskBits[id] = 0;
    this.groupIndex[id] = 0;
    this.flags[id] = 0;
    this.x[id] = 0;
    this.y[id] = 0;
    this.vx[id] = 0;
    this.vy[id] = 0;
    this.halfWidth[id] = 0;
    this.halfHeight[id] = 0;
    this.inverseMass[id] = 0;
    this.restTime[id] = 0;
    this.liveCount--;
    while (this.slotCount > 0 && this.flags[this.slotCount - 1] === 0) this.slotCount--;
    if (wasExtreme) this.recomputeExtents();
  }

  /** Whether a live body's filter is the default one (category 1, every mask bit, group 0). */
  hasDefaultFilter(id: number): boolean {
    return (
      this.categoryBits[id] === DEFAULT_CATEGORY_BITS &&
      this.maskBits[id] === DEFAULT_MASK_BITS &&
      this.groupIndex[id] === 0
    );
  }

  /** Whether a live body's material is the default one (the world's friction and restitution, no damping). */
  hasDefaultMaterial(id: number): boolean {
    return (
      this.friction[id] === WORLD_MATERIAL &&
      this.restitution[id] === WORLD_MATERIAL &&
      this.linearDamping[id] === 0
    );
  }

  /** Sets a live body's material (values checked by the caller), keeping {@link materialCount}. */
  setMaterial(id: number, friction: number, restitution: number, linearDamping: number): void {
    const was = this.hasDefaultMaterial(id);
    this.friction[id] = friction;
    this.restitution[id] = restitution;
    this.linearDamping[id] = linearDamping;
    const is = this.hasDefaultMaterial(id);
    if (was !== is) this.materialCount += is ? -1 : 1;
  }

  /** Sets a live body's filter (values checked by the caller), keeping {@link filteredCount}. */
  setFilter(id: number, categoryBits: number, maskBits: number, groupIndex: number): void {
    const was = this.hasDefaultFilter(id);
    this.categoryBits[id] = categoryBits;
    this.maskBits[id] = maskBits;
    this.groupIndex[id] = groupIndex;
    const is = this.hasDefaultFilter(id);
    if (was !== is) this.filteredCount += is ? -1 : 1;
  }

  /** {@link filteredCount}, {@link sensorCount} and {@link materialCount} from scratch (after a load). */
  recountFeatures(): void {
    let filtered = 0;
    let sensors = 0;
    let materials = 0;
    for (let i = 0; i < this.slotCount; i++) {
      const f = this.flags[i]!;
      if (f === 0) continue;
      if ((f & SENSOR) !== 0) sensors++;
      if (!this.hasDefaultFilter(i)) filtered++;
      if (!this.hasDefaultMaterial(i)) materials++;
    }
    this.filteredCount = filtered;
    this.sensorCount = sensors;
    this.materialCount = materials;
  }

  /** {@link largestHalfExtent} and {@link thinnestHalfExtent} from scratch. */
  recomputeExtents(): void {
    let large = 0;
    let small = Infinity;
    for (let i = 0; i < this.slotCount; i++) {
      if (this.flags[i] === 0) continue;
      const a = this.halfWidth[i]!;
      const b = this.halfHeight[i]!;
      large = Math.max(large, a, b);
      small = Math.min(small, a, b);
    }
    this.largestHalfExtent = large;
    this.thinnestHalfExtent = small;
  }

  /** Room for `capacity` slots: state columns keep their contents, scratch starts over. */
  grow(capacity: number): void {
    const keep = <T extends Float64Array | Int32Array | Uint32Array | Uint8Array>(
      a: T,
      b: T,
    ): T => {
      b.set(a.subarray(0, Math.min(a.length, capacity)));
      return b;
    };
    this.flags = keep(this.flags, new Uint8Array(capacity));
    this.x = keep(this.x, new Float64Array(capacity));
    this.y = keep(this.y, new Float64Array(capacity));
    this.vx = keep(this.vx, new Float64Array(capacity));
    this.vy = keep(this.vy, new Float64Array(capacity));
    this.halfWidth = keep(this.halfWidth, new Float64Array(capacity));
    this.halfHeight = keep(this.halfHeight, new Float64Array(capacity));
    this.inverseMass = keep(this.inverseMass, new Float64Array(capacity));
    this.restTime = keep(this.restTime, new Float64Array(capacity));
    this.island = keep(this.island, new Int32Array(capacity));
    this.categoryBits = keep(this.categoryBits, new Uint32Array(capacity));
    this.maskBits = keep(this.maskBits, new Uint32Array(capacity));
    this.groupIndex = keep(this.groupIndex, new Int32Array(capacity));
    this.friction = keep(this.friction, new Float64Array(capacity));
    this.restitution = keep(this.restitution, new Float64Array(capacity));
    this.linearDamping = keep(this.linearDamping, new Float64Array(capacity));
    this.startX = new Float64Array(capacity);
    this.startY = new Float64Array(capacity);
    this.startVx = new Float64Array(capacity);
    this.startVy = new Float64Array(capacity);
    this.pathStartX = new Float64Array(capacity);
    this.pathStartY = new Float64Array(capacity);
    this.solverInverseMass = new Float64Array(capacity);
    this.capacity = capacity;
  }
}
