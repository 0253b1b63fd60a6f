/**
 * The broad phase (Box2D's `broad_phase.c`): which pairs of shapes are close enough to test.
 *
 * Bodies go into a uniform grid rebuilt from scratch every step — a counting sort of their
 * centres by cell — with cells at least as wide as the largest body, so two bodies that overlap
 * sit in the same or neighbouring cells. Pairs are taken in cell order, then in id order: a
 * function of the current state only, never of the grid's history or the arrays' capacity, so a
 * world loaded from a snapshot finds the very same pairs in the very same order. Body–wall pairs
 * are a linear scan over the bodies near a wall (the grid marks their cells). Each candidate pair
 * goes to `manifold.ts`.
 *
 * The grid's array covers the bodies' bounds with at most `4 × slots + 64` cells, its cells
 * doubled until it does. When one body is far from the rest, that doubling crowds the others into
 * a few cells (a 2,000-circle pile with one tiny body 5 km away: some 40 times the pairs to test). So
 * when the doubled grid is crowded ({@link CROWDED}), the grid is *hashed* instead: cells as wide
 * as the bodies again, each cell (column, row) in bucket `hash(column, row)` of a table of about
 * two buckets a body, bodies sorted by bucket, then id; pairs in bucket order, then id order,
 * each body meeting the bodies of its own cell after it and of the cells east, north-west, north
 * and north-east of it (a bucket's bodies filtered by their cell). Both grids are functions of
 * the current state only, and both run in WebAssembly too. Code that walks cells (the sweeps in `ccd.ts`) asks {@link Grid.hashed}
 * and looks a cell up with {@link bucketOf}.
 *
 * Once the world's WebAssembly kernels run (they start in a step with many contacts; see
 * `solver-kernels.ts`), the grid is built there (`gridBounds`, `gridCells` in broad-phase.wat), and
 * in a world of circles only so is the body–body pass (`bodyPairs`): the same cells, order and
 * arithmetic, so the same contacts to the bit (a test runs both), in about half the time. Each
 * export has the name of the function here it twins. They use the world's kernel memory (its
 * layout in `kernel-layout.ts`), which the solvers lay out afresh after them.
 */
import { BodyFlag, type BodyStore } from './body.js';
import { ContactOverflow, type ContactList } from './contacts.js';
import type { WorldDef } from './def.js';
import {
  BOUNDS_FLAGS,
  BOUNDS_MAX_X,
  BOUNDS_MAX_Y,
  BOUNDS_MIN_X,
  BOUNDS_MIN_Y,
} from './kernel-layout.js';
import { boxBox, boxSegment, circleBox, circleCircle, circleSegment } from './manifold.js';
import type { KernelMemory } from './solver-kernels.js';
import { WallKind, staticRef, type StaticStore } from './statics.js';

const { ASLEEP, BOX, KINEMATIC } = BodyFlag;
const STATIC_BOX = WallKind.BOX;

/** The uniform grid of one step: body ids sorted by cell (see the file comment). */
export class Grid {
  /** Cells across and up; 0 when no body is in the grid this step. */
  cols = 0;
  rows = 0;
  /** The lower-left corner of cell 0. Metres. */
  minX = 0;
  minY = 0;
  /** A cell's width and height, metres, and its inverse. */
  cellSize = 0;
  inverseCellSize = 0;
  /** By body: its cell, or -1 (free slot). */
  cellOf = new Int32Array(0);
  /** By cell: where its bodies start in {@link cellItems} (cell c is `[start[c], start[c+1])`). */
  cellStart = new Int32Array(0);
  private cellCursor = new Int32Array(0);
  /** Body ids sorted by cell, in id order within a cell. */
  cellItems = new Int32Array(0);
  /**
   * By cell: 1 if a wall may reach a body whose centre starts the step in it (see
   * {@link markWalls}); valid when {@link wallMarks} is true.
   */
  nearWall = new Uint8Array(0);
  /**
   * The bodies whose cell is marked, in id order: `nearWallBodies[0, nearWallCount)`; valid when
   * {@link wallMarks} is true. (Taken once, without a branch per body: whether a body is near a
   * wall is as good as random in id order, a branch the processor mostly mispredicts.)
   */
  nearWallBodies = new Int32Array(0);
  nearWallCount = 0;
  /** Every live body's flags or-ed together (a {@link BodyFlag} BOX bit: some body is a box). */
  flagUnion = 0;
  /** Whether {@link nearWall} holds this step's marks (false: test every body against the walls). */
  wallMarks = false;
  /**
   * Whether this step's grid is hashed (see the file comment): then a "cell" of
   * {@link cellStart}, {@link cellOf} is a bucket — {@link bucketOf} of a cell's column and row —
   * and {@link cols} and {@link rows} only bound the columns and rows the bodies are in.
   */
  hashed = false;
  /** Buckets − 1 of the hashed grid (a power of two, minus one). */
  bucketMask = 0;
  /** By body: its cell's column and row in the hashed grid. */
  cellX = new Int32Array(0);
  cellY = new Int32Array(0);
  /**
   * Where {@link build} left its columns in the kernel memory this step, for the circle pass
   * (byte offsets; see `build`), or `inKernel` false: built in JavaScript, or no grid.
   */
  inKernel = false;
  kernelColumns = 0;
  kernelStartAt = 0;
  kernelItemsAt = 0;
  kernelFlagsAt = 0;
  kernelEnd = 0;
  /** The bounds record (kernel-layout.ts) when {@link gridBounds} runs in JavaScript. */
  private readonly boundsF64 = new Float64Array((BOUNDS_FLAGS + 8) >>> 3);
  private readonly boundsI32 = new Int32Array(this.boundsF64.buffer);

