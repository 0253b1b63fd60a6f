/**
 * One interface over the physics engines the `physics-circles` suite compares: each builds the
 * same {@link PhysicsScene} (fixedstep's scene description: static walls, then circles in order)
 * as closely as the engine allows, steps it by the scene's fixed step and reads the circles back
 * in the scene's frame (metres, y up).
 */
import { createRequire } from 'node:module';
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import type { PhysicsScene } from 'fixedstep';

export interface PeerWorld {
  /** Engine and version, for tables: `planck 1.5.0`. */
  readonly name: string;
  /** How it was configured, in one line (iterations, sleeping, rotation …). */
  readonly settings: string;
  /** Dynamic bodies (the scene's, in its order). */
  readonly count: number;
  /** One fixed step of the scene's `def.timeStep`. */
  step(): void;
  /** Writes the body centres, in metres with y up (the scene's frame), into `x` and `y`. */
  positions(x: Float64Array, y: Float64Array): void;
  /** Radius of every body as the engine holds it, in metres (for the parity test). */
  radii(): Float64Array;
  /** Bodies asleep now (should stay 0: the benchmark turns sleeping off everywhere). */
  sleeping(): number;
  /** Frees what the engine does not collect by itself (rapier's WASM memory). */
  dispose(): void;
}

export type PeerBuilder = (scene: PhysicsScene) => PeerWorld;

/** The scene's circles, or a clear error if it holds anything else (the peers build circles only). */
export function sceneCircles(scene: PhysicsScene): { x: number; y: number; r: number }[] {
  if (scene.segments.length > 0)
    throw new RangeError('peers: scenes with segments are not supported');
  return scene.bodies.map((b, i) => {
    if (b.radius === undefined) throw new RangeError(`peers: body ${i} is not a circle`);
    if (b.vx !== 0 || b.vy !== 0) throw new RangeError(`peers: body ${i} does not start at rest`);
    return { x: b.x, y: b.y, r: b.radius };
  });
}

/** The installed version of an npm package (from its package.json), or `?`. */
export function packageVersion(name: string): string {
  try {
    let dir = dirname(createRequire(import.meta.url).resolve(name));
    for (;;) {
      const file = join(dir, 'package.json');
      if (existsSync(file)) {
        const pkg = JSON.parse(readFileSync(file, 'utf8')) as { name?: string; version?: string };
        if (pkg.name === name && pkg.version !== undefined) return pkg.version;
      }
      const up = dirname(dir);
      if (up === dir) return '?';
      dir = up;
    }
  } catch {
    return '?';
  }
}
