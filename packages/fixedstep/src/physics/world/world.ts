import { fnv1a64 } from '../../det/hash.js';
import type { Simulation } from '../../sim/simulation.js';
import { BodyFlag, BodyStore, WORLD_MATERIAL } from './body.js';
import { Grid, findContacts } from './broad-phase.js';
import { ContinuousSolver } from './ccd.js';
import { SolverSchedule, solvePositions, solveVelocities } from './contact-solver.js';
import { ContactList, ContactOverflow, WarmStartCache } from './contacts.js';
import {
  ContactEvents,
  SensorOverlaps,
  type ContactEvent,
  type SensorEvent,
  type StepEvents,
} from './events.js';
import { checkFilter, defaultFilter, filterContacts, type BodyFilter } from './filter.js';
import {
  defaultWorldDef,
  type BodyOptions,
  type BoxOptions,
  type CircleOptions,
  type Exact,
  type WorldDef,
} from './def.js';
import { Islands, WakeLog, wakeByNewContacts, wakeIsland } from './island.js';
import { QueryIndex, type QueryFilter, type RayFilter, type RayHit } from './queries.js';
import { RuleCheck, type TunnellingWarning } from './rule.js';
import {
  SnapshotReader,
  SnapshotWriter,
  needsVersion2,
  snapshotSize,
  writeCanonical,
  type WorldState,
} from './snapshot.js';
import { StaticStore, WallKind } from './statics.js';
import {
  BOX_KEYS,
  CIRCLE_KEYS,
  WORLD_LIMITS,
  checkCoordinate,
  checkDef,
  checkDefKeys,
  checkDensity,
  checkFlag,
  checkFriction,
  checkKeys,
  checkLinearDamping,
  checkRestitution,
  checkSize,
  checkSpeed,
  checkWallExtent,
  show,
} from './validate.js';
import type { ByteWriter } from '../../det/bytes.js';

const { ALIVE, ASLEEP, BOX, BULLET, KINEMATIC, SENSOR } = BodyFlag;
const { SEGMENT, BOX: STATIC_BOX } = WallKind;
const DEFAULT_FILTER: Readonly<BodyFilter> = Object.freeze(defaultFilter());

/** A static wall, as returned by {@link PhysicsWorld.getStatic}. */
export type StaticShape =
  | { kind: 'segment'; ax: number; ay: number; bx: number; by: number }
  | { kind: 'box'; x: number; y: number; halfWidth: number; halfHeight: number };

/** Options of the {@link PhysicsWorld} object itself (not simulation state). */
export interface WorldOptions {
  /**
   * Bodies to preallocate room for; the arrays double when full. An integer from 1 to
   * `WORLD_LIMITS.maxCapacity` (at least 16 are allocated). Default 256.
   */
  capacity?: number;
  /**
   * Compute contact begin/end events every step ({@link PhysicsWorld.contactEvents}). Default
   * false: they cost a pass over the contacts and the warm-start cache per step (about 3 % of a
   * 2,000-body pile's step). Not part of the state: the events are a function of the state, so
   * switching them on changes no result.
   */
  contactEvents?: boolean;
}

/**
 * A 2D world of dynamic circles and axis-aligned boxes (no rotation, by design: the talk's arcade
 * world) against static segments and boxes, stepped with a fixed step; a deterministic
 * {@link Simulation}. For rotation, polygons and joints use a Rapier world.
 *
 * **Layout.** Bodies live in preallocated typed arrays (structure of arrays), indexed by body id;
 * a step allocates nothing. Read them directly to render: {@link x}, {@link y}, {@link vx},
 * {@link vy}, {@link halfWidth}, {@link halfHeight} (a circle's radius is its half width), for ids
 * below {@link slotCount} where {@link isAlive}. Re-read the getters after creating bodies or
 * loading: the arrays are replaced when they grow. The arrays are for reading: change bodies
 * through {@link setPosition}, {@link setVelocity} and {@link applyImpulse}, which check the
 * values (a value written straight into an array is not checked). Changing bodies between steps is
 * allowed and deterministic.
 *
 * **Checked input.** Every mutator, the constructor, {@link setDef} and {@link load} refuse a bad
 * value — not finite, out of `WORLD_LIMITS`, an option the world does not know — with an Error
 * naming the method, the body, the field and the value, before changing anything. The def is
 * frozen: change it with {@link setDef}.
 *
 * **A step** (one call of {@link step}), one file per stage:
 * 1. broad phase (`broad-phase.ts`): a uniform grid rebuilt from scratch, pairs in cell order then
 *    id order — a function of the current state only, never of its history;
 * 2. narrow phase (`manifold.ts`): one contact per overlapping pair *at the start of the step*
 *    (it reads positions only, so it can run before gravity: a step that must throw has changed
 *    nothing yet); a contact that is new touches sleeping bodies awake;
 * 3. gravity into velocities (semi-implicit Euler), then sequential impulses
 *    (`contact-solver.ts`), warm-started from last step (`contacts.ts`);
 * 4. move by `v·dt` — or, for bodies that could pass through something (see
 *    {@link WorldDef.ccd}), *sweep* (`ccd.ts`);
 * 5. relaxation of positions (`contact-solver.ts`), walls last; then, under CCD, a guard puts back
 *    any body whose centre crossed a wall;
 * 6. islands that have rested long enough fall asleep (`island.ts`).
 *
 * A body that first overlaps a wall is pushed out through the *nearer* face, exactly as in the
 * talk's discrete model, so with `ccd: 'off'` a share `max(0, 1 − (w + 2r) / (2·v·dt))` of bodies
 * tunnels (see {@link tunnellingShare}); with CCD none does.
 *
 * **State** ({@link save}, `snapshot.ts`): the tick, the def, the walls, every body slot in use
 * (flags, position, velocity, size, inverse mass, rest time, island) and the warm-start cache.
 * Nothing else survives a step.
 */
