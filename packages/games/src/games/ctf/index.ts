import type { Bot, Game, GameDefinition } from '../game.js';
import { decodeGameConfig, encodeGameConfig } from '../config.js';
import { CTF_INFO, CtfGame } from './game.js';
import { ctfBotInput } from './bot.js';

export { CTF_INFO, CtfGame, CtfState, FlagState, NO_CARRIER } from './game.js';
export type { CtfOptions } from './game.js';
export { ctfBotInput } from './bot.js';
export { CTF, CTF_VERSION, CTF_WALLS, FLAG_STAND_X, FLAG_STAND_Y, ctfNav } from './layout.js';

/** The capture-the-flag AI as a {@link Bot}: for a {@link CtfGame} only. */
export const ctfBot: Bot = (game: Game, player: number) => {
  if (!(game instanceof CtfGame)) throw new TypeError('ctfBot: not a capture-the-flag game');
  return ctfBotInput(game, player);
};

/** Capture the flag in the game registry. */
export const ctfGame: GameDefinition = Object.freeze<GameDefinition>({
  info: CTF_INFO,
  create: (config) => new CtfGame(config),
  bot: ctfBot,
  encodeConfig: encodeGameConfig,
  decodeConfig: (bytes) => decodeGameConfig(bytes, CTF_INFO.minPlayers, CTF_INFO.maxPlayers),
});
