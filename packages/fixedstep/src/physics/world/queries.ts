/**
 * World queries (Box2D's `b2World_CastRay`, `b2World_CastRayClosest`, `b2World_OverlapAABB`):
 * ray casts and overlap tests against the bodies where they are now, between steps.
 *
 * The step's own grid is built from where bodies *start* a step, so queries keep a grid of their
 * own, {@link QueryIndex}: every body is listed once, in the cell of its centre (cells at least
 * as wide as the largest body, so a body reaches at most the largest half extent, half a cell,
 * out of its cell), rebuilt on the first query after anything moved — once per body is what makes
 * the rebuild, paid by the first query after each step, cheap. So every query widens its region
 * by that reach: a ray walks the columns (or rows, whichever axis it runs along more) within it of
 * its path, in order, testing each body once; the closest-hit cast stops after the first column
 * whose far edge, less the reach, is beyond its best hit. Overlaps visit the cells of the query's
 * bounding box, widened.
 *
 * **Determinism.** The grid only chooses *which* bodies are tested; each test is exact and the
 * answer is defined without it: the closest hit is the least (fraction, bodies before walls, id),
 * all hits come sorted that way, overlaps in ascending id. So the answer is a function of the
 * state and the query alone — the same in every engine, and the same as testing every body (a
 * test compares both on random worlds). Only `+ − × ÷`, `Math.sqrt` and `Math.floor`.
 *
 * **Conventions** (Box2D v3.0's): a ray that starts inside a shape does not hit it; touching
 * counts as overlapping; sensors are skipped unless a filter asks for them.
 */
import { BodyFlag, DEFAULT_CATEGORY_BITS, DEFAULT_MASK_BITS, type BodyStore } from './body.js';
import { checkBits } from './filter.js';
import { WallKind, type StaticStore } from './statics.js';
import { WORLD_LIMITS, show } from './validate.js';

const { BOX, SENSOR } = BodyFlag;
const { SEGMENT } = WallKind;

/** Which bodies a query sees (Box2D's `b2QueryFilter`, plus a predicate). */
export interface QueryFilter {
  /**
   * The query's categories: a body is seen only if its `maskBits` has one of them. An integer
   * from 0 to 0xFFFFFFFF. Default 0x0001.
   */
  categoryBits?: number;
  /**
   * The categories the query sees: a body is seen only if its `categoryBits` has one of them. An
   * integer from 0 to 0xFFFFFFFF. Default 0xFFFFFFFF.
   */
  maskBits?: number;
  /** Whether sensors are seen. Default false (Box2D's queries skip sensors too). */
  sensors?: boolean;
  /**
   * Called for each body the query would report (for a ray: each body it hits); return false to
   * skip it. Must be a pure function of the world's state and the body id, or the answer is no
   * longer deterministic; it must not change the world.
   */
  predicate?: (body: number) => boolean;
}

/** A {@link QueryFilter} for rays, which can also hit static walls. */
export interface RayFilter extends QueryFilter {
  /**
   * Whether static walls are hit. Default true. Walls have the default filter (category 0x0001,
   * every mask bit), so a query whose `maskBits` lacks bit 1 misses them too.
   */
  walls?: boolean;
}

/** One place a ray hits (Box2D's `b2RayResult`). */
export interface RayHit {
  /** The body hit, or −1 if a wall was hit. */
  body: number;
  /** The static wall hit (its id from `addSegment` / `addStaticBox`), or −1 if a body was hit. */
  wall: number;
  /** Where. Metres. */
  x: number;
  y: number;
  /** The surface's unit normal there, facing the ray's origin. */
  normalX: number;
  normalY: number;
  /** How far along the translation: `origin + fraction × translation` is the point. In [0, 1]. */
  fraction: number;
}

const FILTER_KEYS: ReadonlySet<string> = new Set([
  'categoryBits',
  'maskBits',
  'sensors',
  'predicate',
]);
const RAY_FILTER_KEYS: ReadonlySet<string> = new Set([...FILTER_KEYS, 'walls']);

/** No hit yet. */
const NO_HIT = Infinity;

/**
 * The query grid and the query being answered (fields, not arguments: V8 boxes a double passed
 * to a call it does not inline).
 */
