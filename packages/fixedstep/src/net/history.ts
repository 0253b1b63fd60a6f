/**
 * Rings keyed by absolute tick: per-tick inputs and per-tick snapshots. A slot remembers which
 * tick it holds, so a stale slot is never mistaken for a newer tick.
 * @internal
 */
import type { Simulation } from '../sim/simulation.js';

/** `lanes` u32 inputs per tick for the last `capacity` ticks written. */
export class InputRing {
  readonly capacity: number;
  readonly lanes: number;
  private readonly rows: Uint32Array;
  private readonly tickOf: Float64Array;

  constructor(capacity: number, lanes: number) {
    this.capacity = capacity;
    this.lanes = lanes;
    this.rows = new Uint32Array(capacity * lanes);
    this.tickOf = new Float64Array(capacity).fill(-1);
  }

  has(tick: number): boolean {
    return this.tickOf[tick % this.capacity] === tick;
  }

  /** The tick that slot of `tick` holds now (-1: none): to check before overwriting. */
  occupant(tick: number): number {
    return this.tickOf[tick % this.capacity]!;
  }

  /** Store `lanes` inputs for `tick` from `src[offset…]`. */
  set(tick: number, src: ArrayLike<number>, offset = 0): void {
    const slot = tick % this.capacity;
    this.tickOf[slot] = tick;
    const base = slot * this.lanes;
    for (let p = 0; p < this.lanes; p++) this.rows[base + p] = src[offset + p]! >>> 0;
  }

  /** Store one lane of `tick` (the row must already be `tick`'s, or is claimed and zeroed). */
  setLane(tick: number, lane: number, value: number): void {
    const slot = tick % this.capacity;
    const base = slot * this.lanes;
    if (this.tickOf[slot] !== tick) {
      this.tickOf[slot] = tick;
      this.rows.fill(0, base, base + this.lanes);
    }
    this.rows[base + lane] = value >>> 0;
  }

  /** Input of `lane` at `tick` (the caller checks {@link has}). */
  get(tick: number, lane: number): number {
    return this.rows[(tick % this.capacity) * this.lanes + lane]!;
  }

  /** Copy `tick`'s row into `out[offset…]`. */
  copy(tick: number, out: Uint32Array, offset = 0): void {
    const base = (tick % this.capacity) * this.lanes;
    for (let p = 0; p < this.lanes; p++) out[offset + p] = this.rows[base + p]!;
  }

  /** Forget `tick`. */
  clear(tick: number): void {
    if (this.has(tick)) this.tickOf[tick % this.capacity] = -1;
  }
}

/** A simulation that can write its snapshot into a buffer it is given (see `Simulation.saveInto`). */
export type SavesInto = Required<Pick<Simulation<unknown>, 'snapshotSize' | 'saveInto'>>;

/** The snapshots (`save()` bytes) of the last `capacity` ticks stored. */
export class SnapshotRing {
  readonly capacity: number;
  private readonly bytes: (Uint8Array | undefined)[];
  /** Per slot, the buffer {@link putFrom} writes into (kept from tick to tick). */
  private readonly stores: (Uint8Array | undefined)[];
  private readonly tickOf: Float64Array;

  constructor(capacity: number) {
    this.capacity = Math.max(1, capacity);
    this.bytes = new Array<Uint8Array | undefined>(this.capacity);
    this.stores = new Array<Uint8Array | undefined>(this.capacity);
    this.tickOf = new Float64Array(this.capacity).fill(-1);
  }

  put(tick: number, bytes: Uint8Array): void {
    const slot = tick % this.capacity;
    this.tickOf[slot] = tick;
    this.bytes[slot] = bytes;
  }

  /**
   * Stores `tick`'s snapshot by letting `source` write it into the slot's own buffer, reused from
   * the tick the slot held before (grown when too small). Returns the stored bytes: a view that
   * the slot's next `putFrom` overwrites — copy what must outlive it.
   */
  putFrom(tick: number, source: SavesInto): Uint8Array {
    const slot = tick % this.capacity;
    const size = source.snapshotSize;
    let store = this.stores[slot];
    if (store === undefined || store.length < size) {
      store = this.stores[slot] = new Uint8Array(size + (size >> 3));
    }
    const n = source.saveInto(store);
    if (n !== size) {
      throw new RangeError(`saveInto wrote ${n} bytes where snapshotSize said ${size}`);
    }
    let view = this.bytes[slot];
    if (view?.buffer !== store.buffer || view.length !== n) view = store.subarray(0, n);
    this.bytes[slot] = view;
    this.tickOf[slot] = tick;
    return view;
  }

  get(tick: number): Uint8Array | undefined {
    const slot = tick % this.capacity;
    return this.tickOf[slot] === tick ? this.bytes[slot] : undefined;
  }

  has(tick: number): boolean {
    return this.tickOf[tick % this.capacity] === tick;
  }
}
