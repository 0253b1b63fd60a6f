import { describe, expect, it } from 'vitest';
import {
  PhysicsWorld,
  WORLD_LIMITS,
  circlesInBox,
  hex64,
  type CircleOptions,
  type WorldDef,
} from 'fixedstep';

/**
 * The world refuses bad numbers (issue 15). Each "regression" test is a failure the issue
 * reported, reproduced against the world before the fix (numbers in the test names).
 */

/** Bodies whose position or velocity is not finite. */
function notFinite(w: PhysicsWorld): number {
  let count = 0;
  for (let i = 0; i < w.slotCount; i++) {
    if (!w.isAlive(i)) continue;
    if (![w.x[i], w.y[i], w.vx[i], w.vy[i]].every(Number.isFinite)) count++;
  }
  return count;
}

/** 200 circles in a box, 60 ticks in: a pile still moving. */
function pile(): PhysicsWorld {
  const w = circlesInBox(200, 1);
  for (let t = 0; t < 60; t++) w.step();
  return w;
}

describe('mutators refuse what is not finite or out of bounds, naming body, field and value', () => {
  it('regression: a NaN velocity used to reach 188 of 200 bodies in 60 ticks; now it is refused and nothing changes', () => {
    const w = pile();
    const before = w.save();
    expect(() => {
      w.setVelocity(5, NaN, 0);
    }).toThrow(
      new RangeError(
        'PhysicsWorld.setVelocity: body 5: vx must be a finite number from -1e9 to 1e9 (m/s), got NaN',
      ),
    );
    expect(w.save()).toEqual(before);
    for (let t = 0; t < 60; t++) w.step();
    expect(notFinite(w)).toBe(0);
  });

  it.each<[string, (w: PhysicsWorld) => void, string]>([
    [
      'setPosition NaN',
      (w) => {
        w.setPosition(5, NaN, 0);
      },
      'setPosition: body 5: x must be a finite number from -1e9 to 1e9 (metres), got NaN',
    ],
    [
      'setPosition Infinity',
      (w) => {
        w.setPosition(5, 0, Infinity);
      },
      'setPosition: body 5: y must be a finite number from -1e9 to 1e9 (metres), got Infinity',
    ],
    [
      'setPosition 1e10',
      (w) => {
        w.setPosition(7, 1e10, 0);
      },
      'setPosition: body 7: x must be a finite number from -1e9 to 1e9 (metres), got 10000000000',
    ],
    [
      'setVelocity -Infinity',
      (w) => {
        w.setVelocity(5, 0, -Infinity);
      },
      'setVelocity: body 5: vy must be a finite number from -1e9 to 1e9 (m/s), got -Infinity',
    ],
    [
      'setVelocity a string',
      (w) => {
        w.setVelocity(5, '3' as unknown as number, 0);
      },
      'setVelocity: body 5: vx must be a finite number from -1e9 to 1e9 (m/s), got "3" (a string)',
    ],
    [
      'applyImpulse NaN',
      (w) => {
        w.applyImpulse(9, NaN, 0);
      },
      'applyImpulse: body 9: jx must be finite, got NaN',
    ],
    [
      'applyImpulse Infinity',
      (w) => {
        w.applyImpulse(9, 0, Infinity);
      },
      'applyImpulse: body 9: jy must be finite, got Infinity',
    ],
    [
      'applyImpulse past maxSpeed',
      (w) => {
        w.applyImpulse(9, 1e300, 0);
      },
      'applyImpulse: body 9: the impulse (1e+300, 0) N·s would give it a velocity of',
    ],
    [
      'setBullet not a boolean',
      (w) => {
        w.setBullet(9, 1 as unknown as boolean);
      },
      'setBullet: body 9: bullet must be true or false, got 1',
    ],
    [
      'a body that does not exist',
      (w) => {
        w.setVelocity(500, 0, 0);
      },
      'setVelocity: no body 500',
    ],
    [
      'addSegment NaN',
      (w) => w.addSegment(0, 0, NaN, 1),
      'addSegment: static 4: bx must be a finite number from -1e9 to 1e9 (metres), got NaN',
    ],
    [
      'addStaticBox of zero width',
      (w) => w.addStaticBox(0, 0, 0, 1),
      'addStaticBox: static 4: halfWidth must be a number > 0 and at most 1e9 (metres), got 0',
    ],
  ])('%s', (_name, call, message) => {
    const w = pile();
    const before = w.save();
    expect(() => {
      call(w);
    }).toThrow(`PhysicsWorld.${message}`);
    expect(w.save()).toEqual(before);
  });

  it('regression: one body at an infinite position used to switch off body–body collision (the pile fell through itself)', () => {
    const w = pile();
    expect(() => {
      w.setPosition(5, Infinity, 0);
    }).toThrow(/got Infinity/);
    w.step();
    // The world that took Infinity found 25 contacts here, all with walls; the pile has ~200.
    expect(w.contactCount).toBeGreaterThan(150);
  });

  it('bodies so far apart that their span overflows a double still collide (one grid cell)', () => {
    // Only a snapshot can put bodies there (the mutators stop at 1e9 m); load() takes any finite
    // position, so the grid must not give up on them.
    const w = new PhysicsWorld({ gravityY: 0 });
    w.createCircle({ x: 0, y: 0, radius: 1 });
    w.createCircle({ x: 1, y: 0, radius: 1 });
    w.createCircle({ x: 0, y: 1e9, radius: 1 });
    w.createCircle({ x: 0, y: -1e9, radius: 1 });
    const bytes = w.save();
    const view = new DataView(bytes.buffer);
    const xs = 122 + 4 + 4; // no walls, 4 slots: the x column after the 4 flags
    const ys = xs + 8 * 4;
    view.setFloat64(ys + 16, 1.5e308, true);
    view.setFloat64(ys + 24, -1.5e308, true);
    const far = new PhysicsWorld({ gravityY: 0 });
    far.load(bytes);
    far.step();
    expect(far.contactCount).toBe(1);
    expect(far.x[0]).toBeLessThan(0);
    expect(far.x[1]).toBeGreaterThan(1);
  });
});

