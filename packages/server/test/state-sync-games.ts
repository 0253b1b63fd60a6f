/**
 * Games for the state-sync server tests, loaded by the worker threads (`games` option): a counter
 * that can stall its worker on purpose (5 s), and one whose step throws.
 */
import { BUTTON_WORD, defineGame } from 'fixedstep';
import { Counter } from './counter-game.js';

/** At `stallAt`, block the thread for `stallMs`; at `throwAt`, throw. */
function trouble(stallAt: number, stallMs: number, throwAt = -1) {
  return (tick: number): void => {
    if (tick === throwAt) throw new Error(`the counter broke at tick ${tick}`);
    if (tick === stallAt) {
      // A long computation in this room: the worker's thread is busy, nothing else on it runs.
      Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, stallMs);
    }
  };
}

const base = { version: 1, tickRate: 60, input: BUTTON_WORD, minPlayers: 1, maxPlayers: 4 };

export const GAMES = [
  defineGame({ ...base, id: 'counter', create: (s) => new Counter(s.players) }),
  defineGame({ ...base, id: 'stall', create: (s) => new Counter(s.players, trouble(60, 5000)) }),
  defineGame({ ...base, id: 'broken', create: (s) => new Counter(s.players, trouble(-1, 0, 30)) }),
];
