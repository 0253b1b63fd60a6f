import { decodeGameConfig, encodeGameConfig } from '../config.js';
import type { GameDefinition } from '../game.js';
import { runnerBot } from './bot.js';
import { RUNNER_INFO, RunnerGame } from './runner.js';

export { RunnerGame, RunnerButtons, RUNNER_INFO, RUNNER_TUNING, OBSTACLE_KINDS } from './runner.js';
export type { ObstacleKind } from './runner.js';
export { runnerBot } from './bot.js';
export { RunnerRig } from './rig.js';
export type { RunnerRigOptions, TimedButton } from './rig.js';

/** The runner's registry entry: one player, 60 Hz, config = seed + players (canonical bytes). */
export const runnerGame: GameDefinition = Object.freeze<GameDefinition>({
  info: RUNNER_INFO,
  create: (config) => new RunnerGame(config),
  bot: runnerBot,
  encodeConfig: encodeGameConfig,
  decodeConfig: (bytes) => decodeGameConfig(bytes, RUNNER_INFO.minPlayers, RUNNER_INFO.maxPlayers),
});
