import { PhysicsWorld, Random, tunnellingShare, type CcdMode } from 'fixedstep';

export interface TunnelSetting {
  /** Body speed towards the wall, m/s. */
  speed: number;
  /** Wall thickness, m. */
  wall: number;
  /** Body radius, m. */
  radius: number;
  /** Fixed step, s. */
  dt: number;
  /** CCD mode of the world: 'off' is pure discrete detection. */
  ccd: CcdMode;
}

export interface TunnelResult extends TunnelSetting {
  trials: number;
  /** Bodies that ended on the far side of the wall. */
  tunnelled: number;
  /** tunnelled / trials. */
  share: number;
  /** What geometry predicts for discrete detection with push-out: max(0, 1 − (w + 2r)/(2·v·dt)). */
  theory: number;
}

/**
 * Fires `trials` circles at a wall, each with a uniformly random phase (how far it is from the
 * wall when a step begins), and counts how many end up on the far side. All circles fly in
 * separate lanes of one world, so they never touch each other; gravity is off.
 *
 * The wall reaches far past the outermost lanes (a step of travel, the wall and a body beyond
 * them): a body that lands inside the wall is pushed out through the nearer of its faces, and an
 * end face nearer than the far face would push an outermost body round the wall's end — a harness
 * artefact, not tunnelling. So only the two faces the bodies fly at can be the nearer one, and
 * the measured share is the geometry of {@link TunnelResult.theory}.
 */
export function measureTunnelling(
  setting: TunnelSetting,
  trials: number,
  seed: number,
): TunnelResult {
  const { speed, wall, radius, dt, ccd } = setting;
  if (!(speed > 0 && wall > 0 && radius > 0 && dt > 0)) {
    throw new RangeError('measureTunnelling: speed, wall, radius and dt must be positive');
  }
  if (!(Number.isInteger(trials) && trials >= 1 && trials <= 100_000)) {
    throw new RangeError(
      `measureTunnelling: trials must be an integer from 1 to 100000, got ${trials}`,
    );
  }
  const world = new PhysicsWorld({
    gravityX: 0,
    gravityY: 0,
    timeStep: dt,
    restitution: 0,
    friction: 0,
    ccd,
  });
  const lane = radius * 3;
  const height = trials * lane;
  const wallLeft = 0;
  const step = speed * dt;
  // Deeper than any body can get into the wall (one step plus the wall plus a diameter): the end
  // faces are never the nearer face for any lane.
  const overhang = lane + step + wall + 2 * radius;
  world.addStaticBox(wallLeft + wall / 2, height / 2, wall / 2, height / 2 + overhang);
  const rng = new Random(seed);
  const ids: number[] = [];
  for (let i = 0; i < trials; i++) {
    // One full step away plus a random phase: the first contact can fall anywhere in a step.
    const x = wallLeft - radius - step * (1 + rng.next());
    ids.push(world.createCircle({ x, y: (i + 0.5) * lane, radius, vx: speed }));
  }
  // Long enough to cross the wall at this speed, and then some.
  const steps = 3 + Math.ceil((wall + 2 * radius) / step);
  for (let s = 0; s < steps; s++) world.step();
  let tunnelled = 0;
  const xs = world.x;
  for (const id of ids) if (xs[id]! > wallLeft + wall / 2) tunnelled++;
  return {
    ...setting,
    trials,
    tunnelled,
    share: tunnelled / trials,
    theory: tunnellingShare(speed, wall, radius, dt),
  };
}
