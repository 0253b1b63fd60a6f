import type { BodyFilter } from './filter.js';

/**
 * How fast bodies are moved with continuous collision detection (CCD):
 * - `'auto'` — bodies flagged `bullet`, and any body whose step `speed × timeStep` exceeds its own
 *   smallest half extent plus half the thinnest feature in the world (the thinnest static wall or
 *   dynamic body): exactly the bodies that discrete detection could let through.
 * - `'bullets'` — only bodies flagged `bullet`.
 * - `'off'` — none: pure discrete detection, the talk's "objects fall through walls" demo.
 */
export type CcdMode = 'auto' | 'bullets' | 'off';

/** The ccd modes in the order the snapshot numbers them (0, 1, 2). */
export const CCD_MODES: readonly CcdMode[] = ['off', 'bullets', 'auto'];

/**
 * Everything that configures a {@link PhysicsWorld} (Box2D's `b2WorldDef`). Units are metres,
 * seconds and kilograms; y points up. Get one from {@link defaultWorldDef} and change what you
 * need. Every field but {@link maxContacts} is part of the world's state (saved, loaded, hashed):
 * two worlds with different defs are different simulations.
 *
 * A world checks its def when it is built, freezes it, and checks it again on every
 * {@link PhysicsWorld.setDef} and {@link PhysicsWorld.load}: a def the world holds is always
 * valid (see `WORLD_LIMITS` for the bounds).
 */
export interface WorldDef {
  /** Gravity, x component. Metres per second squared, at most `WORLD_LIMITS.maxGravity` in size. Default 0. */
  gravityX: number;
  /**
   * Gravity, y component (y points up). Metres per second squared, at most
   * `WORLD_LIMITS.maxGravity` in size. Default -9.81.
   */
  gravityY: number;
  /**
   * The fixed step. Seconds, > 0 and at most `WORLD_LIMITS.maxTimeStep`. Default 1/60 (the
   * talk's TIME_STEP is 0.03). Every step advances by exactly this; changing it between steps
   * ({@link PhysicsWorld.setDef}) is deterministic but changes the results.
   */
  timeStep: number;
  /** Coefficient of restitution of every contact, 0 (inelastic) to 1 (elastic). Default 0. */
  restitution: number;
  /**
   * Approach speed below which a contact does not bounce, so resting bodies do not jitter.
   * Metres per second. Default 1.
   */
  restitutionThreshold: number;
  /** Coulomb friction coefficient of every contact (bodies do not rotate). Default 0.6. */
  friction: number;
  /** Sequential-impulse iterations on velocities per step. An integer, 0–1000. Default 8. */
  velocityIterations: number;
  /** Relaxation iterations on positions (push-out) per step. An integer, 0–1000. Default 3. */
  positionIterations: number;
  /** Overlap left alone by the push-out, so resting contacts stay in contact. Metres. Default 0.005. */
  linearSlop: number;
  /** Fraction of the remaining overlap removed per position iteration, (0, 1]. Default 0.8. */
  positionCorrection: number;
  /** Which bodies use continuous collision detection. Default `'auto'`. */
  ccd: CcdMode;
  /**
   * Sweeps per body per step under CCD: each hit advances the body to the time of impact,
   * responds and sweeps the rest of the step; after this many hits the body stops where it is
   * for the rest of the step (it never tunnels). An integer, 0–1000. Default 4.
   */
  maxCcdIterations: number;
  /**
   * Broad-phase grid cell size. Metres. Default 0 = automatic (the largest body diameter). Values
   * smaller than the largest body diameter are raised to it.
   */
  cellSize: number;
  /**
   * Let resting bodies sleep: an island of touching bodies that has been slower than
   * `sleepSpeed` for `timeToSleep` stops being simulated until something new touches it, a sweep
   * hits it, a kinematic body touches it, or you move it ({@link PhysicsWorld.wake}; changing
   * gravity does not wake anything). Deterministic either way (sleep is part of the state).
   * Default true.
   */
  enableSleep: boolean;
  /** Speed below which a body counts as resting. Metres per second. Default 0.05. */
  sleepSpeed: number;
  /** How long an island must rest before it sleeps. Seconds. Default 0.5. */
  timeToSleep: number;
  /**
   * The most contacts one step may find (body–body and body–static together). A step that would
   * find more throws a RangeError *before it changes anything* (the world stays as it was before
   * the step), instead of growing its contact arrays without bound: 10,000 bodies created on one
   * spot make 50 million overlapping pairs. A contact costs 92 bytes of arrays, so the default
   * 1,048,576 (2^20) allows about 96 MB. An integer from 1 to `WORLD_LIMITS.maxContacts`.
   *
   * The one field that is **not** part of the state: it never changes a step that completes,
   * only whether a step throws, so it is not saved, loaded or hashed ({@link PhysicsWorld.load}
   * keeps the loading world's own value).
   */
  maxContacts: number;
}

