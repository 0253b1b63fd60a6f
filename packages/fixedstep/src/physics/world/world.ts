import { ByteReader, ByteWriter } from '../../det/bytes.js';
import { fnv1a64 } from '../../det/hash.js';
import type { Simulation } from '../../sim/simulation.js';
import {
  defaultWorldDef,
  type BodyOptions,
  type BoxOptions,
  type CcdMode,
  type CircleOptions,
  type WorldDef,
} from './def.js';
import { tunnellingShare, type TunnellingWarning } from './rule.js';
import { hitBoxSegment, hitPointCapsule, hitPointCircle, hitPointRoundedBox } from './swept.js';

// Body flags.
const ALIVE = 1;
const BOX = 2;
const BULLET = 4;
const KINEMATIC = 8;
const ASLEEP = 16;
const KNOWN_FLAGS = ALIVE | BOX | BULLET | KINEMATIC | ASLEEP;

// Static shapes: kind + 4 parameters, then derived data.
const SEGMENT = 0;
const SBOX = 1;
// [p0, p1, p2, p3, minX, minY, maxX, maxY, nx|0, ny|0, len|0]
const SS = 11;

const MAGIC = 0x57505346; // "FSPW"
const VERSION = 1;
const CCD_MODES: readonly CcdMode[] = ['off', 'bullets', 'auto'];
/** How many times one body may be swept in one step (its own sweep, then once more if struck). */
const MAX_SWEEPS = 2;

/** A static wall, as returned by {@link PhysicsWorld.getStatic}. */
export type StaticShape =
  | { kind: 'segment'; ax: number; ay: number; bx: number; by: number }
  | { kind: 'box'; x: number; y: number; halfWidth: number; halfHeight: number };

/** Options of the {@link PhysicsWorld} object itself (not simulation state). */
export interface WorldOptions {
  /** Bodies to preallocate room for; the arrays double when full. Default 256. */
  capacity?: number;
}

/**
 * A 2D world of dynamic circles and axis-aligned boxes (no rotation) against static segments and
 * boxes, stepped with a fixed step; a deterministic {@link Simulation}.
 *
 * **Layout.** Bodies live in preallocated typed arrays (structure of arrays), indexed by body id;
 * a step allocates nothing. Read them directly to render: {@link x}, {@link y}, {@link vx},
 * {@link vy}, {@link halfWidth}, {@link halfHeight} (a circle's radius is its half width), for ids
 * below {@link slotCount} where {@link isAlive}. Re-read the getters after creating bodies: the
 * arrays are replaced when they grow. Writing positions or velocities between steps is allowed and
 * deterministic.
 *
 * **A step** (one call of {@link step}), Box2D's order:
 * 1. gravity into velocities (semi-implicit Euler);
 * 2. broad phase: a uniform grid rebuilt from scratch (counting sort by cell), pairs taken in cell
 *    order, then id order — a function of the current state only, never of its history;
 * 3. discrete contacts from the overlaps *at the start of the step* (circle–circle, circle–box,
 *    box–box, circle–segment, box–segment, body–static box), sequential impulses warm-started from
 *    last step, with accumulated clamping, Coulomb friction and restitution above a threshold;
 * 4. move by `v·dt` — or, for bodies that could pass through something (see {@link WorldDef.ccd}),
 *    *sweep*: move to the time of impact, bounce, sweep the rest of the step (against static walls
 *    and moving bodies alike, a bounded number of times);
 * 5. relaxation of positions: minimum-translation push-out along each contact's normal, on the
 *    separation predicted from the motion since the contact was found (walls last, so they have
 *    the final word); then, under CCD, a guard puts back any body whose centre crossed a wall;
 * 6. islands that have rested long enough fall asleep ({@link WorldDef.enableSleep}).
 *
 * A body that first overlaps a wall is pushed out through the *nearer* face, exactly as in the
 * talk's discrete model, so with `ccd: 'off'` a share `max(0, 1 − (w + 2r) / (2·v·dt))` of bodies
 * tunnels (see {@link tunnellingShare}); with CCD none does.
 *
 * **State** ({@link save}): the tick, the def, the static walls, every body slot in use (flags,
 * position, velocity, size, inverse mass, rest time, island) and the warm-start cache (last step's
 * contact pairs and impulses). Nothing else survives a step.
 */
export class PhysicsWorld implements Simulation<unknown> {
  /** The configuration. Part of the state: changing a field between steps is deterministic. */
  readonly def: WorldDef;
  /**
   * Called at the end of a step when the scene starts breaking the tunnelling rule in a way that
   * can let a body through a static wall (a {@link TunnellingWarning} with `canTunnel`), and
   * again only after the scene has been safe for a step. Not part of the state; it must not
   * change the world if you want replays to match runs without it.
   */
  onTunnellingWarning: ((warnings: TunnellingWarning[]) => void) | null = null;

  private _tick = 0;
  private cap = 0;
  /** Slots in use: one past the highest live id. */
  private n = 0;
  private live = 0;
  private maxHalf = 0;
  private dynThinHalf = Infinity;
  private staticThinHalf = Infinity;
  private ruleWasBroken = false;

  private fl = new Uint8Array(0);
  private px = new Float64Array(0);
  private py = new Float64Array(0);
  private pvx = new Float64Array(0);
  private pvy = new Float64Array(0);
  private phw = new Float64Array(0);
  private phh = new Float64Array(0);
  private pim = new Float64Array(0);
  /** Seconds each body has been slower than `def.sleepSpeed` (state). */
  private psleep = new Float64Array(0);
  /** The island a sleeping body fell asleep with: its lowest body id (state; 0 when awake). */
  private pisland = new Int32Array(0);
  private asleep = 0;

  // Per-step scratch (never part of the state).
  private x0 = new Float64Array(0);
  private y0 = new Float64Array(0);
  /** Inverse mass as the solvers see it: 0 for kinematic and sleeping bodies. */
  private sim = new Float64Array(0);
  private ufParent = new Int32Array(0);
  private ufMin = new Float64Array(0);
  private corrX = new Float64Array(0);
  private corrY = new Float64Array(0);
  private cellOf = new Int32Array(0);
  private cellStart = new Int32Array(0);
  private cellCursor = new Int32Array(0);
  private cellItems = new Int32Array(0);
  private maxCells = 0;
  private cols = 0;
  private rows = 0;
  private gMinX = 0;
  private gMinY = 0;
  private gInv = 0;
  private ccdT = new Float64Array(0);
  private ccdState = new Uint8Array(0); // 0 discrete, 1 waiting to be swept, 2 swept
  private ccdSweeps = new Uint8Array(0);
  private queue = new Int32Array(0);
  private qLen = 0;
  private swept = 0;
  // Where each body was when the grid was built, and the bodies whose path strays further than
  // `reach` from there (the grid cannot find those; every sweep tests them explicitly).
  private anchorX = new Float64Array(0);
  private anchorY = new Float64Array(0);
  private reach = 0;
  private cellH = 0;
  private farList = new Int32Array(0);
  private farLen = 0;
  private isFar = new Uint8Array(0);
  private readonly toiOut = new Float64Array(3);
  // The best hit of the current sweep.
  private hitU = 2;
  private hitBody = -1;
  private hitNx = 0;
  private hitNy = 0;
  private hitLen = 0;

  // Contacts of the current step: [0, nbb) body–body, [nbb, nc) body–static.
  private cCap = 0;
  private nc = 0;
  private nbb = 0;
  private cA = new Int32Array(0);
  private cB = new Int32Array(0);
  private cNx = new Float64Array(0);
  private cNy = new Float64Array(0);
  private cSep = new Float64Array(0);
  private cJn = new Float64Array(0);
  private cJt = new Float64Array(0);
  private cMass = new Float64Array(0);
  private cVn0 = new Float64Array(0);
  // Warm-start cache: last step's contacts (pair, normal and tangent impulse). Part of the state.
  private wCount = 0;
  private wA = new Int32Array(0);
  private wB = new Int32Array(0);
  private wJn = new Float64Array(0);
  private wJt = new Float64Array(0);
  private wNext = new Int32Array(0);
  private wHead = new Int32Array(0);

  // Static walls.
  private sCount = 0;
  private sKind = new Uint8Array(0);
  private sData = new Float64Array(0);

  private readonly hashWriter = new ByteWriter(4096);

  /** A world from a (partial) def; missing fields take {@link defaultWorldDef}'s values. */
  constructor(def: Partial<WorldDef> = {}, options: WorldOptions = {}) {
    this.def = { ...defaultWorldDef(), ...def };
    validateDef(this.def);
    this.grow(Math.max(16, options.capacity ?? 256));
    this.growStatics(8);
  }

  // ---------------------------------------------------------------- reading

  /** Ticks stepped so far. Simulated time is `tick × def.timeStep`. */
  get tick(): number {
    return this._tick;
  }
  /** Live bodies. */
  get bodyCount(): number {
    return this.live;
  }
  /** One past the highest live body id: iterate `0 ≤ id < slotCount` and skip dead slots. */
  get slotCount(): number {
    return this.n;
  }
  /** Centres, x (metres), by body id. Replaced when the arrays grow. */
  get x(): Float64Array {
    return this.px;
  }
  /** Centres, y (metres), by body id. */
  get y(): Float64Array {
    return this.py;
  }
  /** Velocities, x (m/s), by body id. */
  get vx(): Float64Array {
    return this.pvx;
  }
  /** Velocities, y (m/s), by body id. */
  get vy(): Float64Array {
    return this.pvy;
  }
  /** Half widths (a circle's radius), metres, by body id. */
  get halfWidth(): Float64Array {
    return this.phw;
  }
  /** Half heights (a circle's radius), metres, by body id. */
  get halfHeight(): Float64Array {
    return this.phh;
  }
  /** Inverse masses (1/kg; 0 for kinematic bodies), by body id. */
  get invMass(): Float64Array {
    return this.pim;
  }
  /** Bodies moved with continuous collision detection in the last step (a diagnostic). */
  get sweptCount(): number {
    return this.swept;
  }
  /** Contacts found in the last step (body–body and body–static). */
  get contactCount(): number {
    return this.nc;
  }
  /** Static walls added so far; their ids are `0 … staticCount − 1`. */
  get staticCount(): number {
    return this.sCount;
  }

  isAlive(id: number): boolean {
    return id >= 0 && id < this.n && (this.fl[id]! & ALIVE) !== 0;
  }
  isBox(id: number): boolean {
    return (this.body(id) & BOX) !== 0;
  }
  isBullet(id: number): boolean {
    return (this.body(id) & BULLET) !== 0;
  }
  isKinematic(id: number): boolean {
    return (this.body(id) & KINEMATIC) !== 0;
  }
  /** A body's speed, m/s. */
  speed(id: number): number {
    this.body(id);
    const ux = this.pvx[id]!;
    const uy = this.pvy[id]!;
    return Math.sqrt(ux * ux + uy * uy);
  }

