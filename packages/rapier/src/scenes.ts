/**
 * Ready-made Rapier scenes: shared by the tests, the cross-engine determinism suite, the
 * benchmarks and (later) the lab — one builder for each, as Box2D's `shared/` does.
 */
import { ByteReader, ByteWriter, isDown, wasPressed, type PhysicsScene } from 'fixedstep';
import type { World } from '@dimforge/rapier2d-deterministic-compat';
import { readyRapier, type RapierModule } from './rapier.js';
import type { RapierSceneDef } from './simulation.js';

/** Buttons of the {@link towerScene}: bit numbers of a `ButtonInput`. */
export const TowerButtons = Object.freeze({
  /** Pressed: launch the ball at the tower (an impulse, once per press). */
  FIRE: 0,
});

/** Options of {@link towerScene}. */
export interface TowerOptions {
  /** Rows of boxes. Default 8. */
  readonly rows?: number;
  /** Boxes side by side in a row. Default 2. */
  readonly columns?: number;
  /** Box side, m. Default 0.5. */
  readonly box?: number;
  /** Ball radius, m. Default 0.3. */
  readonly ballRadius?: number;
  /** Launch speed of the ball, m/s (the impulse gives it this speed from rest). Default 14. */
  readonly launchSpeed?: number;
  /** Players (all may fire; one ball). Default 1. */
  readonly players?: number;
  /** Ticks per second. Default 60. */
  readonly tickRate?: number;
}

/** What {@link towerScene}'s build returns: handles, and the state the world does not hold. */
export interface Tower {
  /** The ball's body handle. */
  readonly ball: number;
  /** The boxes' body handles, bottom row first, left to right. */
  readonly boxes: readonly number[];
  /** The ground's body handle. */
  readonly ground: number;
  /** Where the ball waits, m. */
  readonly home: { readonly x: number; readonly y: number };
  /** Shots fired so far (saved and hashed as user state). */
  shots: number;
  /** The launch speed, m/s. */
  readonly launchSpeed: number;
}

function checkCount(name: string, value: number, min: number, max: number): number {
  if (!(Number.isInteger(value) && value >= min && value <= max)) {
    throw new RangeError(
      `towerScene: ${name} must be an integer from ${min} to ${max}, got ${String(value)}`,
    );
  }
  return value;
}

function checkSize(name: string, value: number, min: number, max: number): number {
  if (!(Number.isFinite(value) && value >= min && value <= max)) {
    throw new RangeError(`towerScene: ${name} must be from ${min} to ${max}, got ${String(value)}`);
  }
  return value;
}

/**
 * Builds a tower of `rows` × `columns` dynamic boxes of side `side` standing on y = 0, the centre
 * of its first column at x = `x0`: 2 % apart across and 0.1 % up (none starts in contact), each a
 * little smaller than its cell, density 1, friction 0.6. Returns their handles, row by row from
 * the bottom, each row from the left.
 */
export function buildTower(
  world: World,
  rapier: RapierModule,
  tower: {
    readonly x0: number;
    readonly rows: number;
    readonly columns: number;
    readonly side: number;
  },
): number[] {
  const { x0, rows, columns, side } = tower;
  const half = side / 2;
  const boxes: number[] = [];
  for (let row = 0; row < rows; row++) {
    for (let col = 0; col < columns; col++) {
      const body = world.createRigidBody(
        rapier.RigidBodyDesc.dynamic().setTranslation(
          x0 + col * side * 1.02,
          half + row * side * 1.001,
        ),
      );
      world.createCollider(
        rapier.ColliderDesc.cuboid(half * 0.98, half * 0.98)
          .setDensity(1)
          .setFriction(0.6),
        body,
      );
      boxes.push(body.handle);
    }
  }
  return boxes;
}

/**
 * A tower of rotating boxes on the ground and a ball that knocks it over: press FIRE
 * ({@link TowerButtons}) and the ball is launched at the tower (an impulse along +x and a little
 * up; each press fires again from wherever the ball is). What the own `PhysicsWorld` cannot do —
 * its boxes do not rotate — and what the lab's Rapier demo shows. Inputs are `ButtonInput`s.
 */
