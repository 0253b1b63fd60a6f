import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  DEFAULT_REPLAY_LIMITS,
  ReplayError,
  deinterleave,
  interleave,
  readReplay,
  verifyReplay,
} from 'fixedstep';
import type { ReadReplayOptions, ReplayErrorCode } from 'fixedstep';
import { arenaFactory, recordArena, reseal } from './replay-fixture.js';

const run = recordArena({ ticks: 1000, seed: 8, checkpointEvery: 50, keyframeEvery: 200 });
const good = run.bytes;
const sections = readReplay(good).sections;
const at = (name: string) => sections.find((s) => s.name === name)!;

function errorOf(bytes: Uint8Array, options?: ReadReplayOptions): ReplayError {
  try {
    readReplay(bytes, options);
  } catch (e) {
    if (e instanceof ReplayError) return e;
    throw e;
  }
  throw new Error('expected a ReplayError');
}

function expectError(bytes: Uint8Array, code: ReplayErrorCode, message?: RegExp, offset?: number) {
  const e = errorOf(bytes);
  expect(e.message).toMatch(new RegExp(`^${code}: `)); // shows the message when the code differs
  expect(e.code).toBe(code);
  expect(e.message).toMatch(message ?? /./);
  expect(e.offset).toBe(offset ?? e.offset);
}

/** A copy of `good` edited in place, checksum recomputed. */
function edited(edit: (b: Uint8Array, v: DataView) => void): Uint8Array {
  const b = good.slice();
  edit(b, new DataView(b.buffer));
  return reseal(b);
}

/** A new file made from a copy of `good`, checksum recomputed. */
function rebuilt(make: (b: Uint8Array) => Uint8Array): Uint8Array {
  return reseal(make(good.slice()));
}

function splice(b: Uint8Array, offset: number, remove: number, insert: number[]): Uint8Array {
  const out = new Uint8Array(b.length - remove + insert.length);
  out.set(b.subarray(0, offset));
  out.set(insert, offset);
  out.set(b.subarray(offset + remove), offset + insert.length);
  return out;
}

