/** The engines of the `physics-circles` suite, by the name the peer program takes. */
import type { PhysicsScene } from 'fixedstep';
import { buildFixedstep } from './fixedstep.js';
import { buildMatter } from './matter.js';
import { buildPlanck } from './planck.js';
import { buildRapier, buildRapierDeterministic, initRapier } from './rapier.js';
import type { PeerWorld } from './types.js';

export const ENGINES = [
  'fixedstep',
  'matter',
  'planck',
  'rapier',
  'rapier-rotating',
  'rapier-deterministic',
  'rapier-4',
] as const;
export type Engine = (typeof ENGINES)[number];

export function isEngine(name: string): name is Engine {
  return (ENGINES as readonly string[]).includes(name);
}

/** Builds `scene` in `engine` (Rapier: its WASM instantiated first). */
export async function buildEngine(engine: Engine, scene: PhysicsScene): Promise<PeerWorld> {
  switch (engine) {
    case 'fixedstep':
      return buildFixedstep(scene);
    case 'matter':
      return buildMatter(scene);
    case 'planck':
      return buildPlanck(scene);
    case 'rapier':
      await initRapier();
      return buildRapier(scene);
    case 'rapier-rotating':
      await initRapier();
      return buildRapier(scene, { rotation: true });
    case 'rapier-deterministic':
      return buildRapierDeterministic(scene);
    case 'rapier-4':
      await initRapier();
      return buildRapier(scene, { solverIterations: 4 });
  }
}
