/**
 * Games for the state-sync server tests, loaded by the worker threads (`games` option): a counter
 * that can stall its worker on purpose (5 s), and one whose step throws.
 */
import {
  ByteReader,
  ByteWriter,
  BUTTON_WORD,
  defineGame,
  fnv1a64,
  type ButtonInput,
  type Simulation,
} from 'fixedstep';

/** A counter per player; `stallAt`: the step of that tick blocks its thread for `stallMs`. */
class Counter implements Simulation {
  tick = 0;
  readonly n: Uint32Array;
  constructor(
    players: number,
    private readonly stallAt: number,
    private readonly stallMs: number,
    private readonly throwAt = -1,
  ) {
    this.n = new Uint32Array(players);
  }
  step(inputs: readonly ButtonInput[]): void {
    if (this.tick === this.throwAt) throw new Error(`the counter broke at tick ${this.tick}`);
    if (this.tick === this.stallAt) {
      // A long computation in this room: the worker's thread is busy, nothing else on it runs.
      Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, this.stallMs);
    }
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

const base = { version: 1, tickRate: 60, input: BUTTON_WORD, minPlayers: 1, maxPlayers: 4 };

export const GAMES = [
  defineGame({ ...base, id: 'counter', create: (s) => new Counter(s.players, -1, 0) }),
  defineGame({ ...base, id: 'stall', create: (s) => new Counter(s.players, 60, 5000) }),
  defineGame({ ...base, id: 'broken', create: (s) => new Counter(s.players, -1, 0, 30) }),
];