/** A {@link WorldDef} with the documented defaults. A fresh object each call. */
export function defaultWorldDef(): WorldDef {
  return {
    gravityX: 0,
    gravityY: -9.81,
    timeStep: 1 / 60,
    restitution: 0,
    restitutionThreshold: 1,
    friction: 0.6,
    velocityIterations: 8,
    positionIterations: 3,
    linearSlop: 0.005,
    positionCorrection: 0.8,
    ccd: 'auto',
    maxCcdIterations: 4,
    cellSize: 0,
    enableSleep: true,
    sleepSpeed: 0.05,
    timeToSleep: 0.5,
    maxContacts: 1 << 20,
  };
}

/**
 * Options of a dynamic body. Metres, metres per second, kilograms per square metre. The bounds are
 * `WORLD_LIMITS`; a value outside them is refused with a RangeError that names the body, the
 * option and the value. Bodies do not rotate: options such as `angle` or `angularVelocity` are a
 * type error (the `create*` methods take exact option types) and a runtime error.
 */
export interface BodyOptions {
  /** Centre, x. Metres, at most `WORLD_LIMITS.maxCoordinate` from 0. */
  x: number;
  /** Centre, y. Metres, at most `WORLD_LIMITS.maxCoordinate` from 0. */
  y: number;
  /** Initial velocity, x. Metres per second, at most `WORLD_LIMITS.maxSpeed` in size. Default 0. */
  vx?: number;
  /** Initial velocity, y. Metres per second, at most `WORLD_LIMITS.maxSpeed` in size. Default 0. */
  vy?: number;
  /**
   * Mass per area. Kilograms per square metre, from `WORLD_LIMITS.minDensity` to
   * `WORLD_LIMITS.maxDensity`. Default 1.
   */
  density?: number;
  /**
   * Always move with continuous collision detection (unless the world's `ccd` is `'off'`): for
   * bullets and anything that must never pass through a wall. Default false.
   */
  bullet?: boolean;
  /**
   * Infinite mass: moves with its velocity, ignores gravity, impulses and static walls, and pushes
   * dynamic bodies. Default false.
   */
  kinematic?: boolean;
  /**
   * A sensor: collides with nothing, reports overlaps as sensor events (see
   * {@link PhysicsWorld.setSensor}). Default false.
   */
  sensor?: boolean;
  /**
   * Collision filter: category, mask and group (Box2D's `b2Filter`; see
   * {@link PhysicsWorld.setFilter}). Fields left out take the defaults: category 0x0001, mask
   * 0xFFFFFFFF, group 0.
   */
  filter?: Partial<BodyFilter>;
  /**
   * Coulomb friction coefficient (Box2D's `friction`), a finite number ≥ 0. Default: the world's
   * `def.friction`, whatever it is at each step. A contact's friction is `sqrt(fa · fb)` of its
   * two bodies' (a wall's is `def.friction`), or the common value when the two are equal.
   */
  friction?: number;
  /**
   * Coefficient of restitution (Box2D's `restitution`), 0 (inelastic) to 1 (elastic). Default:
   * the world's `def.restitution`. A contact bounces with the larger of its two bodies' (a wall's
   * is `def.restitution`), above `def.restitutionThreshold`.
   */
  restitution?: number;
  /**
   * Linear damping (Box2D's `linearDamping`), 1/s, a finite number ≥ 0: each step the velocity
   * is multiplied by `1 / (1 + timeStep · linearDamping)` before gravity is added. No effect on
   * kinematic bodies. Default 0.
   */
  linearDamping?: number;
}

/** A dynamic circle. */
export interface CircleOptions extends BodyOptions {
  /** Metres, from `WORLD_LIMITS.minSize` to `WORLD_LIMITS.maxSize`. */
  radius: number;
}

/** A dynamic axis-aligned box (bodies do not rotate). */
export interface BoxOptions extends BodyOptions {
  /** Half the width. Metres, from `WORLD_LIMITS.minSize` to `WORLD_LIMITS.maxSize`. */
  halfWidth: number;
  /** Half the height. Metres, from `WORLD_LIMITS.minSize` to `WORLD_LIMITS.maxSize`. */
  halfHeight: number;
}

/**
 * `T` with every key that `Shape` does not have typed `never`: passing an option the world does
 * not know (e.g. `{ x, y, radius, angle }` to `createCircle`) is a type error, whether the object
 * is a literal or a variable.
 */
export type Exact<T, Shape> = T & Record<Exclude<keyof T, keyof Shape>, never>;
