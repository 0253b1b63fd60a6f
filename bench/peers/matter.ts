/**
 * matter-js. Its tolerances (slop, resting thresholds) are tuned for pixels, so the scene is built
 * at 100 px per metre with y down, and gravity scaled to 9.81 m/s²; positions are mapped back.
 * Its circles are polygons (10 to 15 sides at this size). Rotation is locked (infinite inertia)
 * like fixedstep's bodies, air friction is 0, sleeping off.
 */
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { compileFunction } from 'node:vm';
import type Matter from 'matter-js';
import type { PhysicsScene } from 'fixedstep';
import { packageVersion, sceneCircles, type PeerWorld } from './types.js';

let matter: typeof Matter | undefined;

/**
 * matter-js, evaluated from its UMD build by hand when first needed rather than imported. It is
 * CommonJS, and under `npm run bench` tsx's CommonJS hook runs such files through esbuild's
 * synchronous API, which detaches an ArrayBuffer in the main thread. That turns off a V8 fast path
 * for the whole process (its "ArrayBufferDetaching" protector): from then on every typed-array
 * access pays a detached-buffer check (spring kernels ran ~30 % slower). The bench process loads
 * this module to list the engines, so importing matter-js here would slow down every suite.
 */
export function loadMatter(): typeof Matter {
  if (matter === undefined) {
    const file = createRequire(import.meta.url).resolve('matter-js');
    const module = { exports: {} as unknown };
    const factory = compileFunction(readFileSync(file, 'utf8'), ['module', 'exports'], {
      filename: file,
    });
    factory.call(globalThis, module, module.exports);
    matter = module.exports as typeof Matter;
  }
  return matter;
}

/** Pixels per metre. */
export const MATTER_SCALE = 100;

export function buildMatter(scene: PhysicsScene): PeerWorld {
  const { Bodies, Body, Composite, Engine } = loadMatter();
  const d = scene.def;
  const s = MATTER_SCALE;
  const g = Math.hypot(d.gravityX, d.gravityY);
  const engine = Engine.create({
    enableSleeping: false,
    velocityIterations: d.velocityIterations,
    positionIterations: d.positionIterations,
    // matter: acceleration in px/ms² = gravity × scale.
    gravity:
      g > 0
        ? { x: d.gravityX / g, y: -d.gravityY / g, scale: (g * s) / 1e6 }
        : { x: 0, y: 0, scale: 0 },
  });
  const material = {
    friction: d.friction,
    restitution: d.restitution,
    frictionAir: 0,
    slop: d.linearSlop * s,
  };
  const walls = scene.walls.map((w) =>
    Bodies.rectangle(w.x * s, -w.y * s, 2 * w.halfWidth * s, 2 * w.halfHeight * s, {
      ...material,
      isStatic: true,
    }),
  );
  const bodies = sceneCircles(scene).map((c) => {
    const body = Bodies.circle(c.x * s, -c.y * s, c.r * s, { ...material, density: 1 / (s * s) });
    Body.setInertia(body, Infinity);
    return body;
  });
  Composite.add(engine.world, [...walls, ...bodies]);
  const stepMs = d.timeStep * 1000;
  return {
    name: `matter-js ${packageVersion('matter-js')}`,
    settings:
      `${d.velocityIterations} velocity + ${d.positionIterations} position iterations ` +
      `(defaults 4 + 6), no sleeping, rotation locked, polygon circles, ${s} px/m`,
    count: bodies.length,
    step: () => {
      Engine.update(engine, stepMs);
    },
    positions(x, y) {
      for (let i = 0; i < bodies.length; i++) {
        const p = bodies[i]!.position;
        x[i] = p.x / s;
        y[i] = -p.y / s;
      }
    },
    radii: () => Float64Array.from(bodies, (b) => (b.circleRadius ?? NaN) / s),
    sleeping: () => bodies.filter((b) => b.isSleeping).length,
    dispose() {
      Engine.clear(engine);
    },
  };
}
