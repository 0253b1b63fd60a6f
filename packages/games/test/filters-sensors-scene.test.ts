/**
 * The four-engine suite's filters-and-sensors scene (`physics/filters-sensors`): a golden trace,
 * a version 2 snapshot whose field map covers it, and the features it is there for actually used.
 */
import { describe, expect, it } from 'vitest';
import { fnv1a64Hex } from 'fixedstep';
import {
  filtersSensorsFields,
  filtersSensorsScene,
  filtersSensorsWorld,
  sceneStateAt,
  traceScene,
  traceCatalogue,
} from '@fixedstep/games';

describe('physics/filters-sensors', () => {
  it('golden digest of the 600-tick trace', () => {
    const trace = traceScene(filtersSensorsScene());
    const digest = fnv1a64Hex(new TextEncoder().encode(trace));
    if (digest !== GOLDEN) console.log(`physics/filters-sensors golden digest is now ${digest}`);
    expect(digest).toBe(GOLDEN);
  });

  it('is in the catalogue', () => {
    expect(traceCatalogue({ games: [] }).map((s) => s.id)).toContain('physics/filters-sensors');
  });

  it('saves version 2, and the field map names every byte, to the tail', () => {
    const state = sceneStateAt(filtersSensorsScene(), 300);
    expect(new DataView(state.buffer).getUint32(4, true)).toBe(2);
    const fields = filtersSensorsFields(state)!;
    expect(fields).toBeDefined();
    const names = fields.map((f) => f.name);
    expect(names).toContain('body[0].groupIndex');
    expect(names).toContain('sensorOverlapCount');
    expect(names.at(-1)).toBe('ray.y');
  });

  it('uses what it is there for: team mates pass through each other, ghosts through walls, sensors see visitors', () => {
    const world = filtersSensorsWorld();
    let sensorBegins = 0;
    let contactBegins = 0;
    for (let t = 0; t < 600; t++) {
      world.step();
      sensorBegins += world.sensorEvents().begin.length;
      contactBegins += world.contactEvents().begin.length;
    }
    expect(sensorBegins).toBeGreaterThan(10);
    expect(contactBegins).toBeGreaterThan(10);
    // Ghosts (every third body) ignore the floor: by now they have fallen far below it.
    const ghostsBelow = [2, 5, 8, 11].filter((id) => world.y[id]! < -10).length;
    expect(ghostsBelow).toBe(4);
    // Teams rest on the floor.
    for (const id of [0, 1, 3, 4]) expect(world.y[id]!).toBeGreaterThan(0);
  });
});

const GOLDEN = '6e1cd5d7d1b72eb7';
