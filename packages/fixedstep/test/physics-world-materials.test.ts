/**
 * Per-body materials of the own world (Box2D's `friction`, `restitution`, `linearDamping`):
 * checked options and setters, what they do (with numbers), version 3 snapshots written only when
 * needed, a save/load round trip, and the JavaScript and WebAssembly paths giving the same bits.
 */
import { describe, expect, it } from 'vitest';
import { PhysicsWorld, circlesInBox, hex64 } from 'fixedstep';
import { solverKernelsSetting } from '../src/physics/world/solver-kernels.js';

const versionOf = (w: PhysicsWorld) => new DataView(w.save().buffer).getUint32(4, true);

/** A pile with a bit of everything: own friction, restitution and damping on some bodies. */
function materialPile(n = 400, seed = 7): PhysicsWorld {
  const w = circlesInBox(n, seed);
  w.setDef({ restitution: 0.1 });
  for (let i = 0; i < w.slotCount; i++) {
    if (i % 5 === 0) w.setFriction(i, 0.05 + (i % 7) * 0.2);
    if (i % 7 === 0) w.setRestitution(i, 0.3 + (i % 3) * 0.3);
    if (i % 11 === 0) w.setLinearDamping(i, 0.5 + (i % 4));
  }
  return w;
}

describe('materials: options and setters', () => {
  it('defaults are the world’s friction and restitution and no damping; own values read back', () => {
    const w = new PhysicsWorld({ friction: 0.3, restitution: 0.2 });
    const a = w.createCircle({ x: 0, y: 0, radius: 0.5 });
    const b = w.createBox({
      x: 2,
      y: 0,
      halfWidth: 0.5,
      halfHeight: 0.5,
      friction: 0.9,
      restitution: 0.7,
      linearDamping: 1.5,
    });
    expect([w.getFriction(a), w.getRestitution(a), w.getLinearDamping(a)]).toEqual([0.3, 0.2, 0]);
    expect([w.getFriction(b), w.getRestitution(b), w.getLinearDamping(b)]).toEqual([0.9, 0.7, 1.5]);
    w.setDef({ friction: 0.4 });
    expect(w.getFriction(a)).toBe(0.4); // follows the world
    w.setFriction(a, 0.1);
    w.setRestitution(a, 1);
    w.setLinearDamping(a, 0.25);
    expect([w.getFriction(a), w.getRestitution(a), w.getLinearDamping(a)]).toEqual([0.1, 1, 0.25]);
  });

  it('refuses bad values with errors naming the method, body, field and value, changing nothing', () => {
    const w = new PhysicsWorld();
    const id = w.createCircle({ x: 0, y: 0, radius: 0.5 });
    expect(() => w.createCircle({ x: 0, y: 0, radius: 0.5, friction: -0.1 })).toThrow(
      new RangeError(
        'PhysicsWorld.createCircle: body 1: friction must be a finite number ≥ 0, got -0.1',
      ),
    );
    expect(() =>
      w.createBox({ x: 0, y: 0, halfWidth: 1, halfHeight: 1, restitution: 1.5 }),
    ).toThrow(
      new RangeError('PhysicsWorld.createBox: body 1: restitution must be in [0, 1], got 1.5'),
    );
    expect(() => {
      w.setLinearDamping(id, NaN);
    }).toThrow(
      new RangeError(
        'PhysicsWorld.setLinearDamping: body 0: linearDamping must be a finite number ≥ 0 (1/s), got NaN',
      ),
    );
    expect(() => {
      w.setFriction(id, Infinity);
    }).toThrow(RangeError);
    expect(() => {
      w.setRestitution(id, '0.5' as unknown as number);
    }).toThrow(
      new TypeError(
        'PhysicsWorld.setRestitution: body 0: restitution must be in [0, 1], got "0.5" (a string)',
      ),
    );
    expect(() => {
      w.setFriction(7, 0.5);
    }).toThrow(/body 7/);
    expect(w.bodyCount).toBe(1);
    expect([w.getFriction(id), w.getRestitution(id), w.getLinearDamping(id)]).toEqual([0.6, 0, 0]);
    expect(versionOf(w)).toBe(1);
  });
});

