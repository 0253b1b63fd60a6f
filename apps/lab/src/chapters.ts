/**
 * The lab follows the talk, one chapter per section, in the talk's order. This list is the only
 * place a chapter is registered: the navigation, the router and the browser test that loads every
 * chapter at desktop and phone width all read it (see apps/lab/README.md).
 */
import type { ChapterHead, MountChapter } from './shell/chapter-shell.js';

export interface Chapter extends ChapterHead {
  /** One line for the navigation's tooltip. */
  readonly summary: string;
  /** Loads the chapter module (a separate chunk). */
  readonly load: () => Promise<{ mount: MountChapter }>;
}

export const CHAPTERS: readonly Chapter[] = [
  {
    id: 'loop',
    number: 1,
    title: 'The loop',
    summary: 'Frame-locked, variable Δt, fixed step and its final fixes, side by side.',
    load: () => import('./chapters/loop/loop.js'),
  },
  {
    id: 'movement',
    number: 2,
    title: 'Movement',
    summary:
      'The same jump at 30, 60, 144 and 240 Hz: variable Δt fans out, a fixed step does not.',
    load: () => import('./chapters/movement/movement.js'),
  },
  {
    id: 'collisions',
    number: 3,
    title: 'Collisions',
    summary: 'Fast bodies against thin walls: tunnelling, the rule minWallSize = v·dt, and CCD.',
    load: () => import('./chapters/collisions/collisions.js'),
  },
  {
    id: 'physics',
    number: 4,
    title: 'Physics',
    summary: 'A spring at a 0.03 s step under six integrators: explicit Euler explodes.',
    load: () => import('./chapters/physics/physics.js'),
  },
  {
    id: 'replays',
    number: 5,
    title: 'Replays',
    summary: 'Record only the inputs and the seeds.',
    load: () => import('./chapters/replays/replays.js'),
  },
  {
    id: 'network',
    number: 6,
    title: 'Network',
    summary: 'Synchronise only the inputs and the clock.',
    load: () => import('./chapters/network/network.js'),
  },
  {
    id: 'debugging',
    number: 7,
    title: 'Debugging',
    summary: 'The same recorded inputs at every display rate: one hash under a fixed step.',
    load: () => import('./chapters/debugging/debugging.js'),
  },
  {
    id: 'final-fixes',
    number: 8,
    title: 'Final fixes',
    summary:
      'A hitch without the clamp (the spiral of death), with it, and a clock that jumps back.',
    load: () => import('./chapters/final-fixes/final-fixes.js'),
  },
  {
    id: 'games',
    number: 9,
    title: 'Games',
    summary: 'The talk’s three games: play them, break them under a variable Δt, replay them.',
    load: () => import('./chapters/games/games.js'),
  },
  {
    id: 'rigid-bodies',
    number: 10,
    title: 'Rigid bodies',
    summary:
      'Boxes that rotate, through Rapier: a tower knocked over, replayed and rolled back, equal hashes.',
    load: () => import('./chapters/rigid-bodies/rigid-bodies.js'),
  },
];

/** The chapter id of a location hash: `#/loop` → `loop`; empty for `#` or `#/`. */
export function routeOf(hash: string): string {
  const m = /^#\/([a-z0-9-]*)/.exec(hash);
  return m?.[1] ?? '';
}
