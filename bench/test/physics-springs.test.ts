import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { afterAll, describe, expect, it } from 'vitest';
import { fnv1a64Hex, SpringModel, SpringSystem, springChain } from 'fixedstep';
import {
  compileArgs,
  compileSprings,
  decodeSpringScene,
  encodeSpringScene,
  gccVersion,
  jsProgramArgs,
  JS_CONTESTANTS,
  parseAffinity,
  parseReply,
  sceneOfModel,
  SpringsProcess,
  stateHash,
} from '../c/springs.js';

const rope = (method: 'semi-implicit-euler' | 'velocity-verlet') =>
  springChain({
    count: 12,
    from: [0, 0],
    to: [1.1, 0.3],
    mass: 0.1,
    stiffness: 200,
    damping: 0.2,
    dt: 1 / 60,
    integrator: method,
  });

describe('the scene file for springs.c', () => {
  it('round-trips a library model bit for bit', () => {
    const model = new SpringModel(rope('velocity-verlet'));
    const scene = sceneOfModel(model, 'velocity-verlet', 1 / 60);
    const bytes = encodeSpringScene(scene);
    // header 48 B + 5 f64 per particle + 32 B per spring
    expect(bytes.length).toBe(48 + 40 * 12 + 32 * 11);
    expect(Array.from(bytes.subarray(0, 4), (b) => String.fromCharCode(b)).join('')).toBe('FSSP');
    const back = decodeSpringScene(bytes);
    expect(back.method).toBe('velocity-verlet');
    expect(back.dt).toBe(1 / 60);
    expect(back.gravity).toEqual([0, -9.81]);
    expect(back.x).toEqual(model.startPosition);
    expect(back.v).toEqual(model.startVelocity);
    expect(back.inverseMass).toEqual(model.inverseMass);
    expect(back.springA).toEqual(model.springA);
    expect(back.springB).toEqual(model.springB);
    expect(back.restLength).toEqual(model.restLength);
    expect(back.stiffness).toEqual(model.stiffness);
    expect(back.damping).toEqual(model.damping);
  });

  it('rejects what springs.c cannot read', () => {
    const model = new SpringModel(rope('semi-implicit-euler'));
    const good = encodeSpringScene(sceneOfModel(model, 'semi-implicit-euler', 1 / 60));
    expect(() => decodeSpringScene(good.subarray(0, good.length - 1))).toThrow(/length/);
    const bad = good.slice();
    bad[0] = 0;
    expect(() => decodeSpringScene(bad)).toThrow(/version 1/);
    const threeD = new SpringModel({
      dim: 3,
      particles: [{ position: [0, 0, 0] }, { position: [1, 0, 0] }],
      springs: [{ a: 0, b: 1, stiffness: 1 }],
    });
    expect(() => sceneOfModel(threeD, 'semi-implicit-euler', 0.1)).toThrow(/2D only/);
    expect(() =>
      encodeSpringScene({
        ...sceneOfModel(model, 'semi-implicit-euler', 0.1),
        v: new Float64Array(3),
      }),
    ).toThrow(RangeError);
  });
});

describe("springs.c's replies", () => {
  it('parses every kind of line', () => {
    expect(parseReply('ready 1000 999')).toEqual({ kind: 'ready', particles: 1000, springs: 999 });
    expect(parseReply('time 123456789\n')).toEqual({ kind: 'time', ns: 123456789 });
    expect(parseReply('hash 0536b72a311f1434')).toEqual({ kind: 'hash', hex: '0536b72a311f1434' });
    expect(parseReply('ok')).toEqual({ kind: 'ok' });
    expect(parseReply('error scene file too short')).toEqual({
      kind: 'error',
      message: 'scene file too short',
    });
  });

  it('refuses anything else', () => {
    expect(() => parseReply('time -5')).toThrow(/unexpected output/);
    expect(() => parseReply('hash 12')).toThrow(/unexpected output/);
    expect(() => parseReply('Segmentation fault')).toThrow(/unexpected output/);
  });
});

describe('the CPU affinity', () => {
  it("reads taskset's mask as a list of CPUs", () => {
    expect(parseAffinity("pid 18729's current affinity mask: 3\n")).toEqual([0, 1]);
    expect(parseAffinity("pid 7's current affinity mask: a")).toEqual([1, 3]);
    expect(parseAffinity("pid 7's current affinity mask: 10000000000000000")).toEqual([64]);
    expect(parseAffinity('taskset: failed to get pid 7 affinity')).toBeUndefined();
  });
});

