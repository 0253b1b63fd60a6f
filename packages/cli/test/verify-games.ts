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
import {
  ByteReader,
  ByteWriter,
  BUTTON_WORD,
  defineGame,
  fnv1a64,
  type ButtonInput,
  type Simulation,
} from 'fixedstep';

type Hook = ((tick: number) => void) | undefined;

class Counter implements Simulation {
  tick = 0;
  readonly n: Uint32Array;
  constructor(
    players: number,
    private readonly hook: Hook,
  ) {
    this.n = new Uint32Array(players);
  }
  step(inputs: readonly ButtonInput[]): void {
    this.hook?.(this.tick);
    for (let p = 0; p < this.n.length; p++) this.n[p] = (this.n[p]! + 1 + (inputs[p]! & 1)) >>> 0;
    this.tick++;
  }
  save(): Uint8Array {
    return new ByteWriter(16).u32(this.tick).ints(this.n).finish();
  }
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    this.tick = r.u32();
    r.ints(this.n);
    r.end();
  }
  hash(): bigint {
    return fnv1a64(this.save());
  }
}

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