  /**
   * Whether this body would be moved with continuous collision detection at its current velocity
   * (the step itself decides after gravity and contacts have changed the velocity).
   */
  usesContinuous(id: number): boolean {
    const f = this.body(id);
    const mode = this.def.ccd;
    if (mode === 'off') return false;
    const ux = this.pvx[id]! * this.def.timeStep;
    const uy = this.pvy[id]! * this.def.timeStep;
    const d2 = ux * ux + uy * uy;
    if ((f & BULLET) !== 0) return d2 > 0;
    if (mode === 'bullets') return false;
    const h = Math.min(this.phw[id]!, this.phh[id]!);
    const lim = h + Math.min(this.staticThinHalf, this.dynThinHalf);
    return d2 > lim * lim;
  }

  /** A static wall's shape (a fresh object). */
  getStatic(id: number): StaticShape {
    this.checkStatic(id);
    const o = id * SS;
    const d = this.sData;
    return this.sKind[id] === SEGMENT
      ? { kind: 'segment', ax: d[o]!, ay: d[o + 1]!, bx: d[o + 2]!, by: d[o + 3]! }
      : { kind: 'box', x: d[o]!, y: d[o + 1]!, halfWidth: d[o + 2]!, halfHeight: d[o + 3]! };
  }

  /** A static wall's thickness: 0 for a segment, the smaller full extent of a box. Metres. */
  staticThickness(id: number): number {
    this.checkStatic(id);
    const o = id * SS;
    return this.sKind[id] === SEGMENT ? 0 : 2 * Math.min(this.sData[o + 2]!, this.sData[o + 3]!);
  }

  // ---------------------------------------------------------------- building

  /** Adds a dynamic (or kinematic) circle; returns its id (the lowest free slot). */
  createCircle(o: CircleOptions): number {
    const r = o.radius;
    if (!(r > 0 && r < Infinity))
      throw new RangeError(`createCircle: radius must be positive, got ${String(r)}`);
    return this.createBody(0, o, r, r, Math.PI * r * r);
  }

  /** Adds a dynamic (or kinematic) axis-aligned box; returns its id (the lowest free slot). */
  createBox(o: BoxOptions): number {
    const w = o.halfWidth;
    const h = o.halfHeight;
    if (!(w > 0 && w < Infinity && h > 0 && h < Infinity))
      throw new RangeError(
        `createBox: halfWidth and halfHeight must be positive, got ${String(w)}, ${String(h)}`,
      );
    return this.createBody(BOX, o, w, h, 4 * w * h);
  }

  /**
   * Removes a body. Its slot is cleared to zeros and reused by the next body created, so the
   * state after any history of creations and removals depends only on which slots hold what.
   */
  destroyBody(id: number): void {
    this.wake(id); // what rested on it must fall
    const wasExtreme =
      Math.max(this.phw[id]!, this.phh[id]!) >= this.maxHalf ||
      Math.min(this.phw[id]!, this.phh[id]!) <= this.dynThinHalf;
    this.fl[id] = 0;
    this.px[id] = 0;
    this.py[id] = 0;
    this.pvx[id] = 0;
    this.pvy[id] = 0;
    this.phw[id] = 0;
    this.phh[id] = 0;
    this.pim[id] = 0;
    this.psleep[id] = 0;
    this.live--;
    while (this.n > 0 && this.fl[this.n - 1] === 0) this.n--;
    if (wasExtreme) this.recomputeExtents();
    // Forget its cached impulses (the slot's next body must not inherit them).
    let m = 0;
    for (let k = 0; k < this.wCount; k++) {
      if (this.wA[k] === id || this.wB[k] === id) continue;
      this.wA[m] = this.wA[k]!;
      this.wB[m] = this.wB[k]!;
      this.wJn[m] = this.wJn[k]!;
      this.wJt[m] = this.wJt[k]!;
      m++;
    }
    this.wCount = m;
    this.linkWarmStart();
  }

  /** Whether a body is sleeping (see {@link WorldDef.enableSleep}). */
  isAsleep(id: number): boolean {
    return (this.body(id) & ASLEEP) !== 0;
  }
  /** Sleeping bodies. */
  get sleepingCount(): number {
    return this.asleep;
  }
  /** Wakes a sleeping body and its island (a no-op for an awake body). */
  wake(id: number): void {
    this.body(id);
    this.wakeIsland(id);
  }

  /** Teleports a body (metres). Wakes it. */
  setPosition(id: number, x: number, y: number): void {
    this.wake(id);
    this.px[id] = x;
    this.py[id] = y;
  }

  /** Sets a body's velocity (m/s). Wakes it. */
  setVelocity(id: number, vx: number, vy: number): void {
    this.wake(id);
    this.pvx[id] = vx;
    this.pvy[id] = vy;
  }

  /** Adds an impulse (N·s) to a body's velocity; no effect on kinematic bodies. Wakes it. */
  applyImpulse(id: number, jx: number, jy: number): void {
    this.wake(id);
    this.pvx[id] = this.pvx[id]! + jx * this.pim[id]!;
    this.pvy[id] = this.pvy[id]! + jy * this.pim[id]!;
  }

  /** Marks a body as a bullet (always swept) or not. */
  setBullet(id: number, bullet: boolean): void {
    const f = this.body(id);
    this.fl[id] = bullet ? f | BULLET : f & ~BULLET;
  }

  /** Adds a static wall segment (zero thickness, two-sided) from `a` to `b`; returns its id. */
  addSegment(ax: number, ay: number, bx: number, by: number): number {
    if (![ax, ay, bx, by].every(Number.isFinite))
      throw new RangeError('addSegment: coordinates must be finite');
    return this.addStatic(SEGMENT, ax, ay, bx, by);
  }

  /** Adds a static axis-aligned box (centre and half extents, metres); returns its id. */
  addStaticBox(x: number, y: number, halfWidth: number, halfHeight: number): number {
    if (!(Number.isFinite(x) && Number.isFinite(y)))
      throw new RangeError('addStaticBox: centre must be finite');
    if (!(halfWidth > 0 && halfWidth < Infinity && halfHeight > 0 && halfHeight < Infinity))
      throw new RangeError(
        `addStaticBox: half extents must be positive, got ${String(halfWidth)}, ${String(halfHeight)}`,
      );
    return this.addStatic(SBOX, x, y, halfWidth, halfHeight);
  }

  // ---------------------------------------------------------------- the rule

  /**
   * The talk's tunnelling rule checked against the current velocities: one warning per static wall
   * that is thinner than the fastest non-CCD body's `speed × dt` (`'talk-rule'`), or that obeys
   * the rule but can still be pushed through (`'push-through'`, `speed·dt > thickness/2 + radius`).
   * Kinematic bodies are ignored (they pass through walls by design). Allocates; call it between
   * steps, not in a hot loop.
   */
  tunnellingWarnings(): TunnellingWarning[] {
    this.ruleStats();
    const out: TunnellingWarning[] = [];
    const dt = this.def.timeStep;
    const fastD = this.rsFastD;
    const excess = this.rsExcess;
    for (let s = 0; s < this.sCount; s++) {
      const w = this.staticThickness(s);
      let kind: TunnellingWarning['kind'];
      let id: number;
      if (fastD > w) {
        kind = 'talk-rule';
        id = this.rsFastId;
      } else if (excess > w / 2) {
        kind = 'push-through';
        id = this.rsExcessId;
      } else continue;
      const speed = this.speed(id);
      const radius = Math.min(this.phw[id]!, this.phh[id]!);
      const share = tunnellingShare(speed, w, radius, dt);
      const canTunnel = excess > w / 2;
      out.push({
        kind,
        staticId: s,
        wallThickness: w,
        bodyId: id,
        speed,
        radius,
        stepDistance: speed * dt,
        canTunnel,
        share,
        message:
          kind === 'talk-rule'
            ? `static ${s} is ${w} m thick, thinner than body ${id}'s step of ${speed * dt} m (${speed} m/s × ${dt} s): minWallSize is broken` +
              (canTunnel ? '; bodies can pass through it' : '; its radius still stops it')
            : `static ${s} is ${w} m thick, at least one step, but body ${id} moves ${speed * dt} m per step, more than half the wall plus its radius ${radius} m: the push-out can send it through`,
      });
    }
    return out;
  }

  private rsFastD = 0;
  private rsFastId = -1;
  private rsExcess = -Infinity;
  private rsExcessId = -1;

  /** Fastest non-CCD step distance, and the largest `step − radius`, over colliding bodies. */
  private ruleStats(): void {
    this.rsFastD = 0;
    this.rsFastId = -1;
    this.rsExcess = -Infinity;
    this.rsExcessId = -1;
    const dt = this.def.timeStep;
    for (let i = 0; i < this.n; i++) {
      const f = this.fl[i]!;
      if (f === 0 || (f & KINEMATIC) !== 0 || this.usesContinuous(i)) continue;
      const ux = this.pvx[i]!;
      const uy = this.pvy[i]!;
      const d = Math.sqrt(ux * ux + uy * uy) * dt;
      if (d > this.rsFastD) {
        this.rsFastD = d;
        this.rsFastId = i;
      }
      const e = d - Math.min(this.phw[i]!, this.phh[i]!);
      if (d > 0 && e > this.rsExcess) {
        this.rsExcess = e;
        this.rsExcessId = i;
      }
    }
  }

  // ---------------------------------------------------------------- stepping

