import type { Bot, Game, GameDefinition } from '../game.js';
import { decodeGameConfig, encodeGameConfig } from '../config.js';
import { SURVIVAL_INFO, SurvivalGame } from './game.js';
import { survivalBotInput } from './bot.js';

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
export const survivalBot: Bot = (game: Game, player: number) => {
  if (!(game instanceof SurvivalGame)) throw new TypeError('survivalBot: not a survival game');
  return survivalBotInput(game, player);
};

/** Survival in the game registry. */
export const survivalGame: GameDefinition = Object.freeze<GameDefinition>({
  info: SURVIVAL_INFO,
  create: (config) => new SurvivalGame(config),
  bot: survivalBot,
  encodeConfig: encodeGameConfig,
  decodeConfig: (bytes) =>
    decodeGameConfig(bytes, SURVIVAL_INFO.minPlayers, SURVIVAL_INFO.maxPlayers),
});
