/**
 * The counter game of the server tests' games modules (`state-sync-games.ts`,
 * `verify-games.ts`): a count per player, +1 a tick and +1 more while button 0 is held; `hook`
 * runs before each step with the tick (to stall, throw or end a thread on purpose).
 */
import { ByteReader, ByteWriter, fnv1a64, type ButtonInput, type Simulation } from 'fixedstep';

export class Counter implements Simulation {
  tick = 0;
  readonly n: Uint32Array;
  constructor(
    players: number,
    private readonly hook?: (tick: number) => void,
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
