import { readFileSync } from 'node:fs';
import { describe, expect, it } from 'vitest';
import {
  ByteReader,
  ByteWriter,
  ReplayRecorder,
  defineInput,
  fnv1a64,
  readReplay,
  verifyReplay,
} from 'fixedstep';

/** docs/replay-format.md's "counter" game: state = tick (u32) and the sum of its inputs (u32). */
class Counter {
  tick = 0;
  sum = 0;
  step(inputs: readonly number[]): void {
    this.sum = (this.sum + (inputs[0]! & 0xffff)) >>> 0;
    this.tick++;
  }
  save(): Uint8Array {
    return new ByteWriter(8).u32(this.tick).u32(this.sum).finish();
  }
  load(b: Uint8Array): void {
    const r = new ByteReader(b);
    this.tick = r.u32();
    this.sum = r.u32();
    r.end();
  }
  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** The hex bytes of the doc's annotated dump: every pair of hex digits before the comment column. */
function docBytes(): Uint8Array {
  const md = readFileSync(new URL('../../../docs/replay-format.md', import.meta.url), 'utf8');
  const block = md.split('## A complete example')[1]!.split('```')[1]!;
  const out: number[] = [];
  for (const line of block.split('\n')) {
    const m = /^\d+\s+((?:[0-9a-f]{2}(?:\s+|$))+)/.exec(line);
    if (m) for (const b of m[1]!.trim().split(/\s+/)) out.push(parseInt(b, 16));
  }
  return Uint8Array.from(out);
}

describe('the replay format spec’s complete example', () => {
  it('is byte for byte what the recorder writes, and it verifies', () => {
    const input = defineInput({ buttons: ['go'] });
    const sim = new Counter();
    const rec = new ReplayRecorder({
      gameId: 'demo',
      gameVersion: '1',
      tickRate: 60,
      seeds: [7],
      config: Uint8Array.of(0xab),
      players: ['ann'],
      input,
      checkpointEvery: 2,
      keyframeEvery: 4,
    });
    rec.start(sim);
    for (const v of [0x00010001, 1, 1, 0, 0]) {
      sim.step([v]);
      rec.record([v], sim);
    }
    const bytes = rec.finish();
    expect([...docBytes()]).toEqual([...bytes]);
    expect(readReplay(bytes).header.input.buttons).toEqual(['go']);
    expect(verifyReplay(bytes, () => new Counter()).ok).toBe(true);
  });
});
