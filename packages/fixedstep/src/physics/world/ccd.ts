/**
 * Continuous collision detection (Box2D's time-of-impact solver, `solver.c`'s continuous pass):
 * moving the bodies that discrete detection could let through a wall or another body.
 *
 * After the velocities are solved, every body gets a straight path over the step, from
 * `pathStart` to `x`. A body is *fast* when its step is longer than its own smallest half extent
 * plus half the thinnest feature in the world (`'auto'`), or when it is a bullet. Fast bodies are
 * *swept* in queue order: each moves along its path to the first time of impact (against walls
 * and against other bodies' paths), plus a quarter of the linear slop so the discrete solver sees
 * the contact next step; responds (restitution above the threshold, Coulomb friction); and sweeps
 * the rest of the step, at most `maxCcdIterations` times, after which it stops where it is (it
 * never tunnels). A body struck by a sweep gets a new path, and joins the queue if it is now fast
 * and has sweeps left ({@link MAX_SWEEPS}); a slow one is swept against walls only.
 *
 * Finding the bodies a sweep may hit: bodies whose path stays within `reach` of where the grid
 * put them are found through the grid; the few that move further ("far" bodies) are tested one
 * by one.
 *
 * Last, a guard puts back any body whose centre crossed a wall's spine this step (by a sweep's
 * approximation or by the push-out of a crowded contact), just on the side it started from.
 */
import { frictionOf, mixFriction, mixRestitution, restitutionOf } from './material.js';
import { BodyFlag, type BodyStore } from './body.js';
import { bucketOf, type Grid } from './broad-phase.js';
import type { WorldDef } from './def.js';
import { wakeIsland } from './island.js';
import { bodiesCollide, collidesWithWalls } from './filter.js';
import { WallKind, staticRef, type StaticStore } from './statics.js';
import { hitBoxSegment, hitPointCapsule, hitPointCircle, hitPointRoundedBox } from './swept.js';

const { ASLEEP, BOX, BULLET, SENSOR } = BodyFlag;
const { SEGMENT } = WallKind;

/** How many times one body may be swept in one step (its own sweep, then once more if struck). */
export const MAX_SWEEPS = 2;

// A body's continuous state this step.
/** Moved by v·dt (or not moving): not swept. */
const DISCRETE = 0;
/** In the queue, waiting for its sweep. */
const WAITING = 1;
/** Swept (its path is final unless something strikes it). */
const SWEPT = 2;

/** No hit yet: any time of impact is below this. */
const NO_HIT = 2;

/** The continuous mode as a number for the hot loops. */
function modeOf(def: Readonly<WorldDef>): number {
  return def.ccd === 'auto' ? 2 : def.ccd === 'bullets' ? 1 : 0;
}

function clampInt(v: number, lo: number, hi: number): number {
  return v < lo ? lo : v > hi ? hi : v;
}

/**
 * Continuous detection for one world (see the file comment): its per-body scratch, the queue of
 * bodies to sweep, and the sweep in progress.
 */
export class ContinuousSolver {
  /** Bodies swept in the last step (a diagnostic). */
  sweptCount = 0;

  /** By body: the fraction of the step its current path is valid from (its last hit). */
  private pathTime = new Float64Array(0);
  /** By body: {@link DISCRETE}, {@link WAITING} or {@link SWEPT}. */
  private state = new Uint8Array(0);
  /** By body: sweeps started this step. */
  private sweeps = new Uint8Array(0);
  private queue = new Int32Array(0);
  private queueLength = 0;
  /** Bodies whose path strays further than `reach` from where the grid put them. */
  private farList = new Int32Array(0);
  private farCount = 0;
  private isFar = new Uint8Array(0);
  /** How far the other bodies' paths stray from where the grid put them, at most. Metres. */
  private reach = 0;
  private readonly toiOut = new Float64Array(3);
  // The earliest hit of the current sweep: fraction of the sweep, what (body id or staticRef),
  // normal, and the sweep's length.
  private hitU = NO_HIT;
  private hitBody = -1;
  private hitNx = 0;
  private hitNy = 0;
  private hitLength = 0;
  // The motion being tested against walls and bodies: a shape at (qX, qY) moving (qDx, qDy) over
  // the rest of the step from fraction qT (qRest of it), and its bounding box. Fields, not
  // arguments: V8 boxes a double passed to a call it does not inline.
  private qBox = false;
  private qHalfWidth = 0;
  private qHalfHeight = 0;
  private qX = 0;
  private qY = 0;
  private qDx = 0;
  private qDy = 0;
  private qT = 0;
  private qRest = 0;
  private qMinX = 0;
  private qMinY = 0;
  private qMaxX = 0;
  private qMaxY = 0;
  private def: Readonly<WorldDef> | null = null;