export function towerScene(options: TowerOptions = {}): RapierSceneDef<number, Tower> {
  const rows = checkCount('rows', options.rows ?? 8, 1, 60);
  const columns = checkCount('columns', options.columns ?? 2, 1, 20);
  const side = checkSize('box', options.box ?? 0.5, 0.05, 5);
  const radius = checkSize('ballRadius', options.ballRadius ?? 0.3, 0.05, 5);
  const speed = checkSize('launchSpeed', options.launchSpeed ?? 14, 0, 200);
  return {
    id: `rapier-tower-${rows}x${columns}`,
    players: options.players ?? 1,
    tickRate: options.tickRate ?? 60,
    build(world: World, rapier: RapierModule): Tower {
      const ground = world.createRigidBody(rapier.RigidBodyDesc.fixed().setTranslation(0, -0.5));
      world.createCollider(rapier.ColliderDesc.cuboid(30, 0.5).setFriction(0.8), ground);
      const boxes = buildTower(world, rapier, { x0: 4, rows, columns, side });
      const home = { x: -4, y: radius };
      const ball = world.createRigidBody(
        rapier.RigidBodyDesc.dynamic().setTranslation(home.x, home.y).setCcdEnabled(true),
      );
      world.createCollider(
        rapier.ColliderDesc.ball(radius).setDensity(4).setFriction(0.4).setRestitution(0.2),
        ball,
      );
      return {
        ball: ball.handle,
        boxes,
        ground: ground.handle,
        home,
        shots: 0,
        launchSpeed: speed,
      };
    },
    applyInputs(world, inputs, _tick, tower) {
      if (!inputs.some((input) => wasPressed(input, TowerButtons.FIRE))) return;
      const ball = world.getRigidBody(tower.ball);
      // Impulse = mass × Δv: from rest the ball leaves at launchSpeed, 15 % of it upwards.
      const m = ball.mass();
      ball.applyImpulse({ x: m * tower.launchSpeed, y: m * tower.launchSpeed * 0.15 }, true);
      tower.shots++;
    },
    checkInput: checkButtons,
    saveState: (tower) => new ByteWriter(8).u32(tower.shots).finish(),
    loadState(tower, bytes) {
      const r = new ByteReader(bytes);
      const shots = r.u32();
      r.end();
      tower.shots = shots;
    },
  };
}

/** A `ButtonInput` must be a u32. */
export function checkButtons(input: number): string | undefined {
  return Number.isInteger(input) && input >= 0 && input <= 0xffffffff
    ? undefined
    : `${String(input)} is not a ButtonInput (a u32)`;
}

/** Buttons of the {@link jointsScene}. */
export const JointsButtons = Object.freeze({
  /** Held: drive the slider's motor towards −x. */
  LEFT: 0,
  /** Held: drive the slider's motor towards +x. */
  RIGHT: 1,
});

/** What {@link jointsScene}'s build returns. */
export interface Joints {
  /** The chain's links, from the anchor down. */
  readonly links: readonly number[];
  /** The revolute joints of the chain (impulse joint handles). */
  readonly chainJoints: readonly number[];
  /** The slider body on its prismatic joint, and that joint. */
  readonly slider: number;
  readonly sliderJoint: number;
  /** A wheel on a revolute joint with a spring (motor to angle 0) on the slider. */
  readonly wheel: number;
  readonly wheelJoint: number;
}

/**
 * Joints: a chain of `links` boxes hanging by revolute joints from a fixed anchor, released from
 * horizontal; a slider on a prismatic joint whose motor the LEFT/RIGHT buttons drive
 * ({@link JointsButtons}); a wheel on the slider held by a motorised revolute joint acting as a
 * spring; a few boxes for the chain to hit.
 */
export function jointsScene(links = 10): RapierSceneDef<number, Joints> {
  if (!(Number.isInteger(links) && links >= 1 && links <= 100)) {
    throw new RangeError(
      `jointsScene: links must be an integer from 1 to 100, got ${String(links)}`,
    );
  }
  return {
    id: `rapier-joints-${links}`,
    build(world, rapier): Joints {
      const ground = world.createRigidBody(rapier.RigidBodyDesc.fixed());
      world.createCollider(rapier.ColliderDesc.cuboid(20, 0.5).setTranslation(0, -0.5), ground);
      const anchor = world.createRigidBody(rapier.RigidBodyDesc.fixed().setTranslation(0, 8));
      const linkHalf = 0.25;
      const bodies: number[] = [];
      const joints: number[] = [];
      let previous = anchor;
      for (let i = 0; i < links; i++) {
        const link = world.createRigidBody(
          rapier.RigidBodyDesc.dynamic().setTranslation(linkHalf + i * 2 * linkHalf, 8),
        );
        world.createCollider(
          rapier.ColliderDesc.cuboid(linkHalf, 0.08).setDensity(i === links - 1 ? 8 : 1),
          link,
        );
        const joint = world.createImpulseJoint(
          rapier.JointData.revolute(i === 0 ? { x: 0, y: 0 } : { x: linkHalf, y: 0 }, {
            x: -linkHalf,
            y: 0,
          }),
          previous,
          link,
          true,
        );
        bodies.push(link.handle);
        joints.push(joint.handle);
        previous = link;
      }
      const slider = world.createRigidBody(rapier.RigidBodyDesc.dynamic().setTranslation(-6, 1));
      world.createCollider(rapier.ColliderDesc.cuboid(0.6, 0.2).setDensity(2), slider);
      const rail = rapier.JointData.prismatic({ x: -6, y: 1 }, { x: 0, y: 0 }, { x: 1, y: 0 });
      rail.limitsEnabled = true;
      rail.limits = [-4, 4];
      const sliderJoint = world.createImpulseJoint(rail, ground, slider, true);
      const wheel = world.createRigidBody(rapier.RigidBodyDesc.dynamic().setTranslation(-6, 1.8));
      world.createCollider(rapier.ColliderDesc.ball(0.35).setDensity(1), wheel);
      const wheelJoint = world.createImpulseJoint(
        rapier.JointData.revolute({ x: 0, y: 0.8 }, { x: 0, y: 0 }),
        slider,
        wheel,
        true,
      );
      for (let i = 0; i < 4; i++) {
        const box = world.createRigidBody(
          rapier.RigidBodyDesc.dynamic().setTranslation(3 + i * 0.9, 0.4),
        );
        world.createCollider(rapier.ColliderDesc.cuboid(0.4, 0.4).setDensity(0.5), box);
      }
      return {
        links: bodies,
        chainJoints: joints,
        slider: slider.handle,
        sliderJoint: sliderJoint.handle,
        wheel: wheel.handle,
        wheelJoint: wheelJoint.handle,
      };
    },
    applyInputs(world, inputs, _tick, scene) {
      const input = inputs[0]!;
      const direction =
        (isDown(input, JointsButtons.RIGHT) ? 1 : 0) - (isDown(input, JointsButtons.LEFT) ? 1 : 0);
      const rapier = readyRapier('jointsScene');
      const rail = world.getImpulseJoint(scene.sliderJoint);
      const hinge = world.getImpulseJoint(scene.wheelJoint);
      if (
        !(rail instanceof rapier.PrismaticImpulseJoint) ||
        !(hinge instanceof rapier.RevoluteImpulseJoint)
      ) {
        throw new Error('jointsScene: the slider or wheel joint is missing or of another kind');
      }
      rail.configureMotorVelocity(direction * 3, 50);
      hinge.configureMotorPosition(0, 20, 1);
    },
    checkInput: checkButtons,
  };
}

