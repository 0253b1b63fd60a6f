/**
 * Games for the verification-pool tests, loaded by the server and by its verification workers:
 * a counter whose score is the first player's count; `gate`, whose step of tick 5 waits — in a
 * worker thread only — until the file named by `FIXEDSTEP_TEST_GATE` exists (the test decides
 * when a verification may finish, with no timing); `crash`, whose step of tick 5 ends its worker
 * thread (the verifier dying mid-job). On the main thread both are plain counters, so the tests
 * can record their replays.
 */
import { existsSync } from 'node:fs';
import { isMainThread } from 'node:worker_threads';
import { BUTTON_WORD, defineGame } from 'fixedstep';
import { Counter } from './counter-game.js';

type Hook = ((tick: number) => void) | undefined;

const pause = new Int32Array(new SharedArrayBuffer(4));

/** In a worker: at tick 5, wait until the gate file exists. */
const gate: Hook = isMainThread
  ? undefined
  : (tick) => {
      const file = process.env.FIXEDSTEP_TEST_GATE;
      if (tick !== 5 || file === undefined) return;
      while (!existsSync(file)) Atomics.wait(pause, 0, 0, 5);
    };

/** In a worker: at tick 5, end the thread. */
const crash: Hook = isMainThread
  ? undefined
  : (tick) => {
      if (tick === 5) process.exit(3);
    };

const base = {
  version: 1,
  tickRate: 60,
  input: BUTTON_WORD,
  minPlayers: 1,
  maxPlayers: 1,
  score: (sim: Counter) => sim.n[0]!,
};

export const games = [
  defineGame({ ...base, id: 'counter', create: (s) => new Counter(s.players, undefined) }),
  defineGame({ ...base, id: 'gate', create: (s) => new Counter(s.players, gate) }),
  defineGame({ ...base, id: 'crash', create: (s) => new Counter(s.players, crash) }),
];
