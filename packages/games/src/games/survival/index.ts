import type { Bot, RegisteredGame } from '../game.js';
import { arenaBot, arenaDefinition } from '../arena/game.js';
import { SURVIVAL_INFO, SurvivalGame } from './game.js';
import { survivalBotInput } from './bot.js';
import { survivalStateSchema } from './state-schema.js';

export { SURVIVAL_INFO, SurvivalGame, SurvivalState, WavePhase } from './game.js';
export type { SurvivalOptions } from './game.js';
export { survivalBotInput } from './bot.js';
export {
  SURVIVAL,
  SURVIVAL_VERSION,
  SURVIVAL_WALLS,
  waveInterval,
  waveSize,
  waveSpeed,
} from './layout.js';

/** The survival bot as a {@link Bot}: for a {@link SurvivalGame} only. */
export const survivalBot: Bot = arenaBot('survivalBot', 'survival', SurvivalGame, survivalBotInput);

/** Survival in the game registry. */
export const survivalGame: RegisteredGame = arenaDefinition(
  SURVIVAL_INFO,
  (config) => new SurvivalGame(config),
  survivalBot,
  survivalStateSchema(),
);