  /** Room for `capacity` bodies (and the cells a grid of them may use). */
  resize(capacity: number): void {
    this.cellOf = new Int32Array(capacity);
    this.cellItems = new Int32Array(capacity);
    this.cellX = new Int32Array(capacity);
    this.cellY = new Int32Array(capacity);
    this.nearWallBodies = new Int32Array(capacity);
    const maxCells = 4 * capacity + 64;
    this.cellStart = new Int32Array(maxCells + 2);
    this.cellCursor = new Int32Array(maxCells + 1);
    this.nearWall = new Uint8Array(maxCells + 1);
  }

  /**
   * Sorts the live bodies into cells over their bounds. The cell is twice the largest half extent
   * (or `cellSize` if larger), doubled until the grid has at most `4 × slots + 64` cells — a
   * budget from the slot count (state), not the capacity (history). If it had to double and is
   * then {@link CROWDED}, the bodies go into the hashed grid instead (see the file comment).
   */
  build(bodies: BodyStore, def: Readonly<WorldDef>, work: KernelMemory): void {
    const n = bodies.slotCount;
    const budget = 4 * n + 64;
    // In WebAssembly once the solver's kernels run (gridBounds and gridCells in broad-phase.wat: the
    // same comparisons and arithmetic), over columns copied in — x, y, then room for the circle
    // pass's half widths and inverse masses (f64 columns of `columns` bytes), the bounds (4 f64)
    // and the flags or-ed (i32, 8 bytes), cellOf, items (i32), start (budget + 2), cursor
    // (budget + 1), flags (u8) — which the circle pass then reads where they are.
    this.inKernel = false;
    this.hashed = false;
    const columns = 8 * ((n + 1) & ~1);
    const yAt = columns;
    const boundsAt = 4 * columns;
    const cellOfAt = boundsAt + BOUNDS_FLAGS + 8;
    const itemsAt = cellOfAt + columns / 2;
    const startAt = itemsAt + columns / 2;
    const cursorAt = startAt + 4 * (budget + 2);
    const flagsAt = cursorAt + 4 * (budget + 1);
    const kernels = n > 0 ? work.kernelsWith(flagsAt + n) : null;
    // The bounds record (kernel-layout.ts) in the kernel memory, or in the grid's own when the
    // JavaScript twin writes it.
    let f64 = this.boundsF64;
    let i32 = this.boundsI32;
    let at = 0;
    if (kernels) {
      work.f64.set(bodies.x.subarray(0, n), 0);
      work.f64.set(bodies.y.subarray(0, n), yAt >>> 3);
      new Uint8Array(work.memory, flagsAt, n).set(bodies.flags.subarray(0, n));
      kernels.gridBounds(n, 0, yAt, flagsAt, cellOfAt, boundsAt);
      f64 = work.f64;
      i32 = work.i32;
      at = boundsAt;
    } else gridBounds(n, bodies.x, bodies.y, bodies.flags, this.cellOf, f64, i32, 0);
    let minX = f64[(at + BOUNDS_MIN_X) >>> 3]!;
    let minY = f64[(at + BOUNDS_MIN_Y) >>> 3]!;
    const maxX = f64[(at + BOUNDS_MAX_X) >>> 3]!;
    const maxY = f64[(at + BOUNDS_MAX_Y) >>> 3]!;
    this.flagUnion = i32[(at + BOUNDS_FLAGS) >>> 2]!;
    let spanX = maxX - minX;
    let spanY = maxY - minY;
    // Positions so far apart that the span overflows (finite ones beyond ±8.9e307 m, which only a
    // step could reach): every body in one cell. Slow, but every pair is still tested.
    const oneCell = spanX === Infinity || spanY === Infinity;
    if (
      oneCell &&
      maxX - maxX === 0 &&
      minX - minX === 0 &&
      maxY - maxY === 0 &&
      minY - minY === 0
    ) {
      minX = 0;
      minY = 0;
      spanX = 0;
      spanY = 0;
    }
    if (!(spanX >= 0 && spanX < Infinity && spanY >= 0 && spanY < Infinity)) {
      // No bodies, or a position that is not finite (the world never lets one in): no pairs.
      this.cols = 0;
      this.rows = 0;
      this.cellOf.fill(-1, 0, n);
      return;
    }
    const twice = 2 * bodies.largestHalfExtent;
    const base = def.cellSize > twice ? def.cellSize : twice;
    let h = base;
    let inv = 1 / h;
    let cols = Math.floor(spanX * inv) + 1;
    let rows = Math.floor(spanY * inv) + 1;
    while (cols * rows > budget) {
      h *= 2;
      inv = 1 / h;
      cols = Math.floor(spanX * inv) + 1;
      rows = Math.floor(spanY * inv) + 1;
    }
    if (oneCell) inv = 0;
    this.cols = cols;
    this.rows = rows;
    this.minX = minX;
    this.minY = minY;
    this.inverseCellSize = inv;
    this.cellSize = h;
    const cells = cols * rows;
    if (kernels) {
      kernels.gridCells(
        n,
        0,
        yAt,
        cellOfAt,
        minX,
        minY,
        inv,
        cols,
        cells,
        startAt,
        cursorAt,
        itemsAt,
      );
      const i32 = work.i32;
      const start = startAt >>> 2;
      this.cellOf.set(i32.subarray(cellOfAt >>> 2, (cellOfAt >>> 2) + n));
      this.cellStart.set(i32.subarray(start, start + cells + 1));
      this.cellItems.set(i32.subarray(itemsAt >>> 2, (itemsAt >>> 2) + i32[start + cells]!));
      this.inKernel = true;
      this.kernelColumns = columns;
      this.kernelStartAt = startAt;
      this.kernelItemsAt = itemsAt;
      this.kernelFlagsAt = flagsAt;
      this.kernelEnd = (flagsAt + n + 7) & ~7;
    } else this.gridCells(bodies, cells);
    if (h !== base && !oneCell && hashedGridSetting.enabled && this.crowded(cells, n))
      this.hashCells(bodies, base, spanX, spanY);
  }