  constructor(
    private readonly bodies: BodyStore,
    private readonly statics: StaticStore,
    private readonly grid: Grid,
  ) {}

  resize(capacity: number): void {
    this.pathTime = new Float64Array(capacity);
    this.state = new Uint8Array(capacity);
    this.sweeps = new Uint8Array(capacity);
    this.queue = new Int32Array(capacity * MAX_SWEEPS);
    this.farList = new Int32Array(capacity);
    this.isFar = new Uint8Array(capacity);
  }

  /** Half the thinnest feature in the world: the thinnest wall or body. */
  private thinnest(): number {
    const s = this.statics.thinnestHalfExtent;
    const b = this.bodies.thinnestHalfExtent;
    return s < b ? s : b;
  }

  /**
   * Whether body `id` would be swept at its current velocity (the step decides after gravity
   * and contacts have changed it).
   */
  wouldSweep(id: number, def: Readonly<WorldDef>): boolean {
    const f = this.bodies.flags[id]!;
    if (def.ccd === 'off') return false;
    const ux = this.bodies.vx[id]! * def.timeStep;
    const uy = this.bodies.vy[id]! * def.timeStep;
    const d2 = ux * ux + uy * uy;
    if ((f & BULLET) !== 0) return d2 > 0;
    if (def.ccd === 'bullets') return false;
    const h = Math.min(this.bodies.halfWidth[id]!, this.bodies.halfHeight[id]!);
    const lim = h + Math.min(this.statics.thinnestHalfExtent, this.bodies.thinnestHalfExtent);
    return d2 > lim * lim;
  }

  /**
   * Semi-implicit Euler on positions (`x += v·dt`) for every awake body, remembering each path's
   * start; queues the fast bodies and lists the far ones, then sweeps the queue.
   */
  integratePositions(def: Readonly<WorldDef>): void {
    const bodies = this.bodies;
    const n = bodies.slotCount;
    const flags = bodies.flags;
    const x = bodies.x;
    const y = bodies.y;
    const vx = bodies.vx;
    const vy = bodies.vy;
    const hw = bodies.halfWidth;
    const hh = bodies.halfHeight;
    const pathStartX = bodies.pathStartX;
    const pathStartY = bodies.pathStartY;
    const pathTime = this.pathTime;
    const state = this.state;
    const sweeps = this.sweeps;
    const queue = this.queue;
    const isFar = this.isFar;
    const farList = this.farList;
    const dt = def.timeStep;
    const mode = modeOf(def);
    const wallThin = this.statics.thinnestHalfExtent;
    const bodyThin = bodies.thinnestHalfExtent;
    const thin = wallThin < bodyThin ? wallThin : bodyThin;
    const cell = this.grid.cellSize;
    // Bodies moving further than two cells are not found through the grid by the sweeps.
    const farLimit2 = this.grid.cols > 0 ? 4 * cell * cell : 0;
    let reach2 = 0;
    let far = 0;
    let queued = 0;
    isFar.fill(0, 0, n);
    pathTime.fill(0, 0, n);
    state.fill(DISCRETE, 0, n);
    sweeps.fill(0, 0, n);
    // The moves, and the longest of them, and every moving body's flags or-ed…
    let longest2 = 0;
    let union = 0;
    for (let i = 0; i < n; i++) {
      const f = flags[i]!;
      if (f === 0) continue;
      if ((f & ASLEEP) !== 0) {
        pathStartX[i] = x[i]!;
        pathStartY[i] = y[i]!;
        continue;
      }
      union |= f;
      const mx = vx[i]! * dt;
      const my = vy[i]! * dt;
      const sx = x[i]!;
      const sy = y[i]!;
      pathStartX[i] = sx;
      pathStartY[i] = sy;
      x[i] = sx + mx;
      y[i] = sy + my;
      const d2 = mx * mx + my * my;
      if (d2 > longest2) longest2 = d2;
      if (d2 > farLimit2) {
        isFar[i] = 1;
        farList[far++] = i;
      } else if (d2 > reach2) reach2 = d2;
    }
    // …then the fast bodies, in id order, unless none can be: no bullet, and no move longer than
    // the least limit (each body's limit is its smaller half extent plus `thin`, and
    // `bodyThin` is at most every body's smaller half extent).
    const least = bodyThin + thin;
    if (mode !== 0 && ((union & BULLET) !== 0 || (mode === 2 && !(longest2 <= least * least)))) {
      for (let i = 0; i < n; i++) {
        const f = flags[i]!;
        if (f === 0 || (f & ASLEEP) !== 0) continue;
        const mx = vx[i]! * dt;
        const my = vy[i]! * dt;
        const d2 = mx * mx + my * my;
        let fast = false;
        if ((f & BULLET) !== 0) fast = d2 > 0;
        else if (mode === 2) {
          const a = hw[i]!;
          const b = hh[i]!;
          const lim = (a < b ? a : b) + thin;
          fast = d2 > lim * lim;
        }
        if (fast && (f & SENSOR) === 0) {
          queue[queued++] = i;
          state[i] = WAITING;
          sweeps[i] = 1;
        }
      }
    }
    this.queueLength = queued;
    this.farCount = far;
    this.reach = Math.sqrt(reach2);
    this.sweptCount = 0;
    if (queued > 0) {
      this.def = def;
      this.solveQueue();
      this.def = null;
    }
  }

