/**
 * How fast bodies are moved with continuous collision detection (CCD):
 * - `'auto'` — bodies flagged `bullet`, and any body whose step `speed × timeStep` exceeds its own
 *   smallest half extent plus half the thinnest feature in the world (the thinnest static wall or
 *   dynamic body): exactly the bodies that discrete detection could let through.
 * - `'bullets'` — only bodies flagged `bullet`.
 * - `'off'` — none: pure discrete detection, the talk's "objects fall through walls" demo.
 */
export type CcdMode = 'auto' | 'bullets' | 'off';

/**
 * Everything that configures a {@link PhysicsWorld} (Box2D's `b2WorldDef`). Units are metres,
 * seconds and kilograms; y points up. Get one from {@link defaultWorldDef} and change what you
 * need. All of it is part of the world's state (saved, loaded, hashed): two worlds with different
 * defs are different simulations.
 */
export interface WorldDef {
  /** Gravity, x component. Metres per second squared. Default 0. */
  gravityX: number;
  /** Gravity, y component (y points up). Metres per second squared. Default -9.81. */
  gravityY: number;
  /**
   * The fixed step. Seconds. Default 1/60 (the talk's TIME_STEP is 0.03). Every step advances by
   * exactly this; changing it between steps is deterministic but changes the results.
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
  /** Sequential-impulse iterations on velocities per step. Default 8. */
  velocityIterations: number;
  /** Relaxation iterations on positions (push-out) per step. Default 3. */
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
   * for the rest of the step (it never tunnels). Default 4.
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
  };
}

/** Options of a dynamic body. Metres, metres per second, kilograms per square metre. */
export interface BodyOptions {
  /** Centre, x. Metres. */
  x: number;
  /** Centre, y. Metres. */
  y: number;
  /** Initial velocity, x. Metres per second. Default 0. */
  vx?: number;
  /** Initial velocity, y. Metres per second. Default 0. */
  vy?: number;
  /** Mass per area. Kilograms per square metre. Default 1. */
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
}

/** A dynamic circle. */
export interface CircleOptions extends BodyOptions {
  /** Metres, > 0. */
  radius: number;
}

/** A dynamic axis-aligned box (bodies do not rotate). */
export interface BoxOptions extends BodyOptions {
  /** Half the width. Metres, > 0. */
  halfWidth: number;
  /** Half the height. Metres, > 0. */
  halfHeight: number;
}
