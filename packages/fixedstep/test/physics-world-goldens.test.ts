import { describe, expect, it } from 'vitest';
import {
  type PhysicsWorld,
  bodiesInBox,
  buildWorld,
  circlesInBox,
  circlesInBoxScene,
  hex64,
  runForHash,
} from 'fixedstep';

// Golden hashes over what the solver's speed work touches: big piles (long contact chains),
// boxes with circles, restitution, kinematic bodies waking sleeping ones, a rollback of 8 ticks.
// The values were taken before that work; re-bless only for a deliberate change of behaviour, by
// pasting the printed value.

const none = () => [];

/** The rollback benchmark's scene: 2,000 circles settled into a pile, sleeping off. */
function pile(): PhysicsWorld {
  const scene = circlesInBoxScene(2000, 0xb0d1e5);
  return buildWorld({ ...scene, def: { ...scene.def, enableSleep: false } });
}

/** A pile of boxes and circles, sleeping on, that two kinematic bodies plough through. */
function ploughed(): PhysicsWorld {
  const w = bodiesInBox(400, 9);
  w.createBox({ x: -4, y: 0.6, vx: 1.5, vy: 0, halfWidth: 0.3, halfHeight: 0.3, kinematic: true });
  w.createCircle({ x: 4, y: 1.2, vx: -1.2, vy: 0, radius: 0.25, kinematic: true });
  return w;
}

describe('golden hashes of the solver', () => {
  const golden: [string, () => PhysicsWorld, number, string][] = [
    ['the 2,000-circle pile after 150 ticks', pile, 150, 'cea077fd2c05a52b'],
    ['bodiesInBox(500, 4) after 600 ticks', () => bodiesInBox(500, 4), 600, 'ef349e063c329466'],
    [
      'bodiesInBox(500, 4), sleeping off, after 300 ticks',
      () => bodiesInBox(500, 4, { enableSleep: false }),
      300,
      '95eee08146de1521',
    ],
    [
      'circlesInBox(300, 6) with restitution 0.6 after 400 ticks',
      () => circlesInBox(300, 6, { restitution: 0.6, friction: 0.2, restitutionThreshold: 0.5 }),
      400,
      '2c1888a3773bb4b6',
    ],
    ['a pile ploughed by kinematic bodies after 500 ticks', ploughed, 500, '75ac0e141260b483'],
  ];
  it.each(golden)('%s has its golden hash', (name, make, ticks, expected) => {
    const actual = runForHash(make(), ticks, none);
    if (actual !== expected) console.log(`golden hash for "${name}": ${actual}`);
    expect(actual).toBe(expected);
  });

  it('rolls the 2,000-circle pile back 8 ticks to the same golden hash', () => {
    const w = pile();
    for (let t = 0; t < 150; t++) w.step();
    const confirmed = w.save();
    const hashes: string[] = [];
    for (let round = 0; round < 2; round++) {
      w.load(confirmed);
      for (let t = 0; t < 8; t++) w.step();
      hashes.push(hex64(w.hash()));
    }
    if (hashes[0] !== '10f76a275899f08c') console.log(`golden hash after 158 ticks: ${hashes[0]}`);
    expect(hashes).toEqual(['10f76a275899f08c', '10f76a275899f08c']);
  });
});
