/**
 * Rapier 2D (Rust compiled to WASM, the `-compat` build with the WASM embedded), in metres as is,
 * f32 inside. Rotations locked unless asked (fixedstep's bodies do not rotate), sleeping off;
 * `numSolverIterations` (its substeps, default 4) is set to the scene's velocity iterations unless
 * told otherwise. Call {@link initRapier} first. {@link buildRapierDeterministic} builds the same
 * world in Rapier's deterministic build, the one `@fixedstep/rapier` runs.
 */
import RAPIER from '@dimforge/rapier2d-compat';
import { loadRapier, physicsSceneDef, RapierSimulation } from '@fixedstep/rapier';
import type { PhysicsScene } from 'fixedstep';
import { packageVersion, sceneCircles, type PeerWorld } from './types.js';

let ready: Promise<void> | undefined;

/** Instantiates the WASM module (once). */
export function initRapier(): Promise<void> {
  ready ??= RAPIER.init();
  return ready;
}

/** How a Rapier peer is set up. */
export interface RapierPeerOptions {
  /** Rapier's `numSolverIterations`. Default: the scene's velocity iterations. */
  readonly solverIterations?: number;
  /** Let the circles rotate (Rapier's default for a dynamic body). Default false. */
  readonly rotation?: boolean;
}

export function buildRapier(scene: PhysicsScene, options: RapierPeerOptions = {}): PeerWorld {
  const { solverIterations, rotation = false } = options;
  const d = scene.def;
  const iterations = solverIterations ?? d.velocityIterations;
  const world = new RAPIER.World({ x: d.gravityX, y: d.gravityY });
  world.timestep = d.timeStep;
  world.numSolverIterations = iterations;
  for (const w of scene.walls) {
    world.createCollider(
      RAPIER.ColliderDesc.cuboid(w.halfWidth, w.halfHeight)
        .setTranslation(w.x, w.y)
        .setFriction(d.friction)
        .setRestitution(d.restitution),
    );
  }
  const bodies = sceneCircles(scene).map((c) => {
    const desc = RAPIER.RigidBodyDesc.dynamic().setTranslation(c.x, c.y).setCanSleep(false);
    const body = world.createRigidBody(rotation ? desc : desc.lockRotations());
    world.createCollider(
      RAPIER.ColliderDesc.ball(c.r)
        .setDensity(1)
        .setFriction(d.friction)
        .setRestitution(d.restitution),
      body,
    );
    return body;
  });
  return {
    name:
      `rapier2d ${packageVersion('@dimforge/rapier2d-compat')}` +
      (solverIterations === undefined ? '' : ` (${iterations} iterations)`) +
      (rotation ? ' rotating' : ''),
    settings:
      `numSolverIterations ${iterations} (default 4), no sleeping, ` +
      `rotations ${rotation ? 'unlocked' : 'locked'}, no CCD`,
    count: bodies.length,
    step: () => {
      world.step();
    },
    positions(x, y) {
      for (let i = 0; i < bodies.length; i++) {
        const p = bodies[i]!.translation();
        x[i] = p.x;
        y[i] = p.y;
      }
    },
    radii: () =>
      Float64Array.from(bodies, (b) => {
        const collider = b.collider(0);
        return collider.radius();
      }),
    sleeping: () => bodies.filter((b) => b.isSleeping()).length,
    dispose() {
      world.free();
    },
  };
}

/**
 * The scene in Rapier's deterministic build (`@dimforge/rapier2d-deterministic-compat`) through
 * `@fixedstep/rapier`'s {@link RapierSimulation}: rotation unlocked, no sleeping, the scene's
 * velocity iterations — what a game under fixedstep pays per step (the adapter adds an input check).
 */
export async function buildRapierDeterministic(scene: PhysicsScene): Promise<PeerWorld> {
  await loadRapier();
  const sim = new RapierSimulation(physicsSceneDef(scene, { id: 'physics-circles' }));
  const none: readonly number[] = [0];
  const bodies = sim.scene.bodies.map((h) => sim.world.getRigidBody(h));
  return {
    name: `rapier2d-deterministic ${packageVersion('@dimforge/rapier2d-deterministic-compat')} rotating`,
    settings:
      `@fixedstep/rapier RapierSimulation.step(), numSolverIterations ${scene.def.velocityIterations}, ` +
      'no sleeping, rotations unlocked, no CCD',
    count: bodies.length,
    step: () => {
      sim.step(none);
    },
    positions(x, y) {
      for (let i = 0; i < bodies.length; i++) {
        const p = bodies[i]!.translation();
        x[i] = p.x;
        y[i] = p.y;
      }
    },
    radii: () => Float64Array.from(bodies, (b) => b.collider(0).radius()),
    sleeping: () => bodies.filter((b) => b.isSleeping()).length,
    dispose() {
      sim.dispose();
    },
  };
}
