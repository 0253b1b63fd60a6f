import { describe, expect, it } from 'vitest';
import { ByteReader, ByteWriter, Fnv1a64, Random, fnv1a64, fnv1a64Hex } from 'fixedstep';

/** FNV-1a 64 written the textbook way, with BigInt: the reference. */
function referenceFnv1a64(bytes: Uint8Array): bigint {
  const mask = (1n << 64n) - 1n;
  let h = 0xcbf29ce484222325n;
  for (const b of bytes) h = ((h ^ BigInt(b)) * 0x100000001b3n) & mask;
  return h;
}

const text = (s: string) => new TextEncoder().encode(s);

describe('FNV-1a 64', () => {
  it.each([
    ['', 'cbf29ce484222325'],
    ['a', 'af63dc4c8601ec8c'],
    ['foobar', '85944171f73967e8'],
  ])('known vector %j → %s', (input, hex) => {
    expect(fnv1a64Hex(text(input))).toBe(hex);
    expect(fnv1a64(text(input))).toBe(BigInt(`0x${hex}`));
    expect(referenceFnv1a64(text(input))).toBe(BigInt(`0x${hex}`));
  });

  it('1 MB of random bytes: equal to the BigInt reference, in one update or in chunks', () => {
    const r = new Random(1);
    const bytes = new Uint8Array(1 << 20);
    for (let i = 0; i < bytes.length; i += 4) {
      const v = r.nextU32();
      bytes[i] = v & 0xff;
      bytes[i + 1] = (v >>> 8) & 0xff;
      bytes[i + 2] = (v >>> 16) & 0xff;
      bytes[i + 3] = v >>> 24;
    }
    const expected = referenceFnv1a64(bytes);
    expect(fnv1a64(bytes)).toBe(expected);
    const chunked = new Fnv1a64();
    for (let at = 0; at < bytes.length; at += 65_537)
      chunked.update(bytes.subarray(at, at + 65_537));
    expect(chunked.digest()).toBe(expected);
    expect(chunked.hex()).toBe(expected.toString(16).padStart(16, '0'));
  });

  it('mostly zero bytes, as snapshots are: runs of every length, at every alignment, in chunks', () => {
    // Runs of zeros are hashed as one multiplication by a power of the prime, found a word at a
    // time: what must never differ from the byte-by-byte reference. Runs longer than the table
    // of powers (4096), runs that start or end inside a word, views at odd offsets.
    const r = new Random(2);
    const backing = new Uint8Array(40_000);
    let at = 0;
    while (at < backing.length) {
      const run = [0, 1, 2, 3, 4, 5, 7, 8, 15, 16, 17, 31, 64, 4095, 4096, 4097, 9000][r.int(17)]!;
      at = Math.min(backing.length, at + run);
      for (let k = r.int(12); k > 0 && at < backing.length; k--) backing[at++] = 1 + r.int(255);
    }
    for (const offset of [0, 1, 2, 3, 5]) {
      for (const length of [0, 3, 63, 64, 65, 4100, 20_001, 39_990]) {
        const bytes = backing.subarray(offset, offset + length);
        expect(fnv1a64(bytes), `offset ${offset}, length ${length}`).toBe(referenceFnv1a64(bytes));
      }
    }
    const zeros = new Uint8Array(70_000);
    expect(fnv1a64(zeros)).toBe(referenceFnv1a64(zeros));
    const chunked = new Fnv1a64();
    for (let k = 0; k < backing.length; k += 999) chunked.update(backing.subarray(k, k + 999));
    expect(chunked.digest()).toBe(referenceFnv1a64(backing));
  });

  it('every single byte value and the high bits of the state (carries across the halves)', () => {
    for (let b = 0; b < 256; b++) {
      const bytes = Uint8Array.of(b, 255 - b, b ^ 0x5a, 0xff, 0x00, b);
      expect(fnv1a64(bytes), `byte ${b}`).toBe(referenceFnv1a64(bytes));
    }
  });
});