describe('replay format validation', () => {
  it('starts with the magic, the version and the length; ends with the checksum', () => {
    expect(new TextDecoder().decode(good.subarray(0, 8))).toBe('FSREPLAY');
    const v = new DataView(good.buffer);
    expect(v.getUint32(8, true)).toBe(2);
    expect(v.getUint32(12, true)).toBe(good.length);
    expect(sections.map((s) => [s.name, s.offset])[0]).toEqual(['GAME', 16]);
  });

  it('refuses the wrong magic, a truncated file, trailing bytes, another version', () => {
    expectError(new TextEncoder().encode('PK\u0003\u0004 not a replay'), 'BAD_MAGIC', /not a/, 0);
    expectError(new Uint8Array(0), 'TRUNCATED');
    expectError(good.subarray(0, 5), 'TRUNCATED');
    expectError(good.subarray(0, 12), 'TRUNCATED', /header/);
    for (const n of [16, 100, good.length - 1]) {
      expectError(good.subarray(0, n), 'TRUNCATED', new RegExp(`declares ${good.length}`), n);
    }
    expectError(splice(good, good.length, 0, [0]), 'TRAILING_DATA', /1 bytes after/, good.length);
    for (const version of [0, 3]) {
      const other = good.slice();
      new DataView(other.buffer).setUint32(8, version, true);
      expectError(
        other,
        'UNSUPPORTED_VERSION',
        new RegExp(`version ${version}, this reader knows 1 to 2`),
        8,
      );
    }
  });

  it('detects every single bit flip with the checksum', () => {
    // Every bit of every byte outside the length field: FNV-1a detects any single-byte change.
    for (let i = 16; i < good.length; i++) {
      for (let bit = 0; bit < 8; bit++) {
        const b = good.slice();
        b[i] = b[i]! ^ (1 << bit);
        const e = errorOf(b);
        expect(e.code).toBe('BAD_CHECKSUM');
      }
    }
  });

  it('enforces every limit before allocating', () => {
    const code = (options: ReadReplayOptions) => errorOf(good, options).code;
    expect(code({ limits: { maxFileBytes: good.length - 1 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxTicks: 999 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxPlayers: 1 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxSeeds: 0 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxConfigBytes: 10 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxKeyframeBytes: 100 } })).toBe('TOO_LARGE');
    expect(code({ limits: { maxKeyframes: 0 } })).toBe('TOO_LARGE');
    expect(errorOf(good, { limits: { maxKeyframes: 0 } }).message).toMatch(
      /keyframe count is \d+, limit 0/,
    );
    expect(readReplay(good, { limits: { maxTicks: 1000, maxPlayers: 2 } }).tickCount).toBe(1000);
    expect(DEFAULT_REPLAY_LIMITS.maxTicks).toBe(5_184_000);
    // A declared length of 4 GiB is refused without reading further.
    const huge = good.slice();
    new DataView(huge.buffer).setUint32(12, 0xffffffff, true);
    expectError(huge, 'TOO_LARGE', /declared file length/, 12);
  });

  it('refuses content that breaks the format even with a valid checksum', () => {
    const ticks = at('TICKS');
    const cps = at('CHECKPOINTS');
    // A section length beyond the file.
    expectError(
      edited((b, v) => {
        v.setUint32(ticks.offset + 1, 0x7fffffff, true);
      }),
      'CORRUPT',
      /TICKS declares 2147483647 bytes/,
    );
    // Sections out of order / repeated / missing / unknown.
    expectError(
      edited((b) => {
        b[ticks.offset] = 0x01;
      }),
      'CORRUPT',
      /out of order/,
    );
    expectError(
      edited((b) => {
        b[cps.offset] = 0x05;
      }),
      'CORRUPT',
      /CHECKPOINTS is missing/,
    );
    expectError(
      rebuilt((b) => splice(b, good.length - 8, 0, [0x07, 0, 0, 0, 0])),
      'CORRUPT',
      /unknown critical section/,
    );
    expectError(
      rebuilt((b) => splice(b.subarray(0, cps.offset), cps.offset, 0, [0, 0, 0, 0, 0, 0, 0, 0])),
      'CORRUPT',
      /stray bytes|missing/,
    );
    // A tick count that the input runs do not add up to.
    expectError(
      edited((b, v) => {
        v.setUint32(ticks.offset + 5, 1001, true);
      }),
      'CORRUPT',
    );
    // Checkpoint interval 0.
    expectError(
      edited((b) => {
        b[ticks.offset + 5 + 12] = 0;
      }),
      'CORRUPT',
      /checkpoint interval is 0/,
    );
    // A non-canonical varint: the checkpoint interval (50) written in two bytes.
    const interval = ticks.offset + 5 + 12;
    expect(good[interval]).toBe(50);
    expectError(
      rebuilt((b) => {
        const out = splice(b, interval, 1, [50 | 0x80, 0]);
        new DataView(out.buffer).setUint32(ticks.offset + 1, ticks.length + 1, true);
        return out;
      }),
      'CORRUPT',
      /non-canonical varint/,
    );
    // The final hash disagreeing with the last checkpoint.
    expectError(
      edited((b) => {
        b[ticks.offset + 9] = b[ticks.offset + 9]! ^ 1;
      }),
      'CORRUPT',
      /final hash/,
    );
  });

  it('skips an ancillary section it does not know', () => {
    const b = reseal(splice(good, good.length - 8, 0, [0x80, 3, 0, 0, 0, 1, 2, 3]));
    const r = readReplay(b);
    expect(r.sections.at(-1)).toMatchObject({ id: 0x80, length: 3 });
    expect(verifyReplay(r, arenaFactory).ok).toBe(true);
  });

  it('interleaves input bits as a bijection', () => {
    expect(interleave(0x00010001)).toBe(0b11);
    expect(interleave(0x00020002)).toBe(0b1100);
    expect(interleave(0xffffffff)).toBe(0xffffffff);
    fc.assert(
      fc.property(fc.nat({ max: 0xffffffff }), (v) => deinterleave(interleave(v)) === v),
      { seed: 1, numRuns: 2000 },
    );
  });
});
