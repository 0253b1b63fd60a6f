/** Checks of a circles-in-a-box world, so nobody benchmarks an empty or exploded scene. */
import type { PhysicsScene } from 'fixedstep';
import type { PeerWorld } from './types.js';

/** Random close packing of discs, roughly: the share of the pile's area the circles fill. */
export const PACKING = 0.82;

/** Steps to settle: `base` (default 120), plus the free-fall time of the top row to the floor. */
export function settleSteps(scene: PhysicsScene, base = 120): number {
  const top = Math.max(...scene.bodies.map((b) => b.y));
  const g = Math.hypot(scene.def.gravityX, scene.def.gravityY);
  return base + Math.ceil(Math.sqrt((2 * top) / g) / scene.def.timeStep);
}

export interface Sanity {
  /** Bodies whose centre is inside the box's inner extent. */
  readonly inBox: number;
  /** 95th percentile of the bodies' tops (y + r), m. */
  readonly pileTop: number;
  /** Largest overlap of two circles, m. */
  readonly maxOverlap: number;
  /** Mean speed over one step, m/s. */
  readonly meanSpeed: number;
  /** Bodies asleep (must be 0: sleeping is off everywhere). */
  readonly asleep: number;
}

/** Checks a world: steps it once (for the speed) and measures where its bodies are. */
export function sanity(world: PeerWorld, scene: PhysicsScene): Sanity {
  const n = world.count;
  const x0 = new Float64Array(n);
  const y0 = new Float64Array(n);
  const x = new Float64Array(n);
  const y = new Float64Array(n);
  world.positions(x0, y0);
  world.step();
  world.positions(x, y);
  const r = scene.bodies.map((b) => b.radius ?? 0);
  const [minX, minY, maxX, maxY] = scene.inner;
  let inBox = 0;
  let speed = 0;
  for (let i = 0; i < n; i++) {
    const xi = x[i]!;
    const yi = y[i]!;
    if (xi >= minX && xi <= maxX && yi >= minY && yi <= maxY) inBox++;
    speed += Math.sqrt((xi - x0[i]!) ** 2 + (yi - y0[i]!) ** 2) / scene.def.timeStep;
  }
  const tops = Array.from(y, (v, i) => v + r[i]!).sort((a, b) => a - b);
  // Overlaps: sort by x, compare neighbours closer than the largest diameter.
  const order = Array.from(x, (_, i) => i).sort((a, b) => x[a]! - x[b]!);
  const rMax = Math.max(0, ...r);
  let maxOverlap = 0;
  for (let p = 0; p < n; p++) {
    const i = order[p]!;
    for (let q = p + 1; q < n; q++) {
      const j = order[q]!;
      const dx = x[j]! - x[i]!;
      if (dx > 2 * rMax) break;
      const overlap = r[i]! + r[j]! - Math.sqrt(dx * dx + (y[j]! - y[i]!) ** 2);
      if (overlap > maxOverlap) maxOverlap = overlap;
    }
  }
  return {
    inBox,
    pileTop: tops[Math.min(n - 1, Math.floor(0.95 * n))] ?? 0,
    maxOverlap,
    meanSpeed: n > 0 ? speed / n : 0,
    asleep: world.sleeping(),
  };
}

/** Height of the pile if the circles filled `packing` of it: Σπr² / (width × packing), m. */
export function expectedPileHeight(scene: PhysicsScene, packing = PACKING): number {
  const area = scene.bodies.reduce((s, b) => s + Math.PI * (b.radius ?? 0) ** 2, 0);
  return area / ((scene.inner[2] - scene.inner[0]) * packing);
}
