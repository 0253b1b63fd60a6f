import { describe, expect, it } from 'vitest';
import { packButtons, readReplay } from 'fixedstep';
import { botInputs, recordArena } from './replay-fixture.js';

const MINUTE = 60 * 60; // ticks at 60 Hz

function sectionBytes(bytes: Uint8Array, name: string): number {
  const s = readReplay(bytes).sections.find((x) => x.name === name);
  return s ? s.length + 5 : 0;
}

describe('replay compression', () => {
  it('realistic play costs well under 2 KB per minute for one player at 60 Hz (keyframes excluded)', () => {
    const minutes = 10;
    const run = recordArena({
      ticks: minutes * MINUTE,
      players: 1,
      inputSeed: 2024,
      checkpointEvery: 60,
    });
    const r = readReplay(run.bytes);
    const inputPerMinute = sectionBytes(run.bytes, 'INPUTS') / minutes;
    const filePerMinute = run.bytes.length / minutes;
    const changesPerMinute = r.runCount(0) / minutes;
    // The bot changes its input ~100 times a minute (a direction every 0.5–4 s, a jump tap every
    // 1–3 s, fire bursts), each change being a run of ≈ 2–4 bytes: well under 1 KB/min. The
    // checkpoints add 8 B/s = 480 B/min; 2 KB/min leaves room for a busier player.
    expect(inputPerMinute).toBeLessThan(1024);
    expect(filePerMinute).toBeLessThan(2048);
    expect(inputPerMinute / changesPerMinute).toBeLessThan(4);
  });

  it('a button held for a whole minute costs a few bytes; a new input every tick at most 10 bytes a tick', () => {
    const held = new Uint32Array(MINUTE).fill(packButtons(0b10, 0));
    held[0] = packButtons(0b10, 0b10);
    const a = recordArena({ ticks: MINUTE, players: 1, inputs: held, checkpointEvery: MINUTE });
    expect(sectionBytes(a.bytes, 'INPUTS')).toBeLessThanOrEqual(5 + 1 + 6);

    const noisy = botInputs(1, MINUTE, 1).map((_, t) => (t * 2654435761) >>> 0);
    const b = recordArena({ ticks: MINUTE, players: 1, inputs: noisy, checkpointEvery: MINUTE });
    expect(sectionBytes(b.bytes, 'INPUTS')).toBeLessThanOrEqual(5 + 3 + MINUTE * 6);
  });
});
