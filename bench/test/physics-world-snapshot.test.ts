import { describe, expect, it } from 'vitest';
import { bodiesInBox, bodiesInBoxScene, hex64 } from 'fixedstep';
import { quickRun } from '../lib/suite.js';
import type { TableSection } from '../lib/report.js';
import suite, {
  ROLLBACK_TICKS,
  SEED,
  SIZES,
  copyControl,
  loadCandidate,
  rollbackCandidate,
  saveCandidate,
  saveIntoCandidate,
  settledWorld,
} from '../suites/physics-world-snapshot.js';

describe('physics-world-snapshot suite: the candidates do what their names say', () => {
  const world = settledWorld(100, 10);

  it('settles the scene: every body in the box, awake, most of them in contact', () => {
    const scene = bodiesInBoxScene(100, SEED);
    const [minX, minY, maxX, maxY] = scene.inner;
    expect(world.bodyCount).toBe(100);
    expect(world.sleepingCount).toBe(0);
    for (let i = 0; i < 100; i++) {
      expect(world.x[i]).toBeGreaterThan(minX);
      expect(world.x[i]).toBeLessThan(maxX);
      expect(world.y[i]).toBeGreaterThan(minY);
      expect(world.y[i]).toBeLessThan(maxY);
    }
    expect(world.contactCount).toBeGreaterThan(80);
    // Half circles, half boxes.
    expect(Array.from({ length: 100 }, (_, i) => world.isBox(i)).filter(Boolean)).toHaveLength(50);
  });

  it('saveInto writes the bytes of save(); the copy control copies as many', () => {
    const out = new Uint8Array(world.snapshotSize);
    expect(saveIntoCandidate(world).run(3)).toBe(3 * world.snapshotSize);
    world.saveInto(out);
    expect(out).toEqual(world.save());
    expect(saveCandidate(world).run(2)).toBe(2 * world.snapshotSize);
    const copy = copyControl(world.snapshotSize);
    expect(copy.run(5)).toBe(4);
    expect(copy.run(70)).toBe(69);
  });

  it('load and a rollback leave the world exactly where they say', () => {
    const start = world.save();
    const loader = bodiesInBox(100, SEED, { enableSleep: false });
    loader.load(start);
    loadCandidate(loader).run(4);
    expect(loader.save()).toEqual(start);

    // A rollback re-simulates the same 8 ticks every time: it ends where 8 plain steps end.
    const reference = bodiesInBox(100, SEED, { enableSleep: false });
    reference.load(start);
    for (let t = 0; t < ROLLBACK_TICKS; t++) reference.step();
    for (const save of [false, true]) {
      const w = bodiesInBox(100, SEED, { enableSleep: false });
      w.load(start);
      const rollback = rollbackCandidate(w, ROLLBACK_TICKS, save);
      expect(rollback.run(3)).toBe(reference.tick);
      expect(hex64(w.hash())).toBe(hex64(reference.hash()));
    }
  });
});

describe('physics-world-snapshot suite: a tiny run', () => {
  it('reports a comparison per size, the throughput and rollback tables and the allocation table', async () => {
    const { sections, comparisons } = await quickRun(suite);
    expect(comparisons.map((c) => c.title.split(':')[0])).toEqual(SIZES.map((n) => `N = ${n}`));
    for (const c of comparisons) {
      expect(c.candidates.map((x) => x.name)).toEqual([
        'Uint8Array.set (same bytes)',
        'saveInto (reused buffer)',
        'save() (new array)',
        'load',
        `load + ${ROLLBACK_TICKS} steps`,
        `rollback: load + ${ROLLBACK_TICKS} × (step + saveInto)`,
      ]);
    }
    const tables = sections.filter((s): s is TableSection => s.kind === 'table');
    expect(tables.map((t) => t.rows.map((r) => r[0]))).toEqual([
      SIZES.map(String),
      SIZES.map(String),
      [
        'saveInto (reused buffer)',
        'load',
        `rollback: load + ${ROLLBACK_TICKS} × (step + saveInto)`,
        'save() (new array)',
      ],
    ]);
    // Bytes per body: about 100 (69 per slot, 24 per warm-start entry, a few entries a body).
    for (const row of tables[0]!.rows) {
      expect(Number(row[2])).toBeGreaterThan(69);
      expect(Number(row[2])).toBeLessThan(200);
    }
  });
});
