import type { Bot, RegisteredGame } from '../game.js';
import { arenaBot, arenaDefinition } from '../arena/game.js';
import { CTF_INFO, CtfGame } from './game.js';
import { ctfBotInput } from './bot.js';
import { CTF } from './layout.js';
import { ctfStateSchema } from './state-schema.js';

export { CTF_INFO, CtfGame, CtfState, FlagState, NO_CARRIER } from './game.js';
export type { CtfOptions } from './game.js';
export { ctfBotInput } from './bot.js';
export { CTF, CTF_VERSION, CTF_WALLS, FLAG_STAND_X, FLAG_STAND_Y, ctfNav } from './layout.js';

/** The capture-the-flag AI as a {@link Bot}: for a {@link CtfGame} only. */
export const ctfBot: Bot = arenaBot('ctfBot', 'capture-the-flag', CtfGame, ctfBotInput);

/** Capture the flag in the game registry. */
export const ctfGame: RegisteredGame = arenaDefinition(
  CTF_INFO,
  (config) => new CtfGame(config),
  ctfBot,
  ctfStateSchema(CTF),
);
