import { setupFromReplayHeader, type ReplayHeader, type ReplayRecorderOptions } from 'fixedstep';
import type { Game, GameConfig, RegisteredGame } from './game.js';
import { findGame } from './registry.js';

/** The recorder options of a game started with `config`: game id and version, step, seed, config bytes. */
export function replayOptionsFor(
  def: RegisteredGame,
  config: GameConfig,
  players: readonly string[],
  extra: Pick<ReplayRecorderOptions, 'checkpointEvery' | 'keyframeEvery' | 'tickHashes'> = {},
): ReplayRecorderOptions {
  if (players.length !== config.players) {
    throw new RangeError(
      `replayOptionsFor: ${players.length} player names for ${config.players} players`,
    );
  }
  return {
    gameId: def.info.id,
    gameVersion: String(def.info.version),
    tickRate: def.info.tickRate,
    seeds: [config.seed],
    config: def.encodeConfig(config),
    players,
    input: def.input,
    ...extra,
  };
}

/**
 * Builds the game a replay header describes — the factory for `verifyReplay` and `ReplayPlayer`.
 * Throws a RangeError naming what does not match: an unknown game, another version of it, another
 * step, a config it cannot read, or a player count that disagrees with the config.
 */
export function gameFromReplayHeader(header: ReplayHeader): Game {
  const def = findGame(header.gameId);
  if (!def) throw new RangeError(`unknown game "${header.gameId}"`);
  const setup = setupFromReplayHeader(def, header);
  const config = def.decodeConfig(setup.options);
  if (config.players !== setup.players) {
    throw new RangeError(
      `${def.info.id} replay names ${setup.players} players, its config says ${config.players}`,
    );
  }
  if (config.seed !== setup.seed)
    throw new RangeError(`${def.info.id} replay seeds do not match its config`);
  return def.create(setup);
}
