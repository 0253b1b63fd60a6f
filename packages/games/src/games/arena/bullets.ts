import type { ByteReader, ByteWriter } from 'fixedstep';
import { SWEPT, pointCircle as pointCircle_, sweptRegisters } from './swept.js';
import { isFiniteNumber } from './motion.js';
import type { Walls } from './walls.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const pointCircle = pointCircle_;
/** Where the swept test writes the fraction of a hit. */
const U = SWEPT.u;
/** The swept test's registers (see `swept.ts`); never part of any state. */
const reg = sweptRegisters();
/** Scratch: the targets a bullet's move can hit (grown on demand); never part of any state. */
let near = new Int32Array(16);

/**
 * What bullets can hit besides walls: circles in structure-of-arrays form (players in capture the
 * flag, enemies in survival). The game decides, per bullet and target, whether they can meet,
 * and what a hit does.
 */
export interface BulletTargets {
  /** Number of target slots (iterated in index order). */
  readonly targetCount: number;
  readonly targetX: Float64Array;
  readonly targetY: Float64Array;
  /** Radius of every target, arena units. */
  readonly targetRadius: number;
  /**
   * Optional: the only targets that can be hit during this {@link Bullets.advance}, in increasing
   * index order (`targetList[0 … targetListCount − 1]`; may include some that cannot). Absent:
   * every slot. A pool of mostly empty slots (survival's enemies) saves visiting them all.
   */
  readonly targetList?: Int32Array;
  readonly targetListCount?: number;
  /** Whether bullet `b` can hit target `t` now (alive, not a teammate …). */
  canHit(b: number, t: number): boolean;
  /** Bullet `b` hit target `t`. The bullet is removed right after. */
  hit(b: number, t: number): void;
}

/**
 * A fixed-capacity pool of bullets (small circles flying straight), structure of arrays. A new
 * bullet takes the lowest free slot, a removed bullet's slot is zeroed, slots are visited in
 * index order: the state depends only on what is where, never on history, and a step allocates
 * nothing.
 */
export class Bullets {
  readonly capacity: number;
  /** 1 while the slot holds a bullet. */
  readonly alive: Uint8Array;
  /** The slot of the player who fired it. */
  readonly owner: Uint8Array;
  /** The shooter's team (0 or 1; 0 in survival). */
  readonly team: Uint8Array;
  /** A number unique to each bullet fired in a game (for the renderer and for tests). */
  readonly serial: Uint32Array;
  /** Position (arena units) and velocity (units per second). */
  readonly x: Float64Array;
  readonly y: Float64Array;
  readonly vx: Float64Array;
  readonly vy: Float64Array;
  /** Seconds left before it fades out. */
  readonly life: Float64Array;
  /** Position before the last step or update: for render interpolation; not part of the state. */
  readonly prevX: Float64Array;
  readonly prevY: Float64Array;
  /** Bullet radius, arena units. */
  readonly radius: number;
  /**
   * The registers of {@link spawnLaunched}: x, y (arena units), vx, vy (units per second), life
   * (seconds). Scratch, never part of any state.
   */
  readonly launch = new Float64Array(5);
  /** Number of live bullets. */
  live = 0;
  /** One past the highest slot that may hold a bullet (slots from here on are empty). Not state. */
  private end = 0;
  /** The serial the next bullet gets. */
  nextSerial = 1;
  /** Bullets that went through a wall (their path crossed a wall and they flew on): a diagnostic, part of the state. */
  throughWalls = 0;

  constructor(capacity: number, radius: number) {
    this.capacity = capacity;
    this.radius = radius;
    this.alive = new Uint8Array(capacity);
    this.owner = new Uint8Array(capacity);
    this.team = new Uint8Array(capacity);
    this.serial = new Uint32Array(capacity);
    this.x = new Float64Array(capacity);
    this.y = new Float64Array(capacity);
    this.vx = new Float64Array(capacity);
    this.vy = new Float64Array(capacity);
    this.life = new Float64Array(capacity);
    this.prevX = new Float64Array(capacity);
    this.prevY = new Float64Array(capacity);
  }

  /** Fire a bullet; returns its slot, or -1 if the pool is full (the shot is lost). */
  spawn(
    owner: number,
    team: number,
    x: number,
    y: number,
    vx: number,
    vy: number,
    life: number,
  ): number {
    const l = this.launch;
    l[0] = x;
    l[1] = y;
    l[2] = vx;
    l[3] = vy;
    l[4] = life;
    return this.spawnLaunched(owner, team);
  }