export class PhysicsWorld implements Simulation<unknown> {
  /**
   * Called at the end of a step when the scene starts breaking the tunnelling rule in a way that
   * can let a body through a static wall (a {@link TunnellingWarning} with `canTunnel`), and
   * again only after the scene has been safe for a step. Not part of the state; it must not
   * change the world if you want replays to match runs without it.
   */
  onTunnellingWarning: ((warnings: TunnellingWarning[]) => void) | null = null;

  private _def: Readonly<WorldDef>;
  private _tick = 0;
  private readonly bodies = new BodyStore();
  private readonly statics = new StaticStore(8);
  private readonly grid = new Grid();
  private readonly contacts = new ContactList();
  private readonly cache = new WarmStartCache();
  private readonly schedule = new SolverSchedule();
  private readonly islands = new Islands();
  private readonly wakeLog = new WakeLog();
  private readonly ccd: ContinuousSolver;
  private readonly rule: RuleCheck;
  private readonly writer = new SnapshotWriter();
  private readonly reader = new SnapshotReader();
  private hashBuffer = new Uint8Array(4096);
  private readonly queries = new QueryIndex(this.bodies, this.statics);
  private readonly overlaps = new SensorOverlaps();
  private readonly contactLog = new ContactEvents();
  private readonly contactEventsOn: boolean;

  /**
   * A world from a (partial) def; missing fields take {@link defaultWorldDef}'s values. Throws a
   * RangeError (TypeError for a wrong type or an unknown field) naming a bad field.
   */
  constructor(def: Partial<WorldDef> = {}, options: WorldOptions = {}) {
    checkDefKeys('new PhysicsWorld', def);
    this._def = checkDef('new PhysicsWorld', { ...defaultWorldDef(), ...def });
    if (typeof options !== 'object')
      throw new TypeError('new PhysicsWorld: options must be an object');
    for (const key in options) {
      if (key !== 'capacity' && key !== 'contactEvents')
        throw new TypeError(
          `new PhysicsWorld: unknown option "${key}"; the options are capacity, contactEvents`,
        );
    }
    const contactEvents: unknown = options.contactEvents ?? false;
    if (typeof contactEvents !== 'boolean')
      throw new TypeError(
        `new PhysicsWorld: contactEvents must be true or false, got ${show(contactEvents)}`,
      );
    this.contactEventsOn = contactEvents;
    const capacity: unknown = options.capacity ?? 256;
    if (!(
      typeof capacity === 'number' &&
      Number.isInteger(capacity) &&
      capacity >= 1 &&
      capacity <= WORLD_LIMITS.maxCapacity
    ))
      throw new RangeError(
        `new PhysicsWorld: capacity must be an integer from 1 to ${WORLD_LIMITS.maxCapacity}, got ${show(capacity)}`,
      );
    this.ccd = new ContinuousSolver(this.bodies, this.statics, this.grid);
    this.rule = new RuleCheck(this.bodies, this.statics, (id) =>
      this.ccd.wouldSweep(id, this._def),
    );
    this.contacts.setLimit(this._def.maxContacts);
    this.grow(Math.max(16, capacity));
  }

  // ---------------------------------------------------------------- reading

  /**
   * The configuration, frozen (assigning a field throws a TypeError). Part of the state (but
   * `maxContacts`); change it between steps with {@link setDef}.
   */
  get def(): Readonly<WorldDef> {
    return this._def;
  }
  /** Ticks stepped so far. Simulated time is `tick × def.timeStep`. */
  get tick(): number {
    return this._tick;
  }
  /** Live bodies. */
  get bodyCount(): number {
    return this.bodies.liveCount;
  }
  /** One past the highest live body id: iterate `0 ≤ id < slotCount` and skip dead slots. */
  get slotCount(): number {
    return this.bodies.slotCount;
  }
  /**
   * Centres, x (metres), by body id. Replaced when the arrays grow. Like every body array here it
   * is the world's own, for reading: write through {@link setPosition} / {@link setVelocity} (a
   * value written here skips their checks; `step` refuses one that is not finite).
   */
  get x(): Float64Array {
    return this.bodies.x;
  }
  /** Centres, y (metres), by body id. */
  get y(): Float64Array {
    return this.bodies.y;
  }
  /** Velocities, x (m/s), by body id. */
  get vx(): Float64Array {
    return this.bodies.vx;
  }
  /** Velocities, y (m/s), by body id. */
  get vy(): Float64Array {
    return this.bodies.vy;
  }
  /** Half widths (a circle's radius), metres, by body id. */
  get halfWidth(): Float64Array {
    return this.bodies.halfWidth;
  }
  /** Half heights (a circle's radius), metres, by body id. */
  get halfHeight(): Float64Array {
    return this.bodies.halfHeight;
  }
  /** Inverse masses (1/kg; 0 for kinematic bodies), by body id. */
  get invMass(): Float64Array {
    return this.bodies.inverseMass;
  }
  /** Bodies moved with continuous collision detection in the last step (a diagnostic). */
  get sweptCount(): number {
    return this.ccd.sweptCount;
  }
  /** Contacts found in the last step (body–body and body–static). */
  get contactCount(): number {
    return this.contacts.count;
  }
  /** Static walls added so far; their ids are `0 … staticCount − 1`. */
  get staticCount(): number {
    return this.statics.count;
  }

