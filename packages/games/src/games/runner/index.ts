import { talkGame, type RegisteredGame } from '../game.js';
import { runnerBot } from './bot.js';
import { RUNNER_INFO, RunnerButtons, RunnerGame } from './runner.js';

export { RunnerGame, RunnerButtons, RUNNER_INFO, RUNNER_TUNING, OBSTACLE_KINDS } from './runner.js';
export type { ObstacleKind } from './runner.js';
export { runnerBot } from './bot.js';
export { RunnerRig } from './rig.js';
export type { RunnerRigOptions, TimedButton } from './rig.js';

/** The runner's registry entry: one player, 60 Hz, config = seed + players (canonical bytes). */
export const runnerGame: RegisteredGame = talkGame(
  RUNNER_INFO,
  RunnerButtons,
  (config) => new RunnerGame(config),
  runnerBot,
);
