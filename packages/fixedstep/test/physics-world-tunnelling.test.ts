import { describe, expect, it } from 'vitest';
import { PhysicsWorld, Random, tunnellingShare, type CcdMode } from 'fixedstep';

/**
 * The talk's collision claims, measured. Every experiment fires many bodies at a wall, each with a
 * uniformly random starting phase (seeded), and counts how many end on the far side.
 */

interface Shot {
  speed: number;
  /** Wall thickness; 0 = a segment. */
  wall: number;
  /** Radius (a box body's half extent). */
  radius: number;
  dt: number;
  ccd: CcdMode;
  shape?: 'circle' | 'box';
  bullet?: boolean;
  /** Largest sideways speed as a share of `speed` (each body gets a random one). */
  spread?: number;
  phases?: number;
  seed?: number;
}

/** Share of bodies whose centre ends past the middle of the wall. */
function fire(s: Shot): number {
  const phases = s.phases ?? 2000;
  const r = s.radius;
  const world = new PhysicsWorld(
    { gravityY: 0, timeStep: s.dt, ccd: s.ccd, restitution: 0.5 },
    { capacity: phases },
  );
  const spacing = 4 * r;
  const height = phases * spacing;
  // Far longer than any sideways drift, so nothing can go round the end.
  if (s.wall > 0) world.addStaticBox(s.wall / 2, height / 2, s.wall / 2, height / 2 + 200);
  else world.addSegment(0, -200, 0, height + 200);
  const rng = new Random(s.seed ?? 1);
  const d = s.speed * s.dt;
  for (let k = 0; k < phases; k++) {
    // Touching distance minus a uniform share of one step: the first overlapping position is
    // uniform over one step.
    const o = {
      x: -r - rng.next() * d,
      y: k * spacing + spacing / 2,
      vx: s.speed,
      vy: (s.spread ?? 0) * s.speed * rng.range(-1, 1),
      bullet: s.bullet ?? false,
    };
    if ((s.shape ?? 'circle') === 'circle') world.createCircle({ ...o, radius: r });
    else world.createBox({ ...o, halfWidth: r, halfHeight: r });
  }
  const steps = Math.ceil((s.wall + 2 * r) / d) + 4;
  for (let t = 0; t < steps; t++) world.step();
  let far = 0;
  for (let k = 0; k < phases; k++) if (world.x[k]! > s.wall / 2) far++;
  return far / phases;
}

// [speed m/s, wall thickness m (0 = segment), radius m, dt s, shape]
const settings: [number, number, number, number, 'circle' | 'box'][] = [
  [10, 0.1, 0.05, 0.03, 'circle'], // talk's rule broken
  [20, 0.2, 0.05, 0.03, 'circle'],
  [10, 0.3, 0.05, 0.03, 'circle'], // w = v·dt exactly: the rule holds, a third still tunnel
  [10, 0.4, 0.02, 0.03, 'circle'], // the rule holds with room to spare: a quarter tunnel
  [30, 0.2, 0.1, 1 / 60, 'circle'],
  [10, 0, 0.05, 0.03, 'circle'], // a segment
  [20, 0.1, 0.05, 0.03, 'box'],
  [5, 0.1, 0.1, 0.03, 'circle'], // v·dt = w/2 + r: always bounces
];

/** Three standard deviations of a share over 2000 phases is at most 0.034; we allow 0.03. */
const TOLERANCE = 0.03;

describe('discrete detection: the share that tunnels is max(0, 1 − (w + 2r) / (2·v·dt))', () => {
  const rows: string[] = [];
  it.each(settings)(
    'v = %s m/s, w = %s m, r = %s m, dt = %s s (%s)',
    (speed, wall, radius, dt, shape) => {
      const theory = tunnellingShare(speed, wall, radius, dt);
      const measured = fire({ speed, wall, radius, dt, shape, ccd: 'off' });
      rows.push(
        `| ${speed} | ${wall} | ${radius} | ${dt.toFixed(4)} | ${shape} | ${wall >= speed * dt ? 'yes' : 'no'} | ${theory.toFixed(3)} | ${measured.toFixed(3)} |`,
      );
      expect(Math.abs(measured - theory)).toBeLessThanOrEqual(TOLERANCE);
    },
  );

  it("shows tunnelling with the talk's rule satisfied whenever v·dt > w/2 + r", () => {
    // w = 0.4 ≥ v·dt = 0.3 > w/2 + r = 0.22
    const share = fire({ speed: 10, wall: 0.4, radius: 0.02, dt: 0.03, ccd: 'off' });
    expect(share).toBeGreaterThan(0.2);
  });
});

