import type { RegisteredGame } from './game.js';
import { runnerGame } from './runner/index.js';
import { ctfGame } from './ctf/index.js';
import { survivalGame } from './survival/index.js';
// Each game adds its import here and its definition to GAMES below.

/** Every game, by id. Replays, the server and the CLI find a game here. */
export const GAMES: readonly RegisteredGame[] = [runnerGame, ctfGame, survivalGame];

/** The game with `id`, or undefined. */
export function findGame(id: string): RegisteredGame | undefined {
  return GAMES.find((g) => g.info.id === id);
}
