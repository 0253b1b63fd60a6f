/**
 * The talk's rule of thumb for walls, `minWallSize = maxObjectSpeed × TIMESTEP`, and what it
 * actually guarantees.
 *
 * With discrete detection a body moving at `v` jumps `v·dt` per step. If the wall is at least that
 * thick, the body cannot jump over it unseen — the overlap is always *detected*. But the response
 * is a minimum-translation push-out, which leaves through the *nearer* face: a body that has already
 * passed the middle of the wall is pushed out on the far side. A body of radius `r` overlaps a wall
 * of thickness `w` while its centre is in a zone `w + 2r` wide; the first overlapping position is
 * uniform over one step `v·dt`; it bounces only if that position is in the first half of the zone.
 * So a correct bounce needs `v·dt ≤ w/2 + r`, and with a uniformly random phase the share of bodies
 * ending on the far side is `max(0, 1 − (w + 2r) / (2·v·dt))` — one third of them when `w = v·dt`
 * exactly and `r` is small next to `w`.
 */
import { BodyFlag, type BodyStore } from './body.js';
import type { WorldDef } from './def.js';
import type { StaticStore } from './statics.js';

const { KINEMATIC } = BodyFlag;

/**
 * The talk's rule: the thinnest wall that a body at `maxSpeed` (m/s) cannot jump over in one step
 * of `dt` seconds, `maxSpeed × dt` metres. It guarantees *detection* only; for a correct bounce see
 * {@link maxSafeSpeed}.
 */
export function minWallSize(maxSpeed: number, dt: number): number {
  return maxSpeed * dt;
}

/**
 * The fastest speed (m/s) at which a body of radius `radius` (its smallest half extent for a box)
 * always bounces off a wall `wallThickness` metres thick under discrete detection with a step of
 * `dt` seconds: `(wallThickness / 2 + radius) / dt`. Above it, some phases push the body out through
 * the far face (see {@link tunnellingShare}). For a point body this is half the talk's speed.
 */
export function maxSafeSpeed(wallThickness: number, radius: number, dt: number): number {
  return (wallThickness / 2 + radius) / dt;
}

/**
 * The share of bodies, over uniformly random starting phases, that end on the far side of a wall
 * under discrete detection with minimum-translation push-out:
 * `max(0, 1 − (wallThickness + 2·radius) / (2·speed·dt))`.
 */
export function tunnellingShare(
  speed: number,
  wallThickness: number,
  radius: number,
  dt: number,
): number {
  const d = speed * dt;
  if (!(d > 0)) return 0;
  const share = 1 - (wallThickness + 2 * radius) / (2 * d);
  return share > 0 ? share : 0;
}

/** One static wall that the current velocities put at risk. */
export interface TunnellingWarning {
  /**
   * `'talk-rule'`: the wall is thinner than the fastest non-CCD body's `speed × dt` (the talk's
   * rule is broken). `'push-through'`: the talk's rule holds, but some body moves more than
   * `wallThickness / 2 + radius` per step, so the push-out can still send it through.
   */
  kind: 'talk-rule' | 'push-through';
  /** The static shape's id. */
  staticId: number;
  /** The wall's thickness: 0 for a segment, the smaller full extent for a static box. Metres. */
  wallThickness: number;
  /** The body that breaks the rule: the fastest one for `'talk-rule'`, the worst one otherwise. */
  bodyId: number;
  /** Its speed. Metres per second. */
  speed: number;
  /** Its radius (smallest half extent for a box). Metres. */
  radius: number;
  /** `speed × dt`: how far it moves in one step. Metres. */
  stepDistance: number;
  /** Whether some body can actually end up on the far side (`speed·dt > wallThickness/2 + radius`). */
  canTunnel: boolean;
  /** {@link tunnellingShare} for the named body. */
  share: number;
  /** A sentence for a log. */
  message: string;
}

/** The world's {@link PhysicsWorld.tunnellingWarnings}: the talk's rule checked on a scene. */
export function checkTunnellingRule(world: {
  tunnellingWarnings(): TunnellingWarning[];
}): TunnellingWarning[] {
  return world.tunnellingWarnings();
}

/**
 * The rule checked against a world's current velocities (what {@link PhysicsWorld.tunnellingWarnings}
 * and the {@link PhysicsWorld.onTunnellingWarning} hook report). Reads the world, never writes it.
 */
export class RuleCheck {
  /** Whether the last step ended with a body able to pass through a wall (for the hook). */
  wasBroken = false;
  // Over bodies that collide and are not swept: the fastest step distance and its body, and the
  // largest `step − radius` and its body.
  private fastest = 0;
  private fastestId = -1;
  private excess = -Infinity;
  private excessId = -1;

  constructor(
    private readonly bodies: BodyStore,
    private readonly statics: StaticStore,
    private readonly wouldSweep: (id: number) => boolean,
  ) {}

  private measure(dt: number): void {
    const b = this.bodies;
    this.fastest = 0;
    this.fastestId = -1;
    this.excess = -Infinity;
    this.excessId = -1;
    for (let i = 0; i < b.slotCount; i++) {
      const f = b.flags[i]!;
      if (f === 0 || (f & KINEMATIC) !== 0 || this.wouldSweep(i)) continue;
      const ux = b.vx[i]!;
      const uy = b.vy[i]!;
      const d = Math.sqrt(ux * ux + uy * uy) * dt;
      if (d > this.fastest) {
        this.fastest = d;
        this.fastestId = i;
      }
      const e = d - Math.min(b.halfWidth[i]!, b.halfHeight[i]!);
      if (d > 0 && e > this.excess) {
        this.excess = e;
        this.excessId = i;
      }
    }
  }

  /** One warning per wall at risk (see {@link PhysicsWorld.tunnellingWarnings}). Allocates. */
  warnings(def: Readonly<WorldDef>): TunnellingWarning[] {
    this.measure(def.timeStep);
    const b = this.bodies;
    const out: TunnellingWarning[] = [];
    const dt = def.timeStep;
    const fastD = this.fastest;
    const excess = this.excess;
    for (let s = 0; s < this.statics.count; s++) {
      const w = this.statics.thickness(s);
      let kind: TunnellingWarning['kind'];
      let id: number;
      if (fastD > w) {
        kind = 'talk-rule';
        id = this.fastestId;
      } else if (excess > w / 2) {
        kind = 'push-through';
        id = this.excessId;
      } else continue;
      const ux = b.vx[id]!;
      const uy = b.vy[id]!;
      const speed = Math.sqrt(ux * ux + uy * uy);
      const radius = Math.min(b.halfWidth[id]!, b.halfHeight[id]!);
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

  /**
   * After a step: calls `hook` with the walls bodies can now pass through, when the scene starts
   * breaking the rule (not again until it has been safe for a step).
   */
  afterStep(def: Readonly<WorldDef>, hook: (warnings: TunnellingWarning[]) => void): void {
    this.measure(def.timeStep);
    let thinnest = Infinity;
    for (let s = 0; s < this.statics.count; s++)
      thinnest = Math.min(thinnest, this.statics.thickness(s));
    const broken = this.excess > thinnest / 2;
    if (broken && !this.wasBroken) hook(this.warnings(def).filter((w) => w.canTunnel));
    this.wasBroken = broken;
  }
}
