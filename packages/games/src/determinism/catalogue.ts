/**
 * The trace catalogue: every scene whose per-tick state hashes must be the same in every
 * JavaScript engine and at every display rate. Node and the browsers run this very code (the
 * browser page bundles it), so their traces are comparable tick for tick.
 */
import type { RegisteredGame } from '../games/game.js';
import { GAMES } from '../games/registry.js';
import { TRACE_DISPLAY_RATES } from './display.js';
import { gameScenes } from './games.js';
import { detMathScene } from './probes.js';
import {
  ballScenes,
  bulletsScenes,
  circlesScene,
  clothScenes,
  filtersSensorsScene,
  materialsScene,
  labScenes,
  randomScene,
  ropeScenes,
} from './scenes.js';
import type { TraceScene } from './trace.js';

/** Options of {@link traceCatalogue}. */
export interface TraceCatalogueOptions {
  /** The games to trace. Default: every game of the registry (`GAMES`). */
  games?: readonly RegisteredGame[];
  /** Ticks of each game's bot match. Default 3600 (a minute at 60 Hz). */
  gameTicks?: number;
  /** Display rates of the display-rate scenes, Hz. Default 30, 59.94, 60, 144, 240. */
  rates?: readonly number[];
  /** Multiplies every default tick count (e.g. 0.1 for a smoke run). Default 1. */
  scale?: number;
}

/** Ticks of each built-in scene at scale 1. */
export const TRACE_TICKS = Object.freeze({
  math: 256,
  random: 2000,
  ball: 3600,
  circles: 600,
  bullets: 400,
  filtersSensors: 600,
  materials: 600,
  rope: 1200,
  cloth: 600,
  lab: 600,
  game: 3600,
});

/** Every scene, in a fixed order; ids are unique. */
export function traceCatalogue(options: TraceCatalogueOptions = {}): TraceScene[] {
  const scale = options.scale ?? 1;
  const n = (ticks: number) => Math.max(1, Math.round(ticks * scale));
  const rates = options.rates ?? TRACE_DISPLAY_RATES;
  const games = options.games ?? GAMES;
  const scenes: TraceScene[] = [
    detMathScene(n(TRACE_TICKS.math)),
    randomScene(n(TRACE_TICKS.random)),
    ...ballScenes(n(TRACE_TICKS.ball), rates),
    circlesScene(n(TRACE_TICKS.circles)),
    ...bulletsScenes(n(TRACE_TICKS.bullets), rates),
    filtersSensorsScene(n(TRACE_TICKS.filtersSensors)),
    materialsScene(n(TRACE_TICKS.materials)),
    ...ropeScenes(n(TRACE_TICKS.rope)),
    ...clothScenes(n(TRACE_TICKS.cloth)),
    ...labScenes(n(TRACE_TICKS.lab)),
    ...games.flatMap((def) => gameScenes(def, n(options.gameTicks ?? TRACE_TICKS.game), rates)),
  ];
  const seen = new Set<string>();
  for (const s of scenes) {
    if (seen.has(s.id)) throw new Error(`traceCatalogue: two scenes named ${s.id}`);
    seen.add(s.id);
  }
  for (const s of scenes) {
    if (s.sameAs !== undefined && !seen.has(s.sameAs)) {
      throw new Error(
        `traceCatalogue: ${s.id} is sameAs ${s.sameAs}, which is not in the catalogue`,
      );
    }
  }
  return scenes;
}
