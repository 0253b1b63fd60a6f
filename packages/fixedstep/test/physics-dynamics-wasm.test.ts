import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import {
  DynamicsState,
  INTEGRATOR_METHODS,
  SpringModel,
  SpringSystem,
  createIntegrator,
  springCloth,
  hex64,
  type IntegratorMethod,
  type SpringSystemDef,
} from 'fixedstep';
import { WASM_MIN_SPRINGS } from '../src/physics/dynamics/springs.js';
import { SPRING_KERNELS_WASM } from '../src/physics/dynamics/kernels-wasm.js';
import { assembleKernels, kernelsModule } from '../../../scripts/wasm.mjs';

/** A w × h cloth hung by its top row, its bottom-left corner kicked. */
function cloth(w: number, h: number, integrator: IntegratorMethod): SpringSystemDef {
  const def = springCloth({ columns: w, rows: h, dt: 1 / 60, integrator });
  const corner = (h - 1) * w;
  return {
    ...def,
    particles: def.particles.map((p, i) => (i === corner ? { ...p, velocity: [0.4, 0.9] } : p)),
  };
}

describe('springCloth', () => {
  it('builds a grid hung by its top row, structural springs only', () => {
    const def = springCloth({ columns: 12, rows: 10, dt: 1 / 60 });
    expect(def.particles).toHaveLength(120);
    expect(def.springs).toHaveLength(11 * 10 + 12 * 9);
    expect(def.particles.filter((p) => p.fixed).length).toBe(12);
    expect(def.particles[13]!.position).toEqual([0.05, -0.05]);
    expect(def.springs.slice(0, 3).map((s) => [s.a, s.b])).toEqual([
      [0, 1],
      [0, 12],
      [1, 2],
    ]);
    expect(() => springCloth({ columns: 1, rows: 5, dt: 1 / 60 })).toThrow(RangeError);
    expect(() => springCloth({ columns: 4, rows: 2.5, dt: 1 / 60 })).toThrow(RangeError);
  });
});

describe('the WebAssembly spring kernel', () => {
  it('is kernels.wat, assembled: the committed bytes are not stale', async () => {
    const bytes = await assembleKernels();
    expect(Array.from(SPRING_KERNELS_WASM)).toEqual(Array.from(bytes));
    const generated = readFileSync(
      new URL('../src/physics/dynamics/kernels-wasm.ts', import.meta.url),
      'utf8',
    );
    expect(generated).toBe(kernelsModule(bytes));
  });

  it('gives the JavaScript kernel’s bits under every integrator, step for step', () => {
    for (const method of INTEGRATOR_METHODS) {
      const def = cloth(12, 10, method);
      const wasm = new SpringSystem(def);
      // The same model stepped on plain arrays: the JavaScript kernel.
      const model = new SpringModel(def);
      const integrator = createIntegrator(method, model);
      const state = new DynamicsState(model.size);
      state.x.set(model.startPosition);
      state.v.set(model.startVelocity);
      integrator.start(state, def.dt);
      // The system's arrays are views of its kernel's memory; the plain ones are not.
      expect(wasm.state.x.buffer).toBe(wasm.state.v.buffer);
      expect(wasm.state.x.buffer.byteLength).toBeGreaterThanOrEqual(65536);
      expect(state.x.buffer.byteLength).toBe(8 * model.size);
      const a: number[][] = [];
      const b: number[][] = [];
      for (let t = 1; t <= 300; t++) {
        wasm.step();
        integrator.step(state, def.dt);
        if (t % 50 === 0) {
          a.push([t, ...wasm.state.x, ...wasm.state.v]);
          b.push([t, ...state.x, ...state.v]);
        }
      }
      expect([method, a]).toEqual([method, b]);
    }
  });

  it('runs only where it pays: 2D models of at least WASM_MIN_SPRINGS springs', () => {
    const small = new SpringSystem(cloth(4, 4, 'semi-implicit-euler')); // 24 springs
    expect(small.model.springA.length).toBeLessThan(WASM_MIN_SPRINGS);
    expect(small.state.x.buffer.byteLength).toBe(8 * small.model.size);
    const big = new SpringSystem(cloth(12, 10, 'semi-implicit-euler'));
    expect(big.model.springA.length).toBeGreaterThanOrEqual(WASM_MIN_SPRINGS);
    expect(big.state.x.buffer).toBe(big.state.v.buffer);
    // Arrays of another size, or beyond the memory's room, are plain ones and still work.
    expect(big.model.allocate(3).buffer.byteLength).toBe(24);
    const extra = Array.from({ length: 20 }, () => big.model.allocate(big.model.size));
    expect(extra.filter((a) => a.buffer === big.state.x.buffer).length).toBeLessThan(20);
    const out = new Float64Array(big.model.size);
    big.model.accelerations(big.state.x, big.state.v, out);
    const out2 = big.model.allocate(big.model.size);
    big.model.accelerations(big.state.x, big.state.v, out2);
    expect(Array.from(out2)).toEqual(Array.from(out));
  });

  it('saves and loads like any system (a golden hash after 600 steps)', () => {
    const a = new SpringSystem(cloth(12, 10, 'velocity-verlet'));
    for (let t = 0; t < 300; t++) a.step();
    const b = new SpringSystem(cloth(12, 10, 'velocity-verlet'));
    b.load(a.save());
    for (let t = 0; t < 300; t++) {
      a.step();
      b.step();
    }
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
    expect(hex64(a.hash())).toBe('3b7e9d87c89189fa');
  });
});
