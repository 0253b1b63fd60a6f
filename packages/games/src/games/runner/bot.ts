import { packButtons, type ButtonInput } from 'fixedstep';
import type { Bot, Game } from '../game.js';
import { OBSTACLE_KINDS, RUNNER_TUNING, RunnerButtons, RunnerGame } from './runner.js';

const JUMP = 1 << RunnerButtons.jump;
const DUCK = 1 << RunnerButtons.duck;
/** Seconds from take-off to the top of a jump (v / g). */
const TIME_TO_APEX = RUNNER_TUNING.jumpSpeed / RUNNER_TUNING.gravity;
/** Start ducking this long before a bird reaches the player, s. */
const DUCK_LEAD = 0.25;
const HALF_PLAYER = RUNNER_TUNING.playerWidth / 2;

/**
 * The runner's bot: it reads the state like a player reads the screen and acts on the nearest
 * obstacle not yet passed. A ground obstacle: it jumps when the obstacle's middle is one
 * take-off-to-apex run away, so the top of the jump is over it. A bird: it ducks (or, in the air,
 * falls fast) from a quarter second before the bird arrives until it has passed. After a crash it
 * presses jump as soon as a restart is allowed. Its inputs look like a player's: a press is one
 * tick of "down + pressed", a held duck is "down" after its first tick. Deterministic and
 * allocation-free; 0 for any game that is not a {@link RunnerGame}.
 */
export const runnerBot: Bot = (game: Game): ButtonInput => {
  if (!(game instanceof RunnerGame)) return 0;
  if (game.over) return game.canRestart ? packButtons(JUMP, JUMP) : 0;
  const d = game.distance;
  const n = game.obstacleCount;
  for (let k = 0; k < n; k++) {
    const x = game.obstacleX(k);
    const kind = OBSTACLE_KINDS[game.obstacleKind(k)]!;
    if (x + kind.width <= d) continue; // passed
    const v = game.speed;
    if (kind.bottom >= RUNNER_TUNING.duckHeight) {
      // Something to duck under.
      if (x - (d + RUNNER_TUNING.playerWidth) > v * DUCK_LEAD) return 0;
      // A press on the first tick of the hold; in the air (a fast fall) it holds without one.
      return game.ducking || !game.onGround ? packButtons(DUCK, 0) : packButtons(DUCK, DUCK);
    }
    if (!game.onGround) return 0;
    const ahead = x + kind.width / 2 - (d + HALF_PLAYER);
    return ahead <= v * TIME_TO_APEX ? packButtons(JUMP, JUMP) : 0;
  }
  return 0;
};