describe('continuous detection: nothing tunnels at any speed up to 1000 m/s at a 0.03 s step', () => {
  it.each(settings)(
    'stops every body of the discrete table: v = %s, w = %s, r = %s, dt = %s (%s)',
    (speed, wall, radius, dt, shape) => {
      expect(fire({ speed, wall, radius, dt, shape, ccd: 'auto' })).toBe(0);
    },
  );

  const speeds = [1, 10, 50, 100, 300, 1000];
  const cases: [string, number, 'circle' | 'box', CcdMode, boolean][] = [];
  for (const wall of [0, 0.01, 0.05])
    for (const shape of ['circle', 'box'] as const)
      cases.push([wall === 0 ? 'segment' : `box ${wall} m thick`, wall, shape, 'auto', false]);
  cases.push(
    ['segment', 0, 'circle', 'bullets', true],
    ['box 0.01 m thick', 0.01, 'box', 'bullets', true],
  );

  it.each(cases)(
    'static %s (%s m), %s bodies, ccd %s, bullet flag %s: 500 phases × 6 speeds, ±17° spread',
    (_name, wall, shape, ccd, bullet) => {
      for (const speed of speeds) {
        const share = fire({
          speed,
          wall,
          radius: 0.02,
          dt: 0.03,
          shape,
          ccd,
          bullet,
          spread: 0.3,
          phases: 500,
          seed: speed,
        });
        expect({ speed, share }).toEqual({ speed, share: 0 });
      }
    },
  );

  type Target = 'kinematic thin box' | 'thin box' | 'circle';

  /**
   * Head-on: a fast circle (or box) against a target moving towards it at 5–50 m/s; in one
   * dimension it can never get past. Returns how many ended on the far side.
   */
  function headOn(
    speed: number,
    target: Target,
    mover: 'circle' | 'box',
    ccd: CcdMode,
    pairs = 300,
  ): number {
    const dt = 0.03;
    const world = new PhysicsWorld(
      { gravityY: 0, timeStep: dt, ccd, restitution: 0.5 },
      { capacity: 2 * pairs },
    );
    const rng = new Random(speed + pairs);
    const ids: [number, number][] = [];
    for (let k = 0; k < pairs; k++) {
      const y = k * 3;
      const u = rng.range(5, 50);
      const gap = rng.next() * (speed + u) * dt;
      const m = { x: -0.03 - gap / 2, y, vx: speed, bullet: ccd === 'bullets' };
      const a =
        mover === 'circle'
          ? world.createCircle({ ...m, radius: 0.03 })
          : world.createBox({ ...m, halfWidth: 0.03, halfHeight: 0.03 });
      const t = { x: 0.005 + gap / 2, vx: -u };
      const b =
        target === 'circle'
          ? world.createCircle({ ...t, y, radius: 0.03 })
          : world.createBox({
              ...t,
              y: y + rng.range(-0.3, 0.3),
              halfWidth: 0.005,
              halfHeight: 0.5,
              kinematic: target === 'kinematic thin box',
            });
      ids.push([a, b]);
    }
    let far = 0;
    for (let s = 0; s < 6; s++) {
      world.step();
      for (const [a, b] of ids) if (world.x[a]! > world.x[b]!) far++;
    }
    return far;
  }

  const movingCases: [Target, 'circle' | 'box', CcdMode][] = [
    ['kinematic thin box', 'circle', 'auto'],
    ['kinematic thin box', 'box', 'auto'],
    ['thin box', 'circle', 'auto'],
    ['circle', 'circle', 'auto'],
    ['circle', 'box', 'auto'],
    ['kinematic thin box', 'circle', 'bullets'],
    ['circle', 'circle', 'bullets'],
  ];

  it.each(movingCases)(
    'against a moving %s, %s movers, ccd %s: 300 pairs × 6 speeds, never past it',
    (target, mover, ccd) => {
      for (const speed of speeds) {
        expect({ speed, far: headOn(speed, target, mover, ccd) }).toEqual({ speed, far: 0 });
      }
    },
  );

  it('(the same experiment does see tunnelling without continuous detection)', () => {
    expect(headOn(1000, 'kinematic thin box', 'circle', 'off')).toBeGreaterThan(250);
    expect(headOn(300, 'circle', 'circle', 'off')).toBeGreaterThan(250);
  });
});
