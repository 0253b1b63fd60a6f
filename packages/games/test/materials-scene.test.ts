/**
 * The four-engine suite's materials scene (`physics/materials-250`): a golden trace digest, and
 * a version 3 snapshot whose field map covers it.
 */
import { describe, expect, it } from 'vitest';
import { fnv1a64Hex } from 'fixedstep';
import { materialsScene, physicsWorldFields, sceneStateAt, traceScene } from '@fixedstep/games';

const GOLDEN = 'e89fd2b9bb7c35f5';

describe('physics/materials-250', () => {
  it('golden digest of the 600-tick trace', () => {
    const digest = fnv1a64Hex(new TextEncoder().encode(traceScene(materialsScene())));
    if (digest !== GOLDEN) console.log(`physics/materials-250 golden digest is now ${digest}`);
    expect(digest).toBe(GOLDEN);
  });

  it('saves version 3, and the field map names the material columns', () => {
    const state = sceneStateAt(materialsScene(), 60);
    expect(new DataView(state.buffer).getUint32(4, true)).toBe(3);
    const names = physicsWorldFields(state)!.map((f) => f.name);
    expect(names.at(-1)).toBe('body[249].linearDamping');
    expect(names).toContain('body[5].friction');
  });
});