  isAlive(id: number): boolean {
    return id >= 0 && id < this.bodies.slotCount && (this.bodies.flags[id]! & ALIVE) !== 0;
  }
  isBox(id: number): boolean {
    return (this.body(id, 'isBox') & BOX) !== 0;
  }
  isBullet(id: number): boolean {
    return (this.body(id, 'isBullet') & BULLET) !== 0;
  }
  isKinematic(id: number): boolean {
    return (this.body(id, 'isKinematic') & KINEMATIC) !== 0;
  }
  /** Whether a body is a sensor (Box2D's `b2Shape_IsSensor`; see {@link setSensor}). */
  isSensor(id: number): boolean {
    return (this.body(id, 'isSensor') & SENSOR) !== 0;
  }
  /** A body's collision filter (a fresh object; see {@link setFilter}). */
  getFilter(id: number): BodyFilter {
    this.body(id, 'getFilter');
    const b = this.bodies;
    return {
      categoryBits: b.categoryBits[id]!,
      maskBits: b.maskBits[id]!,
      groupIndex: b.groupIndex[id]!,
    };
  }
  /** A body's speed, m/s. */
  speed(id: number): number {
    this.body(id, 'speed');
    const ux = this.bodies.vx[id]!;
    const uy = this.bodies.vy[id]!;
    return Math.sqrt(ux * ux + uy * uy);
  }

  /**
   * Whether this body would be moved with continuous collision detection at its current velocity
   * (the step itself decides after gravity and contacts have changed the velocity).
   */
  usesContinuous(id: number): boolean {
    this.body(id, 'usesContinuous');
    return this.ccd.wouldSweep(id, this._def);
  }

  /** A static wall's shape (a fresh object). */
  getStatic(id: number): StaticShape {
    this.checkStatic(id);
    const w = this.statics;
    return w.kind[id] === SEGMENT
      ? { kind: 'segment', ax: w.ax[id]!, ay: w.ay[id]!, bx: w.bx[id]!, by: w.by[id]! }
      : {
          kind: 'box',
          x: w.centerX[id]!,
          y: w.centerY[id]!,
          halfWidth: w.halfWidth[id]!,
          halfHeight: w.halfHeight[id]!,
        };
  }

  /** A static wall's thickness: 0 for a segment, the smaller full extent of a box. Metres. */
  staticThickness(id: number): number {
    this.checkStatic(id);
    return this.statics.thickness(id);
  }

  // ---------------------------------------------------------------- building

  /**
   * Adds a dynamic (or kinematic) circle; returns its id (the lowest free slot). The options are
   * exact: an option the world does not know (`angle`, …) is a type error and a TypeError; a bad
   * value is a RangeError naming the body, the option and the value.
   */
  createCircle<T extends CircleOptions>(options: Exact<T, CircleOptions>): number {
    const o: CircleOptions = options;
    const id = this.bodies.nextId();
    checkKeys('createCircle', id, 'body', o, CIRCLE_KEYS);
    checkSize('createCircle', id, 'radius', o.radius);
    return this.createBody(
      'createCircle',
      id,
      0,
      o,
      o.radius,
      o.radius,
      Math.PI * o.radius * o.radius,
    );
  }

  /**
   * Adds a dynamic (or kinematic) axis-aligned box; returns its id (the lowest free slot). Exact
   * options, checked values, as {@link createCircle}.
   */
  createBox<T extends BoxOptions>(options: Exact<T, BoxOptions>): number {
    const o: BoxOptions = options;
    const id = this.bodies.nextId();
    checkKeys('createBox', id, 'body', o, BOX_KEYS);
    checkSize('createBox', id, 'halfWidth', o.halfWidth);
    checkSize('createBox', id, 'halfHeight', o.halfHeight);
    const w = o.halfWidth;
    const h = o.halfHeight;
    return this.createBody('createBox', id, BOX, o, w, h, 4 * w * h);
  }

  /**
   * Removes a body. Its slot is cleared to zeros and reused by the next body created, so the
   * state after any history of creations and removals depends only on which slots hold what.
   */
  destroyBody(id: number): void {
    this.body(id, 'destroyBody');
    wakeIsland(this.bodies, id); // what rested on it must fall
    this.bodies.destroy(id);
    this.cache.forget(id);
    this.overlaps.forget(id);
    this.contactLog.clearBody(id);
    this.queries.fresh = false;
  }

  /** Whether a body is sleeping (see {@link WorldDef.enableSleep}). */
  isAsleep(id: number): boolean {
    return (this.body(id, 'isAsleep') & ASLEEP) !== 0;
  }
  /** Sleeping bodies. */
  get sleepingCount(): number {
    return this.bodies.sleepingCount;
  }
  /** Wakes a sleeping body and its island (a no-op for an awake body). */
  wake(id: number): void {
    this.body(id, 'wake');
    wakeIsland(this.bodies, id);
  }

  /**
   * Teleports a body. Metres, each within ±`WORLD_LIMITS.maxCoordinate`. Wakes it. Throws a
   * RangeError naming the body and the value (and changes nothing) for a bad one.
   */
  setPosition(id: number, x: number, y: number): void {
    this.body(id, 'setPosition');
    checkCoordinate('setPosition', id, 'body', 'x', x);
    checkCoordinate('setPosition', id, 'body', 'y', y);
    wakeIsland(this.bodies, id);
    this.bodies.x[id] = x + 0; // + 0: −0 becomes +0 (the state stays canonical)
    this.bodies.y[id] = y + 0;
    this.queries.fresh = false;
  }

  /**
   * Sets a body's velocity. m/s, each within ±`WORLD_LIMITS.maxSpeed`. Wakes it. Throws a
   * RangeError naming the body and the value (and changes nothing) for a bad one.
   */
  setVelocity(id: number, vx: number, vy: number): void {
    this.body(id, 'setVelocity');
    checkSpeed('setVelocity', id, 'vx', vx);
    checkSpeed('setVelocity', id, 'vy', vy);
    wakeIsland(this.bodies, id);
    this.bodies.vx[id] = vx + 0;
    this.bodies.vy[id] = vy + 0;
  }