  /**
   * Whether the grid's cells hold more than {@link CROWDED} bodies per body, summed over cells as
   * count² (pairs tested grow with it), plus 64 for small worlds.
   */
  private crowded(cells: number, n: number): boolean {
    const start = this.cellStart;
    let sum = 0;
    for (let c = 0; c < cells; c++) {
      const count = start[c + 1]! - start[c]!;
      sum += count * count;
    }
    return sum > CROWDED * n + 64;
  }

  /**
   * The hashed grid (see the file comment) over the bounds already found: cells of `base` (doubled
   * only while the columns or rows would not fit {@link HASHED_MAX_CELLS}), each body's column and
   * row, a counting sort of the bodies by bucket in id order. In JavaScript whether or not the
   * kernels run (their pair pass copies these columns in).
   */
  private hashCells(bodies: BodyStore, base: number, spanX: number, spanY: number): void {
    const n = bodies.slotCount;
    let h = base;
    let inv = 1 / h;
    while (spanX * inv >= HASHED_MAX_CELLS || spanY * inv >= HASHED_MAX_CELLS) {
      h *= 2;
      inv = 1 / h;
    }
    let buckets = 2;
    while (buckets < 2 * n) buckets *= 2;
    const mask = buckets - 1;
    this.hashed = true;
    this.inKernel = false;
    this.bucketMask = mask;
    this.cellSize = h;
    this.inverseCellSize = inv;
    const cols = Math.floor(spanX * inv) + 1;
    this.cols = cols;
    this.rows = Math.floor(spanY * inv) + 1;
    const flags = bodies.flags;
    const x = bodies.x;
    const y = bodies.y;
    const minX = this.minX;
    const minY = this.minY;
    const cellOf = this.cellOf;
    const cellX = this.cellX;
    const cellY = this.cellY;
    const start = this.cellStart;
    const cursor = this.cellCursor;
    const items = this.cellItems;
    start.fill(0, 0, buckets + 1);
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0) continue;
      const cx = Math.floor((x[i]! - minX) * inv);
      const cy = Math.floor((y[i]! - minY) * inv);
      const b = bucketOf(cx, cy, cols, mask);
      cellX[i] = cx;
      cellY[i] = cy;
      cellOf[i] = b;
      start[b + 1]!++;
    }
    for (let b = 0; b < buckets; b++) {
      const s = start[b]!;
      start[b + 1] = start[b + 1]! + s;
      cursor[b] = s;
    }
    for (let i = 0; i < n; i++) if (flags[i] !== 0) items[cursor[cellOf[i]!]!++] = i;
  }

  /** The counting sort of {@link build} in JavaScript: cells, their starts, the ids in cell order. */
  private gridCells(bodies: BodyStore, cells: number): void {
    const n = bodies.slotCount;
    const x = bodies.x;
    const y = bodies.y;
    const cellOf = this.cellOf;
    const minX = this.minX;
    const minY = this.minY;
    const inv = this.inverseCellSize;
    const cols = this.cols;
    const start = this.cellStart;
    const cursor = this.cellCursor;
    const items = this.cellItems;
    start.fill(0, 0, cells + 1);
    for (let i = 0; i < n; i++) {
      if (cellOf[i] === -1) continue;
      const c = Math.floor((x[i]! - minX) * inv) + Math.floor((y[i]! - minY) * inv) * cols;
      cellOf[i] = c;
      start[c + 1]!++;
    }
    for (let c = 0; c < cells; c++) {
      const s = start[c]!;
      start[c + 1] = start[c + 1]! + s;
      cursor[c] = s;
    }
    for (let i = 0; i < n; i++) {
      const c = cellOf[i]!;
      if (c === -1) continue;
      items[cursor[c]!++] = i;
    }
  }

  /**
   * Marks the cells near a wall, so the body–wall loops (`wallPairs` here, the wall guard in
   * `ccd.ts`) skip at once the bodies in the middle of the world, which no wall can reach. A cell
   * is marked when it is within {@link WALL_MARGIN} cells of a wall's bounding box. A body pokes
   * out of its cell's centre by at most half a cell (a cell is twice the largest half extent),
   * and the guard asks only about bodies that moved at most a cell along each axis: from an
   * unmarked cell neither reaches within a cell of the wall, so skipping it changes nothing (the
   * loops still run their own exact tests on every body they do not skip). Index arithmetic is
   * the same monotone `floor((v − min) / cell)` the bodies were sorted with. Leaves
   * {@link wallMarks} false (every body is tested) when there is no grid this step, or when the
   * walls' boxes cover more cells than the bodies' share of them (marking would cost more than
   * it saves).
   */
  markWalls(statics: StaticStore, slots: number): void {
    this.wallMarks = false;
    const cols = this.cols;
    const rows = this.rows;
    const count = statics.count;
    if (cols === 0 || count === 0 || !wallMarksSetting.enabled) return;
    // A hashed grid marks the bucket of each cell near a wall: a body in a marked bucket may be
    // far from every wall (it is tested, as it would be anyway), one in an unmarked bucket is not.
    const hashed = this.hashed;
    const mask = this.bucketMask;
    const cells = hashed ? mask + 1 : cols * rows;
    const inv = this.inverseCellSize;
    const minX = this.minX;
    const minY = this.minY;
    const wallMinX = statics.minX;
    const wallMinY = statics.minY;
    const wallMaxX = statics.maxX;
    const wallMaxY = statics.maxY;
    const mark = this.nearWall;
    mark.fill(0, 0, cells);
    let area = 0;
    for (let pass = 0; pass < 2; pass++) {
      for (let s = 0; s < count; s++) {
        const x0 = Math.floor((wallMinX[s]! - minX) * inv) - WALL_MARGIN;
        const x1 = Math.floor((wallMaxX[s]! - minX) * inv) + WALL_MARGIN;
        const y0 = Math.floor((wallMinY[s]! - minY) * inv) - WALL_MARGIN;
        const y1 = Math.floor((wallMaxY[s]! - minY) * inv) + WALL_MARGIN;
        if (x1 < 0 || y1 < 0 || x0 >= cols || y0 >= rows) continue; // beside the grid
        const fromX = x0 > 0 ? x0 : 0;
        const toX = x1 < cols ? x1 : cols - 1;
        const fromY = y0 > 0 ? y0 : 0;
        const toY = y1 < rows ? y1 : rows - 1;
        if (pass === 0) {
          area += (toX - fromX + 1) * (toY - fromY + 1);
          continue;
        }
        if (hashed) {
          for (let cy = fromY; cy <= toY; cy++)
            for (let cx = fromX; cx <= toX; cx++) mark[bucketOf(cx, cy, cols, mask)] = 1;
        } else
          for (let cy = fromY; cy <= toY; cy++)
            mark.fill(1, cy * cols + fromX, cy * cols + toX + 1);
      }
      if (pass === 0 && area > cells) return;
    }
    this.wallMarks = true;
    const cellOf = this.cellOf;
    const list = this.nearWallBodies;
    let near = 0;
    for (let i = 0; i < slots; i++) {
      const c = cellOf[i]!;
      list[near] = i;
      near += c < 0 ? 0 : mark[c]!;
    }
    this.nearWallCount = near;
  }
}