export class QueryIndex {
  /** Whether the grid matches the bodies (the world clears it when anything moves). */
  fresh = false;
  /** Builds so far (a diagnostic for tests). */
  builds = 0;
  private cols = 0;
  private rows = 0;
  private minX = 0;
  private minY = 0;
  private cell = 0;
  private inv = 0;
  private cellStart = new Int32Array(1);
  private items = new Int32Array(0);
  private cursor = new Int32Array(0);
  /** By body, while building: its cell. */
  private first = new Int32Array(0);
  /**
   * How far a body reaches beyond the cell its centre is in: the largest half extent, at most half
   * a cell. Every query widens its region by it.
   */
  private pad = 0;
  /** By body: the query that last tested it. */
  private mark = new Int32Array(0);
  private stamp = 0;
  /** Bodies an overlap found, before sorting. */
  private found = new Int32Array(0);
  private foundCount = 0;

  // The query's filter.
  private qCategory = DEFAULT_CATEGORY_BITS;
  private qMask = DEFAULT_MASK_BITS;
  private qSensors = false;
  private qPredicate: ((body: number) => boolean) | null = null;
  // The ray: origin, translation, whether all hits are wanted.
  private ox = 0;
  private oy = 0;
  private dx = 0;
  private dy = 0;
  private all = false;
  // The last shape test's hit.
  private hitF = 0;
  private hitX = 0;
  private hitY = 0;
  private hitNx = 0;
  private hitNy = 0;
  // The best hit so far (closest), or every hit (all): a body id, or −1 − wall.
  private bestF = NO_HIT;
  private bestRef = 0;
  private bestX = 0;
  private bestY = 0;
  private bestNx = 0;
  private bestNy = 0;
  private hits: RayHit[] = [];

  constructor(
    private readonly bodies: BodyStore,
    private readonly statics: StaticStore,
  ) {}

  /** Room for `capacity` bodies. */
  resize(capacity: number): void {
    this.mark = new Int32Array(capacity);
    this.found = new Int32Array(capacity);
    this.stamp = 0;
    this.fresh = false;
  }

  // ------------------------------------------------------------------ the grid

