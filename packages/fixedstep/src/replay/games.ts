import type { ReplayFactory } from './player.js';
import type { ReplayHeader } from './format.js';
import type { AnyGameDefinition, GameSetup } from '../sim/game.js';
import type { Simulation } from '../sim/simulation.js';

/**
 * The {@link GameSetup} a replay header describes for `game`, checked: the same game id and
 * version, the game's tick rate, the game's input schema (a format-1 file, which has none, fits any
 * schema without axes), one seed, a player count the game supports. Throws a RangeError naming what does not match.
 */
export function setupFromReplayHeader(game: AnyGameDefinition, header: ReplayHeader): GameSetup {
  if (header.gameId !== game.id) {
    throw new RangeError(`replay of game "${header.gameId}", not "${game.id}"`);
  }
  if (header.gameVersion !== String(game.version)) {
    throw new RangeError(
      `${game.id} replay of version ${header.gameVersion}, this build plays version ${game.version}`,
    );
  }
  if (header.stepNumerator * game.tickRate !== header.stepDenominator) {
    throw new RangeError(
      `${game.id} replay with a step of ${header.stepNumerator}/${header.stepDenominator} s; the game ticks at ${game.tickRate} Hz`,
    );
  }
  // A format-1 file predates schemas: its words are button words, which any button-only schema
  // reads (bits a game does not define are ignored by that game, as they always were).
  const legacy = header.formatVersion === 1 && game.input.words === 1;
  if (header.input.id !== game.input.id && !legacy) {
    throw new RangeError(
      `${game.id} replay recorded with another input schema (${header.input.id}, the game's is ${game.input.id})`,
    );
  }
  if (header.seeds.length !== 1) {
    throw new RangeError(`${game.id} replay has ${header.seeds.length} seeds, the game takes one`);
  }
  const players = header.players.length;
  if (players < game.minPlayers || players > game.maxPlayers) {
    throw new RangeError(
      `${game.id} replay of ${players} players; the game takes ${game.minPlayers} to ${game.maxPlayers}`,
    );
  }
  return Object.freeze({ seed: header.seeds[0]!, players, options: header.config });
}

/**
 * A {@link ReplayFactory} that builds the game a header names, from one definition or a list
 * (a server's registry). Throws a RangeError for an unknown game or a header that does not fit it.
 */
export function replayFactory(
  games: AnyGameDefinition | readonly AnyGameDefinition[],
): ReplayFactory {
  const list: readonly AnyGameDefinition[] = Array.isArray(games)
    ? (games as readonly AnyGameDefinition[])
    : [games as AnyGameDefinition];
  return (header) => {
    const game = list.find((g) => g.id === header.gameId);
    if (game === undefined) {
      throw new RangeError(
        `unknown game "${header.gameId}" (this build knows ${list.map((g) => g.id).join(', ') || 'none'})`,
      );
    }
    return game.create(setupFromReplayHeader(game, header)) as Simulation<unknown>;
  };
}

/** A factory, or game definitions to build one from. */
export type ReplaySource = ReplayFactory | AnyGameDefinition | readonly AnyGameDefinition[];

/** The factory of a {@link ReplaySource}. @internal */
export function toFactory(source: ReplaySource): ReplayFactory {
  return typeof source === 'function' ? source : replayFactory(source);
}