  /**
   * Adds an impulse (N·s) to a body's velocity; no effect on kinematic bodies. Wakes it. Throws a
   * RangeError (and changes nothing) if the impulse is not finite or the velocity it gives is
   * beyond ±`WORLD_LIMITS.maxSpeed`.
   */
  applyImpulse(id: number, jx: number, jy: number): void {
    this.body(id, 'applyImpulse');
    const b = this.bodies;
    if (!(typeof jx === 'number' && jx - jx === 0))
      throw new RangeError(
        `PhysicsWorld.applyImpulse: body ${id}: jx must be finite, got ${show(jx)}`,
      );
    if (!(typeof jy === 'number' && jy - jy === 0))
      throw new RangeError(
        `PhysicsWorld.applyImpulse: body ${id}: jy must be finite, got ${show(jy)}`,
      );
    const vx = b.vx[id]! + jx * b.inverseMass[id]!;
    const vy = b.vy[id]! + jy * b.inverseMass[id]!;
    const max = WORLD_LIMITS.maxSpeed;
    if (!(vx >= -max && vx <= max && vy >= -max && vy <= max))
      throw new RangeError(
        `PhysicsWorld.applyImpulse: body ${id}: the impulse (${jx}, ${jy}) N·s would give it a velocity of (${vx}, ${vy}) m/s, beyond ±1e9`,
      );
    wakeIsland(b, id);
    b.vx[id] = vx;
    b.vy[id] = vy;
  }

  /** Marks a body as a bullet (always swept) or not. */
  setBullet(id: number, bullet: boolean): void {
    const f = this.body(id, 'setBullet');
    if (typeof bullet !== 'boolean')
      throw new TypeError(
        `PhysicsWorld.setBullet: body ${id}: bullet must be true or false, got ${show(bullet)}`,
      );
    this.bodies.flags[id] = bullet ? f | BULLET : f & ~BULLET;
  }

  /**
   * Makes a body a sensor or not (Box2D's `isSensor`). A sensor collides with nothing — no
   * contact, no sweep, no push-out, with bodies or walls: it moves by its velocity (and gravity,
   * unless kinematic) straight through everything — and reports the bodies it overlaps as
   * {@link sensorEvents} (sensors do not see sensors; their filters apply). A pickup zone is a
   * kinematic sensor. Part of the state. Turning a sensor off forgets its overlaps without end
   * events. Wakes the body.
   */
  setSensor(id: number, sensor: boolean): void {
    const f = this.body(id, 'setSensor');
    if (typeof sensor !== 'boolean')
      throw new TypeError(
        `PhysicsWorld.setSensor: body ${id}: sensor must be true or false, got ${show(sensor)}`,
      );
    if (sensor === ((f & SENSOR) !== 0)) return;
    wakeIsland(this.bodies, id);
    this.bodies.flags[id] = sensor ? f | SENSOR : f & ~SENSOR;
    this.bodies.sensorCount += sensor ? 1 : -1;
    if (!sensor) this.overlaps.forget(id);
  }

  /**
   * Sets a body's collision filter (Box2D's `b2Shape_SetFilter`): the fields given change, the
   * others stay. Two bodies collide when they share a non-zero `groupIndex` and it is positive
   * (negative: never), else when each one's `categoryBits` has a bit of the other's `maskBits`.
   * Walls have the default filter (category 0x0001): a mask without bit 1 passes through them.
   * Part of the state; takes effect from the next step (a pair already touching ends its contact
   * there). Throws a RangeError (TypeError for a wrong type or an unknown field) naming the field,
   * changing nothing. Wakes the body.
   */
  setFilter<T extends Partial<BodyFilter>>(id: number, filter: Exact<T, BodyFilter>): void {
    this.body(id, 'setFilter');
    const f = checkFilter('setFilter', id, filter, this.getFilter(id));
    wakeIsland(this.bodies, id);
    this.bodies.setFilter(id, f.categoryBits, f.maskBits, f.groupIndex);
  }

  /**
   * A body's friction coefficient (Box2D's `b2Shape_GetFriction`): its own, or the world's
   * `def.friction` if it has none.
   */
  getFriction(id: number): number {
    this.body(id, 'getFriction');
    const f = this.bodies.friction[id]!;
    return f === WORLD_MATERIAL ? this._def.friction : f;
  }

  /** A body's coefficient of restitution: its own, or the world's `def.restitution` if it has none. */
  getRestitution(id: number): number {
    this.body(id, 'getRestitution');
    const e = this.bodies.restitution[id]!;
    return e === WORLD_MATERIAL ? this._def.restitution : e;
  }

  /** A body's linear damping, 1/s (Box2D's `b2Body_GetLinearDamping`). */
  getLinearDamping(id: number): number {
    this.body(id, 'getLinearDamping');
    return this.bodies.linearDamping[id]!;
  }

  /**
   * Sets a body's friction coefficient (Box2D's `b2Shape_SetFriction`), a finite number ≥ 0; a
   * contact's is `sqrt(fa · fb)` (see {@link BodyOptions.friction}). Part of the state (a world
   * with any body whose material is not the default saves a version 3 snapshot). Takes effect
   * from the next step. Throws a RangeError (TypeError for a wrong type) naming the body and the
   * value, changing nothing. Wakes the body.
   */
  setFriction(id: number, friction: number): void {
    this.body(id, 'setFriction');
    checkFriction('setFriction', id, friction);
    const b = this.bodies;
    wakeIsland(b, id);
    b.setMaterial(id, friction + 0, b.restitution[id]!, b.linearDamping[id]!);
  }