/**
 * {@link Grid.build}'s first pass: the bounds of the live bodies' centres and every flag or-ed, in
 * the bounds record at byte `at` of `f64` / `i32` (one buffer; see kernel-layout.ts); `cellOf`
 * gets −1 for a free slot, else 0.
 */
function gridBounds(
  n: number,
  x: Float64Array,
  y: Float64Array,
  flags: Uint8Array,
  cellOf: Int32Array,
  f64: Float64Array,
  i32: Int32Array,
  at: number,
): void {
  let minX = Infinity;
  let minY = Infinity;
  let maxX = -Infinity;
  let maxY = -Infinity;
  let union = 0;
  for (let i = 0; i < n; i++) {
    const f = flags[i]!;
    union |= f;
    if (f === 0) {
      cellOf[i] = -1;
      continue;
    }
    const a = x[i]!;
    const b = y[i]!;
    cellOf[i] = 0;
    if (a < minX) minX = a;
    if (a > maxX) maxX = a;
    if (b < minY) minY = b;
    if (b > maxY) maxY = b;
  }
  f64[(at + BOUNDS_MIN_X) >>> 3] = minX;
  f64[(at + BOUNDS_MIN_Y) >>> 3] = minY;
  f64[(at + BOUNDS_MAX_X) >>> 3] = maxX;
  f64[(at + BOUNDS_MAX_Y) >>> 3] = maxY;
  i32[(at + BOUNDS_FLAGS) >>> 2] = union;
}

