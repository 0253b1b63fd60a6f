/**
 * The lab follows the talk, one chapter per section. Only chapters that exist are listed in the
 * navigation; the others are reserved here so their deep links say "coming" instead of failing.
 */

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
];

/** The talk's outline: chapters still to be built (not shown in the navigation). */
export const PLANNED: readonly { id: string; number: number; title: string }[] = [
  { id: 'movement', number: 2, title: 'Movement' },
  { id: 'collisions', number: 3, title: 'Collisions' },
  { id: 'physics', number: 4, title: 'Physics' },
  { id: 'replays', number: 5, title: 'Replays' },
  { id: 'network', number: 6, title: 'Network' },
  { id: 'debugging', number: 7, title: 'Debugging' },
  { id: 'final-fixes', number: 8, title: 'Final fixes' },
];

/** The chapter id of a location hash: `#/loop` → `loop`; empty for `#` or `#/`. */
export function routeOf(hash: string): string {
  const m = /^#\/([a-z0-9-]*)/.exec(hash);
  return m?.[1] ?? '';
}
