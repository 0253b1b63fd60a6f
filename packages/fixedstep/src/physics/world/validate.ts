import { CCD_MODES, defaultWorldDef, type WorldDef } from './def.js';

/**
 * What the world accepts. Every public mutator, the constructor, {@link PhysicsWorld.setDef} and
 * {@link PhysicsWorld.load} refuse a value outside these bounds with an Error that names the
 * method, the body (or wall), the field and the value — before they change anything. The bounds
 * keep every product the solver forms (speed × mass, speed × step, 1 / mass) a finite, normal
 * double, so nothing a caller passes can turn into an infinite inverse mass or spread NaN.
 *
 * The step itself does not check: a body may fall past `maxCoordinate` or be pushed past
 * `maxSpeed`, and {@link PhysicsWorld.load} accepts any finite position and velocity, so a
 * snapshot a world saved is always one its own `load()` accepts.
 */
export const WORLD_LIMITS = Object.freeze({
  /**
   * The largest |x| or |y| of a body's centre or a wall's coordinates, as given. Metres. At 1e9 m a
   * double still resolves 1.2e-7 m, well under the default linear slop of 5 mm.
   */
  maxCoordinate: 1e9,
  /** The largest |vx| or |vy| given to a body (directly, or as the result of an impulse). m/s. */
  maxSpeed: 1e9,
  /** The smallest radius or half extent of a body. Metres. */
  minSize: 1e-6,
  /** The largest radius or half extent of a body. Metres. */
  maxSize: 1e6,
  /** The smallest density. kg/m². With `minSize`, the lightest body is π·1e-18 kg. */
  minDensity: 1e-6,
  /** The largest density. kg/m². With `maxSize`, the heaviest body is 4e18 kg. */
  maxDensity: 1e6,
  /** The largest |gravityX| or |gravityY|. m/s². */
  maxGravity: 1e6,
  /** The longest step. Seconds (an hour: no game steps by more). */
  maxTimeStep: 3600,
  /** The most solver or CCD iterations per step. */
  maxIterations: 1000,
  /** The largest {@link WorldDef.maxContacts}: 2^26 contacts are 6 GB of arrays. */
  maxContacts: 1 << 26,
  /** The most body slots a world may preallocate ({@link WorldOptions.capacity}). */
  maxCapacity: 1 << 24,
});

/** A value for an error message: numbers as JavaScript prints them, anything else labelled. */
export function show(v: unknown): string {
  if (typeof v === 'number') return String(v);
  if (typeof v === 'string') return `${JSON.stringify(v)} (a string)`;
  if (typeof v === 'boolean') return v ? 'true' : 'false';
  if (typeof v === 'bigint') return `${v.toString()}n`;
  if (v === undefined) return 'undefined';
  if (v === null) return 'null';
  return `a ${typeof v}`;
}

/** The subject of an error: `PhysicsWorld.setVelocity: body 5`. */
function subject(method: string, id: number, what: string): string {
  return `PhysicsWorld.${method}: ${what} ${id}`;
}

function fail(
  method: string,
  id: number,
  what: string,
  field: string,
  rule: string,
  v: unknown,
): never {
  const text = `${subject(method, id, what)}: ${field} must be ${rule}, got ${show(v)}`;
  throw typeof v === 'number' || v === undefined ? new RangeError(text) : new TypeError(text);
}

/** A body's (or wall's) coordinate: a number within ±`maxCoordinate`. */
export function checkCoordinate(
  method: string,
  id: number,
  what: string,
  field: string,
  v: unknown,
): void {
  const m = WORLD_LIMITS.maxCoordinate;
  if (typeof v === 'number' && v >= -m && v <= m) return;
  fail(method, id, what, field, `a finite number from -1e9 to 1e9 (metres)`, v);
}

/** A velocity component: a number within ±`maxSpeed`. */
export function checkSpeed(method: string, id: number, field: string, v: unknown): void {
  const m = WORLD_LIMITS.maxSpeed;
  if (typeof v === 'number' && v >= -m && v <= m) return;
  fail(method, id, 'body', field, `a finite number from -1e9 to 1e9 (m/s)`, v);
}

/** A radius or half extent of a body: `minSize` to `maxSize`. */
export function checkSize(method: string, id: number, field: string, v: unknown): void {
  if (typeof v === 'number' && v >= WORLD_LIMITS.minSize && v <= WORLD_LIMITS.maxSize) return;
  fail(method, id, 'body', field, `from 1e-6 to 1e6 (metres)`, v);
}

/** A density: `minDensity` to `maxDensity` (no denormals, no zero, no infinity). */
export function checkDensity(method: string, id: number, v: unknown): void {
  if (typeof v === 'number' && v >= WORLD_LIMITS.minDensity && v <= WORLD_LIMITS.maxDensity) return;
  fail(method, id, 'body', 'density', `from 1e-6 to 1e6 (kg/m²)`, v);
}

/** A static wall's half extent: positive, at most `maxCoordinate`. */
export function checkWallExtent(method: string, id: number, field: string, v: unknown): void {
  if (typeof v === 'number' && v > 0 && v <= WORLD_LIMITS.maxCoordinate) return;
  fail(method, id, 'static', field, `a number > 0 and at most 1e9 (metres)`, v);
}

/** A body's friction coefficient: a finite number ≥ 0. */
export function checkFriction(method: string, id: number, v: unknown): void {
  if (typeof v === 'number' && v >= 0 && v < Infinity) return;
  fail(method, id, 'body', 'friction', 'a finite number ≥ 0', v);
}

/** A body's coefficient of restitution: in [0, 1], as `WorldDef.restitution`. */
export function checkRestitution(method: string, id: number, v: unknown): void {
  if (typeof v === 'number' && v >= 0 && v <= 1) return;
  fail(method, id, 'body', 'restitution', 'in [0, 1]', v);
}