describe('the state hash', () => {
  it('is FNV-1a 64 of the bytes of x then v', () => {
    const x = Float64Array.of(1, -2.5, 1e-300);
    const v = Float64Array.of(0, -0, Infinity);
    const both = new Uint8Array(48);
    both.set(new Uint8Array(x.buffer), 0);
    both.set(new Uint8Array(v.buffer), 24);
    expect(stateHash(x, v)).toBe(fnv1a64Hex(both));
    // a view into a larger buffer hashes only its own bytes
    const big = new Float64Array(8);
    big.set(x, 2);
    expect(stateHash(big.subarray(2, 5), v)).toBe(stateHash(x, v));
  });
});

describe('the JS program command', () => {
  it('runs springs-js.ts with the bench flags', () => {
    const args = jsProgramArgs('/tmp/s.json', 'file:///x/tsx.mjs');
    expect(args).toEqual([
      '--conditions=source',
      '--expose-gc',
      '--import',
      'file:///x/tsx.mjs',
      expect.stringMatching(/bench\/c\/springs-js\.ts$/),
      '/tmp/s.json',
    ]);
  });
});

describe('the compiler command', () => {
  it('optimises at -O2 and forbids fused multiply-add (JavaScript rounds every operation)', () => {
    const args = compileArgs('/src/springs.c', '/tmp/x/springs');
    expect(args).toContain('-O2');
    expect(args).toContain('-ffp-contract=off');
    expect(args.slice(-4)).toEqual(['-o', '/tmp/x/springs', '/src/springs.c', '-lm']);
  });
});

// Not timing: compiles springs.c and checks the claim the benchmark rests on, that the C loop and
// the library produce the same bytes. Skipped without gcc.
describe.runIf(gccVersion() !== undefined)('springs.c against the library (needs gcc)', () => {
  const dir = mkdtempSync(join(tmpdir(), 'fixedstep-springs-test-'));
  afterAll(() => {
    rmSync(dir, { recursive: true, force: true });
  });

  it('is bit-identical to SpringSystem after 300 steps, with either method', async () => {
    const binary = join(dir, 'springs');
    compileSprings(binary);
    for (const method of ['semi-implicit-euler', 'velocity-verlet'] as const) {
      const sys = new SpringSystem(rope(method));
      const file = join(dir, `${method}.bin`);
      writeFileSync(file, encodeSpringScene(sceneOfModel(sys.model, method, sys.dt)));
      const proc = await SpringsProcess.start(binary, [file]);
      try {
        expect(await proc.hash()).toBe(stateHash(sys.state.x, sys.state.v));
        for (let k = 0; k < 300; k++) sys.step();
        await proc.step(100);
        expect(await proc.time(200)).toBeGreaterThan(0);
        expect(await proc.hash()).toBe(stateHash(sys.state.x, sys.state.v));
        await proc.reset();
        expect(await proc.hash()).toBe(stateHash(sys.model.startPosition, sys.model.startVelocity));
      } finally {
        await proc.close();
      }
    }
  });

  it('agrees with springs-js.ts, whose three contestants agree with each other', async () => {
    const def = rope('semi-implicit-euler');
    const sys = new SpringSystem(def);
    const bin = join(dir, 'js.bin');
    const json = join(dir, 'js.json');
    writeFileSync(bin, encodeSpringScene(sceneOfModel(sys.model, 'semi-implicit-euler', sys.dt)));
    writeFileSync(json, JSON.stringify({ def, method: 'semi-implicit-euler' }));
    const binary = join(dir, 'springs');
    compileSprings(binary);
    const c = await SpringsProcess.start(binary, [bin]);
    const js = await SpringsProcess.start(
      process.execPath,
      jsProgramArgs(json, import.meta.resolve('tsx')),
    );
    try {
      await c.step(250);
      const expected = await c.hash();
      for (let who = 0; who < JS_CONTESTANTS.length; who++) {
        await js.step(250, who);
        expect(await js.hash(who)).toBe(expected);
      }
      await js.gc();
      expect(await js.time(10, 2)).toBeGreaterThan(0);
      await expect(js.hash(7)).rejects.toThrow(/no contestant 7/);
    } finally {
      await Promise.all([c.close(), js.close()]);
    }
  });

  it('reports a bad scene file as an error', async () => {
    const file = join(dir, 'bad.bin');
    writeFileSync(file, new Uint8Array(10));
    const binary = join(dir, 'springs');
    compileSprings(binary);
    await expect(SpringsProcess.start(binary, [file])).rejects.toThrow(/too short/);
  });
});