/** Options of {@link physicsSceneDef}. */
export interface PhysicsSceneOptions {
  /** The scene's id. Default `rapier-physics-scene-<bodies>`. */
  readonly id?: string;
  /** Let the bodies rotate (Rapier's default); false locks rotation like the own world. Default true. */
  readonly rotation?: boolean;
  /** Let bodies sleep. Default false (a sleeping pile costs nothing to step). */
  readonly sleep?: boolean;
  /**
   * Rapier's `numSolverIterations`. Default: the scene's `velocityIterations`, as the
   * physics-circles benchmark sets it.
   */
  readonly solverIterations?: number;
  /** Make circles boxes of the same width (2 r); the own world's AABBs. Default false. */
  readonly boxes?: boolean;
}

/**
 * fixedstep's own scene description (`circlesInBoxScene`, `bulletsScene` … without segments)
 * built in Rapier: the same walls, circles (or boxes), gravity, step, friction and restitution.
 * No inputs. For side-by-side comparisons of the two worlds.
 */
export function physicsSceneDef(
  scene: PhysicsScene,
  options: PhysicsSceneOptions = {},
): RapierSceneDef<number, { readonly bodies: readonly number[] }> {
  const d = scene.def;
  if (scene.segments.length > 0) {
    throw new RangeError('physicsSceneDef: scenes with segments are not supported');
  }
  const tickRate = 1 / d.timeStep;
  if (Math.abs(tickRate - Math.round(tickRate)) > 1e-9) {
    throw new RangeError(`physicsSceneDef: the step ${String(d.timeStep)} s is not 1/n s`);
  }
  const rotation = options.rotation ?? true;
  return {
    id: options.id ?? `rapier-physics-scene-${scene.bodies.length}`,
    tickRate: Math.round(tickRate),
    gravity: { x: d.gravityX, y: d.gravityY },
    solverIterations: options.solverIterations ?? d.velocityIterations,
    build(world, rapier) {
      for (const w of scene.walls) {
        world.createCollider(
          rapier.ColliderDesc.cuboid(w.halfWidth, w.halfHeight)
            .setTranslation(w.x, w.y)
            .setFriction(d.friction)
            .setRestitution(d.restitution),
        );
      }
      const bodies = scene.bodies.map((b, i) => {
        const desc = rapier.RigidBodyDesc.dynamic()
          .setTranslation(b.x, b.y)
          .setLinvel(b.vx, b.vy)
          .setCanSleep(options.sleep ?? false);
        if (!rotation) desc.lockRotations();
        const body = world.createRigidBody(desc);
        const r = b.radius;
        const collider =
          r !== undefined
            ? options.boxes
              ? rapier.ColliderDesc.cuboid(r, r)
              : rapier.ColliderDesc.ball(r)
            : b.halfWidth !== undefined && b.halfHeight !== undefined
              ? rapier.ColliderDesc.cuboid(b.halfWidth, b.halfHeight)
              : undefined;
        if (collider === undefined) {
          throw new RangeError(`physicsSceneDef: body ${i} is neither a circle nor a box`);
        }
        world.createCollider(
          collider.setDensity(1).setFriction(d.friction).setRestitution(d.restitution),
          body,
        );
        return body.handle;
      });
      return { bodies };
    },
  };
}