  /** Sweeps every queued body in queue order; bodies struck by a sweep join the queue. */
  private solveQueue(): void {
    let head = 0;
    while (head < this.queueLength) {
      const i = this.queue[head++]!;
      if (this.state[i] !== WAITING) continue;
      this.state[i] = SWEPT;
      this.sweptCount++;
      this.sweep(i, false);
      this.track(i);
    }
  }

  /** Whether a body moving at `(wx, wy)` needs sweeping under the world's ccd mode. */
  private isFast(j: number, wx: number, wy: number): boolean {
    const def = this.def!;
    const f = this.bodies.flags[j]!;
    const dt = def.timeStep;
    const d2 = (wx * wx + wy * wy) * dt * dt;
    if ((f & BULLET) !== 0) return d2 > 0;
    if (def.ccd !== 'auto') return false;
    const a = this.bodies.halfWidth[j]!;
    const b = this.bodies.halfHeight[j]!;
    const lim = (a < b ? a : b) + this.thinnest();
    return d2 > lim * lim;
  }

  /**
   * After body `j`'s path became final for this step: list it as far if the grid can no longer
   * find it. (A body still waiting for its own sweep needs no listing: its sweep comes later and
   * tests it against everyone that swept before.)
   */
  private track(j: number): void {
    if (this.isFar[j] === 1) return;
    const bodies = this.bodies;
    const ax = bodies.startX[j]!;
    const ay = bodies.startY[j]!;
    const r2 = this.reach * this.reach;
    const ex = bodies.x[j]! - ax;
    const ey = bodies.y[j]! - ay;
    const sx = bodies.pathStartX[j]! - ax;
    const sy = bodies.pathStartY[j]! - ay;
    if (ex * ex + ey * ey > r2 || sx * sx + sy * sy > r2) {
      this.isFar[j] = 1;
      this.farList[this.farCount++] = j;
    }
  }

