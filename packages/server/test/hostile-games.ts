/**
 * The game of the hostile suite (`hostile.test.ts`), for the relay, state sync (whose workers load
 * it from this module) and quick match alike: a counter of 1 to 4 players at 10 ticks a second, so
 * a hundred squatted rooms cost the test little.
 */
import { BUTTON_WORD, defineGame } from 'fixedstep';
import { Counter } from './counter-game.js';

/** Ticks a second of {@link SLOW}: a tenth of what a game runs at, the same protocol. */
export const SLOW_TICK_RATE = 10;

export const SLOW = defineGame({
  id: 'slow',
  version: 1,
  tickRate: SLOW_TICK_RATE,
  input: BUTTON_WORD,
  minPlayers: 1,
  maxPlayers: 4,
  create: (s) => new Counter(s.players),
});

export const GAMES = [SLOW];
