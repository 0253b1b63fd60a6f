import { Random } from '../../det/random.js';
import { defaultWorldDef, type WorldDef } from './def.js';
import { PhysicsWorld } from './world.js';

/**
 * Scene builders shared by the tests, the benchmarks and the lab (one builder, many users). Each
 * comes as a plain description (so another engine can build the same scene) and as a ready
 * {@link PhysicsWorld}.
 */

/** A static axis-aligned box: centre and half extents, metres. */
export interface SceneBox {
  x: number;
  y: number;
  halfWidth: number;
  halfHeight: number;
}

/** A static segment, metres. */
export interface SceneSegment {
  ax: number;
  ay: number;
  bx: number;
  by: number;
}

/** A body of a scene. A circle has `radius`; a box has `halfWidth` and `halfHeight`. */
export interface SceneBody {
  x: number;
  y: number;
  vx: number;
  vy: number;
  radius?: number;
  halfWidth?: number;
  halfHeight?: number;
  bullet?: boolean;
}

/** A whole scene: the world's def, static walls, bodies in creation order. */
export interface PhysicsScene {
  def: WorldDef;
  walls: SceneBox[];
  segments: SceneSegment[];
  bodies: SceneBody[];
  /** Inner extent of the container, metres: `[minX, minY, maxX, maxY]`. */
  inner: [number, number, number, number];
}

/** Builds a {@link PhysicsWorld} from a scene: walls, then segments, then bodies, in order. */
export function buildWorld(scene: PhysicsScene): PhysicsWorld {
  const world = new PhysicsWorld(scene.def, { capacity: Math.max(16, scene.bodies.length) });
  for (const w of scene.walls) world.addStaticBox(w.x, w.y, w.halfWidth, w.halfHeight);
  for (const s of scene.segments) world.addSegment(s.ax, s.ay, s.bx, s.by);
  for (const b of scene.bodies) {
    if (b.radius !== undefined) {
      world.createCircle({
        x: b.x,
        y: b.y,
        vx: b.vx,
        vy: b.vy,
        radius: b.radius,
        bullet: b.bullet,
      });
    } else {
      world.createBox({
        x: b.x,
        y: b.y,
        vx: b.vx,
        vy: b.vy,
        halfWidth: b.halfWidth ?? 0,
        halfHeight: b.halfHeight ?? 0,
        bullet: b.bullet,
      });
    }
  }
  return world;
}

/** A closed box of four static walls 1 m thick around `[minX, minY, maxX, maxY]`. */
function container(minX: number, minY: number, maxX: number, maxY: number): SceneBox[] {
  const cx = (minX + maxX) / 2;
  const cy = (minY + maxY) / 2;
  const hw = (maxX - minX) / 2 + 1;
  const hh = (maxY - minY) / 2 + 1;
  return [
    { x: cx, y: minY - 0.5, halfWidth: hw, halfHeight: 0.5 },
    { x: cx, y: maxY + 0.5, halfWidth: hw, halfHeight: 0.5 },
    { x: minX - 0.5, y: cy, halfWidth: 0.5, halfHeight: hh },
    { x: maxX + 0.5, y: cy, halfWidth: 0.5, halfHeight: hh },
  ];
}

/**
 * `n` circles (radius 0.10–0.15 m, density 1) falling into a closed box, the benchmark scene.
 * They start at rest on a jittered 0.4 m lattice, `ceil(1.5·√n)` (at least 10) columns wide, filled
 * row by row from 0.2 m above the floor; the box's inner width is the lattice width and its inner
 * height 2 m above the top row; walls are 1 m thick. Default def: gravity −9.81 m/s², 1/60 s.
 */
export function circlesInBoxScene(
  n: number,
  seed: number,
  def: Partial<WorldDef> = {},
): PhysicsScene {
  return latticeInBox('circlesInBox', n, seed, def, (_k, x, y, rng) => ({
    x,
    y,
    vx: 0,
    vy: 0,
    radius: rng.range(0.1, 0.15),
  }));
}

/** {@link circlesInBoxScene} as a ready world. */
export function circlesInBox(n: number, seed: number, def: Partial<WorldDef> = {}): PhysicsWorld {
  return buildWorld(circlesInBoxScene(n, seed, def));
}

/**
 * `n` bodies falling into a closed box, circles and axis-aligned boxes alternating (even indices
 * circles of radius 0.10–0.15 m, odd ones boxes of half extents 0.08–0.14 m each), density 1:
 * the rollback benchmark scene (`npm run bench -- physics-world-snapshot`), also for other
 * engines (build it from the description, with rotation locked to compare like with like). The
 * lattice, the box and the def are those of {@link circlesInBoxScene}.
 */