describe('materials: behaviour', () => {
  it('a bouncier ball bounces higher: apex after the first bounce ≈ e² × the drop', () => {
    const w = new PhysicsWorld({ enableSleep: false });
    w.addSegment(-20, 0, 20, 0);
    const balls = [
      w.createCircle({ x: -5, y: 3, radius: 0.25, restitution: 0.8 }),
      w.createCircle({ x: 5, y: 3, radius: 0.25, restitution: 0.2 }),
      w.createCircle({ x: 0, y: 3, radius: 0.25 }), // the world's: 0
    ];
    const rising = [false, false, false];
    const apex = [0, 0, 0];
    for (let t = 0; t < 200; t++) {
      w.step();
      balls.forEach((id, k) => {
        if (w.vy[id]! > 0) rising[k] = true;
        if (rising[k]) apex[k] = Math.max(apex[k]!, w.y[id]!);
      });
    }
    // Dropped 2.75 m (centre 3 m, resting at 0.25 m): e² × 2.75 above the rest height.
    expect(apex[0]).toBeCloseTo(2.075135, 6);
    expect((apex[0]! - 0.25) / 2.75).toBeCloseTo(0.64, 1);
    expect(apex[1]).toBeCloseTo(0.34768256, 6);
    expect((apex[1]! - 0.25) / 2.75).toBeCloseTo(0.04, 1);
    expect(apex[2]).toBeLessThan(0.26); // restitution 0: stays down (the push-out lifts it < 1 cm)
  });

  it('a damped body’s speed decays by 1 / (1 + h·c) per step, exactly; an undamped one keeps it', () => {
    const h = 1 / 60;
    const c = 2;
    const w = new PhysicsWorld({ gravityY: 0, timeStep: h });
    const damped = w.createCircle({ x: 0, y: 0, radius: 0.5, vx: 10, vy: -4, linearDamping: c });
    const free = w.createCircle({ x: 0, y: 5, radius: 0.5, vx: 10 });
    const factor = 1 / (1 + h * c);
    expect(factor).toBeCloseTo(0.967742, 6);
    let vx = 10;
    let vy = -4;
    for (let t = 0; t < 120; t++) {
      w.step();
      vx *= factor;
      vy *= factor;
      expect(w.vx[damped]).toBe(vx);
      expect(w.vy[damped]).toBe(vy);
      expect(w.vx[free]).toBe(10);
    }
    // Two seconds: (1/(1 + 1/30))^120 of 10 m/s.
    expect(w.vx[damped]).toBeCloseTo(0.1955, 4);
  });

  it('on a 1:2 slope (26.6°) a box of friction 0.8 stops, one of 0.2 slides, 0 slides freely', () => {
    const run = (friction: number) => {
      const w = new PhysicsWorld({ enableSleep: false });
      w.addSegment(-20, -10, 20, 10);
      const id = w.createBox({ x: 0, y: 0.75, halfWidth: 0.3, halfHeight: 0.3, friction });
      let vx30 = 0;
      let vx60 = 0;
      for (let t = 1; t <= 240; t++) {
        w.step();
        if (t === 30) vx30 = w.vx[id]!;
        if (t === 60) vx60 = w.vx[id]!;
      }
      return { x: w.x[id]!, vx: w.vx[id]!, ax: (vx60 - vx30) / 0.5 };
    };
    const high = run(0.8); // tan 26.6° = 0.5 < 0.8: holds
    expect(high.vx).toBe(0);
    expect(high.x).toBeCloseTo(-0.0086, 4);
    const low = run(0.2);
    expect(low.x).toBeCloseTo(-9.6515, 4);
    // Steady: -1.2054 m/s² along x. (Coulomb's block would do -2.354; the solver's friction on
    // this corner contact is stronger — the same with the world's friction 0.2, not the mixing.)
    expect(low.ax).toBeCloseTo(-1.2054, 4);
    const none = run(0);
    // Frictionless: g·sinθ·cosθ = 9.81 × 0.4 = 3.924 m/s² along x.
    expect(none.ax).toBeCloseTo(-3.924, 6);
  });

  it('a body whose friction is the world’s moves exactly as one without a material', () => {
    const plain = circlesInBox(200, 3);
    const same = circlesInBox(200, 3);
    for (let i = 0; i < same.slotCount; i += 3) same.setFriction(i, same.def.friction);
    for (let t = 0; t < 120; t++) {
      plain.step();
      same.step();
    }
    expect(same.x).toEqual(plain.x);
    expect(same.vy).toEqual(plain.vy);
  });

  it('CCD responses use the materials too: a bouncy bullet comes back off the wall', () => {
    const w = new PhysicsWorld({ gravityY: 0, timeStep: 0.03 });
    w.addSegment(5, -5, 5, 5);
    const dull = w.createCircle({ x: 0, y: 0, radius: 0.05, vx: 300, bullet: true });
    const bouncy = w.createCircle({
      x: 0,
      y: 2,
      radius: 0.05,
      vx: 300,
      bullet: true,
      restitution: 1,
    });
    for (let t = 0; t < 10; t++) w.step();
    expect(w.vx[dull]).toBe(0);
    expect(w.vx[bouncy]).toBeLessThan(-250);
  });
});

