import { beforeAll, describe, expect, it } from 'vitest';
import {
  ByteWriter,
  SyncTestSession,
  packButtons,
  runForHash,
  snapshotRoundTrip,
  varintSize,
} from 'fixedstep';
import {
  BODY_BYTES,
  JointsButtons,
  RapierSimulation,
  TowerButtons,
  canonicalFields,
  createRapierSimulation,
  jointsScene,
  loadRapier,
  splitHandle,
  towerScene,
  type RapierModule,
  type RapierSceneDef,
  type Tower,
} from '@fixedstep/rapier';
import { murmur3 } from '../src/checksum.js';

const FIRE = packButtons(1 << TowerButtons.FIRE, 1 << TowerButtons.FIRE);
/** The tower's script: fire at tick 30 and again at tick 200. */
const towerInput = (tick: number): number[] => [tick === 30 || tick === 200 ? FIRE : 0];
/** The joints' script: the slider right for a second, left for a second, and so on. */
const jointsInput = (tick: number): number[] => [
  1 << (Math.floor(tick / 60) % 2 === 0 ? JointsButtons.RIGHT : JointsButtons.LEFT),
];

/** Boxes whose top is not where it started (toppled, slid or fallen). */
function fallen(sim: RapierSimulation<number, Tower>): number {
  let n = 0;
  for (const h of sim.scene.boxes) {
    const b = sim.world.getRigidBody(h);
    if (Math.abs(b.rotation()) > 0.3 || b.translation().x > 5.5) n++;
  }
  return n;
}

let rapier: RapierModule;
beforeAll(async () => {
  rapier = await loadRapier();
});

describe('golden hashes (print the actual value on mismatch, to re-bless a deliberate change)', () => {
  it('a tower of 16 rotating boxes knocked over by the ball: 360 ticks', () => {
    const sim = new RapierSimulation(towerScene());
    const h = runForHash(sim, 360, towerInput);
    expect(h, `tower: actual hash ${h}`).toBe('4669bfdd4c81f940');
    // Not a trivial scene: the ball was fired twice and the tower fell, turning as it went.
    expect(sim.scene.shots).toBe(2);
    expect(fallen(sim)).toBeGreaterThanOrEqual(8);
    sim.dispose();
  });

  it('a chain of 10 links on revolute joints, a motorised slider and a wheel: 600 ticks', () => {
    const sim = new RapierSimulation(jointsScene(10));
    const h = runForHash(sim, 600, jointsInput);
    expect(h, `joints: actual hash ${h}`).toBe('20f90fb3cd80287b');
    // The chain hangs from its anchor (links 0.5 m long, the joints hold them together).
    const w = sim.world;
    const first = w.getRigidBody(sim.scene.links[0]!).translation();
    expect(Math.hypot(first.x, first.y - 8)).toBeLessThan(0.3);
    for (let i = 1; i < sim.scene.links.length; i++) {
      const a = w.getRigidBody(sim.scene.links[i - 1]!).translation();
      const b = w.getRigidBody(sim.scene.links[i]!).translation();
      expect(Math.hypot(a.x - b.x, a.y - b.y)).toBeLessThan(0.56);
    }
    // The slider moved on its rail (y held at 1 by the prismatic joint) within its limits.
    const s = w.getRigidBody(sim.scene.slider).translation();
    expect(Math.abs(s.y - 1)).toBeLessThan(0.01);
    expect(s.x).toBeGreaterThanOrEqual(-10.01);
    expect(s.x).toBeLessThanOrEqual(-1.99);
    sim.dispose();
  });

  it('the same scene built twice gives the same hash at every tick; another script does not', () => {
    const a = new RapierSimulation(towerScene());
    const b = new RapierSimulation(towerScene());
    const c = new RapierSimulation(towerScene());
    expect(a.fingerprint).toBe(b.fingerprint);
    let differs = -1;
    for (let t = 0; t < 240; t++) {
      a.step(towerInput(t));
      b.step(towerInput(t));
      c.step([t === 31 ? FIRE : 0]);
      expect(a.hash()).toBe(b.hash());
      if (differs < 0 && a.hash() !== c.hash()) differs = a.tick;
    }
    // Firing one tick later changes the state from the tick after the first shot.
    expect(differs).toBe(31);
    for (const s of [a, b, c]) s.dispose();
  });
});

