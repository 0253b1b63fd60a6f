/**
 * Field maps of the states the catalogue traces, written from each `save()`'s documented layout.
 * Each map is checked against the length of the bytes it names: if a layout changes and this file
 * is not updated, the map is dropped (the report falls back to byte offsets) rather than naming
 * the wrong field.
 */
import { ByteReader, type SpringSystem } from 'fixedstep';
import type { Game } from '../games/game.js';
import { StateLayout, type StateField } from './state-fields.js';

const WORLD_DEF_F64 = [
  'gravityX',
  'gravityY',
  'timeStep',
  'restitution',
  'restitutionThreshold',
  'friction',
  'linearSlop',
  'positionCorrection',
  'cellSize',
  'sleepSpeed',
  'timeToSleep',
] as const;
const BODY_F64 = ['x', 'y', 'vx', 'vy', 'halfWidth', 'halfHeight', 'invMass', 'restTime'] as const;

/**
 * `PhysicsWorld.save()`: header, def, statics, body columns, warm-start cache and, in version 2,
 * the filter columns and the sensor overlaps (version 3: then the materials). With `tail`, the map goes on past the snapshot
 * (what a scene appends after it) and must cover the bytes to the end.
 */
export function physicsWorldFields(
  bytes: Uint8Array,
  tail?: (layout: StateLayout) => void,
): StateField[] | undefined {
  try {
    const r = new ByteReader(bytes);
    const l = new StateLayout().add('u32', 'magic').add('u32', 'version').add('f64', 'tick');
    for (const name of WORLD_DEF_F64) l.add('f64', `def.${name}`);
    l.add('u32', 'def.velocityIterations')
      .add('u32', 'def.positionIterations')
      .add('u32', 'def.maxCcdIterations')
      .add('u8', 'def.ccd')
      .add('u8', 'def.enableSleep');
    r.bytes(4);
    const version = r.u32();
    r.bytes(l.length - 8);
    const statics = r.u32();
    l.add('u32', 'staticCount');
    for (let s = 0; s < statics; s++) {
      l.add('u8', `static[${s}].kind`).array('f64', 4, (k) => `static[${s}].p${k}`);
    }
    r.bytes(statics * 33);
    const n = r.u32();
    l.add('u32', 'bodySlots');
    l.array('u8', n, (i) => `body[${i}].flags`);
    for (const name of BODY_F64) l.array('f64', n, (i) => `body[${i}].${name}`);
    l.array('i32', n, (i) => `body[${i}].island`);
    r.bytes(n * (1 + 8 * BODY_F64.length + 4));
    const wc = r.u32();
    l.add('u32', 'contactCount');
    l.array('i32', wc, (k) => `contact[${k}].a`);
    l.array('i32', wc, (k) => `contact[${k}].b`);
    l.array('f64', wc, (k) => `contact[${k}].normalImpulse`);
    l.array('f64', wc, (k) => `contact[${k}].tangentImpulse`);
    if (version >= 2) {
      r.bytes(wc * 24);
      l.array('u32', n, (i) => `body[${i}].categoryBits`);
      l.array('u32', n, (i) => `body[${i}].maskBits`);
      l.array('i32', n, (i) => `body[${i}].groupIndex`);
      r.bytes(n * 12);
      const overlaps = r.u32();
      l.add('u32', 'sensorOverlapCount');
      l.array('i32', overlaps, (k) => `sensorOverlap[${k}].sensor`);
      l.array('i32', overlaps, (k) => `sensorOverlap[${k}].visitor`);
    }
    if (version >= 3) {
      l.array('f64', n, (i) => `body[${i}].friction`);
      l.array('f64', n, (i) => `body[${i}].restitution`);
      l.array('f64', n, (i) => `body[${i}].linearDamping`);
    }
    if (tail) tail(l);
    return l.covering(bytes.length);
  } catch {
    return undefined;
  }
}