describe('bodies are created only from values the world accepts', () => {
  it('regression: density 5e-324 used to give an infinite inverse mass and spread NaN to 43 bodies', () => {
    const w = circlesInBox(50, 1);
    expect(() => w.createCircle({ x: 0, y: 3, radius: 0.2, density: 5e-324 })).toThrow(
      new RangeError(
        'PhysicsWorld.createCircle: body 50: density must be from 1e-6 to 1e6 (kg/m²), got 5e-324',
      ),
    );
    expect(w.bodyCount).toBe(50);
    for (let t = 0; t < 120; t++) w.step();
    expect(notFinite(w)).toBe(0);
  });

  it.each<[string, Record<string, unknown>, RegExp]>([
    ['density 0', { density: 0 }, /density must be from 1e-6 to 1e6 \(kg\/m²\), got 0$/],
    ['density Infinity', { density: Infinity }, /density .* got Infinity$/],
    ['density NaN', { density: NaN }, /density .* got NaN$/],
    ['density 1e300', { density: 1e300 }, /density .* got 1e\+300$/],
    [
      'radius 1e-200 (a mass that rounds to 0)',
      { radius: 1e-200 },
      /radius must be from 1e-6 to 1e6 \(metres\), got 1e-200$/,
    ],
    ['radius 1e7', { radius: 1e7 }, /radius .* got 10000000$/],
    ['y undefined', { y: undefined }, /y must be a finite number .* got undefined$/],
    [
      'vx 2e9',
      { vx: 2e9 },
      /vx must be a finite number from -1e9 to 1e9 \(m\/s\), got 2000000000$/,
    ],
    ['bullet "yes"', { bullet: 'yes' }, /bullet must be true or false, got "yes" \(a string\)$/],
  ])('refuses %s', (_name, change, message) => {
    const w = new PhysicsWorld();
    const o = { x: 0, y: 0, radius: 0.5, ...change } as CircleOptions;
    expect(() => w.createCircle(o)).toThrow(message);
    expect(w.bodyCount).toBe(0);
  });

  it('accepts the extremes of WORLD_LIMITS, with a finite inverse mass', () => {
    const w = new PhysicsWorld();
    const L = WORLD_LIMITS;
    const light = w.createCircle({
      x: -L.maxCoordinate,
      y: 0,
      radius: L.minSize,
      density: L.minDensity,
    });
    const heavy = w.createBox({
      x: L.maxCoordinate,
      y: 0,
      halfWidth: L.maxSize,
      halfHeight: L.maxSize,
      density: L.maxDensity,
      vx: -L.maxSpeed,
    });
    expect(w.invMass[light]).toBeCloseTo(1 / (Math.PI * 1e-18), -10);
    expect(w.invMass[heavy]).toBe(1 / (L.maxDensity * 4 * L.maxSize * L.maxSize));
    w.step();
    expect(notFinite(w)).toBe(0);
  });

  it('regression: options the world does not support (angle, angularVelocity) used to be dropped; now they are a type error and a TypeError', () => {
    const w = new PhysicsWorld();
    expect(() =>
      // @ts-expect-error -- bodies do not rotate: `angle` is not an option
      w.createCircle({ x: 0, y: 0, radius: 1, angle: 0.5 }),
    ).toThrow(
      new TypeError(
        'PhysicsWorld.createCircle: body 0: unknown option "angle": bodies of this world are axis-aligned and never rotate (use a Rapier world for rotation)',
      ),
    );
    // Not only literals: a variable of a wider type is a type error too.
    const spinning = { x: 0, y: 0, halfWidth: 1, halfHeight: 1, angularVelocity: 3 };
    // @ts-expect-error -- `angularVelocity` is not an option
    expect(() => w.createBox(spinning)).toThrow(
      /unknown option "angularVelocity": bodies of this world/,
    );
    const typo = { x: 0, y: 0, radius: 1, desnity: 3 };
    // @ts-expect-error -- a misspelt option
    expect(() => w.createCircle(typo)).toThrow(
      /unknown option "desnity"; known options: x, y, vx, vy, density/,
    );
    // A circle's options are not a box's.
    // @ts-expect-error -- radius on a box
    expect(() => w.createBox({ x: 0, y: 0, halfWidth: 1, halfHeight: 1, radius: 1 })).toThrow(
      /unknown option "radius"/,
    );
    expect(w.bodyCount).toBe(0);
    // An option present but undefined is its default.
    expect(w.createCircle({ x: 0, y: 0, radius: 1, bullet: undefined })).toBe(0);
  });
});

