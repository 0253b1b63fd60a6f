/**
 * Chapter 6, "Play online": where an online match ends. It ends when the game says so — capture
 * the flag's clock runs out or a team reaches the capture limit (`game.over`) — or, only when the
 * address asks for a shorter match (`ticks=`), at that tick. In lockstep every tick a machine steps
 * is confirmed (the inputs of every player are in), so both machines see the end at the same tick
 * with the same state: the final screen and its hash are the same on both.
 */
import type { Game } from '@fixedstep/games';
import { hashHex } from '../../games-view/games.js';

/** The end of a match: its tick, the state there (canonical bytes) and that state's hash. */
export interface MatchEnd {
  /** The tick the game ended at (the state after that many steps). */
  readonly tick: number;
  /** Why it ended: the game's own end, or the tick limit the address set. */
  readonly reason: 'game over' | 'tick limit';
  /** The state at the end, as `game.save()` writes it (to draw the final screen from). */
  readonly bytes: Uint8Array;
  /** The hash of that state, 16 hex digits. */
  readonly hash: string;
}

/**
 * Watch `game`'s steps and call `onEnd` once, right after the step at which the game is over (or
 * reaches `stopAt` ticks, `Infinity` for no limit). Returns the same game (its `step` wrapped; it
 * reads the state, never writes it, so the game steps exactly as before).
 */
export function watchEnd(game: Game, stopAt: number, onEnd: (end: MatchEnd) => void): Game {
  const step = game.step.bind(game);
  let done = false;
  const check = (): void => {
    if (done) return;
    const over = game.over;
    if (!over && game.tick < stopAt) return;
    done = true;
    onEnd({
      tick: game.tick,
      reason: over ? 'game over' : 'tick limit',
      bytes: game.save(),
      hash: hashHex(game),
    });
  };
  game.step = (inputs) => {
    step(inputs);
    check();
  };
  return game;
}
