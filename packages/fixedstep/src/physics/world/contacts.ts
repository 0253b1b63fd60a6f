/**
 * The contacts of one step, and the warm-start cache that carries their impulses to the next
 * (Box2D's `contact.c` and the impulses its manifolds keep).
 *
 * A contact is one point between body `bodyA` and `bodyB` (a body id, or a wall as
 * {@link staticRef}), a unit normal pointing from B to A, and the separation along it (negative:
 * overlap). Body–body contacts come first (`[0, bodyPairCount)`), body–static ones after. A body
 * pair is stored lower id first, so the cache finds it whichever way round it was met.
 */

/** Thrown by {@link ContactList.add} when a step finds more than `def.maxContacts` contacts. */
export class ContactOverflow extends Error {
  constructor(
    readonly limit: number,
    readonly bodyA: number,
    readonly bodyB: number,
  ) {
    super(`more than ${limit} contacts in one step`);
  }
}

/** The contacts of the current step, in structure-of-arrays columns (see the file comment). */
export class ContactList {
  /** Contacts this step. */
  count = 0;
  /** The body–body ones: `[0, bodyPairCount)`. */
  bodyPairCount = 0;
  /** Room in the arrays. */
  capacity = 0;
  /** `def.maxContacts`. */
  limit = 1 << 20;
  /** `min(capacity, limit)`: {@link add} stops here to grow or to throw. */
  private room = 0;

  bodyA = new Int32Array(0);
  bodyB = new Int32Array(0);
  /** Unit normal from B to A. */
  normalX = new Float64Array(0);
  normalY = new Float64Array(0);
  /** Distance between the shapes along the normal when found: negative means overlap. Metres. */
  separation = new Float64Array(0);
  /** The accumulated normal impulse (≥ 0), N·s. */
  normalImpulse = new Float64Array(0);
  /** The accumulated friction impulse along the tangent (ny, −nx), N·s (a zero one is +0). */
  tangentImpulse = new Float64Array(0);
  /** 1 / (1/mA + 1/mB): the mass the contact sees along its normal (and tangent). kg. */
  normalMass = new Float64Array(0);
  /** Relative normal velocity before the solver ran (negative: approaching), for restitution. */
  approachSpeed = new Float64Array(0);

  /** Adds a contact. Throws {@link ContactOverflow} past `limit`. */
  add(a: number, b: number, nx: number, ny: number, separation: number): void {
    if (this.count === this.room) this.makeRoom(a, b);
    const k = this.count++;
    if (b >= 0 && b < a) {
      this.bodyA[k] = b;
      this.bodyB[k] = a;
      this.normalX[k] = -nx;
      this.normalY[k] = -ny;
    } else {
      this.bodyA[k] = a;
      this.bodyB[k] = b;
      this.normalX[k] = nx;
      this.normalY[k] = ny;
    }
    this.separation[k] = separation;
  }

  /** Sets the limit; the arrays grow to it only as contacts come. */
  setLimit(limit: number): void {
    this.limit = limit;
    this.room = Math.min(this.capacity, limit);
  }

  /** Room for at least `capacity` contacts (never beyond need: `limit` is checked by {@link add}). */
  grow(capacity: number): void {
    const i32 = (a: Int32Array) => {
      const b = new Int32Array(capacity);
      b.set(a.subarray(0, Math.min(a.length, capacity)));
      return b;
    };
    const f64 = (a: Float64Array) => {
      const b = new Float64Array(capacity);
      b.set(a.subarray(0, Math.min(a.length, capacity)));
      return b;
    };
    this.bodyA = i32(this.bodyA);
    this.bodyB = i32(this.bodyB);
    this.normalX = f64(this.normalX);
    this.normalY = f64(this.normalY);
    this.separation = f64(this.separation);
    this.normalImpulse = f64(this.normalImpulse);
    this.tangentImpulse = f64(this.tangentImpulse);
    this.normalMass = f64(this.normalMass);
    this.approachSpeed = f64(this.approachSpeed);
    this.capacity = capacity;
    this.room = Math.min(capacity, this.limit);
  }

  private makeRoom(a: number, b: number): void {
    if (this.count >= this.limit) throw new ContactOverflow(this.limit, a, b);
    this.grow(Math.min(this.capacity * 2, this.limit));
  }
}

/** Bytes of one warm-start entry: two i32 ids and two f64 impulses. */
export const CACHE_ENTRY_BYTES = 24;

/**
 * Last step's contacts — pair and impulses — so this step's solver can start from them (warm
 * starting). Part of the state. Each body's entries are chained in cache order from
 * {@link head}, so a lookup walks only that body's few contacts; the chains are made when asked
 * for ({@link chains}), since the solver's WebAssembly plan makes its own.
 *
 * The four columns are views of one buffer laid out as a snapshot stores them — bodyA and bodyB
 * (i32), then the normal and tangent impulses (f64), `count` of each — so a snapshot copies the
 * whole cache at once ({@link image}). Their offsets follow the count: {@link resize} makes new
 * views when it changes.
 */
