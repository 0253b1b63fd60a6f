/**
 * Rapier 2D (Rust compiled to WASM, the `-compat` build with the WASM embedded), in metres as is,
 * f32 inside. Rotations locked, sleeping off; `numSolverIterations` (its substeps, default 4) is
 * set to the scene's velocity iterations unless told otherwise. Call {@link initRapier} first.
 */
import RAPIER from '@dimforge/rapier2d-compat';
import type { PhysicsScene } from 'fixedstep';
import { packageVersion, sceneCircles, type PeerWorld } from './types.js';

let ready: Promise<void> | undefined;

/** Instantiates the WASM module (once). */
export function initRapier(): Promise<void> {
  ready ??= RAPIER.init();
  return ready;
}

export function buildRapier(scene: PhysicsScene, solverIterations?: number): PeerWorld {
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
    const body = world.createRigidBody(
      RAPIER.RigidBodyDesc.dynamic().setTranslation(c.x, c.y).lockRotations().setCanSleep(false),
    );
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
      (solverIterations === undefined ? '' : ` (${iterations} iterations)`),
    settings: `numSolverIterations ${iterations} (default 4), no sleeping, rotations locked, no CCD`,
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