describe('ByteWriter / ByteReader', () => {
  it('round-trips every kind of value, across buffer growth', () => {
    const w = new ByteWriter(16);
    const f64s = Float64Array.of(1.5, -2.25, Math.PI, Number.MAX_VALUE, 5e-324, -Infinity);
    const i8 = Int8Array.of(-128, -1, 0, 127);
    const i16 = Int16Array.of(-32768, -1, 0, 32767);
    const u16 = Uint16Array.of(0, 1, 65535);
    const i32 = Int32Array.of(-2147483648, -1, 0, 2147483647);
    const u32 = Uint32Array.of(0, 1, 4294967295);
    const u8 = Uint8Array.of(0, 128, 255);
    w.u8(255).u16(65535).u32(4294967295).i32(-2147483648).f64(-1e-300);
    w.f64s(f64s).ints(i8).ints(i16).ints(u16).ints(i32).ints(u32).ints(u8).bytes(text('tail'));
    for (let i = 0; i < 100; i++) w.u32(i * 2654435761);
    const bytes = w.finish();
    expect(bytes.length).toBe(w.length);

    const r = new ByteReader(bytes);
    expect([r.u8(), r.u16(), r.u32(), r.i32(), r.f64()]).toEqual([
      255, 65535, 4294967295, -2147483648, -1e-300,
    ]);
    const back = {
      f64s: new Float64Array(f64s.length),
      i8: new Int8Array(i8.length),
      i16: new Int16Array(i16.length),
      u16: new Uint16Array(u16.length),
      i32: new Int32Array(i32.length),
      u32: new Uint32Array(u32.length),
      u8: new Uint8Array(u8.length),
    };
    r.f64s(back.f64s);
    r.ints(back.i8);
    r.ints(back.i16);
    r.ints(back.u16);
    r.ints(back.i32);
    r.ints(back.u32);
    r.ints(back.u8);
    expect(back).toEqual({ f64s, i8, i16, u16, i32, u32, u8 });
    expect(new TextDecoder().decode(r.bytes(4))).toBe('tail');
    for (let i = 0; i < 100; i++) expect(r.u32()).toBe((i * 2654435761) >>> 0);
    expect(r.remaining).toBe(0);
    r.end();
  });

  it('is little-endian', () => {
    expect([...new ByteWriter().u32(0x01020304).u16(0x0506).finish()]).toEqual([4, 3, 2, 1, 6, 5]);
    expect([...new ByteWriter().f64(1).finish()]).toEqual([0, 0, 0, 0, 0, 0, 0xf0, 0x3f]);
  });

  it('writes -0 as +0', () => {
    expect(new ByteWriter().f64(-0).finish()).toEqual(new ByteWriter().f64(0).finish());
    expect(new ByteWriter().f64s(Float64Array.of(-0)).finish()).toEqual(new Uint8Array(8));
  });

  it('writes every NaN as the one quiet NaN, whatever its payload', () => {
    const nanFrom = (hi: number, lo: number) => {
      const v = new DataView(new ArrayBuffer(8));
      v.setUint32(0, hi);
      v.setUint32(4, lo);
      return v.getFloat64(0);
    };
    const nans = [NaN, nanFrom(0x7ff80000, 1), nanFrom(0xfff80000, 0), nanFrom(0x7ff00000, 0xdead)];
    const canonical = [0, 0, 0, 0, 0, 0, 0xf8, 0x7f];
    for (const nan of nans) {
      expect(nan).toBeNaN();
      expect([...new ByteWriter().f64(nan).finish()]).toEqual(canonical);
      expect([...new ByteWriter().f64s(Float64Array.of(nan)).finish()]).toEqual(canonical);
    }
    // and so states that differ only in NaN payloads hash the same
    const a = new ByteWriter().f64(nans[1]!).f64(-0).finish();
    const b = new ByteWriter().f64(nans[2]!).f64(0).finish();
    expect(fnv1a64(a)).toBe(fnv1a64(b));
  });

  it('writes long arrays (copied whole) exactly as element by element, -0 and NaNs included', () => {
    const r = new Random(3);
    const n = 40;
    const f64 = new Float64Array(n);
    for (let i = 0; i < n; i++) f64[i] = [0, -0, NaN, -NaN, 1.5, -r.next(), 1e308][r.int(7)]!;
    f64[0] = -0;
    f64[n - 1] = NaN;
    const ints = [Int8Array, Uint8Array, Int16Array, Uint16Array, Int32Array, Uint32Array].map(
      (Type) => {
        const a = new Type(n);
        for (let i = 0; i < n; i++) a[i] = r.nextU32() | 0;
        return a;
      },
    );
    // From an odd position of the writer, and from views at an offset into a larger array.
    const whole = new ByteWriter(16).u8(1).f64s(f64).f64s(f64.subarray(3, 30));
    const oneByOne = new ByteWriter(16).u8(1);
    for (const v of f64) oneByOne.f64(v);
    for (const v of f64.subarray(3, 30)) oneByOne.f64(v);
    for (const a of ints) {
      whole.ints(a).ints(a.subarray(1, 35));
      for (const v of [...a, ...a.subarray(1, 35)]) {
        if (a.BYTES_PER_ELEMENT === 1) oneByOne.u8(v);
        else if (a.BYTES_PER_ELEMENT === 2) oneByOne.u16(v & 0xffff);
        else oneByOne.u32(v);
      }
    }
    expect(whole.finish()).toEqual(oneByOne.finish());
  });

  it('reads from a view into a larger buffer', () => {
    const inner = new ByteWriter().u32(7).f64(2.5).finish();
    const outer = new Uint8Array(inner.length + 5);
    outer.set(inner, 3);
    const r = new ByteReader(outer.subarray(3, 3 + inner.length));
    expect([r.u32(), r.f64()]).toEqual([7, 2.5]);
    r.end();
  });

  it('reset() and peek()', () => {
    const w = new ByteWriter();
    w.u32(1).reset().u8(9);
    expect([...w.peek()]).toEqual([9]);
  });

  it('truncated input throws a RangeError that names the offset', () => {
    const bytes = new ByteWriter().u8(1).u16(2).finish(); // 3 bytes
    const r = new ByteReader(bytes);
    r.u8();
    r.u16();
    expect(() => r.u8()).toThrow(RangeError);
    expect(() => r.u8()).toThrow(/u8 needs 1 bytes, 0 left \(at byte 3\)/);
    const s = new ByteReader(bytes);
    s.u8();
    expect(() => s.u32()).toThrow(/truncated input: u32 needs 4 bytes, 2 left \(at byte 1\)/);
    expect(() => new ByteReader(bytes).f64()).toThrow(/f64 needs 8 bytes, 3 left \(at byte 0\)/);
    expect(() => {
      new ByteReader(bytes).f64s(new Float64Array(1));
    }).toThrow(/\(at byte 0\)/);
    expect(() => {
      new ByteReader(bytes).ints(new Int32Array(1));
    }).toThrow(/\(at byte 0\)/);
    expect(() => new ByteReader(bytes).bytes(4)).toThrow(
      /4 bytes needs 4 bytes, 3 left \(at byte 0\)/,
    );
    // a failed read consumes nothing
    expect(s.offset).toBe(1);
    expect(s.u16()).toBe(2);
  });

  it('end() names trailing bytes and their offset', () => {
    const r = new ByteReader(Uint8Array.of(1, 2, 3));
    r.u8();
    expect(() => {
      r.end();
    }).toThrow(/2 unexpected trailing bytes \(at byte 1\)/);
  });
});