describe('materials: snapshots, hashes and both paths', () => {
  it('version 3 only while some body has a material; back to version 1 with the defaults', () => {
    const w = circlesInBox(50, 1);
    expect(versionOf(w)).toBe(1);
    const before = w.save();
    w.setRestitution(3, 0.5);
    expect(versionOf(w)).toBe(3);
    // Version 2's section (filters 12 bytes a slot, no overlap), then the materials, 24 a slot.
    expect(w.save().length).toBe(before.length + 12 * w.slotCount + 4 + 24 * w.slotCount);
    w.setRestitution(3, 0);
    expect(versionOf(w)).toBe(3); // 0 is its own value (the world's could change)
    w.setDef({ restitution: 0 });
    expect(w.getRestitution(3)).toBe(0);
    const fresh = circlesInBox(50, 1);
    fresh.setLinearDamping(0, 1);
    fresh.setLinearDamping(0, 0);
    expect(fresh.save()).toEqual(before); // the default material again: version 1, same bytes
    const sensor = circlesInBox(50, 1);
    sensor.setSensor(0, true);
    sensor.setFriction(1, 0.1);
    expect(versionOf(sensor)).toBe(3);
  });

  it('refuses a version 3 snapshot whose materials are all the default, and a bad value', () => {
    const w = circlesInBox(20, 1);
    w.setFriction(2, 0.25);
    const bytes = w.save();
    const n = w.slotCount;
    const at = bytes.length - 24 * n; // friction column
    const view = new DataView(bytes.buffer);
    const bad = bytes.slice();
    new DataView(bad.buffer).setFloat64(at + 8 * 2, -0.5, true);
    expect(() => {
      circlesInBox(20, 1).load(bad);
    }).toThrow(
      "PhysicsWorld.load: body 2: friction must be -1 (the world's) or finite and ≥ 0, got -0.5",
    );
    const plain = bytes.slice();
    new DataView(plain.buffer).setFloat64(at + 8 * 2, -1, true);
    expect(() => {
      circlesInBox(20, 1).load(plain);
    }).toThrow(/not canonical/);
    expect(view.getFloat64(at + 8 * 2, true)).toBe(0.25);
  });

  it('round trip: save A, load into B, 120 steps, equal hashes every step', () => {
    const a = materialPile(300, 5);
    for (let t = 0; t < 60; t++) a.step();
    const b = materialPile(300, 5);
    b.load(a.save());
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
    for (let t = 0; t < 120; t++) {
      a.step();
      b.step();
      expect(hex64(b.hash())).toBe(hex64(a.hash()));
    }
    // Into a world that had no materials at all, too.
    const c = circlesInBox(300, 5);
    c.load(a.save());
    expect(c.getFriction(5)).toBe(a.getFriction(5));
    a.step();
    c.step();
    expect(hex64(c.hash())).toBe(hex64(a.hash()));
    // And back: a world with materials loads a version 1 snapshot and forgets them.
    const d = circlesInBox(300, 5);
    a.load(d.save());
    expect(a.getLinearDamping(0)).toBe(0);
    expect(hex64(a.hash())).toBe(hex64(d.hash()));
  });

  it('gives the same bits in JavaScript and WebAssembly (a pile with materials, 150 steps)', () => {
    solverKernelsSetting.minContacts = 0;
    try {
      const wasm = materialPile();
      solverKernelsSetting.enabled = false;
      let js: PhysicsWorld;
      try {
        js = materialPile();
      } finally {
        solverKernelsSetting.enabled = true;
      }
      let first = -1;
      for (let t = 0; t < 150 && first < 0; t++) {
        wasm.step();
        js.step();
        if (hex64(wasm.hash()) !== hex64(js.hash())) first = t;
      }
      expect(first).toBe(-1);
      const kernels = (w: PhysicsWorld) =>
        (w as unknown as { schedule: { kernels: object | null | undefined } }).schedule.kernels;
      expect(kernels(wasm)).toBeTruthy();
      expect(kernels(js)).toBeNull();
    } finally {
      solverKernelsSetting.minContacts = 256;
    }
  });

  it('golden hash of the material pile after 300 steps', () => {
    const w = materialPile();
    for (let t = 0; t < 300; t++) w.step();
    const h = hex64(w.hash());
    if (h !== GOLDEN) console.log(`material pile golden hash is now ${h}`);
    expect(h).toBe(GOLDEN);
  });
});

const GOLDEN = '3bf4d87e95d89b2a';
