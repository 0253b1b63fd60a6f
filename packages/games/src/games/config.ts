import { ByteReader, ByteWriter } from 'fixedstep';
import type { GameConfig } from './game.js';

/** The canonical bytes of a {@link GameConfig}: seed (u32), players (u8). */
export function encodeGameConfig(config: GameConfig): Uint8Array {
  return new ByteWriter(8).u32(config.seed).u8(config.players).finish();
}

/** Reads {@link encodeGameConfig}'s bytes; throws a RangeError naming what is wrong. */
export function decodeGameConfig(
  bytes: Uint8Array,
  minPlayers: number,
  maxPlayers: number,
): GameConfig {
  const r = new ByteReader(bytes);
  const seed = r.u32();
  const players = r.u8();
  r.end();
  if (players < minPlayers || players > maxPlayers) {
    throw new RangeError(
      `game config: players must be from ${minPlayers} to ${maxPlayers}, got ${players}`,
    );
  }
  return { seed, players };
}
