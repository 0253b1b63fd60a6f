/**
 * The arena games' state schemas (see `defineStateSchema`): their `save()` bytes column by column
 * — the head and the bullet pool that every arena game writes, around each game's own part — with
 * the precision a state-sync client needs. Positions to 1/32 of a unit (a thirty-second of a pixel),
 * velocities to 1/4 unit/s, timers to 1/240 s (a quarter of a tick); counters, flags and the random
 * generator exactly.
 * @module
 */
import { defineStateSchema, type StateColumn, type StateSchema } from 'fixedstep';

/** The arena games' step (their tick rate is 60 Hz). */
const STEP = 1 / 60;

/** Position precision, units. */
export const POSITION_PRECISION = 1 / 32;
/**
 * Velocity precision, units per second: fine enough that a position predicted from it over a
 * snapshot interval and a round trip (~0.2 s) is off by less than a position step.
 */
export const VELOCITY_PRECISION = 1 / 4;
/** Timer precision, seconds. */
export const TIMER_PRECISION = 1 / 240;

/** A float column sent as a multiple of `precision` within `min` … `max`. */
export function quantised(
  name: string,
  group: string,
  count: number,
  precision: number,
  min: number,
  max: number,
): StateColumn {
  return { name, type: 'f64', count, group, precision, min, max };
}

/**
 * Positions within the field (and a margin), of `count` rows of `group`; with `moving`, they move
 * by the group's `${prefix}vx` / `${prefix}vy` columns (see `StateColumn.rate`).
 */
export function positions(
  prefix: string,
  group: string,
  count: number,
  size: number,
  moving = false,
): StateColumn[] {
  const x = quantised(`${prefix}x`, group, count, POSITION_PRECISION, -64, size + 64);
  const y = quantised(`${prefix}y`, group, count, POSITION_PRECISION, -64, size + 64);
  if (moving) {
    x.rate = `${prefix}vx`;
    y.rate = `${prefix}vy`;
  }
  return [x, y];
}

/** Velocities up to ±`max` units per second. */
export function velocities(
  prefix: string,
  group: string,
  count: number,
  max: number,
): StateColumn[] {
  return [
    quantised(`${prefix}vx`, group, count, VELOCITY_PRECISION, -max, max),
    quantised(`${prefix}vy`, group, count, VELOCITY_PRECISION, -max, max),
  ];
}

/** A timer of `count` rows, 0 … `max` seconds. */
export function timer(name: string, group: string, count: number, max: number): StateColumn {
  return quantised(name, group, count, TIMER_PRECISION, -1, max);
}

/** What an arena game's schema needs to know of it. */
export interface ArenaSchemaFormat {
  /** Player slots. */
  slots: number;
  bulletCapacity: number;
  /** The larger side of the field, units. */
  size: number;
  /** The fastest bullet, units per second. */
  bulletSpeed: number;
}

/**
 * The schema of an arena game: the head (magic, players, tick, clock, over flag, generator), the
 * game's own `body` columns, the bullet pool — the order `ArenaState.write` writes them in.
 */
export function arenaStateSchema(format: ArenaSchemaFormat, body: StateColumn[]): StateSchema {
  const cap = format.bulletCapacity;
  return defineStateSchema({
    columns: [
      { name: 'magic', type: 'u32', group: 'head' },
      { name: 'players', type: 'u8', group: 'head' },
      { name: 'tick', type: 'u32', group: 'head' },
      // The clock is tick × step: sent as the tick it is (up to 2^30 ticks).
      quantised('clock', 'head', 1, STEP, 0, 1073741824 * STEP),
      { name: 'over', type: 'u8', group: 'head' },
      // Sent (16 bytes a snapshot): two clients then hold the same bytes, as the lab shows.
      { name: 'rng', type: 'u32', count: 4, group: 'rng' },
      ...body,
      { name: 'bulletNext', type: 'u32', group: 'bulletPool' },
      { name: 'bulletsThroughWalls', type: 'u32', group: 'bulletPool' },
      { name: 'bulletAlive', type: 'u8', count: cap, group: 'bullets' },
      { name: 'bulletOwner', type: 'u8', count: cap, group: 'bullets' },
      { name: 'bulletTeam', type: 'u8', count: cap, group: 'bullets' },
      { name: 'bulletSerial', type: 'u32', count: cap, group: 'bullets' },
      ...positions('bullet', 'bullets', cap, format.size, true),
      ...velocities('bullet', 'bullets', cap, format.bulletSpeed * 2),
      // A live bullet's life is > 0: it rounds up, never to 0.
      { ...timer('bulletLife', 'bullets', cap, 60), rounding: 'away' },
    ],
  });
}