export function bodiesInBoxScene(
  n: number,
  seed: number,
  def: Partial<WorldDef> = {},
): PhysicsScene {
  return latticeInBox('bodiesInBox', n, seed, def, (k, x, y, rng) => {
    if (k % 2 === 0) return { x, y, vx: 0, vy: 0, radius: rng.range(0.1, 0.15) };
    const halfWidth = rng.range(0.08, 0.14);
    return { x, y, vx: 0, vy: 0, halfWidth, halfHeight: rng.range(0.08, 0.14) };
  });
}

/**
 * The box scenes' layout: `n` bodies at rest on a jittered 0.4 m lattice, `ceil(1.5·√n)` (at least
 * 10) columns wide, filled row by row from 0.2 m above the floor, in a closed box as wide as the
 * lattice and 2 m higher than its top row. `make` makes body `k` at (x, y), drawing its size from
 * `rng` after the jitter of its position.
 */
function latticeInBox(
  what: string,
  n: number,
  seed: number,
  def: Partial<WorldDef>,
  make: (k: number, x: number, y: number, rng: Random) => SceneBody,
): PhysicsScene {
  if (!(Number.isInteger(n) && n >= 0))
    throw new RangeError(`${what}: n must be a non-negative integer, got ${String(n)}`);
  const rng = new Random(seed);
  const spacing = 0.4;
  const cols = Math.max(10, Math.ceil(1.5 * Math.sqrt(n)));
  const rows = Math.ceil(n / cols);
  const width = cols * spacing;
  const height = rows * spacing + 2;
  const bodies: SceneBody[] = [];
  for (let k = 0; k < n; k++) {
    const col = k % cols;
    const row = (k - col) / cols;
    const x = -width / 2 + spacing / 2 + col * spacing + rng.range(-0.04, 0.04);
    const y = spacing / 2 + row * spacing + rng.range(-0.04, 0.04);
    bodies.push(make(k, x, y, rng));
  }
  return {
    def: { ...defaultWorldDef(), ...def },
    walls: container(-width / 2, 0, width / 2, height),
    segments: [],
    bodies,
    inner: [-width / 2, 0, width / 2, height],
  };
}

/** {@link bodiesInBoxScene} as a ready world. */
export function bodiesInBox(n: number, seed: number, def: Partial<WorldDef> = {}): PhysicsWorld {
  return buildWorld(bodiesInBoxScene(n, seed, def));
}

/**
 * Bullets in a walled room, at the talk's step of 0.03 s: a closed 20 × 10 m box, three thin
 * vertical wall segments, two thin shelves (static boxes 2 cm thick), 20 circles and 10 boxes
 * dropped on the floor, and 30 bullets (radius 3 cm) fired at 200–1000 m/s in random directions.
 * Restitution 0.5, so bullets ricochet. Without continuous detection they leave the room.
 */
export function bulletsScene(seed: number, def: Partial<WorldDef> = {}): PhysicsScene {
  const rng = new Random(seed);
  const bodies: SceneBody[] = [];
  const xs = [-7.5, -2.5, 2.5, 7.5];
  for (let k = 0; k < 30; k++) {
    const x = xs[k % 4]! + rng.range(-1.5, 1.5);
    const y = 0.4 + Math.floor(k / 4) * 0.6;
    if (k < 20) bodies.push({ x, y, vx: 0, vy: 0, radius: rng.range(0.15, 0.25) });
    else bodies.push({ x, y, vx: 0, vy: 0, halfWidth: 0.25, halfHeight: rng.range(0.15, 0.25) });
  }
  for (let k = 0; k < 30; k++) {
    let dx = 0;
    let dy = 0;
    let len2 = 0;
    while (len2 < 0.01 || len2 > 1) {
      dx = rng.range(-1, 1);
      dy = rng.range(-1, 1);
      len2 = dx * dx + dy * dy;
    }
    const len = Math.sqrt(len2);
    const speed = rng.range(200, 1000);
    bodies.push({
      x: xs[k % 4]! + rng.range(-1.5, 1.5),
      y: rng.range(6, 9.5),
      vx: (speed * dx) / len,
      vy: (speed * dy) / len,
      radius: 0.03,
      bullet: true,
    });
  }
  return {
    def: { ...defaultWorldDef(), timeStep: 0.03, restitution: 0.5, ...def },
    walls: [
      ...container(-10, 0, 10, 10),
      { x: -5, y: 5, halfWidth: 3, halfHeight: 0.01 },
      { x: 5, y: 5, halfWidth: 3, halfHeight: 0.01 },
    ],
    segments: [
      { ax: -5, ay: 1.5, bx: -5, by: 8 },
      { ax: 0, ay: 2, bx: 0, by: 10 },
      { ax: 5, ay: 1.5, bx: 5, by: 8 },
    ],
    bodies,
    inner: [-10, 0, 10, 10],
  };
}