  /**
   * Moves body `i` from its position at fraction `pathTime[i]` of the step to the end, stopping at
   * each time of impact (plus a quarter of the linear slop), responding, and sweeping the rest.
   * Keeps its path `pathStart → x` consistent when it changes its velocity, so later sweeps see
   * where it is at any time. With `wallsOnly`, only walls are hit.
   */
  private sweep(i: number, wallsOnly: boolean): void {
    const def = this.def!;
    const bodies = this.bodies;
    const grid = this.grid;
    const dt = def.timeStep;
    const x = bodies.x;
    const y = bodies.y;
    const pathStartX = bodies.pathStartX;
    const pathStartY = bodies.pathStartY;
    const vx = bodies.vx;
    const vy = bodies.vy;
    const flags = bodies.flags;
    const inverseMass = bodies.inverseMass;
    const overshoot = 0.25 * def.linearSlop;
    const ia = inverseMass[i]!;
    const isBox = (flags[i]! & BOX) !== 0;
    const wi = bodies.halfWidth[i]!;
    const hi = bodies.halfHeight[i]!;
    let t = this.pathTime[i]!;
    let px = pathStartX[i]! + t * (x[i]! - pathStartX[i]!);
    let py = pathStartY[i]! + t * (y[i]! - pathStartY[i]!);
    let ux = vx[i]!;
    let uy = vy[i]!;
    let frozen = false;
    let iteration = 0;
    // The path after the last hit is straight from `tLast`; that is what later sweeps see.
    let tLast = t;
    let lastX = px;
    let lastY = py;
    while (t < 1) {
      if (iteration === def.maxCcdIterations) {
        frozen = true;
        break;
      }
      iteration++;
      const rest = 1 - t;
      const dx = ux * dt * rest;
      const dy = uy * dt * rest;
      this.hitU = NO_HIT;
      this.hitBody = -1;
      const minX = (dx < 0 ? px + dx : px) - wi;
      const maxX = (dx < 0 ? px : px + dx) + wi;
      const minY = (dy < 0 ? py + dy : py) - hi;
      const maxY = (dy < 0 ? py : py + dy) + hi;

      this.qBox = isBox;
      this.qHalfWidth = wi;
      this.qHalfHeight = hi;
      this.qX = px;
      this.qY = py;
      this.qDx = dx;
      this.qDy = dy;
      this.qT = t;
      this.qRest = rest;
      this.qMinX = minX;
      this.qMinY = minY;
      this.qMaxX = maxX;
      this.qMaxY = maxY;
      if (ia > 0 && this.hitsWalls(i)) this.findWallHit();

      // Bodies whose path stays within `reach` of their grid position, through the grid…
      if (!wallsOnly && grid.cols > 0) {
        const margin = bodies.largestHalfExtent + this.reach + overshoot;
        const loX = minX - margin;
        const hiX = maxX + margin;
        const loY = minY - margin;
        const hiY = maxY + margin;
        const startX = bodies.startX;
        const startY = bodies.startY;
        const inv = grid.inverseCellSize;
        const c0 = clampInt(Math.floor((loX - grid.minX) * inv), 0, grid.cols - 1);
        const c1 = clampInt(Math.floor((hiX - grid.minX) * inv), 0, grid.cols - 1);
        const r0 = clampInt(Math.floor((loY - grid.minY) * inv), 0, grid.rows - 1);
        const r1 = clampInt(Math.floor((hiY - grid.minY) * inv), 0, grid.rows - 1);
        if ((c1 - c0 + 1) * (r1 - r0 + 1) > bodies.slotCount) {
          for (let j = 0; j < bodies.slotCount; j++) this.sweepAgainst(i, j);
        } else if (grid.hashed) {
          // The same cells in the same order, each from its bucket.
          const start = grid.cellStart;
          const items = grid.cellItems;
          const cellX = grid.cellX;
          const cellY = grid.cellY;
          const mask = grid.bucketMask;
          const cols = grid.cols;
          for (let r = r0; r <= r1; r++) {
            for (let c = c0; c <= c1; c++) {
              const b = bucketOf(c, r, cols, mask);
              const e = start[b + 1]!;
              for (let m = start[b]!; m < e; m++) {
                const j = items[m]!;
                if (cellX[j] !== c || cellY[j] !== r) continue;
                const ax = startX[j]!;
                const ay = startY[j]!;
                if (ax < loX || ax > hiX || ay < loY || ay > hiY) continue;
                this.sweepAgainst(i, j);
              }
            }
          }
        } else {
          const start = grid.cellStart;
          const items = grid.cellItems;
          const cols = grid.cols;
          for (let r = r0; r <= r1; r++) {
            const e = start[r * cols + c1 + 1]!;
            for (let m = start[r * cols + c0]!; m < e; m++) {
              const j = items[m]!;
              const ax = startX[j]!;
              const ay = startY[j]!;
              if (ax < loX || ax > hiX || ay < loY || ay > hiY) continue;
              this.sweepAgainst(i, j);
            }
          }
        }
      }
      // …and the far ones, one by one.
      for (let m = 0; !wallsOnly && m < this.farCount; m++) {
        this.sweepAgainst(i, this.farList[m]!);
      }

      const best = this.hitU;
      if (best > 1) {
        px += dx;
        py += dy;
        break;
      }
      let u = best + overshoot / this.hitLength;
      if (u > 1) u = 1;
      const nx = this.hitNx;
      const ny = this.hitNy;
      const j = this.hitBody;
      if (j >= 0 && !this.clearToWalls(j, t + rest * u)) continue; // j bounced first: look again
      px += dx * u;
      py += dy * u;
      t += rest * u;
      tLast = t;
      lastX = px;
      lastY = py;
      // The contact's material (material.ts): the world's unless a body has its own.
      const mixed = bodies.materialCount > 0;
      const threshold = def.restitutionThreshold;
      const e = !mixed
        ? def.restitution
        : mixRestitution(
            restitutionOf(bodies, def, i),
            j < 0 ? def.restitution : restitutionOf(bodies, def, j),
          );
      const mu = !mixed
        ? def.friction
        : mixFriction(
            frictionOf(bodies, def, i),
            j < 0 ? def.friction : frictionOf(bodies, def, j),
          );
      if (j < 0) {
        // A wall: bounce off its normal, friction along it.
        const vn = ux * nx + uy * ny;
        if (vn < 0) {
          const jn = -(1 + (-vn > threshold ? e : 0)) * vn;
          const vt = uy * nx - ux * ny;
          const maxFriction = mu * jn;
          const lt = -vt > maxFriction ? maxFriction : -vt < -maxFriction ? -maxFriction : -vt;
          ux += jn * nx - lt * ny;
          uy += jn * ny + lt * nx;
        }
      } else {
        // A body: one impulse between the two, then j gets a new path.
        if ((flags[j]! & ASLEEP) !== 0) wakeIsland(bodies, j);
        const ib = inverseMass[j]!;
        const qx = pathStartX[j]! + t * (x[j]! - pathStartX[j]!);
        const qy = pathStartY[j]! + t * (y[j]! - pathStartY[j]!);
        const relativeVx = ux - vx[j]!;
        const relativeVy = uy - vy[j]!;
        const vn = relativeVx * nx + relativeVy * ny;
        if (vn < 0) {
          const mass = 1 / (ia + ib);
          const pn = -(1 + (-vn > threshold ? e : 0)) * vn * mass;
          const vt = relativeVy * nx - relativeVx * ny;
          const maxFriction = mu * pn;
          let pt = -vt * mass;
          if (pt > maxFriction) pt = maxFriction;
          else if (pt < -maxFriction) pt = -maxFriction;
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
      pathStartX[i] = px;
      pathStartY[i] = py;
    } else {
      // A line through (lastX, lastY) at tLast with the final velocity.
      pathStartX[i] = lastX - tLast * dt * ux;
      pathStartY[i] = lastY - tLast * dt * uy;
    }
    this.pathTime[i] = tLast;
  }

  /** The earliest hit of the motion `q*` against the walls, into `hit*`. */
  private findWallHit(): void {
    const isBox = this.qBox;
    const wi = this.qHalfWidth;
    const hi = this.qHalfHeight;
    const px = this.qX;
    const py = this.qY;
    const dx = this.qDx;
    const dy = this.qDy;
    const minX = this.qMinX;
    const minY = this.qMinY;
    const maxX = this.qMaxX;
    const maxY = this.qMaxY;
    const out = this.toiOut;
    const statics = this.statics;
    for (let s = 0; s < statics.count; s++) {
      if (
        minX > statics.maxX[s]! ||
        maxX < statics.minX[s]! ||
        minY > statics.maxY[s]! ||
        maxY < statics.minY[s]!
      )
        continue;
      let touched: boolean;
      if (statics.kind[s] === SEGMENT) {
        const ax = statics.ax[s]!;
        const ay = statics.ay[s]!;
        const bx = statics.bx[s]!;
        const by = statics.by[s]!;
        touched = isBox
          ? hitBoxSegment(px, py, dx, dy, wi, hi, ax, ay, bx, by, out)
          : hitPointCapsule(px, py, dx, dy, ax, ay, bx, by, wi, out);
      } else {
        const rx = px - statics.centerX[s]!;
        const ry = py - statics.centerY[s]!;
        const bw = statics.halfWidth[s]!;
        const bh = statics.halfHeight[s]!;
        // A box sweeps a point against the box grown by its half extents; a circle against the
        // box rounded by its radius.
        touched = isBox
          ? hitPointRoundedBox(rx, ry, dx, dy, wi + bw, hi + bh, 0, out)
          : hitPointRoundedBox(rx, ry, dx, dy, bw, bh, wi, out);
      }
      const u = touched ? out[2]! : -1;
      if (u >= 0 && u < this.hitU) {
        this.hitU = u;
        this.hitBody = staticRef(s);
        this.hitNx = out[0]!;
        this.hitNy = out[1]!;
        this.hitLength = Math.sqrt(dx * dx + dy * dy);
      }
    }
  }

  /**
   * Before a sweep strikes body `j` at fraction `tHit`: if `j` is still waiting for its own
   * sweep, its motion up to `tHit` has not been checked. Check it against the walls; if `j` hits
   * one first, move it there, bounce it, and return false (the strike is void: look again).
   */
  private clearToWalls(j: number, tHit: number): boolean {
    const def = this.def!;
    const bodies = this.bodies;
    const t0 = this.pathTime[j]!;
    if (this.state[j] !== WAITING || bodies.inverseMass[j] === 0 || tHit <= t0) return true;
    if (!this.hitsWalls(j)) return true;
    const pathStartX = bodies.pathStartX;
    const pathStartY = bodies.pathStartY;
    const ex = bodies.x[j]! - pathStartX[j]!;
    const ey = bodies.y[j]! - pathStartY[j]!;
    const px = pathStartX[j]! + t0 * ex;
    const py = pathStartY[j]! + t0 * ey;
    const dx = ex * (tHit - t0);
    const dy = ey * (tHit - t0);
    const wj = bodies.halfWidth[j]!;
    const hj = bodies.halfHeight[j]!;
    this.hitU = NO_HIT;
    this.qBox = (bodies.flags[j]! & BOX) !== 0;
    this.qHalfWidth = wj;
    this.qHalfHeight = hj;
    this.qX = px;
    this.qY = py;
    this.qDx = dx;
    this.qDy = dy;
    this.qMinX = (dx < 0 ? px + dx : px) - wj;
    this.qMinY = (dy < 0 ? py + dy : py) - hj;
    this.qMaxX = (dx < 0 ? px : px + dx) + wj;
    this.qMaxY = (dy < 0 ? py : py + dy) + hj;
    this.findWallHit();
    if (this.hitU > 1) return true;
    let u = this.hitU + (0.25 * def.linearSlop) / this.hitLength;
    if (u > 1) u = 1;
    const t = t0 + (tHit - t0) * u;
    const qx = px + dx * u;
    const qy = py + dy * u;
    const nx = this.hitNx;
    const ny = this.hitNy;
    let ux = bodies.vx[j]!;
    let uy = bodies.vy[j]!;
    const vn = ux * nx + uy * ny;
    if (vn < 0) {
      const mixed = bodies.materialCount > 0;
      const e = mixed
        ? mixRestitution(restitutionOf(bodies, def, j), def.restitution)
        : def.restitution;
      const mu = mixed ? mixFriction(frictionOf(bodies, def, j), def.friction) : def.friction;
      const jn = -(1 + (-vn > def.restitutionThreshold ? e : 0)) * vn;
      const vt = uy * nx - ux * ny;
      const maxFriction = mu * jn;
      const lt = -vt > maxFriction ? maxFriction : -vt < -maxFriction ? -maxFriction : -vt;
      ux += jn * nx - lt * ny;
      uy += jn * ny + lt * nx;
    }
    const dt = def.timeStep;
    bodies.vx[j] = ux;
    bodies.vy[j] = uy;
    this.pathTime[j] = t;
    bodies.x[j] = qx + (1 - t) * dt * ux;
    bodies.y[j] = qy + (1 - t) * dt * uy;
    pathStartX[j] = qx - t * dt * ux;
    pathStartY[j] = qy - t * dt * uy;
    return false;
  }

  /**
   * Body `j` was struck at fraction `t` at `(qx, qy)` and now moves at `w`: re-plan its path, and
   * sweep it (again) if it is now fast and has sweeps left; a fast body out of sweeps stays where
   * it was struck for the rest of the step.
   */
  private replan(j: number, t: number, qx: number, qy: number, wx: number, wy: number): void {
    const dt = this.def!.timeStep;
    const bodies = this.bodies;
    const state = this.state[j]!;
    this.pathTime[j] = t;
    bodies.x[j] = qx + (1 - t) * dt * wx;
    bodies.y[j] = qy + (1 - t) * dt * wy;
    bodies.pathStartX[j] = qx - t * dt * wx;
    bodies.pathStartY[j] = qy - t * dt * wy;
    if (state === WAITING) return;
    if (this.isFast(j, wx, wy)) {
      if (this.sweeps[j]! < MAX_SWEEPS) {
        this.sweeps[j] = this.sweeps[j]! + 1;
        this.state[j] = WAITING;
        this.queue[this.queueLength++] = j;
        return;
      }
      bodies.x[j] = qx;
      bodies.y[j] = qy;
      bodies.pathStartX[j] = qx;
      bodies.pathStartY[j] = qy;
    } else {
      // Slow enough for the discrete solver against other bodies, but it may have been knocked
      // into a thin wall it was resting against: sweep it against the walls now.
      this.sweep(j, true);
    }
    this.track(j);
  }

  /** Whether body `i` may hit walls (`filter.ts`: not a sensor, a mask with the walls' bit). */
  private hitsWalls(i: number): boolean {
    const bodies = this.bodies;
    return bodies.filteredCount + bodies.sensorCount === 0 || collidesWithWalls(bodies, i);
  }

  /** Time of impact of body `i`'s motion `q*` against body `j`'s path, into `hit*`. */
  private sweepAgainst(i: number, j: number): void {
    if (j === i) return;
    const t = this.qT;
    const px = this.qX;
    const py = this.qY;
    const dx = this.qDx;
    const dy = this.qDy;
    const rest = this.qRest;
    const bodies = this.bodies;
    const fj = bodies.flags[j]!;
    if (fj === 0) return;
    const ia = bodies.inverseMass[i]!;
    const ib = bodies.inverseMass[j]!;
    if (ia === 0 && ib === 0) return;
    if (bodies.filteredCount + bodies.sensorCount > 0 && !bodiesCollide(bodies, i, j)) return;
    const pathStartX = bodies.pathStartX;
    const pathStartY = bodies.pathStartY;
    const pjx = bodies.x[j]! - pathStartX[j]!;
    const pjy = bodies.y[j]! - pathStartY[j]!;
    // j's path is valid from pathTime[j] (its last hit); start there if that is later than t.
    const tv = this.pathTime[j]!;
    let s0 = t;
    let f0 = 0;
    if (tv > t) {
      if (tv >= 1) return;
      s0 = tv;
      f0 = (tv - t) / rest;
    }
    const f1 = 1 - f0;
    // i relative to j: where it starts, and how it moves.
    const rx = px + f0 * dx - (pathStartX[j]! + s0 * pjx);
    const ry = py + f0 * dy - (pathStartY[j]! + s0 * pjy);
    const rdx = f1 * dx - pjx * (1 - s0);
    const rdy = f1 * dy - pjy * (1 - s0);
    const fi = bodies.flags[i]!;
    const wi = bodies.halfWidth[i]!;
    const hi = bodies.halfHeight[i]!;
    const wj = bodies.halfWidth[j]!;
    const hj = bodies.halfHeight[j]!;
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
      this.hitLength = Math.sqrt(rdx * rdx + rdy * rdy) / f1;
    }
  }

  /**
   * The safety net under continuous detection: a body whose centre crossed a wall's spine this
   * step (the segment itself, or a box's long midline) is put back just on the side it started
   * from, where the next step's push-out takes it out through the near face. Under `'bullets'`
   * (`all` false) only bullets are guarded. One bounding-box test per body and wall; the exact
   * test only near walls.
   */
  guardWalls(all: boolean): void {
    const bodies = this.bodies;
    const n = bodies.slotCount;
    const grid = this.grid;
    if (!grid.wallMarks) {
      for (let i = 0; i < n; i++) this.guardBody(i, all);
      return;
    }
    // A body that starts in a cell far from every wall and moves at most a cell along each axis
    // cannot cross one (Grid.markWalls): the bodies in marked cells first, then those of the
    // others that moved further (each body is guarded on its own, so the order changes nothing).
    const list = grid.nearWallBodies;
    const near = grid.nearWallCount;
    for (let k = 0; k < near; k++) this.guardBody(list[k]!, all);
    const x = bodies.x;
    const y = bodies.y;
    const startX = bodies.startX;
    const startY = bodies.startY;
    const nearWall = grid.nearWall;
    const cellOf = grid.cellOf;
    const cell = grid.cellSize;
    for (let i = 0; i < n; i++) {
      const dx = x[i]! - startX[i]!;
      const dy = y[i]! - startY[i]!;
      if (dx <= cell && dx >= -cell && dy <= cell && dy >= -cell) continue;
      const c = cellOf[i]!;
      if (c >= 0 && nearWall[c] === 0) this.guardBody(i, all);
    }
  }

  /** {@link guardWalls} for body `i`. */
  private guardBody(i: number, all: boolean): void {
    const bodies = this.bodies;
    const f = bodies.flags[i]!;
    if (f === 0 || bodies.inverseMass[i] === 0 || (!all && (f & BULLET) === 0)) return;
    if (!this.hitsWalls(i)) return;
    const statics = this.statics;
    const x = bodies.x;
    const y = bodies.y;
    const kind = statics.kind;
    const wallMinX = statics.minX;
    const wallMinY = statics.minY;
    const wallMaxX = statics.maxX;
    const wallMaxY = statics.maxY;
    const centerX = statics.centerX;
    const centerY = statics.centerY;
    const halfWidth = statics.halfWidth;
    const halfHeight = statics.halfHeight;
    const wallCount = statics.count;
    const p0x = bodies.startX[i]!;
    const p0y = bodies.startY[i]!;
    let p1x = x[i]!;
    let p1y = y[i]!;
    // The path's bounding box, made again only when a wall moves the end.
    let loX = p0x < p1x ? p0x : p1x;
    let hiX = p0x < p1x ? p1x : p0x;
    let loY = p0y < p1y ? p0y : p1y;
    let hiY = p0y < p1y ? p1y : p0y;
    for (let s = 0; s < wallCount; s++) {
      if (loX > wallMaxX[s]! || hiX < wallMinX[s]! || loY > wallMaxY[s]! || hiY < wallMinY[s]!)
        continue;
      // The wall's spine from (ax, ay) to (bx, by).
      let ax: number;
      let ay: number;
      let bx: number;
      let by: number;
      if (kind[s] === SEGMENT) {
        ax = statics.ax[s]!;
        ay = statics.ay[s]!;
        bx = statics.bx[s]!;
        by = statics.by[s]!;
      } else if (halfWidth[s]! >= halfHeight[s]!) {
        ax = centerX[s]! - halfWidth[s]!;
        bx = centerX[s]! + halfWidth[s]!;
        ay = centerY[s]!;
        by = ay;
      } else {
        ay = centerY[s]! - halfHeight[s]!;
        by = centerY[s]! + halfHeight[s]!;
        ax = centerX[s]!;
        bx = ax;
      }
      const ex = bx - ax;
      const ey = by - ay;
      // Which side of the spine the path starts and ends on…
      const side0 = ex * (p0y - ay) - ey * (p0x - ax);
      const side1 = ex * (p1y - ay) - ey * (p1x - ax);
      if (side0 === 0 || (side0 > 0 ? side1 > 0 : side1 < 0)) continue; // on it, or same side
      // …and whether the path passes between the spine's ends.
      const mx = p1x - p0x;
      const my = p1y - p0y;
      const endA = mx * (ay - p0y) - my * (ax - p0x);
      const endB = mx * (by - p0y) - my * (bx - p0x);
      if ((endA > 0 && endB > 0) || (endA < 0 && endB < 0)) continue; // passed beside it
      // Back to where the path meets the spine, then a hair onto the starting side.
      const u = side0 / (side0 - side1);
      const len = Math.sqrt(ex * ex + ey * ey);
      const side = side0 > 0 ? 1 : -1;
      const eps = 1e-9 + 1e-12 * (Math.abs(ax) + Math.abs(ay));
      p1x = p0x + u * mx - (side * ey * eps) / len;
      p1y = p0y + u * my + (side * ex * eps) / len;
      x[i] = p1x;
      y[i] = p1y;
      loX = p0x < p1x ? p0x : p1x;
      hiX = p0x < p1x ? p1x : p0x;
      loY = p0y < p1y ? p0y : p1y;
      hiY = p0y < p1y ? p1y : p0y;
    }
  }
}