  /** Advances exactly one fixed step of `def.timeStep` seconds. Inputs are ignored. */
  step(): void {
    if (this.asleep === this.live && this.live > 0) {
      // Everything sleeps: the full step would find no contact and move nothing.
      this.nc = 0;
      this.nbb = 0;
      this.swept = 0;
      if (this.wCount > 0) {
        this.wCount = 0;
        this.linkWarmStart();
      }
      this.ruleWasBroken = false;
      this._tick++;
      return;
    }
    const def = this.def;
    const dt = def.timeStep;
    const n = this.n;
    const fl = this.fl;
    const x = this.px;
    const y = this.py;
    const vx = this.pvx;
    const vy = this.pvy;
    const hw = this.phw;
    const hh = this.phh;
    const im = this.pim;
    const x0 = this.x0;
    const y0 = this.y0;
    const corrX = this.corrX;
    const corrY = this.corrY;
    const ccdState = this.ccdState;
    const ccdSweeps = this.ccdSweeps;
    const ccdT = this.ccdT;
    const queue = this.queue;
    const gx = def.gravityX * dt;
    const gy = def.gravityY * dt;
    const mode = def.ccd === 'auto' ? 2 : def.ccd === 'bullets' ? 1 : 0;
    const thin = this.staticThinHalf < this.dynThinHalf ? this.staticThinHalf : this.dynThinHalf;

    const anchorX = this.anchorX;
    const anchorY = this.anchorY;

    const sim = this.sim;

    // 1. Gravity into velocities; remember where every body starts.
    for (let i = 0; i < n; i++) {
      const f = fl[i]!;
      if (f === 0) continue;
      anchorX[i] = x[i]!;
      anchorY[i] = y[i]!;
      if ((f & ASLEEP) !== 0) {
        sim[i] = 0;
        continue;
      }
      const m = im[i]!;
      sim[i] = m;
      if (m > 0) {
        vx[i] = vx[i]! + gx;
        vy[i] = vy[i]! + gy;
      }
    }

    // 2. Contacts where the bodies are now (a new one wakes what it touches); velocities.
    this.buildGrid();
    this.collide();
    if (this.asleep > 0 && this.wakeByNewContacts()) this.collide();
    this.solveVelocities();
    this.storeWarmStart();

    // 3. Move: semi-implicit Euler, or a sweep for the bodies that could pass through something.
    const isFar = this.isFar;
    const farList = this.farList;
    const cap2 = this.cols > 0 ? 4 * this.cellH * this.cellH : 0;
    let reach2 = 0;
    let far = 0;
    let q = 0;
    for (let i = 0; i < n; i++) {
      const f = fl[i]!;
      isFar[i] = 0;
      ccdT[i] = 0;
      ccdState[i] = 0;
      ccdSweeps[i] = 0;
      if (f === 0) continue;
      if ((f & ASLEEP) !== 0) {
        x0[i] = x[i]!;
        y0[i] = y[i]!;
        continue;
      }
      const mx = vx[i]! * dt;
      const my = vy[i]! * dt;
      const sx = x[i]!;
      const sy = y[i]!;
      x0[i] = sx;
      y0[i] = sy;
      x[i] = sx + mx;
      y[i] = sy + my;
      const d2 = mx * mx + my * my;
      // Bodies moving further than two cells are not found through the grid by the sweeps.
      if (d2 > cap2) {
        isFar[i] = 1;
        farList[far++] = i;
      } else if (d2 > reach2) reach2 = d2;
      let fast = false;
      if (mode !== 0) {
        if ((f & BULLET) !== 0) fast = d2 > 0;
        else if (mode === 2) {
          const a = hw[i]!;
          const b = hh[i]!;
          const lim = (a < b ? a : b) + thin;
          fast = d2 > lim * lim;
        }
      }
      if (fast) {
        queue[q++] = i;
        ccdState[i] = 1;
        ccdSweeps[i] = 1;
      }
    }
    this.qLen = q;
    this.farLen = far;
    this.reach = Math.sqrt(reach2);
    this.swept = 0;
    if (q > 0) this.solveContinuous();

    // 4. Push-out, on separations predicted from each body's motion since its contacts were found.
    for (let i = 0; i < n; i++) {
      if (fl[i] === 0) continue;
      corrX[i] = x[i]! - anchorX[i]!;
      corrY[i] = y[i]! - anchorY[i]!;
    }
    this.solvePositions();
    if (mode !== 0 && this.sCount > 0) this.guardStatics(mode === 2);
    this.updateSleep();
    this._tick++;

    if (this.onTunnellingWarning !== null) {
      this.ruleStats();
      let minW = Infinity;
      for (let s = 0; s < this.sCount; s++) minW = Math.min(minW, this.staticThickness(s));
      const broken = this.rsExcess > minW / 2;
      if (broken && !this.ruleWasBroken) {
        const warnings = this.tunnellingWarnings().filter((w) => w.canTunnel);
        this.onTunnellingWarning(warnings);
      }
      this.ruleWasBroken = broken;
    }
  }

