/** Before Rapier's WebAssembly is loaded (this file runs in a fresh module graph of its own). */
import { describe, expect, it } from 'vitest';
import {
  RapierSimulation,
  loadRapier,
  rapierReady,
  rapierVersion,
  towerScene,
} from '@fixedstep/rapier';

describe('before loadRapier()', () => {
  it('building a simulation says what to do; after loading it works', async () => {
    expect(rapierReady()).toBe(false);
    expect(() => new RapierSimulation(towerScene())).toThrow(
      'RapierSimulation "rapier-tower-8x2": Rapier is not initialised yet: await loadRapier() once first',
    );
    const [a, b] = await Promise.all([loadRapier(), loadRapier()]);
    expect(a).toBe(b);
    expect(rapierReady()).toBe(true);
    expect(rapierVersion()).toBe('0.20.0');
    const sim = new RapierSimulation(towerScene());
    sim.step([0]);
    expect(sim.tick).toBe(1);
    sim.dispose();
  });
});