describe('the def is frozen and checked', () => {
  it('regression: a def changed after construction (a NaN step made all 10 bodies NaN) is now a TypeError', () => {
    const w = circlesInBox(10, 1);
    const def = w.def as WorldDef;
    expect(() => {
      def.timeStep = NaN;
    }).toThrow(TypeError);
    expect(w.def.timeStep).toBe(1 / 60);
    w.step();
    expect(notFinite(w)).toBe(0);
    expect(Object.isFrozen(w.def)).toBe(true);
  });

  it.each<[Partial<WorldDef>, string]>([
    [{ timeStep: NaN }, 'WorldDef.timeStep must be positive and at most 3600 (seconds), got NaN'],
    [
      { timeStep: 1e300 },
      'WorldDef.timeStep must be positive and at most 3600 (seconds), got 1e+300',
    ],
    [
      { velocityIterations: 1e9 },
      'WorldDef.velocityIterations must be an integer from 0 to 1000, got 1000000000',
    ],
    [
      { positionIterations: -1 },
      'WorldDef.positionIterations must be an integer from 0 to 1000, got -1',
    ],
    [
      { maxCcdIterations: 2.5 },
      'WorldDef.maxCcdIterations must be an integer from 0 to 1000, got 2.5',
    ],
    [
      { gravityX: 1e7 },
      'WorldDef.gravityX must be a finite number from -1e6 to 1e6 (m/s²), got 10000000',
    ],
    [{ friction: Infinity }, 'WorldDef.friction must be a finite number ≥ 0, got Infinity'],
    [{ linearSlop: -0.1 }, 'WorldDef.linearSlop must be a finite number ≥ 0, got -0.1'],
    [{ maxContacts: 0 }, 'WorldDef.maxContacts must be an integer from 1 to 67108864, got 0'],
    [
      { ccd: 'always' as WorldDef['ccd'] },
      `WorldDef.ccd must be 'auto', 'bullets' or 'off', got "always" (a string)`,
    ],
  ])('setDef(%o) is refused and changes nothing; so is the constructor', (change, message) => {
    const w = circlesInBox(10, 1);
    const before = w.save();
    expect(() => {
      w.setDef(change);
    }).toThrow(`PhysicsWorld.setDef: ${message}`);
    expect(w.save()).toEqual(before);
    expect(() => new PhysicsWorld(change)).toThrow(`new PhysicsWorld: ${message}`);
  });

  it('refuses unknown def fields, at compile time and at run time', () => {
    // @ts-expect-error -- not a WorldDef field
    expect(() => new PhysicsWorld({ angularDamping: 0.1 })).toThrow(
      /new PhysicsWorld: unknown WorldDef field "angularDamping"/,
    );
    const w = new PhysicsWorld();
    expect(() => {
      // @ts-expect-error -- not a WorldDef field
      w.setDef({ gravity: -9.81 });
    }).toThrow(/PhysicsWorld.setDef: unknown WorldDef field "gravity"/);
    expect(() => new PhysicsWorld({}, { capacity: 0 })).toThrow(
      /capacity must be an integer from 1 to 16777216, got 0/,
    );
  });

  it('setDef changes the run deterministically, and what the world then saves it loads back', () => {
    const run = () => {
      const w = circlesInBox(50, 2);
      for (let t = 0; t < 30; t++) w.step();
      w.setDef({ gravityX: 3, velocityIterations: 4, timeStep: 0.02 });
      for (let t = 0; t < 30; t++) w.step();
      return w;
    };
    const a = run();
    const b = run();
    expect(hex64(a.hash())).toBe(hex64(b.hash()));
    expect(a.def).toMatchObject({ gravityX: 3, velocityIterations: 4, timeStep: 0.02 });
    const c = new PhysicsWorld();
    c.load(a.save());
    expect(c.def).toEqual(a.def);
    expect(hex64(c.hash())).toBe(hex64(a.hash()));
  });
});