/**
 * Whether steps mark the cells near walls (true); tests switch it off to compare the bits.
 * @internal
 */
export const wallMarksSetting = { enabled: true };

/**
 * Whether a crowded doubled grid is hashed (true); the outlier benchmark switches it off to show
 * the grid before, side by side.
 * @internal
 */
export const hashedGridSetting = { enabled: true };

/** Cells of margin around a wall's box in {@link Grid.markWalls} (one would do; two for rounding). */
const WALL_MARGIN = 2;

/**
 * When a grid that had to double its cells to fit its budget is crowded: its cells' counts squared
 * sum to more than this many per body (plus 64). At the bodies' own cell size a settled pile sums
 * to about 1.8 per body; each doubling puts about four times the bodies in a cell, so past this
 * the array grid tests several times the pairs a hashed grid at the bodies' size does (a
 * 2,000-circle pile with a body 500 m away: 13–20, 5 km away: 70). The talk's bullet room (doubled
 * once, bodies spread out) stays at 2.7 at most: its grid, and so its pair order and golden
 * hashes, are unchanged.
 */
const CROWDED = 4;

/**
 * Columns or rows a hashed grid may span (cells double beyond; a body's column and row are i32,
 * and a sweep's cell range stays exact).
 */
const HASHED_MAX_CELLS = 1 << 30;

/**
 * The bucket of the hashed grid's cell (`cx`, `cy`): an integer hash of the two, masked (`mask`:
 * a power of two, minus one). The same in every engine (Math.imul is exact).
 */
export function bucketOf(cx: number, cy: number, cols: number, mask: number): number {
  return (Math.imul(cy, cols) + cx) & mask;
}

/**
 * Every contact of this step into `contacts`: body–body pairs through the grid (cell order, then
 * id order; in WebAssembly when the kernels of `work` run), then body–wall pairs (body order, then
 * wall order). `inverseMass` is the solver's (0 for kinematic and sleeping bodies): a pair of two
 * such bodies is skipped — unless a kinematic body touches a sleeping one, which must wake.
 * `gravityPending`: gravity is still to be added to the moving bodies' velocities this step
 * (`def`'s), for the one test that reads a velocity.
 * (Flags and objects as arguments, not doubles: V8 boxes a double passed to a call it does not
 * inline, and this one is too large to inline.)
 */