  /**
   * Sets a body's coefficient of restitution (Box2D's `b2Shape_SetRestitution`), in [0, 1]; a
   * contact bounces with the larger of its two bodies'. As {@link setFriction}.
   */
  setRestitution(id: number, restitution: number): void {
    this.body(id, 'setRestitution');
    checkRestitution('setRestitution', id, restitution);
    const b = this.bodies;
    wakeIsland(b, id);
    b.setMaterial(id, b.friction[id]!, restitution + 0, b.linearDamping[id]!);
  }

  /**
   * Sets a body's linear damping (Box2D's `b2Body_SetLinearDamping`), 1/s, a finite number ≥ 0:
   * each step its velocity is multiplied by `1 / (1 + timeStep · linearDamping)` before gravity.
   * As {@link setFriction}.
   */
  setLinearDamping(id: number, linearDamping: number): void {
    this.body(id, 'setLinearDamping');
    checkLinearDamping('setLinearDamping', id, linearDamping);
    const b = this.bodies;
    wakeIsland(b, id);
    b.setMaterial(id, b.friction[id]!, b.restitution[id]!, linearDamping + 0);
  }

  /**
   * Adds a static wall segment (zero thickness, two-sided) from `a` to `b` (metres, each within
   * ±`WORLD_LIMITS.maxCoordinate`); returns its id. Wakes every sleeping body.
   */
  addSegment(ax: number, ay: number, bx: number, by: number): number {
    const id = this.statics.count;
    checkCoordinate('addSegment', id, 'static', 'ax', ax);
    checkCoordinate('addSegment', id, 'static', 'ay', ay);
    checkCoordinate('addSegment', id, 'static', 'bx', bx);
    checkCoordinate('addSegment', id, 'static', 'by', by);
    return this.addStatic(SEGMENT, ax, ay, bx, by);
  }

  /**
   * Adds a static axis-aligned box (centre within ±`WORLD_LIMITS.maxCoordinate`, half extents
   * > 0 and at most that; metres); returns its id. Wakes every sleeping body.
   */
  addStaticBox(x: number, y: number, halfWidth: number, halfHeight: number): number {
    const id = this.statics.count;
    checkCoordinate('addStaticBox', id, 'static', 'x', x);
    checkCoordinate('addStaticBox', id, 'static', 'y', y);
    checkWallExtent('addStaticBox', id, 'halfWidth', halfWidth);
    checkWallExtent('addStaticBox', id, 'halfHeight', halfHeight);
    return this.addStatic(STATIC_BOX, x, y, halfWidth, halfHeight);
  }

  /**
   * Changes the def between steps: `changes` is merged into the current def, the result checked
   * like the constructor's (a RangeError or TypeError naming the field, and nothing changes) and
   * frozen. Deterministic (the def is part of the state) but it changes what follows; wakes
   * nothing (turning `enableSleep` off wakes everything at the next step).
   */
  setDef<T extends Partial<WorldDef>>(changes: Exact<T, WorldDef>): void {
    const c: Partial<WorldDef> = changes;
    checkDefKeys('PhysicsWorld.setDef', c);
    this._def = checkDef('PhysicsWorld.setDef', { ...this._def, ...c });
    this.contacts.setLimit(this._def.maxContacts);
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
    return this.rule.warnings(this._def);
  }

  // ---------------------------------------------------------------- queries

  /**
   * The closest place where the ray from `origin` along `translation` hits a body or a static wall
   * (Box2D's `b2World_CastRayClosest`), or null. Metres; the hit's `fraction` in [0, 1] is how far
   * along the translation. Circles, boxes, segments and static boxes, where they are now (between
   * steps). Ties go to bodies before walls, then the lower id; a ray that starts inside a shape
   * does not hit it; sensors are skipped unless `filter.sensors`. Deterministic: the answer is a
   * function of the state and the arguments (a `filter.predicate` must be too). Fast in big
   * worlds: a grid of its own, rebuilt on the first query after bodies moved, then only the cells
   * along the ray. Throws a RangeError (TypeError for a wrong type) for a coordinate beyond
   * ±`WORLD_LIMITS.maxCoordinate` (translation ±2e9) or a bad filter.
   */
  castRayClosest(
    originX: number,
    originY: number,
    translationX: number,
    translationY: number,
    filter?: RayFilter,
  ): RayHit | null {
    return this.queries.castRayClosest(originX, originY, translationX, translationY, filter);
  }

  /**
   * Every place where the ray hits a body or wall (Box2D's `b2World_CastRay` collecting them all),
   * sorted by fraction, then bodies before walls, then id. One hit per shape: where the ray
   * enters it. Otherwise as {@link castRayClosest}.
   */
  castRay(
    originX: number,
    originY: number,
    translationX: number,
    translationY: number,
    filter?: RayFilter,
  ): RayHit[] {
    return this.queries.castRay(originX, originY, translationX, translationY, filter);
  }

  /**
   * The bodies whose shape touches the box `[minX, maxX] × [minY, maxY]` (touching counts), in
   * ascending id (Box2D's `b2World_OverlapAABB`, but exact for circles). Walls are not reported.
   * Sensors only with `filter.sensors`. Metres.
   */
  overlapAABB(
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    filter?: QueryFilter,
  ): number[] {
    return this.queries.overlapAABB(minX, minY, maxX, maxY, filter);
  }

  /** The bodies whose shape touches the circle, in ascending id; as {@link overlapAABB}. */
  overlapCircle(x: number, y: number, radius: number, filter?: QueryFilter): number[] {
    return this.queries.overlapCircle(x, y, radius, filter);
  }

  /** The bodies that contain the point (on the edge counts), in ascending id; as {@link overlapAABB}. */
  overlapPoint(x: number, y: number, filter?: QueryFilter): number[] {
    return this.queries.overlapPoint(x, y, filter);
  }

  // ---------------------------------------------------------------- events