  /** The grid from where the bodies are now (see the file comment), if it is not fresh. */
  private update(): void {
    if (this.fresh) return;
    this.fresh = true;
    this.builds++;
    const b = this.bodies;
    const n = b.slotCount;
    const flags = b.flags;
    const x = b.x;
    const y = b.y;
    const hw = b.halfWidth;
    const hh = b.halfHeight;
    let minX = Infinity;
    let minY = Infinity;
    let maxX = -Infinity;
    let maxY = -Infinity;
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0) continue;
      const x0 = x[i]! - hw[i]!;
      const x1 = x[i]! + hw[i]!;
      const y0 = y[i]! - hh[i]!;
      const y1 = y[i]! + hh[i]!;
      if (x0 < minX) minX = x0;
      if (x1 > maxX) maxX = x1;
      if (y0 < minY) minY = y0;
      if (y1 > maxY) maxY = y1;
    }
    const spanX = maxX - minX;
    const spanY = maxY - minY;
    if (!(spanX >= 0 && spanY >= 0)) {
      this.cols = 0; // no bodies
      this.rows = 0;
      return;
    }
    const budget = 4 * n + 64;
    let h = 2 * b.largestHalfExtent;
    let inv = 1 / h;
    let cols = Math.floor(spanX * inv) + 1;
    let rows = Math.floor(spanY * inv) + 1;
    if (spanX === Infinity || spanY === Infinity) {
      // Bodies beyond ±8.9e307 m (only a step can put them there): one cell, every body in it.
      h = Infinity;
      inv = 0;
      cols = 1;
      rows = 1;
    }
    while (cols * rows > budget) {
      h *= 2;
      inv = 1 / h;
      cols = Math.floor(spanX * inv) + 1;
      rows = Math.floor(spanY * inv) + 1;
    }
    this.cols = cols;
    this.rows = rows;
    this.minX = minX;
    this.minY = minY;
    this.cell = h;
    this.inv = inv;
    this.pad = b.largestHalfExtent;
    const cells = cols * rows;
    if (this.cellStart.length < cells + 1) this.cellStart = new Int32Array(cells + 1);
    if (this.cursor.length < cells) this.cursor = new Int32Array(cells);
    const start = this.cellStart;
    start.fill(0, 0, cells + 1);
    // Count, then place: every body in each cell its box touches, ids ascending within a cell.
    // (Inline clamps and locals: this runs on the first query after every step.)
    if (this.first.length < n) this.first = new Int32Array(b.capacity);
    const first = this.first;
    const lastCol = cols - 1;
    const lastRow = rows - 1;
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0) continue;
      let c = Math.floor((x[i]! - minX) * inv);
      let r = Math.floor((y[i]! - minY) * inv);
      c = c < 0 ? 0 : c > lastCol ? lastCol : c;
      r = r < 0 ? 0 : r > lastRow ? lastRow : r;
      const cell = r * cols + c;
      first[i] = cell;
      start[cell + 1]!++;
    }
    const cursor = this.cursor;
    for (let c = 0; c < cells; c++) {
      start[c + 1] = start[c + 1]! + start[c]!;
      cursor[c] = start[c]!;
    }
    if (this.items.length < start[cells]!)
      this.items = new Int32Array(Math.max(start[cells]!, 2 * this.items.length));
    const items = this.items;
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0) continue;
      items[cursor[first[i]!]!++] = i;
    }
  }

  /** The column of x, clamped to the grid (monotone in x: the same formula everywhere). */
  private colOf(v: number): number {
    const c = Math.floor((v - this.minX) * this.inv);
    return c < 0 ? 0 : c >= this.cols ? this.cols - 1 : c;
  }

  private rowOf(v: number): number {
    const r = Math.floor((v - this.minY) * this.inv);
    return r < 0 ? 0 : r >= this.rows ? this.rows - 1 : r;
  }

  /** Starts a query: a new stamp for {@link mark}. */
  private nextStamp(): number {
    if (this.stamp === 0x7fffffff) {
      this.mark.fill(0);
      this.stamp = 0;
    }
    return ++this.stamp;
  }

  // ------------------------------------------------------------------ filters

  /** Checks and takes a filter for `method`; returns whether walls are wanted (rays). */
  private takeFilter(method: string, filter: unknown, ray: boolean): boolean {
    this.qCategory = DEFAULT_CATEGORY_BITS;
    this.qMask = DEFAULT_MASK_BITS;
    this.qSensors = false;
    this.qPredicate = null;
    if (filter === undefined) return true;
    const where = `PhysicsWorld.${method}`;
    if (typeof filter !== 'object' || filter === null)
      throw new TypeError(`${where}: filter must be an object, got ${show(filter)}`);
    const known = ray ? RAY_FILTER_KEYS : FILTER_KEYS;
    for (const key in filter) {
      if (!known.has(key))
        throw new TypeError(
          `${where}: unknown filter field "${key}"; the fields are ${[...known].join(', ')}`,
        );
    }
    const f = filter as Partial<Record<keyof RayFilter, unknown>>;
    const category = f.categoryBits ?? DEFAULT_CATEGORY_BITS;
    const mask = f.maskBits ?? DEFAULT_MASK_BITS;
    checkBits(`${where}: filter`, 'categoryBits', category);
    checkBits(`${where}: filter`, 'maskBits', mask);
    const sensors = f.sensors ?? false;
    const walls = f.walls ?? true;
    const predicate = f.predicate ?? null;
    if (typeof sensors !== 'boolean')
      throw new TypeError(`${where}: filter.sensors must be true or false, got ${show(sensors)}`);
    if (typeof walls !== 'boolean')
      throw new TypeError(`${where}: filter.walls must be true or false, got ${show(walls)}`);
    if (predicate !== null && typeof predicate !== 'function')
      throw new TypeError(`${where}: filter.predicate must be a function, got ${show(predicate)}`);
    this.qCategory = category;
    this.qMask = mask;
    this.qSensors = sensors;
    this.qPredicate = predicate as ((body: number) => boolean) | null;
    return walls;
  }

  /** Whether the query's filter sees body `i` (its bits and sensor flag; not the predicate). */
  private sees(i: number): boolean {
    const b = this.bodies;
    const f = b.flags[i]!;
    if (f === 0 || ((f & SENSOR) !== 0 && !this.qSensors)) return false;
    return (b.categoryBits[i]! & this.qMask) !== 0 && (b.maskBits[i]! & this.qCategory) !== 0;
  }

  // ------------------------------------------------------------------ rays

  /** Checks a ray's numbers for `method`. */
  private takeRay(method: string, ox: unknown, oy: unknown, dx: unknown, dy: unknown): void {
    const m = WORLD_LIMITS.maxCoordinate;
    const names = ['originX', 'originY', 'translationX', 'translationY'];
    const values = [ox, oy, dx, dy];
    for (let k = 0; k < 4; k++) {
      const v = values[k];
      const limit = k < 2 ? m : 2 * m;
      if (!(typeof v === 'number' && v >= -limit && v <= limit)) {
        const text = `PhysicsWorld.${method}: ${names[k]!} must be a finite number from ${-limit} to ${limit} (metres), got ${show(v)}`;
        throw typeof v === 'number' ? new RangeError(text) : new TypeError(text);
      }
    }
    this.ox = ox as number;
    this.oy = oy as number;
    this.dx = dx as number;
    this.dy = dy as number;
  }

  /** Box2D's `b2World_CastRayClosest`; see `PhysicsWorld.castRayClosest`. */
  castRayClosest(
    ox: number,
    oy: number,
    dx: number,
    dy: number,
    filter: RayFilter | undefined,
  ): RayHit | null {
    this.takeRay('castRayClosest', ox, oy, dx, dy);
    const walls = this.takeFilter('castRayClosest', filter, true);
    this.all = false;
    this.bestF = NO_HIT;
    this.cast(walls);
    if (this.bestF === NO_HIT) return null;
    const ref = this.bestRef;
    return {
      body: ref >= 0 ? ref : -1,
      wall: ref >= 0 ? -1 : -1 - ref,
      x: this.bestX,
      y: this.bestY,
      normalX: this.bestNx,
      normalY: this.bestNy,
      fraction: this.bestF,
    };
  }

  /** Box2D's `b2World_CastRay` collecting every hit; see `PhysicsWorld.castRay`. */
  castRay(ox: number, oy: number, dx: number, dy: number, filter: RayFilter | undefined): RayHit[] {
    this.takeRay('castRay', ox, oy, dx, dy);
    const walls = this.takeFilter('castRay', filter, true);
    this.all = true;
    this.bestF = NO_HIT;
    const hits: RayHit[] = [];
    this.hits = hits;
    this.cast(walls);
    this.hits = [];
    // Bodies before walls at equal fractions, then by id: a total order, so the sort is exact.
    hits.sort(
      (a, b) =>
        a.fraction - b.fraction ||
        (a.body < 0 ? 1 : 0) - (b.body < 0 ? 1 : 0) ||
        a.body - b.body ||
        a.wall - b.wall,
    );
    return hits;
  }

  /** Walls, then bodies through the grid, into `best*` or `hits`. */
  private cast(walls: boolean): void {
    // A translation whose square underflows (shorter than ~1e-154 m) hits nothing.
    if (this.dx * this.dx + this.dy * this.dy === 0) return;
    const s = this.statics;
    // Walls have the default filter.
    if (walls && (this.qMask & DEFAULT_CATEGORY_BITS) !== 0 && this.qCategory !== 0) {
      for (let w = 0; w < s.count; w++) {
        const hit =
          s.kind[w] === SEGMENT
            ? this.raySegment(w)
            : this.rayBox(s.centerX[w]!, s.centerY[w]!, s.halfWidth[w]!, s.halfHeight[w]!);
        if (hit) this.offer(-1 - w);
      }
    }
    this.update();
    if (this.cols === 0) return;
    const stamp = this.nextStamp();
    if (this.cols * this.rows <= 4 || this.inv === 0) {
      for (let i = 0; i < this.bodies.slotCount; i++) this.rayBody(i, stamp);
      return;
    }
    this.walk(stamp);
  }

  /** The columns (or rows) the ray crosses, in order; see the file comment. */
  private walk(stamp: number): void {
    const ox = this.ox;
    const oy = this.oy;
    const dx = this.dx;
    const dy = this.dy;
    const h = this.cell;
    const inv = this.inv;
    const cols = this.cols;
    const rows = this.rows;
    // Clip the ray to the grid's rectangle.
    let tA = 0;
    let tB = 1;
    const gx0 = this.minX;
    const gy0 = this.minY;
    const gx1 = gx0 + cols * h;
    const gy1 = gy0 + rows * h;
    if (dx === 0) {
      if (ox < gx0 || ox > gx1) return;
    } else {
      const t1 = (gx0 - ox) / dx;
      const t2 = (gx1 - ox) / dx;
      tA = Math.max(tA, Math.min(t1, t2));
      tB = Math.min(tB, Math.max(t1, t2));
    }
    if (dy === 0) {
      if (oy < gy0 || oy > gy1) return;
    } else {
      const t1 = (gy0 - oy) / dy;
      const t2 = (gy1 - oy) / dy;
      tA = Math.max(tA, Math.min(t1, t2));
      tB = Math.min(tB, Math.max(t1, t2));
    }
    if (!(tA <= tB)) return; // misses the grid
    const xMajor = (dx < 0 ? -dx : dx) >= (dy < 0 ? -dy : dy);
    const p0 = xMajor ? ox : oy;
    const dp = xMajor ? dx : dy;
    const s0 = xMajor ? oy : ox;
    const ds = xMajor ? dy : dx;
    const pMin = xMajor ? gx0 : gy0;
    const sMin = xMajor ? gy0 : gx0;
    const nP = xMajor ? cols : rows;
    const nS = xMajor ? rows : cols;
    // Slack for rounding, in metres: cells are only ever visited too generously.
    const eps =
      1e-7 * h +
      1e-12 *
        ((p0 < 0 ? -p0 : p0) +
          (s0 < 0 ? -s0 : s0) +
          (pMin < 0 ? -pMin : pMin) +
          (sMin < 0 ? -sMin : sMin) +
          (dp < 0 ? -dp : dp) +
          (ds < 0 ? -ds : ds));
    const epsT = eps / (dp < 0 ? -dp : dp);
    tA -= epsT;
    tB += epsT;
    if (tA < 0) tA = 0;
    if (tB > 1) tB = 1;
    if (!(tA <= tB)) return;
    const forward = dp > 0;
    const pa = p0 + tA * dp;
    const pb = p0 + tB * dp;
    // A body is listed in the cell of its centre and reaches `pad` beyond it: the columns whose
    // bodies can touch the ray are those within `pad` of where it runs, and so are the rows.
    const pad = this.pad;
    const first = clampCell(Math.floor((pa + (forward ? -eps - pad : eps + pad) - pMin) * inv), nP);
    const last = clampCell(Math.floor((pb + (forward ? eps + pad : -eps - pad) - pMin) * inv), nP);
    const start = this.cellStart;
    const items = this.items;
    for (let ci = first; ; ci += forward ? 1 : -1) {
      let t0 = (pMin + ci * h - pad - eps - p0) / dp;
      let t1 = (pMin + (ci + 1) * h + pad + eps - p0) / dp;
      if (t0 > t1) {
        const t = t0;
        t0 = t1;
        t1 = t;
      }
      if (t0 < tA) t0 = tA;
      if (t1 > tB) t1 = tB;
      if (t0 <= t1) {
        const sa = s0 + t0 * ds;
        const sb = s0 + t1 * ds;
        const r0 = clampCell(Math.floor(((sa < sb ? sa : sb) - pad - eps - sMin) * inv), nS);
        const r1 = clampCell(Math.floor(((sa < sb ? sb : sa) + pad + eps - sMin) * inv), nS);
        for (let r = r0; r <= r1; r++) {
          const c = xMajor ? r * cols + ci : ci * cols + r;
          const e = start[c + 1]!;
          for (let m = start[c]!; m < e; m++) this.rayBody(items[m]!, stamp);
        }
      }
      if (ci === last) break;
      // Closest: every body not yet tested reaches no nearer than `pad` short of this column's
      // far edge.
      if (
        !this.all &&
        this.bestF < (pMin + (forward ? ci + 1 : ci) * h + (forward ? -pad : pad) - p0) / dp - epsT
      )
        break;
    }
  }

  /** Tests body `i` once per query, and offers its hit. */
  private rayBody(i: number, stamp: number): void {
    const mark = this.mark;
    if (mark[i] === stamp) return;
    mark[i] = stamp;
    if (!this.sees(i)) return;
    const b = this.bodies;
    const hit =
      (b.flags[i]! & BOX) !== 0
        ? this.rayBox(b.x[i]!, b.y[i]!, b.halfWidth[i]!, b.halfHeight[i]!)
        : this.rayCircle(b.x[i]!, b.y[i]!, b.halfWidth[i]!);
    if (hit) this.offer(i);
  }

  /** The last shape test's hit, for `ref` (a body id, or −1 − wall). */
  private offer(ref: number): void {
    const f = this.hitF;
    if (!this.all) {
      const best = this.bestF;
      // The least (fraction, bodies before walls, id).
      if (f > best) return;
      if (f === best) {
        const bestRef = this.bestRef;
        if (ref >= 0 ? bestRef >= 0 && bestRef < ref : bestRef >= 0 || bestRef > ref) return;
      }
    }
    if (ref >= 0 && this.qPredicate !== null && !this.qPredicate(ref)) return;
    if (this.all) {
      this.hits.push({
        body: ref >= 0 ? ref : -1,
        wall: ref >= 0 ? -1 : -1 - ref,
        x: this.hitX,
        y: this.hitY,
        normalX: this.hitNx,
        normalY: this.hitNy,
        fraction: f,
      });
      return;
    }
    this.bestF = f;
    this.bestRef = ref;
    this.bestX = this.hitX;
    this.bestY = this.hitY;
    this.bestNx = this.hitNx;
    this.bestNy = this.hitNy;
  }

  /** The ray against a circle (Box2D's `b2RayCastCircle`), into `hit*`. */
  private rayCircle(cx: number, cy: number, r: number): boolean {
    const dx = this.dx;
    const dy = this.dy;
    const length = Math.sqrt(dx * dx + dy * dy);
    const ux = dx / length;
    const uy = dy / length;
    const sx = this.ox - cx;
    const sy = this.oy - cy;
    // The closest approach of the line, then back along it by the half chord.
    const t = -(sx * ux + sy * uy);
    const qx = sx + t * ux;
    const qy = sy + t * uy;
    const cc = qx * qx + qy * qy;
    const rr = r * r;
    if (cc > rr) return false;
    const along = t - Math.sqrt(rr - cc);
    if (!(along >= 0 && along <= length)) return false; // starts inside, or too short
    const fraction = along / length;
    if (fraction > this.bestF) return false;
    const hx = sx + along * ux;
    const hy = sy + along * uy;
    const hl = Math.sqrt(hx * hx + hy * hy);
    const nx = hl > 0 ? hx / hl : -ux;
    const ny = hl > 0 ? hy / hl : -uy;
    this.hitF = fraction;
    this.hitNx = nx;
    this.hitNy = ny;
    this.hitX = cx + r * nx;
    this.hitY = cy + r * ny;
    return true;
  }

  /** The ray against an axis-aligned box (Box2D's `b2AABB_RayCast`), into `hit*`. */
  private rayBox(cx: number, cy: number, w: number, h: number): boolean {
    const ox = this.ox;
    const oy = this.oy;
    const dx = this.dx;
    const dy = this.dy;
    let lower = -Infinity;
    let upper = Infinity;
    let nx = 0;
    let ny = 0;
    if (dx === 0) {
      if (ox < cx - w || ox > cx + w) return false;
    } else {
      let t1 = (cx - w - ox) / dx;
      let t2 = (cx + w - ox) / dx;
      let side = -1;
      if (t1 > t2) {
        const t = t1;
        t1 = t2;
        t2 = t;
        side = 1;
      }
      lower = t1;
      nx = side;
      upper = t2;
    }
    if (dy === 0) {
      if (oy < cy - h || oy > cy + h) return false;
    } else {
      let t1 = (cy - h - oy) / dy;
      let t2 = (cy + h - oy) / dy;
      let side = -1;
      if (t1 > t2) {
        const t = t1;
        t1 = t2;
        t2 = t;
        side = 1;
      }
      if (t1 > lower) {
        lower = t1;
        nx = 0;
        ny = side;
      }
      if (t2 < upper) upper = t2;
    }
    if (lower > upper || !(lower >= 0 && lower <= 1) || lower > this.bestF) return false;
    this.hitF = lower;
    this.hitNx = nx;
    this.hitNy = ny;
    this.hitX = ox + lower * dx;
    this.hitY = oy + lower * dy;
    return true;
  }

  /** The ray against a two-sided static segment (Box2D's `b2RayCastSegment`), into `hit*`. */
  private raySegment(w: number): boolean {
    const s = this.statics;
    const length = s.length[w]!;
    if (!(length > 0)) return false;
    const ax = s.ax[w]!;
    const ay = s.ay[w]!;
    let nx = s.normalX[w]!;
    let ny = s.normalY[w]!;
    const ox = this.ox;
    const oy = this.oy;
    const dx = this.dx;
    const dy = this.dy;
    const numerator = nx * (ax - ox) + ny * (ay - oy);
    const denominator = nx * dx + ny * dy;
    if (denominator === 0) return false; // parallel
    const t = numerator / denominator;
    if (!(t >= 0 && t <= 1) || t > this.bestF) return false;
    const px = ox + t * dx;
    const py = oy + t * dy;
    const along = ((px - ax) * (s.bx[w]! - ax) + (py - ay) * (s.by[w]! - ay)) / length;
    if (!(along >= 0 && along <= length)) return false;
    if (numerator > 0) {
      nx = -nx;
      ny = -ny;
    }
    this.hitF = t;
    this.hitNx = nx + 0;
    this.hitNy = ny + 0;
    this.hitX = px;
    this.hitY = py;
    return true;
  }

  // ------------------------------------------------------------------ overlaps

  /** Bodies whose shape touches the box; see `PhysicsWorld.overlapAABB`. */
  overlapAABB(
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    filter: QueryFilter | undefined,
  ): number[] {
    checkPoint('overlapAABB', 'minX', minX);
    checkPoint('overlapAABB', 'minY', minY);
    checkPoint('overlapAABB', 'maxX', maxX);
    checkPoint('overlapAABB', 'maxY', maxY);
    if (!(minX <= maxX && minY <= maxY))
      throw new RangeError(
        `PhysicsWorld.overlapAABB: needs minX ≤ maxX and minY ≤ maxY, got (${minX}, ${minY}) – (${maxX}, ${maxY})`,
      );
    this.takeFilter('overlapAABB', filter, false);
    return this.overlap(0, minX, minY, maxX, maxY, 0, 0, 0);
  }

  /** Bodies whose shape touches the circle; see `PhysicsWorld.overlapCircle`. */
  overlapCircle(x: number, y: number, radius: number, filter: QueryFilter | undefined): number[] {
    checkPoint('overlapCircle', 'x', x);
    checkPoint('overlapCircle', 'y', y);
    if (!(typeof radius === 'number' && radius >= 0 && radius <= WORLD_LIMITS.maxCoordinate)) {
      const text = `PhysicsWorld.overlapCircle: radius must be a number from 0 to 1e9 (metres), got ${show(radius)}`;
      throw typeof radius === 'number' ? new RangeError(text) : new TypeError(text);
    }
    this.takeFilter('overlapCircle', filter, false);
    return this.overlap(1, x - radius, y - radius, x + radius, y + radius, x, y, radius);
  }

  /** Bodies that contain the point; see `PhysicsWorld.overlapPoint`. */
  overlapPoint(x: number, y: number, filter: QueryFilter | undefined): number[] {
    checkPoint('overlapPoint', 'x', x);
    checkPoint('overlapPoint', 'y', y);
    this.takeFilter('overlapPoint', filter, false);
    return this.overlap(1, x, y, x, y, x, y, 0);
  }

  /**
   * The bodies seen by the filter whose shape touches a box (`kind` 0) or a circle (1: centre
   * `cx, cy`, radius `r`; a point is a circle of radius 0) with bounds `minX … maxY`, ascending.
   */
  private overlap(
    kind: number,
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    cx: number,
    cy: number,
    r: number,
  ): number[] {
    this.update();
    this.foundCount = 0;
    if (this.cols === 0) return [];
    const stamp = this.nextStamp();
    const b = this.bodies;
    const mark = this.mark;
    const pad = this.pad;
    const c0 = this.colOf(minX - pad);
    const c1 = this.colOf(maxX + pad);
    const r0 = this.rowOf(minY - pad);
    const r1 = this.rowOf(maxY + pad);
    const start = this.cellStart;
    const items = this.items;
    for (let row = r0; row <= r1; row++) {
      const e = start[row * this.cols + c1 + 1]!;
      for (let m = start[row * this.cols + c0]!; m < e; m++) {
        const i = items[m]!;
        if (mark[i] === stamp) continue;
        mark[i] = stamp;
        if (!this.sees(i)) continue;
        const touches =
          kind === 0
            ? shapeTouchesBox(b, i, minX, minY, maxX, maxY)
            : shapeTouchesCircle(b, i, cx, cy, r);
        if (touches) this.found[this.foundCount++] = i;
      }
    }
    const found = this.found.subarray(0, this.foundCount).sort();
    const out: number[] = [];
    for (const i of found) if (this.qPredicate === null || this.qPredicate(i)) out.push(i);
    return out;
  }

  /**
   * The bodies (not sensors) that sensor `s` overlaps and whose filters agree with its, ascending,
   * appended to `out` from `count`; returns the new count. For `events.ts`.
   */
  sensorVisitors(s: number, out: Int32Array, count: number): number {
    this.update();
    if (this.cols === 0) return count;
    const stamp = this.nextStamp();
    const b = this.bodies;
    const mark = this.mark;
    const flags = b.flags;
    const x = b.x[s]!;
    const y = b.y[s]!;
    const w = b.halfWidth[s]!;
    const h = b.halfHeight[s]!;
    const box = (flags[s]! & BOX) !== 0;
    const pad = this.pad;
    const c0 = this.colOf(x - w - pad);
    const c1 = this.colOf(x + w + pad);
    const r0 = this.rowOf(y - h - pad);
    const r1 = this.rowOf(y + h + pad);
    const start = this.cellStart;
    const items = this.items;
    const from = count;
    mark[s] = stamp;
    for (let row = r0; row <= r1; row++) {
      const e = start[row * this.cols + c1 + 1]!;
      for (let m = start[row * this.cols + c0]!; m < e; m++) {
        const i = items[m]!;
        if (mark[i] === stamp) continue;
        mark[i] = stamp;
        const f = flags[i]!;
        if (f === 0 || (f & SENSOR) !== 0) continue;
        const ga = b.groupIndex[s]!;
        const collide =
          ga === b.groupIndex[i] && ga !== 0
            ? ga > 0
            : (b.maskBits[s]! & b.categoryBits[i]!) !== 0 &&
              (b.categoryBits[s]! & b.maskBits[i]!) !== 0;
        if (!collide) continue;
        const touches = box
          ? shapeTouchesBox(b, i, x - w, y - h, x + w, y + h)
          : shapeTouchesCircle(b, i, x, y, w);
        if (touches) out[count++] = i;
      }
    }
    out.subarray(from, count).sort();
    return count;
  }
}