export function findContacts(
  grid: Grid,
  bodies: BodyStore,
  statics: StaticStore,
  contacts: ContactList,
  gravityPending: boolean,
  def: Readonly<WorldDef>,
  work: KernelMemory,
): void {
  contacts.count = 0;
  if (bodyPairsInKernel(grid, bodies, contacts, work)) {
    // The kernels found them (a world of circles).
  } else if (grid.hashed) hashedBodyPairs(grid, bodies, statics, contacts);
  else bodyPairs(grid, bodies, statics, contacts);
  contacts.bodyPairCount = contacts.count;
  wallPairs(grid, bodies, statics, contacts, gravityPending, def);
}

/**
 * The body–body pass of `findContacts` in WebAssembly (`bodyPairs`, or `hashedBodyPairs` for the
 * hashed grid, in broad-phase.wat: the same cells, order and arithmetic), for a world of circles
 * only once the kernels run: the array grid's pass reads the positions, cell starts and items where
 * `Grid.build` left them, with the half widths, inverse masses and flags copied in (a wake between
 * two calls changes the last two); the hashed grid's copies in all its columns. Puts the contacts in `contacts` (from 0) and returns true. Returns false, having
 * changed nothing, when it does not apply. Throws {@link ContactOverflow} where `contacts.add`
 * would.
 */
function bodyPairsInKernel(
  grid: Grid,
  bodies: BodyStore,
  contacts: ContactList,
  work: KernelMemory,
): boolean {
  const hashed = grid.hashed;
  if ((grid.flagUnion & BOX) !== 0 || !(hashed ? work.kernels : grid.inKernel)) return false;
  const n = bodies.slotCount;
  // The array grid left its columns in the kernel memory; the hashed grid's (built in JavaScript)
  // are copied in: x, y, half widths, inverse masses (f64 columns of `columns` bytes), the
  // buckets' starts, the items, each body's column and row (i32), the flags (u8).
  const columns = hashed ? 8 * ((n + 1) & ~1) : grid.kernelColumns;
  const buckets = grid.bucketMask + 1;
  const startAt = hashed ? 4 * columns : grid.kernelStartAt;
  const itemsAt = hashed ? startAt + 4 * (buckets + 1) : grid.kernelItemsAt;
  const cellXAt = itemsAt + 4 * n;
  const cellYAt = cellXAt + 4 * n;
  const flagsAt = hashed ? cellYAt + 4 * n : grid.kernelFlagsAt;
  // After the grid's columns: 8 bytes for an overflow's bodies, then the contacts' five columns
  // of `room`.
  const outAt = (hashed ? (flagsAt + n + 7) & ~7 : grid.kernelEnd) + 8;
  const limit = contacts.limit;
  let room = Math.min(limit, Math.max(contacts.capacity, 4 * n));
  for (;;) {
    // kernelsWith() drops the kernels when their memory cannot grow (growing keeps the grid's
    // columns): JavaScript does it then.
    // Then room for one body's candidates (i32; at most every other body) for the array grid's pass.
    const scratchAt = outAt + 32 * room;
    const kernels = work.kernelsWith(scratchAt + 4 * n);
    if (!kernels) return false;
    const f64 = work.f64;
    const i32 = work.i32;
    f64.set(bodies.halfWidth.subarray(0, n), (2 * columns) >>> 3);
    f64.set(bodies.solverInverseMass.subarray(0, n), (3 * columns) >>> 3);
    new Uint8Array(work.memory, flagsAt, n).set(bodies.flags.subarray(0, n));
    let count: number;
    if (hashed) {
      f64.set(bodies.x.subarray(0, n), 0);
      f64.set(bodies.y.subarray(0, n), columns >>> 3);
      i32.set(grid.cellStart.subarray(0, buckets + 1), startAt >>> 2);
      i32.set(grid.cellItems.subarray(0, grid.cellStart[buckets]), itemsAt >>> 2);
      i32.set(grid.cellX.subarray(0, n), cellXAt >>> 2);
      i32.set(grid.cellY.subarray(0, n), cellYAt >>> 2);
      count = kernels.hashedBodyPairs(
        0,
        columns,
        2 * columns,
        3 * columns,
        flagsAt,
        startAt,
        itemsAt,
        cellXAt,
        cellYAt,
        grid.bucketMask,
        grid.rows,
        grid.cols,
        outAt,
        room,
      );
    } else
      count = kernels.bodyPairs(
        0,
        columns,
        2 * columns,
        3 * columns,
        flagsAt,
        startAt,
        itemsAt,
        grid.rows,
        grid.cols,
        outAt,
        room,
        scratchAt,
      );
    if (count < 0) {
      if (room < limit) {
        room = Math.min(limit, 2 * room);
        continue;
      }
      throw new ContactOverflow(limit, i32[(outAt >>> 2) - 2]!, i32[(outAt >>> 2) - 1]!);
    }
    if (contacts.capacity < count) contacts.grow(count);
    const ids = outAt >>> 2;
    const values = (outAt + 8 * room) >>> 3;
    contacts.bodyA.set(i32.subarray(ids, ids + count));
    contacts.bodyB.set(i32.subarray(ids + room, ids + room + count));
    contacts.normalX.set(f64.subarray(values, values + count));
    contacts.normalY.set(f64.subarray(values + room, values + room + count));
    contacts.separation.set(f64.subarray(values + 2 * room, values + 2 * room + count));
    contacts.count = count;
    return true;
  }
}