  /**
   * The sensors' overlap events of the last step (Box2D's `b2World_GetSensorEvents`): `begin`,
   * bodies that overlap a sensor now and did not at the end of the step before; `end`, the
   * reverse. Each sorted by sensor id, then visitor id. What the sensors overlap is part of the
   * state, so a world loaded from a snapshot reports the very same events. Empty after a load or
   * when nothing changed. The arrays are the world's: read them, do not change them.
   */
  sensorEvents(): StepEvents<SensorEvent> {
    return this.overlaps.events;
  }

  /**
   * The contact events of the last step (Box2D's `b2World_GetContactEvents`): `begin`, pairs (of
   * bodies, or a body and a wall) touching now that did not touch the step before; `end`, the
   * reverse. Sorted by `bodyA`, then bodies before walls, then id. Needs
   * `new PhysicsWorld(def, { contactEvents: true })` (otherwise always empty). A pair that falls
   * asleep touching stays touching (no end, and no begin when it wakes). Empty after a load.
   */
  contactEvents(): StepEvents<ContactEvent> {
    return this.contactLog.events;
  }

  /** The sensors' overlaps at the end of the step (see `events.ts`), when there is anything to track. */
  private updateSensors(): void {
    if (this.bodies.sensorCount > 0 || this.overlaps.count > 0)
      this.overlaps.update(this.bodies, this.queries);
    else this.overlaps.quiet();
  }

  // ---------------------------------------------------------------- stepping

  /**
   * Advances exactly one fixed step of `def.timeStep` seconds. Inputs are ignored. Throws a
   * RangeError — and leaves the world exactly as it was before the step — if the step finds more
   * than `def.maxContacts` contacts.
   */
  step(): void {
    this.checkArrays();
    const bodies = this.bodies;
    const def = this._def;
    if (bodies.sleepingCount === bodies.liveCount && bodies.liveCount > 0) {
      // Everything sleeps: the full step would find no contact and move nothing.
      this.contacts.count = 0;
      this.contacts.bodyPairCount = 0;
      this.ccd.sweptCount = 0;
      if (this.cache.count > 0) this.cache.clear();
      this.rule.wasBroken = false;
      this.contactLog.quiet();
      this.updateSensors();
      this._tick++;
      return;
    }

    // Contacts where the bodies are now (a new one wakes what it touches), gravity, velocities.
    this.beginStep();
    this.grid.build(bodies, def, this.schedule);
    this.grid.markWalls(this.statics, bodies.slotCount);
    this.findContactsOrUndo(def);
    if (this.contactEventsOn) this.contactLog.diff(this.contacts, this.cache, bodies);
    this.solverStep(def);

    this.ccd.integratePositions(def);

    // Push-out, on separations predicted from each body's motion since its contacts were found.
    solvePositions(this.contacts, bodies, def, this.schedule);
    if (def.ccd !== 'off' && this.statics.count > 0) this.ccd.guardWalls(def.ccd === 'auto');
    this.islands.update(bodies, this.contacts, def, this._tick);
    this.queries.fresh = false;
    if (this.contactEventsOn) this.contactLog.remember(bodies);
    this.updateSensors();
    this._tick++;

    if (this.onTunnellingWarning !== null) this.rule.afterStep(def, this.onTunnellingWarning);
  }

  /**
   * Remembers where every body starts, and which bodies the solvers move this step. Whole columns
   * are copied (what a free slot gets is never used: it has no contact and moves nothing), then
   * the sleepers' solver masses zeroed.
   */
  /**
   * The body arrays (`x`, `y`, `vx`, `vy` …) are the world's own, handed out for reading: a value
   * written into them skips every check the setters make. Before a step changes anything, one
   * look at each live body's position and velocity refuses a number that is not finite — the write
   * that spreads, through contacts, to the bodies around it and into snapshots `load` refuses —
   * naming the body. Cheap next to a step: four subtractions a body.
   */
  private checkArrays(): void {
    const b = this.bodies;
    const n = b.slotCount;
    const { x, y, vx, vy, flags } = b;
    for (let i = 0; i < n; i++) {
      // v − v is 0 for a finite v, NaN for NaN and ±∞: one test for the four.
      if (x[i]! - x[i]! + (y[i]! - y[i]!) + (vx[i]! - vx[i]!) + (vy[i]! - vy[i]!) === 0) continue;
      if ((flags[i]! & ALIVE) === 0) continue;
      for (const [name, column] of [
        ['x', x],
        ['y', y],
        ['vx', vx],
        ['vy', vy],
      ] as const) {
        const v = column[i]!;
        if (!Number.isFinite(v)) {
          throw new RangeError(
            `PhysicsWorld.step: body ${i}'s ${name} is ${String(v)}, written into world.${name} ` +
              `from outside? The arrays are for reading: move a body with setPosition or ` +
              `setVelocity, which check what they take. Nothing was stepped.`,
          );
        }
      }
    }
  }

  private beginStep(): void {
    const b = this.bodies;
    const n = b.slotCount;
    b.startX.set(b.x.subarray(0, n));
    b.startY.set(b.y.subarray(0, n));
    b.solverInverseMass.set(b.inverseMass.subarray(0, n));
    if (b.sleepingCount === 0) return;
    const flags = b.flags;
    const solverInverseMass = b.solverInverseMass;
    for (let i = 0; i < n; i++) if ((flags[i]! & ASLEEP) !== 0) solverInverseMass[i] = 0;
  }

