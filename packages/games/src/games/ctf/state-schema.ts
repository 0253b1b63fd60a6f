/**
 * Capture the flag's state schema: {@link CtfState}'s bytes, column by column (the order of its
 * `writeBody`), for state sync. See `arena/state-schema.ts` for the precisions.
 * @module
 */
import type { StateSchema } from 'fixedstep';
import { arenaStateSchema, positions, timer, velocities } from '../arena/state-schema.js';

/** What the schema needs of the layout. */
export interface CtfSchemaLayout {
  width: number;
  height: number;
  slots: number;
  bulletCapacity: number;
  bulletSpeed: number;
  playerSpeed: number;
}

/** The schema of a capture-the-flag state. */
export function ctfStateSchema(layout: CtfSchemaLayout): StateSchema {
  const n = layout.slots;
  const size = Math.max(layout.width, layout.height);
  return arenaStateSchema(
    { slots: n, bulletCapacity: layout.bulletCapacity, size, bulletSpeed: layout.bulletSpeed },
    [
      { name: 'score', type: 'u32', count: 2, group: 'score' },
      { name: 'shots', type: 'u32', group: 'counters' },
      { name: 'playersThroughWalls', type: 'u32', group: 'counters' },
      { name: 'active', type: 'u8', count: n, group: 'players' },
      { name: 'alive', type: 'u8', count: n, group: 'players' },
      { name: 'health', type: 'u8', count: n, group: 'players' },
      { name: 'facing', type: 'u8', count: n, group: 'players' },
      ...positions('', 'players', n, size, true),
      ...velocities('', 'players', n, layout.playerSpeed * 2),
      timer('cooldown', 'players', n, 60),
      timer('respawn', 'players', n, 60),
      timer('protect', 'players', n, 60),
      { name: 'kills', type: 'u32', count: n, group: 'players' },
      { name: 'deaths', type: 'u32', count: n, group: 'players' },
      { name: 'captures', type: 'u32', count: n, group: 'players' },
      { name: 'flagState', type: 'u8', count: 2, group: 'flags' },
      { name: 'flagCarrier', type: 'u8', count: 2, group: 'flags' },
      ...positions('flag', 'flags', 2, size),
      timer('flagTimer', 'flags', 2, 600),
    ],
  );
}