/** The `physics/filters-sensors` scene's state: the snapshot, then its queries and events. */
export function filtersSensorsFields(bytes: Uint8Array): StateField[] | undefined {
  return physicsWorldFields(bytes, (l) => {
    l.add('u32', 'sensorEvents.begin')
      .add('u32', 'sensorEvents.end')
      .add('u32', 'contactEvents.begin')
      .add('u32', 'contactEvents.end')
      .add('u32', 'ray.body')
      .add('u32', 'ray.wall')
      .add('u32', 'overlapAABB(red).length')
      .add('u32', 'overlapCircle.length')
      .add('f64', 'ray.fraction')
      .add('f64', 'ray.x')
      .add('f64', 'ray.y');
  });
}

const AXES = ['x', 'y', 'z'];

/** `SpringSystem.save()`: header, tick, then x, v (and the method's a, xPrev), per particle. */
export function springSystemFields(
  system: SpringSystem,
  bytes: Uint8Array,
): StateField[] | undefined {
  const dim = system.model.dim;
  const size = system.model.size;
  const l = new StateLayout()
    .add('u8', 'format')
    .add('u8', 'dim')
    .add('u8', 'method')
    .add('u8', 'reserved')
    .add('u32', 'particles')
    .add('u32', 'springs')
    .add('u32', 'configHashHi')
    .add('u32', 'configHashLo')
    .add('f64', 'tick');
  const arrays = ['x', 'v'];
  if (system.integrator.keepsAcceleration) arrays.push('a');
  if (system.integrator.keepsPreviousPosition) arrays.push('xPrev');
  for (const name of arrays) {
    l.array(
      'f64',
      size,
      (i) => `particle[${Math.floor(i / dim)}].${name}.${AXES[i % dim] ?? String(i % dim)}`,
    );
  }
  return l.covering(bytes.length);
}

/** `BallScene.save()`: its Float64Array state. */
export function ballFields(bytes: Uint8Array): StateField[] | undefined {
  return new StateLayout()
    .add('f64', 'ball.x')
    .add('f64', 'ball.y')
    .add('f64', 'ball.vx')
    .add('f64', 'ball.vy')
    .add('f64', 'ball.bounces')
    .add('f64', 'ball.throws')
    .covering(bytes.length);
}

/** `RunnerGame.save()`, as its TSDoc lays it out (84 bytes + 9 per obstacle). */
function runnerFields(bytes: Uint8Array): StateField[] | undefined {
  const l = new StateLayout()
    .add('u32', 'magic')
    .add('u32', 'tick')
    .add('u32', 'highscore')
    .add('u32', 'runs')
    .add('u8', 'crashed')
    .add('u8', 'onGround')
    .add('u8', 'ducking')
    .add('f64', 'distance')
    .add('f64', 'speed')
    .add('f64', 'height')
    .add('f64', 'verticalSpeed')
    .add('f64', 'nextObstacleAt')
    .add('f64', 'secondsSinceCrash')
    .array('u32', 4, (k) => `rng.s${k}`)
    .add('u8', 'obstacleCount');
  if (bytes.length < l.length) return undefined;
  const count = bytes[l.length - 1]!;
  for (let k = 0; k < count; k++) {
    l.add('u8', `obstacle[${k}].kind`).add('f64', `obstacle[${k}].left`);
  }
  return l.covering(bytes.length);
}

/**
 * What a game may offer so that a mismatch report names its fields: `stateFields(bytes)` returning
 * a field map of its `save()` bytes (see {@link StateLayout}). Optional; without it the report
 * gives byte offsets and raw values.
 */
export interface DescribesState {
  stateFields(bytes: Uint8Array): readonly StateField[] | undefined;
}

function describesState(game: unknown): game is DescribesState {
  return (
    typeof game === 'object' &&
    game !== null &&
    typeof (game as Partial<DescribesState>).stateFields === 'function'
  );
}

/** The field map of a game's state: its own `stateFields`, else one known here, else undefined. */
export function gameFields(game: Game, bytes: Uint8Array): readonly StateField[] | undefined {
  if (describesState(game)) return game.stateFields(bytes);
  if (game.info.id === 'runner') return runnerFields(bytes);
  return undefined;
}