export class WarmStartCache {
  count = 0;
  /** Entries the buffer has room for. */
  capacity = 0;
  bodyA = new Int32Array(0);
  bodyB = new Int32Array(0);
  normalImpulse = new Float64Array(0);
  tangentImpulse = new Float64Array(0);
  /** The four columns' bytes, in that order: what a snapshot holds after the entry count. */
  image = new Uint8Array(0);
  /** The next entry with the same `bodyA`, or -1 (valid after {@link chains}). */
  next = new Int32Array(0);
  /** By body id: its first entry, or -1 (valid after {@link chains}, for its slot count). */
  head = new Int32Array(0);
  private buffer = new ArrayBuffer(0);
  /** The slot count {@link head} and {@link next} were made for, or -1: to be made again. */
  private linkedSlots = -1;

  /**
   * Sets the entry count: the columns become views of `count` entries each. Their values are
   * undefined unless the count is unchanged (then the views, and values, stay as they were).
   */
  resize(count: number): void {
    if (count > this.capacity) this.grow(Math.max(count, 2 * this.capacity));
    else if (count === this.count && this.bodyA.length === count) return;
    this.view(count);
  }

  private view(count: number): void {
    const b = this.buffer;
    this.bodyA = new Int32Array(b, 0, count);
    this.bodyB = new Int32Array(b, 4 * count, count);
    this.normalImpulse = new Float64Array(b, 8 * count, count);
    this.tangentImpulse = new Float64Array(b, 16 * count, count);
    this.image = new Uint8Array(b, 0, CACHE_ENTRY_BYTES * count);
    this.count = count;
  }

  /**
   * Keeps this step's contacts and impulses: copies, since the solver leaves no −0 in them (it
   * stores a zero tangent impulse as +0), so the state is canonical as it is.
   */
  store(contacts: ContactList): void {
    const n = contacts.count;
    this.resize(n);
    this.bodyA.set(contacts.bodyA.subarray(0, n));
    this.bodyB.set(contacts.bodyB.subarray(0, n));
    this.normalImpulse.set(contacts.normalImpulse.subarray(0, n));
    this.tangentImpulse.set(contacts.tangentImpulse.subarray(0, n));
    this.linkedSlots = -1;
  }

  /**
   * The per-body chains ({@link head}, {@link next}) over the first `slotCount` bodies, made
   * again if the entries changed since; returns the cache.
   */
  chains(slotCount: number): this {
    if (this.linkedSlots !== slotCount) this.link(slotCount);
    return this;
  }

  /** The entries were written in place (a load): the chains are made again when asked for. */
  changed(): void {
    this.linkedSlots = -1;
  }

  /** Rebuilds the per-body chains, in cache order. */
  link(slotCount: number): void {
    this.linkedSlots = slotCount;
    const head = this.head;
    const next = this.next;
    const wA = this.bodyA;
    head.fill(-1, 0, slotCount);
    for (let k = this.count - 1; k >= 0; k--) {
      const a = wA[k]!;
      next[k] = head[a]!;
      head[a] = k;
    }
  }

  /** No entries. */
  clear(): void {
    this.resize(0);
    this.linkedSlots = -1;
  }

  /** Forgets every entry of body `id` (its slot's next body must not inherit them). */
  forget(id: number): void {
    const kept: number[] = [];
    for (let k = 0; k < this.count; k++)
      if (this.bodyA[k] !== id && this.bodyB[k] !== id) kept.push(k);
    const bodyA = kept.map((k) => this.bodyA[k]!);
    const bodyB = kept.map((k) => this.bodyB[k]!);
    const normal = kept.map((k) => this.normalImpulse[k]!);
    const tangent = kept.map((k) => this.tangentImpulse[k]!);
    this.resize(kept.length);
    this.bodyA.set(bodyA);
    this.bodyB.set(bodyB);
    this.normalImpulse.set(normal);
    this.tangentImpulse.set(tangent);
    this.linkedSlots = -1;
  }

  /** Room for `capacity` entries, keeping the current ones. */
  grow(capacity: number): void {
    const image = this.image;
    this.buffer = new ArrayBuffer(CACHE_ENTRY_BYTES * capacity);
    new Uint8Array(this.buffer).set(image);
    const next = new Int32Array(capacity);
    next.set(this.next.subarray(0, Math.min(this.next.length, capacity)));
    this.next = next;
    this.capacity = capacity;
    this.linkedSlots = -1;
    this.view(this.count);
  }

  /** Room for `capacity` bodies in {@link head}. */
  growBodies(capacity: number): void {
    const head = new Int32Array(capacity).fill(-1);
    head.set(this.head.subarray(0, Math.min(this.head.length, capacity)));
    this.head = head;
    this.linkedSlots = -1;
  }
}