describe('bodies by handle', () => {
  it('a handle reaches its body across a load; a removed one is refused by name, not with a null pointer', () => {
    const sim = new RapierSimulation(towerScene());
    for (let t = 0; t < 40; t++) sim.step(towerInput(t));
    const h = sim.scene.boxes[3]!;
    const saved = sim.save();
    const before = sim.body(h).translation();
    sim.load(saved);
    // A new world after the load: the handle still finds the same body.
    expect(sim.body(h).translation()).toEqual(before);
    sim.world.removeRigidBody(sim.body(h));
    const [index] = splitHandle(h);
    expect(() => sim.body(h)).toThrow(
      new RegExp(
        `no rigid body with handle \\S+ \\(index ${index}, generation 0\\) in the world at tick 40 \\(removed, or never made\\)`,
      ),
    );
    expect(() => sim.body(Number.NaN)).toThrow(/a handle is a number, got NaN/);
    sim.dispose();
  });
});

describe('save and load', () => {
  it("Box2D's snapshot test: save A, load into B, step both 120 ticks, equal hashes every tick", () => {
    for (const [name, make, inputs] of [
      ['tower', () => new RapierSimulation(towerScene()), towerInput],
      ['joints', () => new RapierSimulation(jointsScene()), jointsInput],
    ] as const) {
      const r = snapshotRoundTrip(make, inputs, 100, 120);
      expect(r.message, `${name}: snapshot round trip`).toBe(
        'equal hashes for 120 ticks after the snapshot',
      );
    }
  });

  it('load restores tick, world and user state; save after load gives the same bytes', () => {
    const a = new RapierSimulation(towerScene());
    for (let t = 0; t < 90; t++) a.step(towerInput(t));
    const bytes = a.save();
    const b = new RapierSimulation(towerScene());
    const oldWorld = b.world;
    b.load(bytes);
    expect(b.tick).toBe(90);
    expect(b.scene.shots).toBe(1);
    expect(b.world).not.toBe(oldWorld);
    expect(b.save()).toEqual(bytes);
    expect(b.canonicalState()).toEqual(a.canonicalState());
    // Loading rewinds: A steps on, loads its own save, and is back at tick 90.
    for (let t = 90; t < 150; t++) a.step(towerInput(t));
    a.load(bytes);
    expect(a.tick).toBe(90);
    expect(a.hash()).toBe(b.hash());
    a.dispose();
    b.dispose();
  });

  it('SyncTestSession: rolling back 8 ticks every tick and re-simulating matches, byte for byte', () => {
    for (const [make, inputs] of [
      [() => new RapierSimulation(towerScene()), towerInput],
      [() => new RapierSimulation(jointsScene()), jointsInput],
    ] as const) {
      const sim = make();
      const st = new SyncTestSession(sim, { checkDistance: 8 });
      for (let t = 0; t < 300; t++) st.step(inputs(t));
      expect(st.mismatch).toBeUndefined();
      expect(st.checkedTicks).toBe(300);
      sim.dispose();
    }
  });

  it('SyncTestSession catches a scene that keeps state outside the world and its user state', () => {
    let pushes = 0; // lives outside the simulation: a rerun sees another value
    const def: RapierSceneDef<number, { ball: number }> = {
      ...towerScene(),
      saveState: undefined,
      loadState: undefined,
      id: 'leaky',
      build(world, rapier) {
        const ball = world.createRigidBody(rapier.RigidBodyDesc.dynamic().setTranslation(0, 5));
        world.createCollider(rapier.ColliderDesc.ball(0.5), ball);
        return { ball: ball.handle };
      },
      applyInputs(world, _inputs, tick, scene) {
        if (tick >= 20) world.getRigidBody(scene.ball).applyImpulse({ x: ++pushes, y: 0 }, true);
      },
    };
    const st = new SyncTestSession(new RapierSimulation(def), { throwOnMismatch: false });
    for (let t = 0; t < 40; t++) st.step([0]);
    expect(st.mismatch?.kind).toBe('step');
    expect(st.mismatch?.tick).toBe(21);
  });
});

describe('the canonical hash', () => {
  it('covers every body: handle, type, sleep, position, angle and velocities, in handle order', () => {
    const sim = new RapierSimulation(towerScene({ rows: 2, columns: 1 }));
    sim.step([0]);
    const bytes = sim.canonicalState().slice();
    // ground, 2 boxes, ball; 4 bytes of user state (the shot count).
    expect(bytes.length).toBe(4 + 4 + 4 + 16 + 4 * BODY_BYTES);
    const fields = canonicalFields(bytes)!;
    expect(fields.map((f) => f.name).slice(0, 9)).toEqual([
      'tick',
      'user state length',
      'user[0]',
      'user[1]',
      'user[2]',
      'user[3]',
      'count of bodies',
      'count of colliders',
      'count of impulse joints',
    ]);
    expect(fields.at(-1)!.name).toBe('body[3].angvel');
    expect(fields.find((f) => f.name === 'body[1].angle')!.type).toBe('f64');
    // The ball's y in the bytes is the world's, exactly.
    const y = fields.find((f) => f.name === 'body[3].y')!;
    const view = new DataView(bytes.buffer);
    expect(view.getFloat64(y.offset, true)).toBe(
      sim.world.getRigidBody(sim.scene.ball).translation().y,
    );
    expect(canonicalFields(bytes.subarray(0, bytes.length - 1))).toBeUndefined();
    sim.dispose();
  });

  it('names handles by arena index and generation: a removed body’s slot is reused with generation 1', () => {
    const sim = new RapierSimulation(towerScene({ rows: 2, columns: 1 }));
    const w = sim.world;
    const [box0] = sim.scene.boxes;
    expect(splitHandle(box0!)).toEqual([1, 0]);
    w.removeRigidBody(w.getRigidBody(box0!));
    const again = w.createRigidBody(rapier.RigidBodyDesc.dynamic().setTranslation(9, 9));
    expect(splitHandle(again.handle)).toEqual([1, 1]);
    const names = canonicalFields(sim.canonicalState())!.map((f) => f.name);
    expect(names).toContain('body[1 gen 1].x');
    sim.dispose();
  });
});