  /**
   * {@link spawn} of the bullet in {@link launch}: its register form (the games fire through it,
   * so no fractional number crosses a call: V8 would box it).
   */
  spawnLaunched(owner: number, team: number): number {
    const l = this.launch;
    for (let i = 0; i < this.capacity; i++) {
      if (this.alive[i] !== 0) continue;
      const x = l[0]!;
      const y = l[1]!;
      this.alive[i] = 1;
      this.owner[i] = owner;
      this.team[i] = team;
      this.serial[i] = this.nextSerial;
      this.nextSerial = (this.nextSerial + 1) >>> 0;
      this.x[i] = x;
      this.y[i] = y;
      this.prevX[i] = x;
      this.prevY[i] = y;
      this.vx[i] = l[2]!;
      this.vy[i] = l[3]!;
      this.life[i] = l[4]!;
      this.live++;
      if (i >= this.end) this.end = i + 1;
      return i;
    }
    return -1;
  }

  /** Remove bullet `i` (zeroing its slot, so equal states stay equal bytes). */
  remove(i: number): void {
    if (this.alive[i] === 0) return;
    this.alive[i] = 0;
    this.owner[i] = 0;
    this.team[i] = 0;
    this.serial[i] = 0;
    this.x[i] = 0;
    this.y[i] = 0;
    this.vx[i] = 0;
    this.vy[i] = 0;
    this.life[i] = 0;
    this.live--;
    while (this.end > 0 && this.alive[this.end - 1] === 0) this.end--;
  }

  /**
   * Move every bullet by `dt` seconds and collide it with `walls` and `targets`.
   *
   * - `continuous` (continuous collision detection): the whole move is swept (`Walls.sweep`, the library's `hitPointCircle`) and
   *   the bullet stops at the earliest impact — nothing passes through anything, at any speed.
   * - otherwise (discrete, the talk's naive game): the bullet jumps to its new position and only overlaps there
   *   count. A bullet that jumps over a wall (its move is longer than the wall's thickness plus
   *   its diameter) flies on: counted in {@link throughWalls}.
   *
   * Targets are taken where they are now (they move first and are much slower).
   */
  advance(dt: number, walls: Walls, targets: BulletTargets, continuous: boolean): void {
    const r = this.radius;
    const tr = targets.targetRadius + r;
    // How far from a move a target's centre must be for no test to hit it (the slack: far more
    // than any rounding): such targets are passed over before asking `canHit` — it changes nothing.
    const reach = tr + 1;
    const targetX = targets.targetX;
    const targetY = targets.targetY;
    const list = targets.targetList;
    const q = walls.query;
    const listed = list === undefined ? targets.targetCount : (targets.targetListCount ?? 0);
    if (near.length < listed) near = new Int32Array(listed);
    const candidates = near;
    for (let b = 0; b < this.end; b++) {
      if (this.alive[b] === 0) continue;
      const x = this.x[b]!;
      const y = this.y[b]!;
      this.prevX[b] = x;
      this.prevY[b] = y;
      const dx = this.vx[b]! * dt;
      const dy = this.vy[b]! * dt;
      const minX = (dx < 0 ? x + dx : x) - reach;
      const maxX = (dx < 0 ? x : x + dx) + reach;
      const minY = (dy < 0 ? y + dy : y) - reach;
      const maxY = (dy < 0 ? y : y + dy) + reach;
      // The targets it can hit whose centres are near its move, in index order: the only ones
      // the tests below need to see.
      let m = 0;
      for (let k = 0; k < listed; k++) {
        const t = list === undefined ? k : list[k]!;
        const tx = targetX[t]!;
        const ty = targetY[t]!;
        if (tx < minX || tx > maxX || ty < minY || ty > maxY) continue;
        if (targets.canHit(b, t)) candidates[m++] = t;
      }
      let u = 1;
      let hitWall = false;
      let hitTarget = -1;
      if (continuous) {
        // (The walls' register forms: see `Walls`.)
        q[0] = x;
        q[1] = y;
        q[2] = dx;
        q[3] = dy;
        if (walls.sweepQuery(r)) {
          u = q[4]!;
          hitWall = true;
        }
        for (let j = 0; j < m; j++) {
          const t = candidates[j]!;
          const px = x - targetX[t]!;
          const py = y - targetY[t]!;
          // A bullet that starts inside a target (fired point-blank) hits it at once, whichever
          // way it flies; otherwise the swept test.
          let ut = 0;
          if (px * px + py * py >= tr * tr) {
            reg[0] = px;
            reg[1] = py;
            reg[2] = dx;
            reg[3] = dy;
            reg[6] = tr;
            ut = pointCircle(reg) ? reg[U]! : -1;
          }
          if (ut >= 0 && ut < u) {
            u = ut;
            hitWall = false;
            hitTarget = t;
          }
        }
      } else {
        const nx = x + dx;
        const ny = y + dy;
        q[0] = nx;
        q[1] = ny;
        if (walls.overlapsQuery(r)) hitWall = true;
        else {
          for (let j = 0; j < m; j++) {
            const t = candidates[j]!;
            const ex = nx - targetX[t]!;
            const ey = ny - targetY[t]!;
            if (ex * ex + ey * ey < tr * tr) {
              hitTarget = t;
              break;
            }
          }
        }
      }
      const ex = x + u * dx;
      const ey = y + u * dy;
      // The diagnostic: a bullet that no wall stopped but whose path met a wall went through it.
      q[0] = x;
      q[1] = y;
      q[2] = ex;
      q[3] = ey;
      if (!hitWall && walls.crossesQuery()) this.throughWalls++;
      this.x[b] = ex;
      this.y[b] = ey;
      if (hitWall) {
        this.remove(b);
        continue;
      }
      if (hitTarget >= 0) {
        targets.hit(b, hitTarget);
        this.remove(b);
        continue;
      }
      const life = this.life[b]! - dt;
      if (life <= 0) this.remove(b);
      else this.life[b] = life;
    }
  }

