import {
  Relay,
  relayCatalog,
  type AnyGameDefinition,
  type RelayCatalog,
  type RelayOptions,
} from 'fixedstep';
import { GAMES } from '@fixedstep/games';

/**
 * The relay's catalog over the game registry (or `games`): a room may play any registered game,
 * and every member must run the same version and input schema.
 */
export function gameCatalog(games: readonly AnyGameDefinition[] = GAMES): RelayCatalog {
  return relayCatalog(games);
}

/** A {@link Relay} over the game registry (the catalog may be replaced, e.g. by test games). */
export function createRelay(
  options: Omit<RelayOptions, 'catalog'> & { catalog?: RelayCatalog },
): Relay {
  return new Relay({ ...options, catalog: options.catalog ?? gameCatalog() });
}
