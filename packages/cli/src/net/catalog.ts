import {
  Relay,
  relayGameOf,
  type RelayCatalog,
  type RelayGame,
  type RelayOptions,
} from 'fixedstep';
import { GAMES, type GameDefinition } from '@fixedstep/games';

/** A game of the registry as the relay sees it: id, version, tick rate, players, config bytes. */
export function relayGame(def: GameDefinition): RelayGame {
  return relayGameOf(def);
}

/**
 * The relay's catalog over the game registry (or `games`): a room may play any registered game,
 * and every member must run the same version.
 */
export function gameCatalog(games: readonly GameDefinition[] = GAMES): RelayCatalog {
  const byId = new Map(games.map((g) => [g.info.id, relayGame(g)]));
  return (id, version) => {
    const game = byId.get(id);
    if (!game) return { code: 'UNKNOWN_GAME', message: `no game "${id}" on this server` };
    if (game.version !== version) {
      return {
        code: 'GAME_MISMATCH',
        message: `this server plays ${id} version ${game.version}, not ${version}`,
      };
    }
    return game;
  };
}

/** A {@link Relay} over the game registry (the catalog may be replaced, e.g. by test games). */
export function createRelay(
  options: Omit<RelayOptions, 'catalog'> & { catalog?: RelayCatalog },
): Relay {
  return new Relay({ ...options, catalog: options.catalog ?? gameCatalog() });
}