  /** Counting sort of body centres into a uniform grid over their bounds. */
  private buildGrid(): void {
    const n = this.n;
    const fl = this.fl;
    const x = this.px;
    const y = this.py;
    const cellOf = this.cellOf;
    let minX = Infinity;
    let minY = Infinity;
    let maxX = -Infinity;
    let maxY = -Infinity;
    for (let i = 0; i < n; i++) {
      if (fl[i] === 0) {
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
    const spanX = maxX - minX;
    const spanY = maxY - minY;
    if (!(spanX >= 0 && spanX < Infinity && spanY >= 0 && spanY < Infinity)) {
      // No bodies, or a non-finite position: no pairs this step.
      this.cols = 0;
      this.rows = 0;
      for (let i = 0; i < n; i++) cellOf[i] = -1;
      return;
    }
    let h = this.def.cellSize > 2 * this.maxHalf ? this.def.cellSize : 2 * this.maxHalf;
    let inv = 1 / h;
    let cols = Math.floor(spanX * inv) + 1;
    let rows = Math.floor(spanY * inv) + 1;
    // The cell budget depends on the slot count (state), never on the arrays' capacity
    // (history): a world loaded from a snapshot must build the same grid as the one that saved it.
    const budget = 4 * n + 64;
    while (cols * rows > budget) {
      h *= 2;
      inv = 1 / h;
      cols = Math.floor(spanX * inv) + 1;
      rows = Math.floor(spanY * inv) + 1;
    }
    this.cols = cols;
    this.rows = rows;
    this.gMinX = minX;
    this.gMinY = minY;
    this.gInv = inv;
    this.cellH = h;
    const cells = cols * rows;
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

  private addContact(a: number, b: number, nx: number, ny: number, sep: number): void {
    if (this.nc === this.cCap) this.growContacts();
    const k = this.nc++;
    // Body pairs are stored lower id first, so the warm-start cache finds them in either order.
    if (b >= 0 && b < a) {
      this.cA[k] = b;
      this.cB[k] = a;
      this.cNx[k] = -nx;
      this.cNy[k] = -ny;
    } else {
      this.cA[k] = a;
      this.cB[k] = b;
      this.cNx[k] = nx;
      this.cNy[k] = ny;
    }
    this.cSep[k] = sep;
  }

  /** Broad phase over the grid, then narrow phase; fills the contact arrays. */
  private collide(): void {
    this.nc = 0;
    const cols = this.cols;
    const rows = this.rows;
    const start = this.cellStart;
    const items = this.cellItems;
    const fl = this.fl;
    const x = this.px;
    const y = this.py;
    const hw = this.phw;
    const hh = this.phh;
    const im = this.sim; // 0 for kinematic and sleeping bodies: such pairs are skipped
    for (let cy = 0; cy < rows; cy++) {
      for (let cx = 0; cx < cols; cx++) {
        const c = cy * cols + cx;
        const s = start[c]!;
        const e = start[c + 1]!;
        if (s === e) continue;
        // Forward neighbours: the rest of this cell and the next cell (contiguous), then the
        // three cells above (contiguous too). Every pair once, in a fixed order.
        const e1 = cx + 1 < cols ? start[c + 2]! : e;
        let s2 = 0;
        let e2 = 0;
        if (cy + 1 < rows) {
          const up = c + cols;
          s2 = start[cx > 0 ? up - 1 : up]!;
          e2 = start[cx + 1 < cols ? up + 2 : up + 1]!;
        }
        for (let k = s; k < e; k++) {
          const i = items[k]!;
          const fi = fl[i]!;
          const xi = x[i]!;
          const yi = y[i]!;
          const wi = hw[i]!;
          const hi = hh[i]!;
          const ii = im[i]!;
          for (let pass = 0; pass < 2; pass++) {
            const from = pass === 0 ? k + 1 : s2;
            const to = pass === 0 ? e1 : e2;
            for (let m = from; m < to; m++) {
              const j = items[m]!;
              const dx = xi - x[j]!;
              const dy = yi - y[j]!;
              const sw = wi + hw[j]!;
              const sh = hi + hh[j]!;
              if (dx >= sw || dx <= -sw || dy >= sh || dy <= -sh) continue;
              const fj = fl[j]!;
              // Both immovable here: skip — unless a kinematic body touches a sleeping one.
              if (
                ii === 0 &&
                im[j] === 0 &&
                (((fi | fj) & ASLEEP) === 0 || ((fi | fj) & KINEMATIC) === 0)
              )
                continue;
              if (((fi | fj) & BOX) === 0) {
                // circle–circle, the hot case
                const d2 = dx * dx + dy * dy;
                if (d2 >= sw * sw) continue;
                const d = Math.sqrt(d2);
                if (d > 0) this.addContact(i, j, dx / d, dy / d, d - sw);
                else this.addContact(i, j, 0, 1, -sw);
              } else if ((fi & fj & BOX) !== 0) {
                const ox = sw - (dx < 0 ? -dx : dx);
                const oy = sh - (dy < 0 ? -dy : dy);
                if (ox < oy) this.addContact(i, j, dx >= 0 ? 1 : -1, 0, -ox);
                else this.addContact(i, j, 0, dy >= 0 ? 1 : -1, -oy);
              } else if ((fi & BOX) === 0) {
                this.circleBox(i, j, xi, yi, wi, x[j]!, y[j]!, hw[j]!, hh[j]!, 1);
              } else {
                this.circleBox(i, j, x[j]!, y[j]!, hw[j]!, xi, yi, wi, hi, -1);
              }
            }
          }
        }
      }
    }
    this.nbb = this.nc;

    // Body–static, body index order then static order (statics are few: a linear scan).
    const sc = this.sCount;
    if (sc === 0) return;
    const sd = this.sData;
    const sk = this.sKind;
    const n = this.n;
    for (let i = 0; i < n; i++) {
      const f = fl[i]!;
      if (f === 0 || im[i] === 0) continue;
      const xi = x[i]!;
      const yi = y[i]!;
      const wi = hw[i]!;
      const hi = hh[i]!;
      const isBox = (f & BOX) !== 0;
      for (let s = 0; s < sc; s++) {
        const o = s * SS;
        if (
          xi - wi >= sd[o + 6]! ||
          xi + wi <= sd[o + 4]! ||
          yi - hi >= sd[o + 7]! ||
          yi + hi <= sd[o + 5]!
        )
          continue;
        if (sk[s] === SBOX) {
          if (isBox) {
            const dx = xi - sd[o]!;
            const dy = yi - sd[o + 1]!;
            const ox = wi + sd[o + 2]! - (dx < 0 ? -dx : dx);
            const oy = hi + sd[o + 3]! - (dy < 0 ? -dy : dy);
            if (ox < oy) this.addContact(i, -1 - s, dx >= 0 ? 1 : -1, 0, -ox);
            else this.addContact(i, -1 - s, 0, dy >= 0 ? 1 : -1, -oy);
          } else {
            this.circleBox(i, -1 - s, xi, yi, wi, sd[o]!, sd[o + 1]!, sd[o + 2]!, sd[o + 3]!, 1);
          }
        } else if (isBox) this.boxSegment(i, s, xi, yi, wi, hi);
        else this.circleSegment(i, s, xi, yi, wi);
      }
    }
  }

  /**
   * Circle (centre `c`, radius `r`) against box (centre `b`, half extents): a contact between `a`
   * and `bIdx` whose normal is `sign ×` (box → circle).
   */
  private circleBox(
    a: number,
    bIdx: number,
    cx: number,
    cy: number,
    r: number,
    bx: number,
    by: number,
    bw: number,
    bh: number,
    sign: number,
  ): void {
    const lx = cx - bx;
    const ly = cy - by;
    const alx = lx < 0 ? -lx : lx;
    const aly = ly < 0 ? -ly : ly;
    if (alx <= bw && aly <= bh) {
      // Centre inside the box: out through the nearer face.
      if (bw - alx <= bh - aly) this.addContact(a, bIdx, lx >= 0 ? sign : -sign, 0, alx - bw - r);
      else this.addContact(a, bIdx, 0, ly >= 0 ? sign : -sign, aly - bh - r);
      return;
    }
    const qx = lx > bw ? bw : lx < -bw ? -bw : lx;
    const qy = ly > bh ? bh : ly < -bh ? -bh : ly;
    const ex = lx - qx;
    const ey = ly - qy;
    const d2 = ex * ex + ey * ey;
    if (d2 >= r * r) return;
    const d = Math.sqrt(d2);
    this.addContact(a, bIdx, (sign * ex) / d, (sign * ey) / d, d - r);
  }

  private circleSegment(i: number, s: number, cx: number, cy: number, r: number): void {
    const o = s * SS;
    const sd = this.sData;
    const ax = sd[o]!;
    const ay = sd[o + 1]!;
    const nx = sd[o + 8]!;
    const ny = sd[o + 9]!;
    const len = sd[o + 10]!;
    // tangent = (ny, -nx)
    const rx = cx - ax;
    const ry = cy - ay;
    const along = rx * ny - ry * nx;
    let qx = ax;
    let qy = ay;
    if (along >= len) {
      qx = sd[o + 2]!;
      qy = sd[o + 3]!;
    } else if (along > 0) {
      qx = ax + along * ny;
      qy = ay - along * nx;
    }
    const ex = cx - qx;
    const ey = cy - qy;
    const d2 = ex * ex + ey * ey;
    if (d2 >= r * r) return;
    const d = Math.sqrt(d2);
    if (d > 0) this.addContact(i, -1 - s, ex / d, ey / d, d - r);
    else {
      // Centre exactly on the segment: back the way it came.
      const side = this.pvx[i]! * nx + this.pvy[i]! * ny > 0 ? -1 : 1;
      this.addContact(i, -1 - s, side * nx, side * ny, -r);
    }
  }

  /** Separating axes x, y and the segment normal; the smallest overlap wins. */
  private boxSegment(i: number, s: number, cx: number, cy: number, w: number, h: number): void {
    const o = s * SS;
    const sd = this.sData;
    const ax = sd[o]!;
    const ay = sd[o + 1]!;
    const bx = sd[o + 2]!;
    const by = sd[o + 3]!;
    const nx = sd[o + 8]!;
    const ny = sd[o + 9]!;
    const rn = w * (nx < 0 ? -nx : nx) + h * (ny < 0 ? -ny : ny);
    const sv = (cx - ax) * nx + (cy - ay) * ny;
    const pn = rn - (sv < 0 ? -sv : sv);
    if (pn <= 0) return;
    let best = pn;
    let bnx = sv >= 0 ? nx : -nx;
    let bny = sv >= 0 ? ny : -ny;
    const lox = (ax < bx ? ax : bx) - w;
    const hix = (ax < bx ? bx : ax) + w;
    const loy = (ay < by ? ay : by) - h;
    const hiy = (ay < by ? by : ay) + h;
    const pxl = cx - lox;
    const pxh = hix - cx;
    const pyl = cy - loy;
    const pyh = hiy - cy;
    if (pxl <= 0 || pxh <= 0 || pyl <= 0 || pyh <= 0) return;
    if (pxl < best) {
      best = pxl;
      bnx = -1;
      bny = 0;
    }
    if (pxh < best) {
      best = pxh;
      bnx = 1;
      bny = 0;
    }
    if (pyl < best) {
      best = pyl;
      bnx = 0;
      bny = -1;
    }
    if (pyh < best) {
      best = pyh;
      bnx = 0;
      bny = 1;
    }
    this.addContact(i, -1 - s, bnx, bny, -best);
  }

  private solveVelocities(): void {
    const def = this.def;
    const nc = this.nc;
    const nbb = this.nbb;
    const cA = this.cA;
    const cB = this.cB;
    const cNx = this.cNx;
    const cNy = this.cNy;
    const cJn = this.cJn;
    const cJt = this.cJt;
    const cMass = this.cMass;
    const cVn0 = this.cVn0;
    const vx = this.pvx;
    const vy = this.pvy;
    const im = this.sim;
    const mu = def.friction;

    const wHead = this.wHead;
    const wNext = this.wNext;
    const wB = this.wB;
    const wJn = this.wJn;
    const wJt = this.wJt;
    for (let k = 0; k < nc; k++) {
      const a = cA[k]!;
      const b = cB[k]!;
      const nx = cNx[k]!;
      const ny = cNy[k]!;
      if (k < nbb) {
        cMass[k] = 1 / (im[a]! + im[b]!);
        cVn0[k] = (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
      } else {
        cMass[k] = 1 / im[a]!;
        cVn0[k] = vx[a]! * nx + vy[a]! * ny;
      }
      // Warm start: the impulses this pair needed last step.
      let jn = 0;
      let jt = 0;
      for (let w = wHead[a]!; w !== -1; w = wNext[w]!) {
        if (wB[w] === b) {
          jn = wJn[w]!;
          jt = wJt[w]!;
          break;
        }
      }
      cJn[k] = jn;
      cJt[k] = jt;
    }
    for (let k = 0; k < nc; k++) {
      const jn = cJn[k]!;
      const jt = cJt[k]!;
      if (jn === 0 && jt === 0) continue;
      const a = cA[k]!;
      const nx = cNx[k]!;
      const ny = cNy[k]!;
      const ix = jn * nx - jt * ny;
      const iy = jn * ny + jt * nx;
      const ia = im[a]!;
      vx[a] = vx[a]! + ix * ia;
      vy[a] = vy[a]! + iy * ia;
      if (k < nbb) {
        const b = cB[k]!;
        const ib = im[b]!;
        vx[b] = vx[b]! - ix * ib;
        vy[b] = vy[b]! - iy * ib;
      }
    }

    const iters = def.velocityIterations;
    for (let it = 0; it < iters; it++) {
      for (let k = 0; k < nbb; k++) {
        const a = cA[k]!;
        const b = cB[k]!;
        const nx = cNx[k]!;
        const ny = cNy[k]!;
        const m = cMass[k]!;
        const rvx = vx[a]! - vx[b]!;
        const rvy = vy[a]! - vy[b]!;
        const jn = cJn[k]!;
        let nj = jn - (rvx * nx + rvy * ny) * m;
        if (nj < 0) nj = 0;
        const ln = nj - jn;
        cJn[k] = nj;
        const jt = cJt[k]!;
        const maxF = mu * nj;
        let tj = jt - (rvy * nx - rvx * ny) * m;
        if (tj > maxF) tj = maxF;
        else if (tj < -maxF) tj = -maxF;
        const lt = tj - jt;
        cJt[k] = tj;
        const ix = ln * nx - lt * ny;
        const iy = ln * ny + lt * nx;
        const ia = im[a]!;
        const ib = im[b]!;
        vx[a] = vx[a]! + ix * ia;
        vy[a] = vy[a]! + iy * ia;
        vx[b] = vx[b]! - ix * ib;
        vy[b] = vy[b]! - iy * ib;
      }
      for (let k = nbb; k < nc; k++) {
        const a = cA[k]!;
        const nx = cNx[k]!;
        const ny = cNy[k]!;
        const m = cMass[k]!;
        const rvx = vx[a]!;
        const rvy = vy[a]!;
        const jn = cJn[k]!;
        let nj = jn - (rvx * nx + rvy * ny) * m;
        if (nj < 0) nj = 0;
        const ln = nj - jn;
        cJn[k] = nj;
        const jt = cJt[k]!;
        const maxF = mu * nj;
        let tj = jt - (rvy * nx - rvx * ny) * m;
        if (tj > maxF) tj = maxF;
        else if (tj < -maxF) tj = -maxF;
        const lt = tj - jt;
        cJt[k] = tj;
        const ia = im[a]!;
        vx[a] = rvx + (ln * nx - lt * ny) * ia;
        vy[a] = rvy + (ln * ny + lt * nx) * ia;
      }
    }

    // Restitution, Box2D style: once, after the iterations, for contacts that approached fast.
    const e = def.restitution;
    const thr = -def.restitutionThreshold;
    for (let k = 0; e > 0 && k < nc; k++) {
      const vn0 = cVn0[k]!;
      if (vn0 > thr || cJn[k] === 0) continue;
      const a = cA[k]!;
      const b = cB[k]!;
      const nx = cNx[k]!;
      const ny = cNy[k]!;
      const stat = k >= nbb;
      const vn = stat ? vx[a]! * nx + vy[a]! * ny : (vx[a]! - vx[b]!) * nx + (vy[a]! - vy[b]!) * ny;
      const jn = cJn[k]!;
      let nj = jn - (vn + e * vn0) * cMass[k]!;
      if (nj < 0) nj = 0;
      const ln = nj - jn;
      cJn[k] = nj;
      const ia = im[a]!;
      vx[a] = vx[a]! + ln * nx * ia;
      vy[a] = vy[a]! + ln * ny * ia;
      if (!stat) {
        const ib = im[b]!;
        vx[b] = vx[b]! - ln * nx * ib;
        vy[b] = vy[b]! - ln * ny * ib;
      }
    }
  }

  /** Keeps this step's impulses for the next step's warm start (part of the state). */
  private storeWarmStart(): void {
    const nc = this.nc;
    const cA = this.cA;
    const wA = this.wA;
    const wB = this.wB;
    const wJn = this.wJn;
    const wJt = this.wJt;
    const cB = this.cB;
    const cJn = this.cJn;
    const cJt = this.cJt;
    for (let k = 0; k < nc; k++) {
      wA[k] = cA[k]!;
      wB[k] = cB[k]!;
      wJn[k] = cJn[k]!;
      wJt[k] = cJt[k]!;
    }
    this.wCount = nc;
    this.linkWarmStart();
  }

  /** Per-body chains through the warm-start cache, in cache order. */
  private linkWarmStart(): void {
    const wHead = this.wHead;
    const wNext = this.wNext;
    const wA = this.wA;
    wHead.fill(-1, 0, this.n);
    for (let k = this.wCount - 1; k >= 0; k--) {
      const a = wA[k]!;
      wNext[k] = wHead[a]!;
      wHead[a] = k;
    }
  }

  /** Relaxation: push overlapping pairs apart along their normals (static contacts last). */
  private solvePositions(): void {
    const def = this.def;
    const nc = this.nc;
    const nbb = this.nbb;
    const cA = this.cA;
    const cB = this.cB;
    const cNx = this.cNx;
    const cNy = this.cNy;
    const cSep = this.cSep;
    const x = this.px;
    const y = this.py;
    const corrX = this.corrX;
    const corrY = this.corrY;
    const im = this.sim;
    const slop = def.linearSlop;
    const beta = def.positionCorrection;
    const iters = def.positionIterations;
    for (let it = 0; it < iters; it++) {
      for (let k = 0; k < nbb; k++) {
        const a = cA[k]!;
        const b = cB[k]!;
        const nx = cNx[k]!;
        const ny = cNy[k]!;
        const sep = cSep[k]! + (corrX[a]! - corrX[b]!) * nx + (corrY[a]! - corrY[b]!) * ny;
        if (sep >= -slop) continue;
        const ia = im[a]!;
        const ib = im[b]!;
        const c = (-(sep + slop) * beta) / (ia + ib);
        const pa = c * ia;
        const pb = c * ib;
        corrX[a] = corrX[a]! + pa * nx;
        corrY[a] = corrY[a]! + pa * ny;
        x[a] = x[a]! + pa * nx;
        y[a] = y[a]! + pa * ny;
        corrX[b] = corrX[b]! - pb * nx;
        corrY[b] = corrY[b]! - pb * ny;
        x[b] = x[b]! - pb * nx;
        y[b] = y[b]! - pb * ny;
      }
      for (let k = nbb; k < nc; k++) {
        const a = cA[k]!;
        const nx = cNx[k]!;
        const ny = cNy[k]!;
        const sep = cSep[k]! + corrX[a]! * nx + corrY[a]! * ny;
        if (sep >= -slop) continue;
        const c = -(sep + slop) * beta;
        corrX[a] = corrX[a]! + c * nx;
        corrY[a] = corrY[a]! + c * ny;
        x[a] = x[a]! + c * nx;
        y[a] = y[a]! + c * ny;
      }
    }
  }

  /**
   * Islands (bodies joined by contacts, kinematic bodies and walls excluded) fall asleep together
   * when every body in them has been slower than `sleepSpeed` for `timeToSleep`: a sleeping body
   * is not moved, and pairs of sleeping bodies are not even looked at.
   */
  private updateSleep(): void {
    const def = this.def;
    const n = this.n;
    const fl = this.fl;
    if (!def.enableSleep) {
      if (this.asleep > 0) for (let i = 0; i < n; i++) this.wakeIsland(i);
      return;
    }
    const vx = this.pvx;
    const vy = this.pvy;
    const sim = this.sim;
    const slept = this.psleep;
    const parent = this.ufParent;
    const minT = this.ufMin;
    const dt = def.timeStep;
    const s2 = def.sleepSpeed * def.sleepSpeed;
    let candidates = 0;
    for (let i = 0; i < n; i++) {
      parent[i] = i;
      minT[i] = Infinity;
      const f = fl[i]!;
      if (f === 0 || (f & ASLEEP) !== 0) continue;
      if (sim[i] === 0) {
        slept[i] = 0; // kinematic: never sleeps
        continue;
      }
      const u = vx[i]!;
      const w = vy[i]!;
      if (u * u + w * w < s2) {
        slept[i] = slept[i]! + dt;
        if (slept[i]! >= def.timeToSleep) candidates++;
      } else slept[i] = 0;
    }
    // Islands are formed every 8th tick only (sleep comes at most 7 ticks late; it costs a pass
    // over all contacts).
    if (candidates === 0 || (this._tick & 7) !== 0) return;
    const cA = this.cA;
    const cB = this.cB;
    for (let k = 0; k < this.nbb; k++) {
      const a = cA[k]!;
      const b = cB[k]!;
      if (sim[a] === 0 || sim[b] === 0) continue;
      const ra = find(parent, a);
      const rb = find(parent, b);
      if (ra < rb) parent[rb] = ra;
      else if (rb < ra) parent[ra] = rb;
    }
    for (let i = 0; i < n; i++) {
      if (sim[i] === 0 || fl[i] === 0 || (fl[i]! & ASLEEP) !== 0) continue;
      const r = find(parent, i);
      if (slept[i]! < minT[r]!) minT[r] = slept[i]!;
    }
    for (let i = 0; i < n; i++) {
      if (sim[i] === 0 || fl[i] === 0 || (fl[i]! & ASLEEP) !== 0) continue;
      const r = find(parent, i);
      if (minT[r]! < def.timeToSleep) continue;
      fl[i] = fl[i]! | ASLEEP;
      vx[i] = 0;
      vy[i] = 0;
      this.pisland[i] = r;
      this.asleep++;
    }
  }

  /** Wakes the sleeping partner of every contact that is new this step (not in the cache). */
  private wakeByNewContacts(): boolean {
    const fl = this.fl;
    const cA = this.cA;
    const cB = this.cB;
    const wHead = this.wHead;
    const wNext = this.wNext;
    const wB = this.wB;
    let woke = false;
    for (let k = 0; k < this.nbb; k++) {
      const a = cA[k]!;
      const b = cB[k]!;
      const sa = (fl[a]! & ASLEEP) !== 0;
      const sb = (fl[b]! & ASLEEP) !== 0;
      if (sa === sb) continue;
      // A kinematic body pushes: what it touches never sleeps.
      let cached = ((fl[a]! | fl[b]!) & KINEMATIC) === 0 ? false : null;
      for (let w = wHead[a]!; cached === false && w !== -1; w = wNext[w]!) {
        if (wB[w] === b) cached = true;
      }
      if (cached === true) continue;
      this.wakeIsland(sa ? a : b);
      woke = true;
    }
    return woke;
  }

  /** Wakes a sleeping body and everything that fell asleep with it. */
  private wakeIsland(id: number): void {
    const fl = this.fl;
    if ((fl[id]! & ASLEEP) === 0) return;
    const island = this.pisland[id]!;
    for (let i = 0; i < this.n; i++) {
      const f = fl[i]!;
      if ((f & ASLEEP) === 0 || this.pisland[i] !== island) continue;
      fl[i] = f & ~ASLEEP;
      this.psleep[i] = 0;
      this.pisland[i] = 0;
      this.sim[i] = this.pim[i]!;
      this.x0[i] = this.px[i]!;
      this.y0[i] = this.py[i]!;
      this.asleep--;
    }
  }

  /**
   * The safety net under continuous detection: a body whose centre crossed a static wall's spine
   * this step (the segment itself, or a box's long midline) — by a sweep's approximation or by
   * the push-out of a crowded contact — is put back just on the side it started from, where the
   * next step's push-out takes it out through the near face. Bodies under `'bullets'` are only
   * guarded when flagged. One AABB test per body and wall; the exact test only near walls.
   */
  private guardStatics(all: boolean): void {
    const n = this.n;
    const fl = this.fl;
    const x = this.px;
    const y = this.py;
    const ax0 = this.anchorX;
    const ay0 = this.anchorY;
    const im = this.pim;
    const sd = this.sData;
    const sk = this.sKind;
    const sc = this.sCount;
    for (let i = 0; i < n; i++) {
      const f = fl[i]!;
      if (f === 0 || im[i] === 0 || (!all && (f & BULLET) === 0)) continue;
      const p0x = ax0[i]!;
      const p0y = ay0[i]!;
      let p1x = x[i]!;
      let p1y = y[i]!;
      for (let s = 0; s < sc; s++) {
        const o = s * SS;
        if (
          (p0x < p1x ? p0x : p1x) > sd[o + 6]! ||
          (p0x < p1x ? p1x : p0x) < sd[o + 4]! ||
          (p0y < p1y ? p0y : p1y) > sd[o + 7]! ||
          (p0y < p1y ? p1y : p0y) < sd[o + 5]!
        )
          continue;
        let ax: number;
        let ay: number;
        let bx: number;
        let by: number;
        if (sk[s] === SEGMENT) {
          ax = sd[o]!;
          ay = sd[o + 1]!;
          bx = sd[o + 2]!;
          by = sd[o + 3]!;
        } else if (sd[o + 2]! >= sd[o + 3]!) {
          ax = sd[o]! - sd[o + 2]!;
          bx = sd[o]! + sd[o + 2]!;
          ay = sd[o + 1]!;
          by = ay;
        } else {
          ay = sd[o + 1]! - sd[o + 3]!;
          by = sd[o + 1]! + sd[o + 3]!;
          ax = sd[o]!;
          bx = ax;
        }
        const ex = bx - ax;
        const ey = by - ay;
        const o1 = ex * (p0y - ay) - ey * (p0x - ax);
        const o2 = ex * (p1y - ay) - ey * (p1x - ax);
        if (o1 === 0 || (o1 > 0 ? o2 > 0 : o2 < 0)) continue; // started on it, or same side
        const mx = p1x - p0x;
        const my = p1y - p0y;
        const o3 = mx * (ay - p0y) - my * (ax - p0x);
        const o4 = mx * (by - p0y) - my * (bx - p0x);
        if ((o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0)) continue; // passed beside it
        // Back to where the path meets the spine, then a hair onto the starting side.
        const u = o1 / (o1 - o2);
        const len = Math.sqrt(ex * ex + ey * ey);
        const side = o1 > 0 ? 1 : -1;
        const eps = 1e-9 + 1e-12 * (Math.abs(ax) + Math.abs(ay));
        p1x = p0x + u * mx - (side * ey * eps) / len;
        p1y = p0y + u * my + (side * ex * eps) / len;
        x[i] = p1x;
        y[i] = p1y;
      }
    }
  }

  // ---------------------------------------------------------------- continuous

  /** Sweeps every queued body in queue order; bodies struck by a sweep join the queue. */
  private solveContinuous(): void {
    let head = 0;
    while (head < this.qLen) {
      const i = this.queue[head++]!;
      if (this.ccdState[i] !== 1) continue;
      this.ccdState[i] = 2;
      this.swept++;
      this.sweep(i, false);
      this.track(i);
    }
  }

  /** Whether a body moving at `(wx, wy)` needs sweeping under the world's ccd mode. */
  private isFast(j: number, wx: number, wy: number): boolean {
    const f = this.fl[j]!;
    const dt = this.def.timeStep;
    const d2 = (wx * wx + wy * wy) * dt * dt;
    if ((f & BULLET) !== 0) return d2 > 0;
    if (this.def.ccd !== 'auto') return false;
    const a = this.phw[j]!;
    const b = this.phh[j]!;
    const thin = this.staticThinHalf < this.dynThinHalf ? this.staticThinHalf : this.dynThinHalf;
    const lim = (a < b ? a : b) + thin;
    return d2 > lim * lim;
  }

  /**
   * After body `j`'s path became final for this step: list it as far if the grid can no longer
   * find it. (A body still waiting for its own sweep needs no listing: its sweep comes later and
   * tests it against everyone that swept before.)
   */
  private track(j: number): void {
    if (this.isFar[j] === 1) return;
    const ax = this.anchorX[j]!;
    const ay = this.anchorY[j]!;
    const r2 = this.reach * this.reach;
    const ex = this.px[j]! - ax;
    const ey = this.py[j]! - ay;
    const sx = this.x0[j]! - ax;
    const sy = this.y0[j]! - ay;
    if (ex * ex + ey * ey > r2 || sx * sx + sy * sy > r2) {
      this.isFar[j] = 1;
      this.farList[this.farLen++] = j;
    }
  }

  /**
   * Moves body `i` from its position at fraction `ccdT[i]` of the step to the end, stopping at each
   * time of impact (plus a quarter of the linear slop, so the discrete solver sees the contact),
   * responding, and sweeping the rest.
   * Every body has a linear path `x0 → x` over the step, which this keeps consistent when it
   * changes a body's velocity, so later sweeps see where the others are at any time.
   */
  private sweep(i: number, staticsOnly: boolean): void {
    const def = this.def;
    const dt = def.timeStep;
    const x = this.px;
    const y = this.py;
    const x0 = this.x0;
    const y0 = this.y0;
    const vx = this.pvx;
    const vy = this.pvy;
    const fl = this.fl;
    const im = this.pim;
    const overshoot = 0.25 * def.linearSlop;
    const ia = im[i]!;
    const isBox = (fl[i]! & BOX) !== 0;
    const wi = this.phw[i]!;
    const hi = this.phh[i]!;
    let t = this.ccdT[i]!;
    let px = x0[i]! + t * (x[i]! - x0[i]!);
    let py = y0[i]! + t * (y[i]! - y0[i]!);
    let ux = vx[i]!;
    let uy = vy[i]!;
    let frozen = false;
    let iter = 0;
    // The path after the last hit is linear from `tLast`; that is what later sweeps see.
    let tLast = t;
    let lastX = px;
    let lastY = py;
    while (t < 1) {
      if (iter === def.maxCcdIterations) {
        frozen = true;
        break;
      }
      iter++;
      const rem = 1 - t;
      const dx = ux * dt * rem;
      const dy = uy * dt * rem;
      this.hitU = 2;
      this.hitBody = -1;
      const minX = (dx < 0 ? px + dx : px) - wi;
      const maxX = (dx < 0 ? px : px + dx) + wi;
      const minY = (dy < 0 ? py + dy : py) - hi;
      const maxY = (dy < 0 ? py : py + dy) + hi;

      if (ia > 0) this.findStaticHit(isBox, wi, hi, px, py, dx, dy, minX, minY, maxX, maxY);

      // Bodies whose path stays within `reach` of their grid position, through the grid…
      if (!staticsOnly && this.cols > 0) {
        const margin = this.maxHalf + this.reach + overshoot;
        const loX = minX - margin;
        const hiX = maxX + margin;
        const loY = minY - margin;
        const hiY = maxY + margin;
        const anchorX = this.anchorX;
        const anchorY = this.anchorY;
        const inv = this.gInv;
        const c0 = clampInt(Math.floor((loX - this.gMinX) * inv), 0, this.cols - 1);
        const c1 = clampInt(Math.floor((hiX - this.gMinX) * inv), 0, this.cols - 1);
        const r0 = clampInt(Math.floor((loY - this.gMinY) * inv), 0, this.rows - 1);
        const r1 = clampInt(Math.floor((hiY - this.gMinY) * inv), 0, this.rows - 1);
        if ((c1 - c0 + 1) * (r1 - r0 + 1) > this.n) {
          for (let j = 0; j < this.n; j++) this.sweepAgainst(i, j, t, px, py, dx, dy, rem);
        } else {
          const start = this.cellStart;
          const items = this.cellItems;
          for (let r = r0; r <= r1; r++) {
            const e = start[r * this.cols + c1 + 1]!;
            for (let m = start[r * this.cols + c0]!; m < e; m++) {
              const j = items[m]!;
              const ax = anchorX[j]!;
              const ay = anchorY[j]!;
              if (ax < loX || ax > hiX || ay < loY || ay > hiY) continue;
              this.sweepAgainst(i, j, t, px, py, dx, dy, rem);
            }
          }
        }
      }
      // …and the others, one by one.
      for (let m = 0; !staticsOnly && m < this.farLen; m++) {
        this.sweepAgainst(i, this.farList[m]!, t, px, py, dx, dy, rem);
      }

      const best = this.hitU;
      if (best > 1) {
        px += dx;
        py += dy;
        break;
      }
      let ua = best + overshoot / this.hitLen;
      if (ua > 1) ua = 1;
      const nx = this.hitNx;
      const ny = this.hitNy;
      const j = this.hitBody;
      if (j >= 0 && !this.clearToStatics(j, t + rem * ua)) continue; // j bounced first: look again
      px += dx * ua;
      py += dy * ua;
      t += rem * ua;
      tLast = t;
      lastX = px;
      lastY = py;
      const e = def.restitution;
      const thr = def.restitutionThreshold;
      const mu = def.friction;
      if (j < 0) {
        const vn = ux * nx + uy * ny;
        if (vn < 0) {
          const jn = -(1 + (-vn > thr ? e : 0)) * vn;
          const vt = uy * nx - ux * ny;
          const maxF = mu * jn;
          const lt = -vt > maxF ? maxF : -vt < -maxF ? -maxF : -vt;
          ux += jn * nx - lt * ny;
          uy += jn * ny + lt * nx;
        }
      } else {
        if ((fl[j]! & ASLEEP) !== 0) this.wakeIsland(j);
        const ib = im[j]!;
        const qx = x0[j]! + t * (x[j]! - x0[j]!);
        const qy = y0[j]! + t * (y[j]! - y0[j]!);
        const rvx = ux - vx[j]!;
        const rvy = uy - vy[j]!;
        const vn = rvx * nx + rvy * ny;
        if (vn < 0) {
          const m = 1 / (ia + ib);
          const pn = -(1 + (-vn > thr ? e : 0)) * vn * m;
          const vt = rvy * nx - rvx * ny;
          const maxF = mu * pn;
          let pt = -vt * m;
          if (pt > maxF) pt = maxF;
          else if (pt < -maxF) pt = -maxF;
          const ix = pn * nx - pt * ny;
          const iy = pn * ny + pt * nx;
          ux += ix * ia;
          uy += iy * ia;
          if (ib > 0) {
            const wx = vx[j]! - ix * ib;
            const wy = vy[j]! - iy * ib;
            vx[j] = wx;
            vy[j] = wy;
            this.replan(j, t, qx, qy, wx, wy);
          }
        }
      }
    }
    x[i] = px;
    y[i] = py;
    vx[i] = ux;
    vy[i] = uy;
    if (frozen) {
      x0[i] = px;
      y0[i] = py;
    } else {
      // A line through (lastX, lastY) at tLast with the final velocity: x0 + s·(x − x0).
      x0[i] = lastX - tLast * dt * ux;
      y0[i] = lastY - tLast * dt * uy;
    }
    this.ccdT[i] = tLast;
  }

  /** The earliest hit of a shape at `p` moving `d` against the static walls, into `hit*`. */
  private findStaticHit(
    isBox: boolean,
    wi: number,
    hi: number,
    px: number,
    py: number,
    dx: number,
    dy: number,
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
  ): void {
    const out = this.toiOut;
    const sd = this.sData;
    for (let s = 0; s < this.sCount; s++) {
      const o = s * SS;
      if (minX > sd[o + 6]! || maxX < sd[o + 4]! || minY > sd[o + 7]! || maxY < sd[o + 5]!)
        continue;
      let touched: boolean;
      if (this.sKind[s] === SEGMENT) {
        touched = isBox
          ? hitBoxSegment(px, py, dx, dy, wi, hi, sd[o]!, sd[o + 1]!, sd[o + 2]!, sd[o + 3]!, out)
          : hitPointCapsule(px, py, dx, dy, sd[o]!, sd[o + 1]!, sd[o + 2]!, sd[o + 3]!, wi, out);
      } else {
        touched = isBox
          ? hitPointRoundedBox(
              px - sd[o]!,
              py - sd[o + 1]!,
              dx,
              dy,
              wi + sd[o + 2]!,
              hi + sd[o + 3]!,
              0,
              out,
            )
          : hitPointRoundedBox(
              px - sd[o]!,
              py - sd[o + 1]!,
              dx,
              dy,
              sd[o + 2]!,
              sd[o + 3]!,
              wi,
              out,
            );
      }
      const u = touched ? out[2]! : -1;
      if (u >= 0 && u < this.hitU) {
        this.hitU = u;
        this.hitBody = -1 - s;
        this.hitNx = out[0]!;
        this.hitNy = out[1]!;
        this.hitLen = Math.sqrt(dx * dx + dy * dy);
      }
    }
  }

  /**
   * Before body `i` strikes body `j` at fraction `tHit`: if `j` is still waiting for its own
   * sweep, its motion up to `tHit` has not been checked. Check it against the static walls; if
   * `j` hits one first, move it there, bounce it, and return false (the strike is void: `i`
   * must look again).
   */
  private clearToStatics(j: number, tHit: number): boolean {
    const t0 = this.ccdT[j]!;
    if (this.ccdState[j] !== 1 || this.pim[j] === 0 || tHit <= t0) return true;
    const x0 = this.x0;
    const y0 = this.y0;
    const ex = this.px[j]! - x0[j]!;
    const ey = this.py[j]! - y0[j]!;
    const px = x0[j]! + t0 * ex;
    const py = y0[j]! + t0 * ey;
    const dx = ex * (tHit - t0);
    const dy = ey * (tHit - t0);
    const wj = this.phw[j]!;
    const hj = this.phh[j]!;
    this.hitU = 2;
    this.findStaticHit(
      (this.fl[j]! & BOX) !== 0,
      wj,
      hj,
      px,
      py,
      dx,
      dy,
      (dx < 0 ? px + dx : px) - wj,
      (dy < 0 ? py + dy : py) - hj,
      (dx < 0 ? px : px + dx) + wj,
      (dy < 0 ? py : py + dy) + hj,
    );
    if (this.hitU > 1) return true;
    let ua = this.hitU + (0.25 * this.def.linearSlop) / this.hitLen;
    if (ua > 1) ua = 1;
    const t = t0 + (tHit - t0) * ua;
    const qx = px + dx * ua;
    const qy = py + dy * ua;
    const nx = this.hitNx;
    const ny = this.hitNy;
    let ux = this.pvx[j]!;
    let uy = this.pvy[j]!;
    const vn = ux * nx + uy * ny;
    if (vn < 0) {
      const jn = -(1 + (-vn > this.def.restitutionThreshold ? this.def.restitution : 0)) * vn;
      const vt = uy * nx - ux * ny;
      const maxF = this.def.friction * jn;
      const lt = -vt > maxF ? maxF : -vt < -maxF ? -maxF : -vt;
      ux += jn * nx - lt * ny;
      uy += jn * ny + lt * nx;
    }
    const dt = this.def.timeStep;
    this.pvx[j] = ux;
    this.pvy[j] = uy;
    this.ccdT[j] = t;
    this.px[j] = qx + (1 - t) * dt * ux;
    this.py[j] = qy + (1 - t) * dt * uy;
    x0[j] = qx - t * dt * ux;
    y0[j] = qy - t * dt * uy;
    return false;
  }

  /**
   * Body `j` was struck at fraction `t` at `(qx, qy)` and now moves at `w`: re-plan its path, and
   * sweep it (again) if it is now fast and has sweeps left; a fast body out of sweeps stays where
   * it was struck for the rest of the step.
   */
  private replan(j: number, t: number, qx: number, qy: number, wx: number, wy: number): void {
    const dt = this.def.timeStep;
    const state = this.ccdState[j]!;
    this.ccdT[j] = t;
    this.px[j] = qx + (1 - t) * dt * wx;
    this.py[j] = qy + (1 - t) * dt * wy;
    this.x0[j] = qx - t * dt * wx;
    this.y0[j] = qy - t * dt * wy;
    if (state === 1) return;
    if (this.isFast(j, wx, wy)) {
      if (this.ccdSweeps[j]! < MAX_SWEEPS) {
        this.ccdSweeps[j] = this.ccdSweeps[j]! + 1;
        this.ccdState[j] = 1;
        this.queue[this.qLen++] = j;
        return;
      }
      this.px[j] = qx;
      this.py[j] = qy;
      this.x0[j] = qx;
      this.y0[j] = qy;
    } else {
      // Slow enough for the discrete solver against other bodies, but it may have been knocked
      // into a thin wall it was resting against: sweep it against the static walls now.
      this.sweep(j, true);
    }
    this.track(j);
  }

  /** Time of impact of `i` (at `p`, moving `d` over the rest of the step) against body `j`'s path. */
  private sweepAgainst(
    i: number,
    j: number,
    t: number,
    px: number,
    py: number,
    dx: number,
    dy: number,
    rem: number,
  ): void {
    if (j === i) return;
    const fj = this.fl[j]!;
    if (fj === 0) return;
    const ia = this.pim[i]!;
    const ib = this.pim[j]!;
    if (ia === 0 && ib === 0) return;
    const x0 = this.x0;
    const y0 = this.y0;
    const pjx = this.px[j]! - x0[j]!;
    const pjy = this.py[j]! - y0[j]!;
    // j's path is valid from ccdT[j] (its last hit); start there if that is later than t.
    const tv = this.ccdT[j]!;
    let s0 = t;
    let f0 = 0;
    if (tv > t) {
      if (tv >= 1) return;
      s0 = tv;
      f0 = (tv - t) / rem;
    }
    const f1 = 1 - f0;
    const rx = px + f0 * dx - (x0[j]! + s0 * pjx);
    const ry = py + f0 * dy - (y0[j]! + s0 * pjy);
    const rdx = f1 * dx - pjx * (1 - s0);
    const rdy = f1 * dy - pjy * (1 - s0);
    const fi = this.fl[i]!;
    const wi = this.phw[i]!;
    const hi = this.phh[i]!;
    const wj = this.phw[j]!;
    const hj = this.phh[j]!;
    const ex = wi + wj;
    const ey = hi + hj;
    if ((rx > ex && rx + rdx > ex) || (rx < -ex && rx + rdx < -ex)) return;
    if ((ry > ey && ry + rdy > ey) || (ry < -ey && ry + rdy < -ey)) return;
    const out = this.toiOut;
    let touched: boolean;
    if (((fi | fj) & BOX) === 0) touched = hitPointCircle(rx, ry, rdx, rdy, ex, out);
    else if ((fi & fj & BOX) !== 0) touched = hitPointRoundedBox(rx, ry, rdx, rdy, ex, ey, 0, out);
    else if ((fi & BOX) === 0) touched = hitPointRoundedBox(rx, ry, rdx, rdy, wj, hj, wi, out);
    else touched = hitPointRoundedBox(rx, ry, rdx, rdy, wi, hi, wj, out);
    const u = touched ? f0 + out[2]! * f1 : -1;
    if (u >= 0 && u < this.hitU) {
      this.hitU = u;
      this.hitBody = j;
      this.hitNx = out[0]!;
      this.hitNy = out[1]!;
      this.hitLen = Math.sqrt(rdx * rdx + rdy * rdy) / f1;
    }
  }

  // ---------------------------------------------------------------- state

  /** The whole state as canonical bytes: tick, def, static walls, every body slot in use. */
  save(): Uint8Array {
    const w = new ByteWriter(128 + this.sCount * 40 + this.n * 69 + this.wCount * 24);
    this.write(w);
    return w.finish();
  }

  /** FNV-1a 64 of {@link save}'s bytes (without allocating them). */
  hash(): bigint {
    const w = this.hashWriter.reset();
    this.write(w);
    return fnv1a64(w.peek());
  }

  private write(w: ByteWriter): void {
    const d = this.def;
    w.u32(MAGIC).u32(VERSION).f64(this._tick);
    w.f64(d.gravityX).f64(d.gravityY).f64(d.timeStep).f64(d.restitution);
    w.f64(d.restitutionThreshold).f64(d.friction).f64(d.linearSlop).f64(d.positionCorrection);
    w.f64(d.cellSize).f64(d.sleepSpeed).f64(d.timeToSleep);
    w.u32(d.velocityIterations).u32(d.positionIterations).u32(d.maxCcdIterations);
    w.u8(CCD_MODES.indexOf(d.ccd)).u8(d.enableSleep ? 1 : 0);
    w.u32(this.sCount);
    for (let s = 0; s < this.sCount; s++) {
      const o = s * SS;
      w.u8(this.sKind[s]!);
      for (let k = 0; k < 4; k++) w.f64(this.sData[o + k]!);
    }
    const n = this.n;
    w.u32(n);
    w.ints(this.fl.subarray(0, n));
    w.f64s(this.px.subarray(0, n));
    w.f64s(this.py.subarray(0, n));
    w.f64s(this.pvx.subarray(0, n));
    w.f64s(this.pvy.subarray(0, n));
    w.f64s(this.phw.subarray(0, n));
    w.f64s(this.phh.subarray(0, n));
    w.f64s(this.pim.subarray(0, n));
    w.f64s(this.psleep.subarray(0, n));
    w.ints(this.pisland.subarray(0, n));
    const wc = this.wCount;
    w.u32(wc);
    w.ints(this.wA.subarray(0, wc));
    w.ints(this.wB.subarray(0, wc));
    w.f64s(this.wJn.subarray(0, wc));
    w.f64s(this.wJt.subarray(0, wc));
  }

  /** Restores a state from {@link save}. Throws a RangeError (and changes nothing) on bad bytes. */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32() !== MAGIC) throw new RangeError('PhysicsWorld.load: not a physics world snapshot');
    const version = r.u32();
    if (version !== VERSION)
      throw new RangeError(`PhysicsWorld.load: unsupported snapshot version ${version}`);
    const tick = r.f64();
    if (!(Number.isInteger(tick) && tick >= 0))
      throw new RangeError(`PhysicsWorld.load: bad tick ${tick}`);
    const def: WorldDef = {
      gravityX: r.f64(),
      gravityY: r.f64(),
      timeStep: r.f64(),
      restitution: r.f64(),
      restitutionThreshold: r.f64(),
      friction: r.f64(),
      linearSlop: r.f64(),
      positionCorrection: r.f64(),
      cellSize: r.f64(),
      sleepSpeed: r.f64(),
      timeToSleep: r.f64(),
      velocityIterations: r.u32(),
      positionIterations: r.u32(),
      maxCcdIterations: r.u32(),
      ccd: 'auto',
      enableSleep: true,
    };
    const mode = CCD_MODES[r.u8()];
    if (mode === undefined) throw new RangeError('PhysicsWorld.load: bad ccd mode');
    def.ccd = mode;
    const sleep = r.u8();
    if (sleep > 1) throw new RangeError('PhysicsWorld.load: bad enableSleep');
    def.enableSleep = sleep === 1;
    validateDef(def);
    const sc = r.u32();
    if (sc * 33 > r.remaining) throw new RangeError('PhysicsWorld.load: truncated statics');
    const kinds = new Uint8Array(sc);
    const params = new Float64Array(sc * 4);
    for (let s = 0; s < sc; s++) {
      const k = r.u8();
      if (k !== SEGMENT && k !== SBOX)
        throw new RangeError(`PhysicsWorld.load: bad static kind ${k}`);
      kinds[s] = k;
      for (let m = 0; m < 4; m++) params[s * 4 + m] = r.f64();
    }
    const n = r.u32();
    if (n * 69 > r.remaining) throw new RangeError('PhysicsWorld.load: truncated bodies');
    const fl = new Uint8Array(n);
    r.ints(fl);
    const arrays = Array.from({ length: 8 }, () => new Float64Array(n));
    for (const a of arrays) r.f64s(a);
    const island = new Int32Array(n);
    r.ints(island);
    const wc = r.u32();
    if (wc * 24 > r.remaining) throw new RangeError('PhysicsWorld.load: truncated contact cache');
    const wA = new Int32Array(wc);
    const wB = new Int32Array(wc);
    const wJn = new Float64Array(wc);
    const wJt = new Float64Array(wc);
    r.ints(wA);
    r.ints(wB);
    r.f64s(wJn);
    r.f64s(wJt);
    r.end();
    for (let k = 0; k < wc; k++) {
      const a = wA[k]!;
      const b = wB[k]!;
      if (!(
        a >= 0 &&
        a < n &&
        fl[a] !== 0 &&
        (b < 0 ? -1 - b < sc : b > a && b < n && fl[b] !== 0)
      ))
        throw new RangeError(`PhysicsWorld.load: bad contact cache entry ${k}`);
    }
    for (let i = 0; i < n; i++) {
      const f = fl[i]!;
      if ((f & ~KNOWN_FLAGS) !== 0 || (f !== 0 && (f & ALIVE) === 0))
        throw new RangeError(`PhysicsWorld.load: bad flags ${f} for body ${i}`);
    }
    if (n > 0 && fl[n - 1] === 0)
      throw new RangeError('PhysicsWorld.load: trailing dead slot (not canonical)');

    // Commit.
    Object.assign(this.def, def);
    this._tick = tick;
    this.sCount = 0;
    for (let s = 0; s < sc; s++) {
      this.addStatic(
        kinds[s]!,
        params[s * 4]!,
        params[s * 4 + 1]!,
        params[s * 4 + 2]!,
        params[s * 4 + 3]!,
      );
    }
    if (n > this.cap) this.grow(n);
    this.fl.fill(0);
    this.fl.set(fl);
    const dst = [this.px, this.py, this.pvx, this.pvy, this.phw, this.phh, this.pim, this.psleep];
    for (let k = 0; k < 8; k++) {
      dst[k]!.fill(0);
      dst[k]!.set(arrays[k]!);
    }
    this.pisland.fill(0);
    this.pisland.set(island);
    this.n = n;
    this.live = 0;
    this.asleep = 0;
    for (let i = 0; i < n; i++) {
      if (fl[i] !== 0) this.live++;
      if ((fl[i]! & ASLEEP) !== 0) this.asleep++;
    }
    this.recomputeExtents();
    this.nc = 0;
    this.nbb = 0;
    if (wc > this.cCap) this.growContacts(wc);
    this.wA.set(wA);
    this.wB.set(wB);
    this.wJn.set(wJn);
    this.wJt.set(wJt);
    this.wCount = wc;
    this.linkWarmStart();
    this.ruleWasBroken = false;
  }

  // ---------------------------------------------------------------- internals

  private body(id: number): number {
    if (!this.isAlive(id)) throw new RangeError(`PhysicsWorld: no body ${id}`);
    return this.fl[id]!;
  }

  private checkStatic(id: number): void {
    if (!(Number.isInteger(id) && id >= 0 && id < this.sCount))
      throw new RangeError(`PhysicsWorld: no static ${id}`);
  }

  private createBody(shape: number, o: BodyOptions, w: number, h: number, area: number): number {
    const vx = o.vx ?? 0;
    const vy = o.vy ?? 0;
    const density = o.density ?? 1;
    if (![o.x, o.y, vx, vy].every(Number.isFinite))
      throw new RangeError('PhysicsWorld: position and velocity must be finite');
    if (!(density > 0 && density < Infinity))
      throw new RangeError(`PhysicsWorld: density must be positive, got ${String(density)}`);
    let id = this.n;
    if (this.live < this.n) {
      id = 0;
      while (this.fl[id] !== 0) id++;
    }
    if (id >= this.cap) this.grow(this.cap * 2);
    if (id === this.n) this.n++;
    const kinematic = o.kinematic === true;
    this.fl[id] = ALIVE | shape | (o.bullet === true ? BULLET : 0) | (kinematic ? KINEMATIC : 0);
    this.px[id] = o.x;
    this.py[id] = o.y;
    this.pvx[id] = vx;
    this.pvy[id] = vy;
    this.phw[id] = w;
    this.phh[id] = h;
    this.pim[id] = kinematic ? 0 : 1 / (density * area);
    this.live++;
    if (Math.max(w, h) > this.maxHalf) this.maxHalf = Math.max(w, h);
    if (Math.min(w, h) < this.dynThinHalf) this.dynThinHalf = Math.min(w, h);
    return id;
  }

  private recomputeExtents(): void {
    let mx = 0;
    let mn = Infinity;
    for (let i = 0; i < this.n; i++) {
      if (this.fl[i] === 0) continue;
      const a = this.phw[i]!;
      const b = this.phh[i]!;
      mx = Math.max(mx, a, b);
      mn = Math.min(mn, a, b);
    }
    this.maxHalf = mx;
    this.dynThinHalf = mn;
  }

  private addStatic(kind: number, p0: number, p1: number, p2: number, p3: number): number {
    for (let i = 0; this.asleep > 0 && i < this.n; i++) this.wakeIsland(i);
    if (this.sCount * SS >= this.sData.length) this.growStatics(this.sKind.length * 2);
    const s = this.sCount++;
    const o = s * SS;
    const d = this.sData;
    this.sKind[s] = kind;
    d[o] = p0;
    d[o + 1] = p1;
    d[o + 2] = p2;
    d[o + 3] = p3;
    if (kind === SEGMENT) {
      d[o + 4] = Math.min(p0, p2);
      d[o + 5] = Math.min(p1, p3);
      d[o + 6] = Math.max(p0, p2);
      d[o + 7] = Math.max(p1, p3);
      const ex = p2 - p0;
      const ey = p3 - p1;
      const len = Math.sqrt(ex * ex + ey * ey);
      // normal = left of a → b; a degenerate segment gets (0, 1)
      d[o + 8] = len > 0 ? -ey / len : 0;
      d[o + 9] = len > 0 ? ex / len : 1;
      d[o + 10] = len;
    } else {
      d[o + 4] = p0 - p2;
      d[o + 5] = p1 - p3;
      d[o + 6] = p0 + p2;
      d[o + 7] = p1 + p3;
      d[o + 8] = 0;
      d[o + 9] = 0;
      d[o + 10] = 0;
    }
    this.staticThinHalf = Math.min(
      s === 0 ? Infinity : this.staticThinHalf,
      kind === SEGMENT ? 0 : Math.min(p2, p3),
    );
    return s;
  }

  private growStatics(cap: number): void {
    const kinds = new Uint8Array(cap);
    kinds.set(this.sKind);
    const data = new Float64Array(cap * SS);
    data.set(this.sData);
    this.sKind = kinds;
    this.sData = data;
  }

  private grow(cap: number): void {
    const f64 = (a: Float64Array) => {
      const b = new Float64Array(cap);
      b.set(a.subarray(0, Math.min(a.length, cap)));
      return b;
    };
    const fl = new Uint8Array(cap);
    fl.set(this.fl.subarray(0, Math.min(this.fl.length, cap)));
    this.fl = fl;
    this.px = f64(this.px);
    this.py = f64(this.py);
    this.pvx = f64(this.pvx);
    this.pvy = f64(this.pvy);
    this.phw = f64(this.phw);
    this.phh = f64(this.phh);
    this.pim = f64(this.pim);
    this.psleep = f64(this.psleep);
    const island = new Int32Array(cap);
    island.set(this.pisland.subarray(0, Math.min(this.pisland.length, cap)));
    this.pisland = island;
    this.sim = new Float64Array(cap);
    this.ufParent = new Int32Array(cap);
    this.ufMin = new Float64Array(cap);
    this.x0 = new Float64Array(cap);
    this.y0 = new Float64Array(cap);
    this.corrX = new Float64Array(cap);
    this.corrY = new Float64Array(cap);
    this.cellOf = new Int32Array(cap);
    this.cellItems = new Int32Array(cap);
    this.maxCells = 4 * cap + 64;
    this.cellStart = new Int32Array(this.maxCells + 2);
    this.cellCursor = new Int32Array(this.maxCells + 1);
    this.ccdT = new Float64Array(cap);
    this.ccdState = new Uint8Array(cap);
    this.ccdSweeps = new Uint8Array(cap);
    this.queue = new Int32Array(cap * MAX_SWEEPS);
    this.anchorX = new Float64Array(cap);
    this.anchorY = new Float64Array(cap);
    this.farList = new Int32Array(cap);
    this.isFar = new Uint8Array(cap);
    const head = new Int32Array(cap).fill(-1);
    head.set(this.wHead.subarray(0, Math.min(this.wHead.length, cap)));
    this.wHead = head;
    this.cap = cap;
    if (this.cCap < 4 * cap) this.growContacts(4 * cap);
  }

  private growContacts(cap = this.cCap * 2): void {
    const i32 = (a: Int32Array) => {
      const b = new Int32Array(cap);
      b.set(a);
      return b;
    };
    const f64 = (a: Float64Array) => {
      const b = new Float64Array(cap);
      b.set(a);
      return b;
    };
    this.cA = i32(this.cA);
    this.cB = i32(this.cB);
    this.cNx = f64(this.cNx);
    this.cNy = f64(this.cNy);
    this.cSep = f64(this.cSep);
    this.cJn = f64(this.cJn);
    this.cJt = f64(this.cJt);
    this.cMass = f64(this.cMass);
    this.cVn0 = f64(this.cVn0);
    this.wA = i32(this.wA);
    this.wB = i32(this.wB);
    this.wJn = f64(this.wJn);
    this.wJt = f64(this.wJt);
    this.wNext = i32(this.wNext);
    this.cCap = cap;
  }
}

/** Union–find root, with path halving. */
function find(parent: Int32Array, i: number): number {
  let r = i;
  while (parent[r] !== r) {
    const g = parent[parent[r]!]!;
    parent[r] = g;
    r = g;
  }
  return r;
}

function clampInt(v: number, lo: number, hi: number): number {
  return v < lo ? lo : v > hi ? hi : v;
}

function validateDef(d: WorldDef): void {
  const pos = (v: number) => v > 0 && v < Infinity;
  if (!pos(d.timeStep))
    throw new RangeError(`WorldDef: timeStep must be positive, got ${d.timeStep}`);
  if (!(Number.isFinite(d.gravityX) && Number.isFinite(d.gravityY)))
    throw new RangeError('WorldDef: gravity must be finite');
  if (!(d.restitution >= 0 && d.restitution <= 1))
    throw new RangeError(`WorldDef: restitution must be in [0, 1], got ${d.restitution}`);
  if (!(d.restitutionThreshold >= 0 && d.restitutionThreshold < Infinity))
    throw new RangeError('WorldDef: restitutionThreshold must be ≥ 0');
  if (!(d.friction >= 0 && d.friction < Infinity))
    throw new RangeError('WorldDef: friction must be ≥ 0');
  if (!(d.linearSlop >= 0 && d.linearSlop < Infinity))
    throw new RangeError('WorldDef: linearSlop must be ≥ 0');
  if (!(d.positionCorrection > 0 && d.positionCorrection <= 1))
    throw new RangeError('WorldDef: positionCorrection must be in (0, 1]');
  if (!(d.cellSize >= 0 && d.cellSize < Infinity))
    throw new RangeError('WorldDef: cellSize must be ≥ 0');
  if (!(d.sleepSpeed >= 0 && d.sleepSpeed < Infinity))
    throw new RangeError('WorldDef: sleepSpeed must be ≥ 0');
  if (!(d.timeToSleep >= 0 && d.timeToSleep < Infinity))
    throw new RangeError('WorldDef: timeToSleep must be ≥ 0');
  for (const k of ['velocityIterations', 'positionIterations', 'maxCcdIterations'] as const) {
    const v = d[k];
    if (!(Number.isInteger(v) && v >= 0 && v <= 1000))
      throw new RangeError(`WorldDef: ${k} must be an integer from 0 to 1000, got ${v}`);
  }
  if (!CCD_MODES.includes(d.ccd))
    throw new RangeError(`WorldDef: bad ccd mode ${JSON.stringify(d.ccd)}`);
}