/** A body's linear damping: a finite number ≥ 0 (1/s). */
export function checkLinearDamping(method: string, id: number, v: unknown): void {
  if (typeof v === 'number' && v >= 0 && v < Infinity) return;
  fail(method, id, 'body', 'linearDamping', 'a finite number ≥ 0 (1/s)', v);
}

/** A boolean option (`undefined` allowed: the default). */
export function checkFlag(method: string, id: number, field: string, v: unknown): void {
  if (v === undefined || typeof v === 'boolean') return;
  fail(method, id, 'body', field, 'true or false', v);
}

/** Options that a rotating engine would take: named in the error so the reason is clear. */
const ROTATION_OPTIONS = new Set([
  'angle',
  'rotation',
  'angularVelocity',
  'angularDamping',
  'inertia',
  'torque',
  'fixedRotation',
]);

/**
 * Refuses an option object with a key outside `known` (a TypeError naming the key): options the
 * world does not support are never silently dropped.
 */
export function checkKeys(
  method: string,
  id: number,
  what: string,
  options: object,
  known: ReadonlySet<string>,
): void {
  for (const key in options) {
    if (known.has(key)) continue;
    const why = ROTATION_OPTIONS.has(key)
      ? ': bodies of this world are axis-aligned and never rotate (use a Rapier world for rotation)'
      : `; known options: ${[...known].join(', ')}`;
    throw new TypeError(`${subject(method, id, what)}: unknown option "${key}"${why}`);
  }
}

/** The options every body takes, whatever its shape. */
const BODY_KEYS = [
  'x',
  'y',
  'vx',
  'vy',
  'density',
  'bullet',
  'kinematic',
  'sensor',
  'filter',
  'friction',
  'restitution',
  'linearDamping',
] as const;
/** The options of {@link PhysicsWorld.createCircle}. */
export const CIRCLE_KEYS: ReadonlySet<string> = new Set([...BODY_KEYS, 'radius']);
/** The options of {@link PhysicsWorld.createBox}. */
export const BOX_KEYS: ReadonlySet<string> = new Set([...BODY_KEYS, 'halfWidth', 'halfHeight']);
/** The fields of a {@link WorldDef}. */
export const DEF_KEYS: ReadonlySet<string> = new Set(Object.keys(defaultWorldDef()));

function defFail(where: string, field: string, rule: string, v: unknown): never {
  const text = `${where}: WorldDef.${field} must be ${rule}, got ${show(v)}`;
  throw typeof v === 'number' ? new RangeError(text) : new TypeError(text);
}

function isNumber(v: unknown): v is number {
  return typeof v === 'number';
}

/**
 * Checks every field of a whole def (where: the method, for the message) and returns it frozen.
 * Throws a RangeError (a TypeError for a value of the wrong type) naming the field and the value.
 */
export function checkDef(where: string, d: WorldDef): Readonly<WorldDef> {
  checkDefKeys(where, d);
  const g = WORLD_LIMITS.maxGravity;
  for (const k of ['gravityX', 'gravityY'] as const) {
    const v: unknown = d[k];
    if (!(isNumber(v) && v >= -g && v <= g))
      defFail(where, k, 'a finite number from -1e6 to 1e6 (m/s²)', v);
  }
  const dt: unknown = d.timeStep;
  if (!(isNumber(dt) && dt > 0 && dt <= WORLD_LIMITS.maxTimeStep))
    defFail(where, 'timeStep', 'positive and at most 3600 (seconds)', dt);
  const e: unknown = d.restitution;
  if (!(isNumber(e) && e >= 0 && e <= 1)) defFail(where, 'restitution', 'in [0, 1]', e);
  for (const k of [
    'restitutionThreshold',
    'friction',
    'linearSlop',
    'cellSize',
    'sleepSpeed',
    'timeToSleep',
  ] as const) {
    const v: unknown = d[k];
    if (!(isNumber(v) && v >= 0 && v < Infinity)) defFail(where, k, 'a finite number ≥ 0', v);
  }
  const beta: unknown = d.positionCorrection;
  if (!(isNumber(beta) && beta > 0 && beta <= 1))
    defFail(where, 'positionCorrection', 'in (0, 1]', beta);
  for (const k of ['velocityIterations', 'positionIterations', 'maxCcdIterations'] as const) {
    const v: unknown = d[k];
    if (!(isNumber(v) && Number.isInteger(v) && v >= 0 && v <= WORLD_LIMITS.maxIterations))
      defFail(where, k, 'an integer from 0 to 1000', v);
  }
  const mc: unknown = d.maxContacts;
  if (!(isNumber(mc) && Number.isInteger(mc) && mc >= 1 && mc <= WORLD_LIMITS.maxContacts))
    defFail(where, 'maxContacts', `an integer from 1 to ${WORLD_LIMITS.maxContacts}`, mc);
  if (!CCD_MODES.includes(d.ccd))
    throw new TypeError(
      `${where}: WorldDef.ccd must be 'auto', 'bullets' or 'off', got ${show(d.ccd)}`,
    );
  if (typeof d.enableSleep !== 'boolean')
    throw new TypeError(
      `${where}: WorldDef.enableSleep must be true or false, got ${show(d.enableSleep)}`,
    );
  return Object.freeze({ ...d });
}

/** Refuses a def (or a change to one) with a field a {@link WorldDef} does not have. */
export function checkDefKeys(where: string, d: object): void {
  for (const key in d) {
    if (!DEF_KEYS.has(key))
      throw new TypeError(
        `${where}: unknown WorldDef field "${key}"; the fields are ${[...DEF_KEYS].join(', ')}`,
      );
  }
}
