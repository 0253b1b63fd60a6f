/**
 * Survival's state schema: {@link SurvivalState}'s bytes, column by column (the order of its
 * `writeBody`), for state sync. See `arena/state-schema.ts` for the precisions.
 * @module
 */
import type { StateSchema } from 'fixedstep';
import {
  arenaStateSchema,
  positions,
  quantised,
  timer,
  velocities,
  VELOCITY_PRECISION,
} from '../arena/state-schema.js';
import { SURVIVAL } from './layout.js';

/** The schema of a survival state. */
export function survivalStateSchema(): StateSchema {
  const n = SURVIVAL.maxPlayers;
  const cap = SURVIVAL.enemyCapacity;
  const size = Math.max(SURVIVAL.width, SURVIVAL.height);
  const fastest = Math.max(SURVIVAL.playerSpeed, SURVIVAL.maxEnemySpeed) * 2;
  return arenaStateSchema(
    {
      slots: n,
      bulletCapacity: SURVIVAL.bulletCapacity,
      size,
      bulletSpeed: SURVIVAL.bulletSpeed,
    },
    [
      { name: 'wave', type: 'u32', group: 'waves' },
      { name: 'phase', type: 'u8', group: 'waves' },
      timer('timer', 'waves', 1, 600),
      { name: 'toSpawn', type: 'u32', group: 'waves' },
      { name: 'cleared', type: 'u32', group: 'waves' },
      { name: 'enemiesThroughWalls', type: 'u32', group: 'waves' },
      { name: 'nextEnemy', type: 'u32', group: 'waves' },
      { name: 'active', type: 'u8', count: n, group: 'players' },
      { name: 'alive', type: 'u8', count: n, group: 'players' },
      { name: 'facing', type: 'u8', count: n, group: 'players' },
      { name: 'lives', type: 'u8', count: n, group: 'players' },
      ...positions('', 'players', n, size, true),
      ...velocities('', 'players', n, fastest),
      timer('cooldown', 'players', n, 60),
      timer('invulnerable', 'players', n, 60),
      { name: 'kills', type: 'u32', count: n, group: 'players' },
      { name: 'enemyAlive', type: 'u8', count: cap, group: 'enemies' },
      { name: 'enemySerial', type: 'u32', count: cap, group: 'enemies' },
      ...positions('e', 'enemies', cap, size),
      // Every step steers each enemy afresh (toward the nearest player) before it moves: its
      // velocity is never read before it is set, so it is not sent and loads as 0.
      ...velocities('e', 'enemyMotion', cap, fastest).map((c) => ({
        ...c,
        local: 'zero' as const,
      })),
      quantised('espeed', 'enemies', cap, VELOCITY_PRECISION, 0, fastest),
      { name: 'eslide', type: 'i8', count: cap, group: 'enemies' },
    ],
  );
}