  /**
   * Gravity into the velocities of the moving bodies (semi-implicit Euler: `v += g·dt`), keeping
   * the old velocities first when `keep` (so a throwing step can put them back).
   */
  private integrateVelocities(def: Readonly<WorldDef>, keep: boolean): void {
    const b = this.bodies;
    const n = b.slotCount;
    const flags = b.flags;
    const vx = b.vx;
    const vy = b.vy;
    const inverseMass = b.solverInverseMass;
    const startVx = b.startVx;
    const startVy = b.startVy;
    if (b.materialCount > 0) {
      this.integrateDampedVelocities(def, keep);
      return;
    }
    const gx = def.gravityX * def.timeStep;
    const gy = def.gravityY * def.timeStep;
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0 || !(inverseMass[i]! > 0)) continue;
      if (keep) {
        startVx[i] = vx[i]!;
        startVy[i] = vy[i]!;
      }
      vx[i] = vx[i]! + gx;
      vy[i] = vy[i]! + gy;
    }
  }

  /**
   * {@link integrateVelocities} with linear damping, Box2D's way: `v = v · 1/(1 + h·c) + h·g`.
   * Apart, so a world where no body has a material of its own runs the plain loop; a body with
   * no damping gets exactly the plain loop's `v + h·g`. JavaScript for both solver paths.
   */
  private integrateDampedVelocities(def: Readonly<WorldDef>, keep: boolean): void {
    const b = this.bodies;
    const n = b.slotCount;
    const flags = b.flags;
    const vx = b.vx;
    const vy = b.vy;
    const inverseMass = b.solverInverseMass;
    const damping = b.linearDamping;
    const h = def.timeStep;
    const gx = def.gravityX * h;
    const gy = def.gravityY * h;
    for (let i = 0; i < n; i++) {
      if (flags[i] === 0 || !(inverseMass[i]! > 0)) continue;
      if (keep) {
        b.startVx[i] = vx[i]!;
        b.startVy[i] = vy[i]!;
      }
      const c = damping[i]!;
      if (c === 0) {
        vx[i] = vx[i]! + gx;
        vy[i] = vy[i]! + gy;
      } else {
        const factor = 1 / (1 + h * c);
        vx[i] = vx[i]! * factor + gx;
        vy[i] = vy[i]! * factor + gy;
      }
    }
  }

  /**
   * The contacts of this step, gravity, and the contacts again if new ones woke sleeping bodies.
   * Past `def.maxContacts`, undoes what the step has done so far (wakes, gravity) and throws: the
   * first search runs before gravity, so only a world with sleeping bodies ever has to undo.
   */
  private findContactsOrUndo(def: Readonly<WorldDef>): void {
    const bodies = this.bodies;
    const log = this.wakeLog;
    const sleepers = bodies.sleepingCount > 0;
    let gravityDone = false;
    log.count = 0;
    try {
      findContacts(this.grid, bodies, this.statics, this.contacts, true, def, this.schedule);
      if (bodies.filteredCount + bodies.sensorCount > 0) filterContacts(this.contacts, bodies);
      this.integrateVelocities(def, sleepers);
      gravityDone = true;
      if (sleepers) {
        log.recording = true;
        const woke = wakeByNewContacts(bodies, this.contacts, this.cache, log);
        log.recording = false;
        if (woke) {
          findContacts(this.grid, bodies, this.statics, this.contacts, false, def, this.schedule);
          if (bodies.filteredCount + bodies.sensorCount > 0) filterContacts(this.contacts, bodies);
        }
      }
    } catch (e) {
      log.recording = false;
      if (!(e instanceof ContactOverflow)) throw e;
      log.undo(bodies);
      if (gravityDone) {
        const flags = bodies.flags;
        for (let i = 0; i < bodies.slotCount; i++) {
          if (flags[i] === 0 || !(bodies.solverInverseMass[i]! > 0)) continue;
          bodies.vx[i] = bodies.startVx[i]!;
          bodies.vy[i] = bodies.startVy[i]!;
        }
      }
      this.contacts.count = 0;
      this.contacts.bodyPairCount = 0;
      const a = e.bodyA;
      const b = e.bodyB;
      const where = `(${bodies.x[a]}, ${bodies.y[a]})`;
      throw new RangeError(
        `PhysicsWorld.step: more than ${e.limit} contacts in one step (def.maxContacts): the ` +
          `next one was between body ${a} at ${where} and ${b >= 0 ? `body ${b}` : `static ${-1 - b}`}. ` +
          `Are many bodies piled on one spot? Nothing was changed: the world is as before the step.`,
        { cause: e },
      );
    }
  }

  /** Velocities from the contacts, and their impulses kept for the next step. */
  private solverStep(def: Readonly<WorldDef>): void {
    solveVelocities(this.contacts, this.cache, this.bodies, def, this.schedule);
    this.cache.store(this.contacts);
  }

  // ---------------------------------------------------------------- state

  /** Bytes of the current snapshot: what {@link save} returns, what {@link saveInto} needs. */
  get snapshotSize(): number {
    const v2 = needsVersion2(this.bodies, this.overlaps);
    return snapshotSize(
      this.statics.count,
      this.bodies.slotCount,
      this.cache.count,
      v2 ? this.overlaps.count : -1,
      this.bodies.materialCount > 0,
    );
  }

  /** The whole state as canonical bytes (a new array; see {@link saveInto} to reuse one). */
  save(): Uint8Array {
    const out = new Uint8Array(this.snapshotSize);
    this.writer.write(out, this.state());
    return out;
  }

  /**
   * Writes {@link save}'s bytes into `out` from its start and returns how many (its first
   * {@link snapshotSize} bytes). Allocates nothing once it has seen `out`'s buffer and the body
   * count: a rollback loop that keeps one buffer per tick saves at copy speed, garbage-free.
   * Throws a RangeError if `out` is shorter than {@link snapshotSize}.
   */
  saveInto(out: Uint8Array): number {
    const size = this.snapshotSize;
    if (!(out instanceof Uint8Array) || out.length < size)
      throw new RangeError(
        `PhysicsWorld.saveInto: needs a Uint8Array of at least ${size} bytes, got ${out instanceof Uint8Array ? `${out.length}` : show(out)}`,
      );
    return this.writer.write(out, this.state());
  }

  /**
   * The snapshot written value by value through a ByteWriter: the format's definition, which
   * {@link saveInto} matches byte for byte (a test holds it).
   * @internal
   */
  writeCanonical(w: ByteWriter): void {
    writeCanonical(w, this.state());
  }

  /** FNV-1a 64 of {@link save}'s bytes. */
  hash(): bigint {
    const size = this.snapshotSize;
    if (this.hashBuffer.length < size)
      this.hashBuffer = new Uint8Array(Math.max(size, 2 * this.hashBuffer.length));
    this.writer.write(this.hashBuffer, this.state());
    return fnv1a64(this.hashBuffer.subarray(0, size));
  }

  private readonly stateView: WorldState = {
    tick: 0,
    def: defaultWorldDef(),
    statics: this.statics,
    bodies: this.bodies,
    cache: this.cache,
    overlaps: this.overlaps,
  };

  private state(): WorldState {
    const s = this.stateView;
    s.tick = this._tick;
    s.def = this._def;
    return s;
  }

  /**
   * Restores a state from {@link save} (or {@link saveInto}). Checks every value — structure,
   * def, walls, and every body (finite position and velocity; sizes, density, flags, islands
   * within what the world accepts; free slots all zeros) and every warm-start entry — and throws
   * a RangeError naming the first problem, changing nothing. Keeps this world's
   * `def.maxContacts`. Allocates nothing when the def is unchanged and the arrays have room.
   */
  load(bytes: Uint8Array): void {
    if (!(bytes instanceof Uint8Array))
      throw new TypeError(`PhysicsWorld.load: needs a Uint8Array, got ${show(bytes)}`);
    const reader = this.reader;
    reader.read(bytes, this.state());
    // Commit.
    if (reader.slots > this.bodies.capacity) this.grow(reader.slots);
    this._def = reader.def!;
    this._tick = reader.tick;
    reader.commit(this.bodies, this.statics, this.cache, this.overlaps);
    this.contacts.count = 0;
    this.contacts.bodyPairCount = 0;
    this.rule.wasBroken = false;
    this.queries.fresh = false;
    this.contactLog.quiet();
    this.contactLog.remember(this.bodies);
  }

  // ---------------------------------------------------------------- internals

  private body(id: number, method: string): number {
    if (!this.isAlive(id)) throw new RangeError(`PhysicsWorld.${method}: no body ${show(id)}`);
    return this.bodies.flags[id]!;
  }

  private checkStatic(id: number): void {
    if (!(Number.isInteger(id) && id >= 0 && id < this.statics.count))
      throw new RangeError(`PhysicsWorld: no static ${show(id)}`);
  }

  private createBody(
    method: string,
    id: number,
    shape: number,
    o: BodyOptions,
    w: number,
    h: number,
    area: number,
  ): number {
    checkCoordinate(method, id, 'body', 'x', o.x);
    checkCoordinate(method, id, 'body', 'y', o.y);
    const vx = o.vx ?? 0;
    const vy = o.vy ?? 0;
    checkSpeed(method, id, 'vx', vx);
    checkSpeed(method, id, 'vy', vy);
    const density = o.density ?? 1;
    checkDensity(method, id, density);
    checkFlag(method, id, 'bullet', o.bullet);
    checkFlag(method, id, 'kinematic', o.kinematic);
    checkFlag(method, id, 'sensor', o.sensor);
    const filter =
      o.filter === undefined ? null : checkFilter(method, id, o.filter, DEFAULT_FILTER);
    if (o.friction !== undefined) checkFriction(method, id, o.friction);
    if (o.restitution !== undefined) checkRestitution(method, id, o.restitution);
    if (o.linearDamping !== undefined) checkLinearDamping(method, id, o.linearDamping);
    if (id >= this.bodies.capacity) this.grow(this.bodies.capacity * 2);
    const kinematic = o.kinematic === true;
    const flags =
      ALIVE |
      shape |
      (o.bullet === true ? BULLET : 0) |
      (kinematic ? KINEMATIC : 0) |
      (o.sensor === true ? SENSOR : 0);
    const inverseMass = kinematic ? 0 : 1 / (density * area);
    this.bodies.create(id, flags, o.x + 0, o.y + 0, vx + 0, vy + 0, w, h, inverseMass);
    if (filter !== null)
      this.bodies.setFilter(id, filter.categoryBits, filter.maskBits, filter.groupIndex);
    if (o.friction !== undefined || o.restitution !== undefined || o.linearDamping !== undefined)
      this.bodies.setMaterial(
        id,
        o.friction === undefined ? WORLD_MATERIAL : o.friction + 0,
        o.restitution === undefined ? WORLD_MATERIAL : o.restitution + 0,
        (o.linearDamping ?? 0) + 0,
      );
    this.contactLog.clearBody(id);
    this.queries.fresh = false;
    return id;
  }

  private addStatic(kind: number, p0: number, p1: number, p2: number, p3: number): number {
    const b = this.bodies;
    for (let i = 0; b.sleepingCount > 0 && i < b.slotCount; i++) wakeIsland(b, i);
    return this.statics.add(kind, p0, p1, p2, p3);
  }

  private grow(capacity: number): void {
    this.bodies.grow(capacity);
    this.grid.resize(capacity);
    this.ccd.resize(capacity);
    this.islands.resize(capacity);
    this.wakeLog.resize(capacity);
    this.cache.growBodies(capacity);
    this.queries.resize(capacity);
    this.contactLog.resize(capacity);
    if (this.contacts.capacity < 4 * capacity) this.contacts.grow(4 * capacity);
    if (this.cache.capacity < 4 * capacity) this.cache.grow(4 * capacity);
  }
}