describe('misuse is refused with a clear error', () => {
  it('inputs: wrong count, non-finite numbers, and what checkInput refuses', () => {
    const sim = new RapierSimulation(towerScene());
    const before = sim.hash();
    expect(() => {
      sim.step([]);
    }).toThrow(/step\(\) needs 1 input\(s\), one per player, got 0/);
    expect(() => {
      sim.step([NaN]);
    }).toThrow(/bad input of player 0 at tick 0: NaN is not a ButtonInput/);
    expect(() => {
      sim.step([-1]);
    }).toThrow(/-1 is not a ButtonInput/);
    expect(sim.tick).toBe(0);
    expect(sim.hash()).toBe(before);
    // The default check (no checkInput): every leaf a number, finite as Rapier's 32-bit floats.
    const stick: RapierSceneDef<{ x: number; y: number }, { ball: number }> = {
      id: 'stick',
      build(world, rapier) {
        const ball = world.createRigidBody(rapier.RigidBodyDesc.dynamic());
        world.createCollider(rapier.ColliderDesc.ball(0.5), ball);
        return { ball: ball.handle };
      },
      applyInputs(world, [input], _tick, s) {
        world.getRigidBody(s.ball).setLinvel(input!, true);
      },
    };
    const analog = new RapierSimulation(stick);
    analog.step([{ x: 1, y: 2 }]);
    const refused: [unknown, RegExp][] = [
      [{ x: 1, y: Infinity }, /at tick 1 at input\.y: Infinity is not finite/],
      // Finite as a double, ∞ as Rapier's f32.
      [{ x: 1e39, y: 0 }, /at input\.x: 1e\+39 is beyond Rapier's 32-bit floats/],
      [{ x: -3.5e38, y: 0 }, /at input\.x: -3\.5e\+38 is beyond Rapier's 32-bit floats/],
      [{ x: '1', y: 0 }, /at input\.x: "1" is a string, not a number/],
      [{ x: 1, y: true }, /at input\.y: true is a boolean, not a number/],
      [{ x: 1, y: undefined }, /at input\.y: undefined, not a number/],
      [{ x: 1, y: { z: [1, new Float64Array([0, NaN])] } }, /at input\.y\.z\[1\]\[1\]: NaN/],
      [new Int32Array(2), /bad input of player 0 at tick 1: a Int32Array/],
      ['1', /bad input of player 0 at tick 1: "1" is a string/],
    ];
    for (const [input, message] of refused) {
      expect(() => {
        analog.step([input as { x: number; y: number }]);
      }).toThrow(message);
    }
    // The largest f32 itself goes in.
    analog.step([{ x: 3.4028234663852886e38, y: 0 }]);
    expect(analog.tick).toBe(2);
    sim.dispose();
    analog.dispose();
  });

  it('loading bytes of another scene, version, tick rate, or bytes that are not a save', () => {
    const tower = new RapierSimulation(towerScene());
    const save = tower.save();
    const joints = new RapierSimulation(jointsScene());
    expect(() => {
      joints.load(save);
    }).toThrow(
      /cannot load these \d+ bytes: it is a save of scene "rapier-tower-8x2", this is "rapier-joints-10"/,
    );
    const v2 = new RapierSimulation({ ...towerScene(), version: 2 });
    expect(() => {
      v2.load(save);
    }).toThrow(/it is version 1 of "rapier-tower-8x2", this is version 2/);
    const fast = new RapierSimulation({ ...towerScene(), tickRate: 120 });
    expect(() => {
      fast.load(save);
    }).toThrow(/scene fingerprint [0-9a-f]+ is not this one's [0-9a-f]+/);
    const lunar = new RapierSimulation({ ...towerScene(), gravity: { x: 0, y: -1.62 } });
    expect(() => {
      lunar.load(save);
    }).toThrow(/was built differently/);
    const taller = new RapierSimulation(towerScene({ launchSpeed: 14, rows: 8, box: 0.6 }));
    expect(() => {
      taller.load(save);
    }).toThrow(/was built differently/);
    expect(() => {
      tower.load(new Uint8Array(3));
    }).toThrow(/no FSRP magic/);
    expect(() => {
      tower.load(save.subarray(0, 40));
    }).toThrow(RangeError);
    // A byte of the snapshot changed: the checksum no longer matches.
    const snapshotLength = tower.world.takeSnapshot().length;
    const head = save.length - snapshotLength;
    const flipped = save.slice();
    flipped[head + 100]! ^= 1;
    expect(() => {
      tower.load(flipped);
    }).toThrow(/its checksum is [0-9a-f]+, its bytes give [0-9a-f]+: corrupted or cut/);
    // A snapshot of garbage with a correct checksum: Rapier cannot read it.
    const garbage = save.slice();
    garbage.fill(0x7f, head, head + 64);
    garbage.fill(0xff, save.length - 2000);
    const checksumAt = head - varintSize(snapshotLength) - 4;
    const user = garbage.subarray(checksumAt - 4, checksumAt);
    new DataView(garbage.buffer).setUint32(
      checksumAt,
      murmur3(garbage.subarray(head), murmur3(user)),
      true,
    );
    expect(() => {
      tower.load(garbage);
    }).toThrow(/Rapier could not read the snapshot/);
    // Every refusal left the simulation as it was.
    expect(tower.save()).toEqual(save);
    for (const s of [tower, joints, v2, fast, lunar, taller]) s.dispose();
  });

  it('a world whose dt was changed, a disposed simulation, and scene options out of range', () => {
    const sim = new RapierSimulation(towerScene());
    sim.world.timestep = 1 / 30;
    expect(() => {
      sim.step([0]);
    }).toThrow(/world\.timestep is 0\.03\d* s, but the simulation steps at 0\.01666\d* s/);
    sim.dispose();
    sim.dispose();
    expect(sim.disposed).toBe(true);
    const uses = [
      () => {
        sim.step([0]);
      },
      () => sim.save(),
      () => sim.hash(),
      () => sim.world,
    ];
    for (const use of uses) {
      expect(use).toThrow(
        'RapierSimulation "rapier-tower-8x2" was disposed: it cannot be used any more',
      );
    }
    expect(() => new RapierSimulation({ ...towerScene(), tickRate: NaN })).toThrow(
      /tickRate must be from 1 to 10000 Hz, got NaN/,
    );
    expect(() => new RapierSimulation({ ...towerScene(), players: 0 })).toThrow(/players must be/);
    expect(() => new RapierSimulation({ ...towerScene(), gravity: { x: 0, y: NaN } })).toThrow(
      /gravity must be finite/,
    );
    expect(() => new RapierSimulation({ ...towerScene(), id: '' })).toThrow(/scene id must be/);
    expect(() => towerScene({ rows: 0 })).toThrow(/rows must be an integer from 1 to 60, got 0/);
    expect(() => towerScene({ launchSpeed: Infinity })).toThrow(
      /launchSpeed must be from 0 to 200/,
    );
  });

  it('user state that cannot be read is refused before anything changes', () => {
    const a = new RapierSimulation(towerScene());
    a.step([FIRE]);
    const bytes = a.save();
    // The user state is the 4-byte shot count, after a 1-byte varint length: cut it to 3 bytes.
    const w = new ByteWriter(bytes.length);
    const id = 'rapier-tower-8x2';
    const lengthAt = 4 + 1 + 1 + id.length + 4 + 8 + 4;
    expect(bytes[lengthAt]).toBe(4);
    w.bytes(bytes.subarray(0, lengthAt))
      .u8(3)
      .bytes(bytes.subarray(lengthAt + 1, lengthAt + 4));
    w.bytes(bytes.subarray(lengthAt + 5));
    const b = new RapierSimulation(towerScene());
    expect(() => {
      b.load(w.finish());
    }).toThrow(RangeError);
    expect(b.tick).toBe(0);
    expect(b.scene.shots).toBe(0);
    a.dispose();
    b.dispose();
  });

  it('createRapierSimulation loads Rapier and builds; the scene may throw, and nothing leaks', async () => {
    const sim = await createRapierSimulation(towerScene({ rows: 3 }));
    expect(sim.scene.boxes).toHaveLength(6);
    sim.dispose();
    await expect(
      createRapierSimulation({
        id: 'broken',
        build() {
          throw new Error('no such level');
        },
      }),
    ).rejects.toThrow('no such level');
  });
});