/** The body–body contacts through the grid: cell order, then id order. */
function bodyPairs(
  grid: Grid,
  bodies: BodyStore,
  statics: StaticStore,
  contacts: ContactList,
): void {
  const cols = grid.cols;
  const rows = grid.rows;
  const start = grid.cellStart;
  const items = grid.cellItems;
  const flags = bodies.flags;
  const x = bodies.x;
  const y = bodies.y;
  const hw = bodies.halfWidth;
  const hh = bodies.halfHeight;
  const im = bodies.solverInverseMass;
  for (let cy = 0; cy < rows; cy++) {
    for (let cx = 0; cx < cols; cx++) {
      const c = cy * cols + cx;
      const s = start[c]!;
      const e = start[c + 1]!;
      if (s === e) continue;
      // Forward neighbours: the rest of this cell and the next cell (contiguous in `items`), then
      // the three cells above (contiguous too). Every pair once, in a fixed order.
      const sameRowEnd = cx + 1 < cols ? start[c + 2]! : e;
      let upStart = 0;
      let upEnd = 0;
      if (cy + 1 < rows) {
        const up = c + cols;
        upStart = start[cx > 0 ? up - 1 : up]!;
        upEnd = start[cx + 1 < cols ? up + 2 : up + 1]!;
      }
      for (let k = s; k < e; k++) {
        const i = items[k]!;
        const fi = flags[i]!;
        const xi = x[i]!;
        const yi = y[i]!;
        const wi = hw[i]!;
        const hi = hh[i]!;
        const ii = im[i]!;
        for (let pass = 0; pass < 2; pass++) {
          const from = pass === 0 ? k + 1 : upStart;
          const to = pass === 0 ? sameRowEnd : upEnd;
          for (let m = from; m < to; m++) {
            const j = items[m]!;
            const dx = xi - x[j]!;
            const dy = yi - y[j]!;
            const sumW = wi + hw[j]!;
            const sumH = hi + hh[j]!;
            if (dx >= sumW || dx <= -sumW || dy >= sumH || dy <= -sumH) continue;
            const fj = flags[j]!;
            // Both immovable here: skip — unless a kinematic body touches a sleeping one.
            if (
              ii === 0 &&
              im[j] === 0 &&
              (((fi | fj) & ASLEEP) === 0 || ((fi | fj) & KINEMATIC) === 0)
            )
              continue;
            if (((fi | fj) & BOX) === 0) circleCircle(contacts, i, j, dx, dy, sumW);
            else if ((fi & fj & BOX) !== 0) boxBox(contacts, i, j, bodies, statics);
            else if ((fi & BOX) === 0) circleBox(contacts, i, j, i, j, 1, bodies, statics);
            else circleBox(contacts, i, j, j, i, -1, bodies, statics);
          }
        }
      }
    }
  }
}

/**
 * The body–body contacts through the hashed grid: bucket order, then id order; each body meets
 * the bodies after it in its own cell, then those of the cells east, north-west, north and
 * north-east of it (each bucket's bodies filtered by their cell).
 */
