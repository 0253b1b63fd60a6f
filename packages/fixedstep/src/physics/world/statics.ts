/**
 * Static walls: two-sided segments and axis-aligned boxes that never move, in columns by wall id.
 * Each wall has a kind and the four parameters it was made with (what a snapshot holds), then
 * what the collision code derives from them once: its bounding box and, for a segment, its unit
 * normal and length.
 */

/** The kinds of wall (hot loops copy them into module constants, as with `BodyFlag`). */
export const WallKind = Object.freeze({
  /** A segment from (ax, ay) to (bx, by), zero thickness. */
  SEGMENT: 0,
  /** An axis-aligned box, centre and half extents. */
  BOX: 1,
});
const { SEGMENT } = WallKind;

/**
 * A contact or a sweep hit refers to a wall as a negative "body": wall `s` is `-1 - s`, so body
 * ids (≥ 0) and walls share one Int32 column.
 */
export function staticRef(s: number): number {
  return -1 - s;
}
/** The wall of a {@link staticRef}. */
export function staticOf(ref: number): number {
  return -1 - ref;
}

/** The walls, a structure of typed arrays by wall id (see the file comment). */
export class StaticStore {
  count = 0;
  /** A {@link WallKind}. */
  kind = new Uint8Array(0);
  // The four parameters. A segment: its ends a and b…
  ax = new Float64Array(0);
  ay = new Float64Array(0);
  bx = new Float64Array(0);
  by = new Float64Array(0);
  // …a box: centre and half extents — the same four columns under their box names.
  centerX = this.ax;
  centerY = this.ay;
  halfWidth = this.bx;
  halfHeight = this.by;
  // Derived: the bounding box of either kind…
  minX = new Float64Array(0);
  minY = new Float64Array(0);
  maxX = new Float64Array(0);
  maxY = new Float64Array(0);
  // …and a segment's unit normal (left of a → b; (0, 1) for a degenerate one) and length.
  normalX = new Float64Array(0);
  normalY = new Float64Array(0);
  length = new Float64Array(0);
  /** Half the thinnest wall's thickness (0 for a segment, Infinity with no walls). */
  thinnestHalfExtent = Infinity;

  constructor(capacity: number) {
    this.grow(capacity);
  }

  /** Adds a wall (its values already checked); returns its id. */
  add(kind: number, p0: number, p1: number, p2: number, p3: number): number {
    if (this.count >= this.kind.length) this.grow(this.kind.length * 2);
    const s = this.count++;
    this.kind[s] = kind;
    this.ax[s] = p0;
    this.ay[s] = p1;
    this.bx[s] = p2;
    this.by[s] = p3;
    if (kind === SEGMENT) {
      this.minX[s] = Math.min(p0, p2);
      this.minY[s] = Math.min(p1, p3);
      this.maxX[s] = Math.max(p0, p2);
      this.maxY[s] = Math.max(p1, p3);
      const ex = p2 - p0;
      const ey = p3 - p1;
      const len = Math.sqrt(ex * ex + ey * ey);
      this.normalX[s] = len > 0 ? -ey / len : 0;
      this.normalY[s] = len > 0 ? ex / len : 1;
      this.length[s] = len;
    } else {
      this.minX[s] = p0 - p2;
      this.minY[s] = p1 - p3;
      this.maxX[s] = p0 + p2;
      this.maxY[s] = p1 + p3;
      this.normalX[s] = 0;
      this.normalY[s] = 0;
      this.length[s] = 0;
    }
    const half = kind === SEGMENT ? 0 : Math.min(p2, p3);
    if (half < this.thinnestHalfExtent) this.thinnestHalfExtent = half;
    return s;
  }

  /** Removes every wall (a snapshot is about to put its own). */
  clear(): void {
    this.count = 0;
    this.thinnestHalfExtent = Infinity;
  }

  /** A wall's thickness: 0 for a segment, the smaller full extent of a box. Metres. */
  thickness(s: number): number {
    return this.kind[s] === SEGMENT ? 0 : 2 * Math.min(this.halfWidth[s]!, this.halfHeight[s]!);
  }

  private grow(capacity: number): void {
    const f64 = (a: Float64Array) => {
      const b = new Float64Array(capacity);
      b.set(a);
      return b;
    };
    const kind = new Uint8Array(capacity);
    kind.set(this.kind);
    this.kind = kind;
    this.ax = this.centerX = f64(this.ax);
    this.ay = this.centerY = f64(this.ay);
    this.bx = this.halfWidth = f64(this.bx);
    this.by = this.halfHeight = f64(this.by);
    this.minX = f64(this.minX);
    this.minY = f64(this.minY);
    this.maxX = f64(this.maxX);
    this.maxY = f64(this.maxY);
    this.normalX = f64(this.normalX);
    this.normalY = f64(this.normalY);
    this.length = f64(this.length);
  }
}
