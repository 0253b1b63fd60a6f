/** The lab follows the talk, one chapter per section, in the talk's order. */

/** What a chapter module exports: it builds itself into `root` and returns how to tear down. */
export type MountChapter = (root: HTMLElement) => () => void;

export interface Chapter {
  /** The route: `#/loop`. */
  readonly id: string;
  readonly number: number;
  readonly title: string;
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
    load: () => import('./chapters/loop.js'),
  },
  {
    id: 'movement',
    number: 2,
    title: 'Movement',
    summary:
      'The same jump at 30, 60, 144 and 240 Hz: variable Δt fans out, a fixed step does not.',
    load: () => import('./chapters/movement.js'),
  },
  {
    id: 'collisions',
    number: 3,
    title: 'Collisions',
    summary: 'Fast bodies against thin walls: tunnelling, the rule minWallSize = v·dt, and CCD.',
    load: () => import('./chapters/collisions.js'),
  },
  {
    id: 'physics',
    number: 4,
    title: 'Physics',
    summary: 'A spring at a 0.03 s step under six integrators: explicit Euler explodes.',
    load: () => import('./chapters/physics.js'),
  },
  {
    id: 'replays',
    number: 5,
    title: 'Replays',
    summary: 'Record only the inputs and the seeds.',
    load: () => import('./chapters/replays.js'),
  },
  {
    id: 'network',
    number: 6,
    title: 'Network',
    summary: 'Synchronise only the inputs and the clock.',
    load: () => import('./chapters/network.js'),
  },
  {
    id: 'debugging',
    number: 7,
    title: 'Debugging',
    summary: 'The same recorded inputs at every display rate: one hash under a fixed step.',
    load: () => import('./chapters/debugging.js'),
  },
  {
    id: 'final-fixes',
    number: 8,
    title: 'Final fixes',
    summary:
      'A hitch without the clamp (the spiral of death), with it, and a clock that jumps back.',
    load: () => import('./chapters/final-fixes.js'),
  },
  {
    id: 'games',
    number: 9,
    title: 'Games',
    summary: 'The talk’s three games: play them, break them under a variable Δt, replay them.',
    load: () => import('./chapters/games.js'),
  },
];

/** The chapter id of a location hash: `#/loop` → `loop`; empty for `#` or `#/`. */
export function routeOf(hash: string): string {
  const m = /^#\/([a-z0-9-]*)/.exec(hash);
  return m?.[1] ?? '';
}