function clampCell(c: number, n: number): number {
  return c < 0 ? 0 : c >= n ? n - 1 : c;
}

function checkPoint(method: string, field: string, v: unknown): void {
  const m = WORLD_LIMITS.maxCoordinate;
  if (typeof v === 'number' && v >= -m && v <= m) return;
  const text = `PhysicsWorld.${method}: ${field} must be a finite number from -1e9 to 1e9 (metres), got ${show(v)}`;
  throw typeof v === 'number' ? new RangeError(text) : new TypeError(text);
}

/** Whether body `i`'s shape touches the box (closed sets: touching counts). */
function shapeTouchesBox(
  b: BodyStore,
  i: number,
  minX: number,
  minY: number,
  maxX: number,
  maxY: number,
): boolean {
  const x = b.x[i]!;
  const y = b.y[i]!;
  const w = b.halfWidth[i]!;
  const h = b.halfHeight[i]!;
  if (x + w < minX || x - w > maxX || y + h < minY || y - h > maxY) return false;
  if ((b.flags[i]! & BOX) !== 0) return true;
  // A circle: the box's closest point to its centre.
  const qx = x < minX ? minX : x > maxX ? maxX : x;
  const qy = y < minY ? minY : y > maxY ? maxY : y;
  const ex = x - qx;
  const ey = y - qy;
  return ex * ex + ey * ey <= w * w;
}

/** Whether body `i`'s shape touches the circle (closed sets: touching counts). */
function shapeTouchesCircle(b: BodyStore, i: number, cx: number, cy: number, r: number): boolean {
  const x = b.x[i]!;
  const y = b.y[i]!;
  const w = b.halfWidth[i]!;
  const h = b.halfHeight[i]!;
  if ((b.flags[i]! & BOX) === 0) {
    const ex = x - cx;
    const ey = y - cy;
    const sum = w + r;
    return ex * ex + ey * ey <= sum * sum;
  }
  const qx = cx < x - w ? x - w : cx > x + w ? x + w : cx;
  const qy = cy < y - h ? y - h : cy > y + h ? y + h : cy;
  const ex = cx - qx;
  const ey = cy - qy;
  return ex * ex + ey * ey <= r * r;
}