  /** Write the pool (every slot, in order) as canonical bytes. */
  write(w: ByteWriter): void {
    w.u32(this.nextSerial).u32(this.throughWalls);
    w.ints(this.alive).ints(this.owner).ints(this.team).ints(this.serial);
    w.f64s(this.x).f64s(this.y).f64s(this.vx).f64s(this.vy).f64s(this.life);
  }

  /**
   * Read what {@link write} wrote into this pool, validating it: throws a RangeError (naming what
   * is wrong) on a slot that is neither empty nor a finite bullet, or a bad owner/team. Call on a
   * scratch pool: on a throw the pool is left half read.
   */
  read(r: ByteReader, maxOwner: number, maxTeam: number): void {
    this.nextSerial = r.u32();
    this.throughWalls = r.u32();
    r.ints(this.alive);
    r.ints(this.owner);
    r.ints(this.team);
    r.ints(this.serial);
    r.f64s(this.x);
    r.f64s(this.y);
    r.f64s(this.vx);
    r.f64s(this.vy);
    r.f64s(this.life);
    let live = 0;
    for (let i = 0; i < this.capacity; i++) {
      const a = this.alive[i]!;
      if (a > 1) throw new RangeError(`bullet ${i}: alive flag ${a}`);
      if (a === 0) {
        if (
          this.owner[i] !== 0 ||
          this.team[i] !== 0 ||
          this.serial[i] !== 0 ||
          this.x[i] !== 0 ||
          this.y[i] !== 0 ||
          this.vx[i] !== 0 ||
          this.vy[i] !== 0 ||
          this.life[i] !== 0
        ) {
          throw new RangeError(`bullet ${i}: an empty slot that is not zeroed`);
        }
        continue;
      }
      live++;
      if (this.owner[i]! > maxOwner) throw new RangeError(`bullet ${i}: owner ${this.owner[i]}`);
      if (this.team[i]! > maxTeam) throw new RangeError(`bullet ${i}: team ${this.team[i]}`);
      if (
        !isFiniteNumber(this.x[i]!) ||
        !isFiniteNumber(this.y[i]!) ||
        !isFiniteNumber(this.vx[i]!) ||
        !isFiniteNumber(this.vy[i]!) ||
        !(this.life[i]! > 0 && isFiniteNumber(this.life[i]!))
      ) {
        throw new RangeError(`bullet ${i}: a position, velocity or life that is not finite`);
      }
    }
    this.live = live;
    this.prevX.set(this.x);
    this.prevY.set(this.y);
    this.end = this.capacity;
    while (this.end > 0 && this.alive[this.end - 1] === 0) this.end--;
  }

  /** Copy another pool of the same capacity into this one. */
  copyFrom(o: Bullets): void {
    this.alive.set(o.alive);
    this.owner.set(o.owner);
    this.team.set(o.team);
    this.serial.set(o.serial);
    this.x.set(o.x);
    this.y.set(o.y);
    this.vx.set(o.vx);
    this.vy.set(o.vy);
    this.life.set(o.life);
    this.prevX.set(o.prevX);
    this.prevY.set(o.prevY);
    this.live = o.live;
    this.end = o.end;
    this.nextSerial = o.nextSerial;
    this.throughWalls = o.throughWalls;
  }
}
