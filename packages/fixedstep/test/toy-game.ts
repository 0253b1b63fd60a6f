/**
 * The net tests' toy game (the library's, and the server's peer-to-peer test): each player's
 * counter moves by its input and a seeded draw. Small and deterministic; save() writes its whole
 * state (the tick, the Random's state, the counters).
 */
import { ByteReader, ByteWriter, Random, fnv1a64, type Simulation } from 'fixedstep';

/**
 * Each player's counter moves by its input and a seeded draw; `glitch` makes a deliberately broken
 * client (extra added to player 0's counter from a tick on).
 */
export class Toy implements Simulation {
  tick = 0;
  readonly x: Int32Array;
  readonly rng: Random;
  constructor(
    players: number,
    seed: number,
    private readonly glitch?: { from: number; extra: () => number },
  ) {
    this.x = new Int32Array(players);
    this.rng = new Random(seed);
  }
  step(inputs: readonly number[]): void {
    for (let p = 0; p < this.x.length; p++) {
      this.x[p] = (this.x[p]! * 3 + (inputs[p]! & 0xffff) + this.rng.int(1000)) | 0;
    }
    if (this.glitch && this.tick >= this.glitch.from)
      this.x[0] = (this.x[0]! + this.glitch.extra()) | 0;
    this.tick++;
  }
  save(): Uint8Array {
    const w = new ByteWriter(64).u32(this.tick).ints(this.rng.getState());
    return w.ints(this.x).finish();
  }
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    this.tick = r.u32();
    const s = new Uint32Array(4);
    r.ints(s);
    this.rng.setState(s);
    r.ints(this.x);
    r.end();
  }
  hash(): bigint {
    return fnv1a64(this.save());
  }
}