describe('a limit on contacts per step', () => {
  it('regression: 10,000 bodies on one spot used to make 18.6 M contacts and 4.6 GB; now the step throws before changing anything', () => {
    const w = new PhysicsWorld({ enableSleep: false });
    for (let k = 0; k < 10_000; k++) w.createCircle({ x: 0, y: 0, radius: 0.1 });
    const before = hex64(w.hash());
    expect(() => {
      w.step();
    }).toThrow(
      /^PhysicsWorld\.step: more than 1048576 contacts in one step \(def\.maxContacts\): the next one was between body \d+ at \(0, 0\) and body \d+\. Are many bodies piled on one spot\? Nothing was changed/,
    );
    expect(w.tick).toBe(0);
    expect(w.contactCount).toBe(0);
    // (Hashes, not bytes: comparing 690 kB byte by byte takes vitest seconds.)
    expect(hex64(w.hash())).toBe(before);
  });

  it('a smaller limit throws at that count; a larger one lets the same step through', () => {
    const w = circlesInBox(300, 5);
    for (let t = 0; t < 120; t++) w.step();
    const reference = circlesInBox(300, 5);
    for (let t = 0; t < 121; t++) reference.step();
    const needed = reference.contactCount;
    expect(needed).toBeGreaterThan(300);
    const before = w.save();
    w.setDef({ maxContacts: needed - 1 });
    expect(() => {
      w.step();
    }).toThrow(`more than ${needed - 1} contacts`);
    expect(w.save()).toEqual(before);
    w.setDef({ maxContacts: needed });
    w.step();
    expect(hex64(w.hash())).toBe(hex64(reference.hash()));
  });

  it('undoes gravity and wakes when the contacts of bodies woken in the step are what overflows', () => {
    // A sleeping pile; a body falls onto it. The step's first search skips pairs of sleeping
    // bodies (it finds only the falling body's few contacts); the touch wakes the pile, and the
    // second search, with the whole pile awake, finds hundreds.
    const a = circlesInBox(200, 6);
    for (let t = 0; t < 400; t++) a.step();
    expect(a.sleepingCount).toBe(200);
    a.createCircle({ x: 0, y: 3, radius: 0.3 });
    let last = a.save();
    for (let t = 0; t < 200 && a.sleepingCount === 200; t++) {
      last = a.save();
      a.step();
    }
    expect(a.sleepingCount).toBeLessThan(200);
    expect(a.contactCount).toBeGreaterThan(150);
    const b = new PhysicsWorld({ maxContacts: 40 });
    b.load(last);
    const before = b.save();
    expect(() => {
      b.step();
    }).toThrow(/more than 40 contacts/);
    expect(b.save()).toEqual(before);
    expect(b.sleepingCount).toBe(200);
    b.setDef({ maxContacts: 1 << 20 });
    b.step();
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
  });
});
