import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  ByteReader,
  ByteWriter,
  VARINT_NOT_CANONICAL,
  VARINT_TOO_LARGE,
  VARINT_TRUNCATED,
  readVarint,
  varintProblem,
  varintSize,
} from '../src/det/bytes.js';

const read = (bytes: number[], end = bytes.length) => {
  const at = { pos: 0 };
  const v = readVarint(at, Uint8Array.from(bytes), end);
  return { v, pos: at.pos };
};

describe('canonical varints (shared by the replay format and the network protocol)', () => {
  it('writes LEB128, low 7 bits first, the shortest form', () => {
    const bytes = (v: number) => Array.from(new ByteWriter().varint(v).finish());
    expect(bytes(0)).toEqual([0]);
    expect(bytes(127)).toEqual([0x7f]);
    expect(bytes(128)).toEqual([0x80, 0x01]);
    expect(bytes(300)).toEqual([0xac, 0x02]);
    expect(bytes(0xffffffff)).toEqual([0xff, 0xff, 0xff, 0xff, 0x0f]);
    expect([0, 127, 128, 16383, 16384, 2 ** 21, 2 ** 28, 0xffffffff].map(varintSize)).toEqual([
      1, 1, 2, 2, 3, 4, 5, 5,
    ]);
  });

  it('round-trips every u32 and reads exactly the bytes it wrote', () => {
    fc.assert(
      fc.property(fc.array(fc.nat({ max: 0xffffffff }), { maxLength: 20 }), (values) => {
        const w = new ByteWriter(4);
        for (const v of values) w.varint(v);
        const buf = w.finish();
        expect(buf.length).toBe(values.reduce((n, v) => n + varintSize(v), 0));
        const at = { pos: 0 };
        for (const v of values) expect(readVarint(at, buf, buf.length)).toBe(v);
        expect(at.pos).toBe(buf.length);
      }),
      { numRuns: 300 },
    );
  });

  it('refuses what it would never write, with a code and words for each', () => {
    expect(read([0x80, 0x80])).toEqual({ v: VARINT_TRUNCATED, pos: 2 });
    expect(read([0x80, 0x01], 1).v).toBe(VARINT_TRUNCATED); // the end bound is respected
    expect(read([0xff, 0xff, 0xff, 0xff, 0x10]).v).toBe(VARINT_TOO_LARGE);
    expect(read([0x80, 0x00]).v).toBe(VARINT_NOT_CANONICAL);
    expect(read([0x80, 0x80, 0x80, 0x80, 0x80, 0x01]).v).toBe(VARINT_TOO_LARGE);
    // A fifth byte with its "more" bit set is above 0x0f too: no varint is longer than 5 bytes.
    expect(read([0x80, 0x80, 0x80, 0x80, 0x8f, 0x00])).toEqual({ v: VARINT_TOO_LARGE, pos: 5 });
    expect(varintProblem(VARINT_TRUNCATED)).toBe('varint runs past the end');
    expect(varintProblem(VARINT_TOO_LARGE)).toBe('varint above 2^32 - 1');
    expect(varintProblem(VARINT_NOT_CANONICAL)).toBe('non-canonical varint (redundant zero byte)');
  });

  it('will not write a value that is not a u32', () => {
    for (const bad of [-1, 0.5, 2 ** 32, Number.NaN, Infinity]) {
      expect(() => new ByteWriter().varint(bad)).toThrow(RangeError);
    }
  });

  it('writes strings as length + UTF-8 and u64s little-endian', () => {
    const w = new ByteWriter().str('Δt').u64(0x0102030405060708n).u64(-1n);
    const buf = w.finish();
    expect(Array.from(buf.subarray(0, 4))).toEqual([3, 0xce, 0x94, 0x74]);
    const r = new ByteReader(buf.subarray(4));
    expect(r.u32()).toBe(0x05060708);
    expect(r.u32()).toBe(0x01020304);
    expect(r.u32()).toBe(0xffffffff);
    expect(r.u32()).toBe(0xffffffff);
    r.end();
  });
});
