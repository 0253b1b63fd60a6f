import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { afterAll, describe, expect, it } from 'vitest';
import { BodyFlag } from '../src/physics/world/body.js';
import * as layout from '../src/physics/world/kernel-layout.js';
import {
  KERNELS,
  expandKernel,
  readLayout,
  unusedLayoutNames,
  type Kernel,
} from '../../../scripts/wasm.mjs';

// kernel-layout.ts is the one source of the world kernels' memory layout: scripts/wasm.mjs puts
// its values into the .wat sources (the goldens test compares the assembled bytes with the
// committed ones), the JavaScript twins import it.

const worldDir = new URL('../src/physics/world/', import.meta.url).pathname;
const layoutPath = `${worldDir}kernel-layout.ts`;
const scratch = mkdtempSync(join(tmpdir(), 'fixedstep-layout-'));
afterAll(() => {
  rmSync(scratch, { recursive: true, force: true });
});

/** A kernel in the scratch folder: `wat` as its source, `layoutText` as its layout. */
function scratchKernel(wat: string, layoutText = readFileSync(layoutPath, 'utf8')): Kernel {
  const dir = mkdtempSync(join(scratch, 'k-'));
  writeFileSync(join(dir, 'k.wat'), wat);
  writeFileSync(join(dir, 'layout.ts'), layoutText);
  return { dir: `${dir}/`, wat: 'k.wat', ts: 'k-wasm.ts', name: 'K', layout: 'layout.ts' };
}

describe('the world kernels’ memory layout', () => {
  it('is read by the build script as the TypeScript module exports it', () => {
    expect(Object.fromEntries(readLayout(layoutPath))).toEqual({ ...layout });
  });

  it('has every name used by a .wat source, and each source substitutes all its placeholders', () => {
    expect(unusedLayoutNames()).toEqual([]);
    for (const kernel of KERNELS.filter((k) => k.layout !== undefined)) {
      const { text, used } = expandKernel(kernel);
      expect(text).not.toMatch(/\{\{|\}\}/);
      expect(used.size).toBeGreaterThan(0);
    }
  });

  it('stops the build on a placeholder that names nothing, naming the file and line', () => {
    const kernel = scratchKernel('(module\n  (func (result i32) (i32.const {{VISIT_BYTE}})))\n');
    expect(() => expandKernel(kernel)).toThrow(
      'k.wat:2: {{VISIT_BYTE}} names VISIT_BYTE, which the layout does not declare',
    );
    const malformed = scratchKernel(
      '(module (func (result i32) (i32.const {{VISIT_PAIR_BYTES +}})))',
    );
    expect(() => expandKernel(malformed)).toThrow('k.wat:1: {{VISIT_PAIR_BYTES +}} is incomplete');
  });

  it('stops the build on a name no source uses, and on a layout line it cannot read', () => {
    const extra = `${readFileSync(layoutPath, 'utf8')}export const SPARE_OFFSET = 72;\n`;
    const kernel = scratchKernel(
      '(module (func (result i32) (i32.const {{VISIT_PAIR_BYTES}})))',
      extra,
    );
    const unused = unusedLayoutNames([kernel]);
    expect(unused).toContain(`${kernel.dir}layout.ts: SPARE_OFFSET`);
    expect(unused).not.toContain(`${kernel.dir}layout.ts: VISIT_PAIR_BYTES`);
    const computed = scratchKernel('', 'export const A = 8;\nexport const B = A * 2;\n');
    expect(() => expandKernel(computed)).toThrow(
      'layout.ts:2: not `export const NAME = <integer>;`: export const B = A * 2;',
    );
  });

  it('evaluates sums and products as integers', () => {
    const kernel = scratchKernel(
      '(i32.const {{2 * VISIT_PAIR_BYTES}}) offset={{VISIT_LANE_BYTES + VISIT_VELOCITY_B}} {{VELOCITY_SHIFT - 3}}',
    );
    expect(expandKernel(kernel).text).toBe('(i32.const 256) offset=124 1');
  });

  it('keeps what the kernels assume of it', () => {
    expect(2 ** layout.VISIT_PAIR_SHIFT).toBe(layout.VISIT_PAIR_BYTES);
    expect(2 ** layout.POSITION_SHIFT).toBe(layout.POSITION_BYTES);
    expect(2 ** layout.VELOCITY_SHIFT).toBe(16); // vx, vy: two f64
    expect(layout.POSITION_XY + 16).toBe(layout.POSITION_BYTES);
    // A pair's f64 fields are f64x2 (the first visit's, then the second's), 16 bytes apart and
    // 16-byte aligned, before the velocity offsets, which the plan's pad leaves after zeroing
    // every f64 field below VISIT_VELOCITY_A; each i32 lane pair (A, B) is one lane's 8 bytes.
    const f64Fields = [
      layout.VISIT_NORMAL_X,
      layout.VISIT_NORMAL_Y,
      layout.VISIT_NORMAL_MASS,
      layout.VISIT_INVERSE_MASS_A,
      layout.VISIT_INVERSE_MASS_B,
      layout.VISIT_NORMAL_IMPULSE,
      layout.VISIT_TANGENT_IMPULSE,
    ];
    expect(f64Fields).toEqual(f64Fields.map((_, i) => 16 * i));
    expect(layout.VISIT_SEPARATION).toBe(layout.VISIT_NORMAL_MASS);
    expect(layout.VISIT_LANE_BYTES).toBe(8);
    expect(layout.VISIT_VELOCITY_A).toBe(16 * f64Fields.length);
    expect(layout.VISIT_VELOCITY_B).toBe(layout.VISIT_VELOCITY_A + 4);
    expect(layout.VISIT_VELOCITY_B + 4 + layout.VISIT_LANE_BYTES).toBe(layout.VISIT_PAIR_BYTES);
    expect(BodyFlag.KINEMATIC).toBe(layout.BODY_KINEMATIC);
    expect(BodyFlag.ASLEEP).toBe(layout.BODY_ASLEEP);
  });
});

describe('the world kernels’ names', () => {
  it.each([
    ['contact-solver.wat', 'contact-solver.ts'],
    ['broad-phase.wat', 'broad-phase.ts'],
  ])('every export of %s is a function of its twin %s', (wat, ts) => {
    const exports = [...readFileSync(`${worldDir}${wat}`, 'utf8').matchAll(/\(export "(\w+)"\)/g)];
    const twin = readFileSync(`${worldDir}${ts}`, 'utf8');
    expect(exports.length).toBeGreaterThan(0);
    const missing = exports
      .map((m) => m[1]!)
      .filter((name) => !new RegExp(`^(?:function |  (?:private )?)${name}\\(`, 'm').test(twin));
    expect(missing).toEqual([]);
  });
});
