/**
 * fixedstep's own PhysicsWorld behind the {@link PeerWorld} interface, with sleeping off like the
 * peers (a sleeping pile costs almost nothing, which is not what the benchmark measures).
 */
import { buildWorld, type PhysicsScene } from 'fixedstep';
import { sceneCircles, type PeerWorld } from './types.js';

export function buildFixedstep(scene: PhysicsScene): PeerWorld {
  const count = sceneCircles(scene).length;
  const def = { ...scene.def, enableSleep: false };
  const world = buildWorld({ ...scene, def });
  return {
    name: 'fixedstep',
    settings:
      `${def.velocityIterations} velocity + ${def.positionIterations} position iterations, ` +
      `no sleeping, no rotation, CCD ${def.ccd}`,
    count,
    step: () => {
      world.step();
    },
    positions(x, y) {
      x.set(world.x.subarray(0, count));
      y.set(world.y.subarray(0, count));
    },
    radii: () => Float64Array.from(world.halfWidth.subarray(0, count)),
    sleeping: () => world.sleepingCount,
    dispose() {
      // Plain typed arrays: nothing to free.
    },
  };
}