function hashedBodyPairs(
  grid: Grid,
  bodies: BodyStore,
  statics: StaticStore,
  contacts: ContactList,
): void {
  const cols = grid.cols;
  const rows = grid.rows;
  const mask = grid.bucketMask;
  const start = grid.cellStart;
  const items = grid.cellItems;
  const cellX = grid.cellX;
  const cellY = grid.cellY;
  const flags = bodies.flags;
  const x = bodies.x;
  const y = bodies.y;
  const hw = bodies.halfWidth;
  const hh = bodies.halfHeight;
  const im = bodies.solverInverseMass;
  for (let b = 0; b <= mask; b++) {
    const e = start[b + 1]!;
    for (let k = start[b]!; k < e; k++) {
      const i = items[k]!;
      const fi = flags[i]!;
      const xi = x[i]!;
      const yi = y[i]!;
      const wi = hw[i]!;
      const hi = hh[i]!;
      const ii = im[i]!;
      const cx = cellX[i]!;
      const cy = cellY[i]!;
      // Cell 0: its own, from the next body on; 1–4: east, north-west, north, north-east.
      for (let q = 0; q < 5; q++) {
        const qx = q === 0 ? cx : q === 1 ? cx + 1 : cx + q - 3;
        const qy = q < 2 ? cy : cy + 1;
        if (qx < 0 || qx >= cols || qy >= rows) continue;
        const bucket = q === 0 ? b : bucketOf(qx, qy, cols, mask);
        const from = q === 0 ? k + 1 : start[bucket]!;
        const to = start[bucket + 1]!;
        for (let m = from; m < to; m++) {
          const j = items[m]!;
          if (cellX[j] !== qx || cellY[j] !== qy) continue;
          const dx = xi - x[j]!;
          const dy = yi - y[j]!;
          const sumW = wi + hw[j]!;
          const sumH = hi + hh[j]!;
          if (dx >= sumW || dx <= -sumW || dy >= sumH || dy <= -sumH) continue;
          const fj = flags[j]!;
          // Both immovable here: skip — unless a kinematic body touches a sleeping one.
          if (
            ii === 0 &&
            im[j] === 0 &&
            (((fi | fj) & ASLEEP) === 0 || ((fi | fj) & KINEMATIC) === 0)
          )
            continue;
          if (((fi | fj) & BOX) === 0) circleCircle(contacts, i, j, dx, dy, sumW);
          else if ((fi & fj & BOX) !== 0) boxBox(contacts, i, j, bodies, statics);
          else if ((fi & BOX) === 0) circleBox(contacts, i, j, i, j, 1, bodies, statics);
          else circleBox(contacts, i, j, j, i, -1, bodies, statics);
        }
      }
    }
  }
}

/** The body–wall contacts: body order, then wall order (bodies far from every wall skipped). */
function wallPairs(
  grid: Grid,
  bodies: BodyStore,
  statics: StaticStore,
  contacts: ContactList,
  gravityPending: boolean,
  def: Readonly<WorldDef>,
): void {
  const flags = bodies.flags;
  const im = bodies.solverInverseMass;
  const x = bodies.x;
  const y = bodies.y;
  const hw = bodies.halfWidth;
  const hh = bodies.halfHeight;
  const wallCount = statics.count;
  if (wallCount === 0) return;
  const kind = statics.kind;
  const wallMinX = statics.minX;
  const wallMinY = statics.minY;
  const wallMaxX = statics.maxX;
  const wallMaxY = statics.maxY;
  // With the marks, only the bodies in marked cells (in id order); else every body.
  const marks = grid.wallMarks;
  const list = grid.nearWallBodies;
  const count = marks ? grid.nearWallCount : bodies.slotCount;
  for (let k = 0; k < count; k++) {
    const i = marks ? list[k]! : k;
    const f = flags[i]!;
    if (f === 0 || im[i] === 0) continue;
    const xi = x[i]!;
    const yi = y[i]!;
    const wi = hw[i]!;
    const hi = hh[i]!;
    const isBox = (f & BOX) !== 0;
    for (let s = 0; s < wallCount; s++) {
      if (
        xi - wi >= wallMaxX[s]! ||
        xi + wi <= wallMinX[s]! ||
        yi - hi >= wallMaxY[s]! ||
        yi + hi <= wallMinY[s]!
      )
        continue;
      if (kind[s] === STATIC_BOX) {
        if (isBox) boxBox(contacts, i, staticRef(s), bodies, statics);
        else circleBox(contacts, i, staticRef(s), i, staticRef(s), 1, bodies, statics);
      } else if (isBox) boxSegment(contacts, i, s, bodies, statics);
      else circleSegment(contacts, i, s, bodies, statics, gravityPending, def);
    }
  }
}
