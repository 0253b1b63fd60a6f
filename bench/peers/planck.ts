/**
 * planck.js (Box2D v2.3 in JavaScript), in metres as is. Rotation fixed, sleeping off; its
 * defaults otherwise (warm starting, continuous collision against static bodies, block solver).
 */
import { Box, Circle, Vec2, World, type Body } from 'planck';
import type { PhysicsScene } from 'fixedstep';
import { packageVersion, sceneCircles, type PeerWorld } from './types.js';

export function buildPlanck(scene: PhysicsScene): PeerWorld {
  const d = scene.def;
  const world = new World({ gravity: new Vec2(d.gravityX, d.gravityY), allowSleep: false });
  const ground = world.createBody();
  for (const w of scene.walls) {
    ground.createFixture(new Box(w.halfWidth, w.halfHeight, new Vec2(w.x, w.y), 0), {
      friction: d.friction,
      restitution: d.restitution,
    });
  }
  const bodies: Body[] = sceneCircles(scene).map((c) => {
    const body = world.createBody({
      type: 'dynamic',
      position: new Vec2(c.x, c.y),
      fixedRotation: true,
      allowSleep: false,
    });
    body.createFixture(new Circle(c.r), {
      density: 1,
      friction: d.friction,
      restitution: d.restitution,
    });
    return body;
  });
  return {
    name: `planck ${packageVersion('planck')}`,
    settings:
      `${d.velocityIterations} velocity + ${d.positionIterations} position iterations, ` +
      `no sleeping, fixed rotation, warm starting, CCD vs static`,
    count: bodies.length,
    step: () => {
      world.step(d.timeStep, d.velocityIterations, d.positionIterations);
    },
    positions(x, y) {
      for (let i = 0; i < bodies.length; i++) {
        const p = bodies[i]!.getPosition();
        x[i] = p.x;
        y[i] = p.y;
      }
    },
    radii: () =>
      Float64Array.from(bodies, (b) => {
        const shape = b.getFixtureList()?.getShape();
        return shape?.getType() === 'circle' ? shape.getRadius() : NaN;
      }),
    sleeping: () => bodies.filter((b) => !b.isAwake()).length,
    dispose() {
      // Garbage-collected.
    },
  };
}
