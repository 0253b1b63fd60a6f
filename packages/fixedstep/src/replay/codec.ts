/**
 * Low-level pieces of the replay format (see docs/replay-format.md): constants, a growable byte
 * sink, a bounds-checked cursor that throws {@link ReplayError}s, LEB128 varints, the bit
 * interleave of input words.
 * @internal
 */
import { ReplayError } from './errors.js';

/** "FSREPLAY" in ASCII. */
export const MAGIC = Uint8Array.of(0x46, 0x53, 0x52, 0x45, 0x50, 0x4c, 0x41, 0x59);
/** The format version this code writes and reads. */
export const FORMAT_VERSION = 1;
/** Magic (8) + version (u32) + file length (u32). */
export const FILE_HEADER_BYTES = 16;
/** The FNV-1a 64 checksum at the end. */
export const CHECKSUM_BYTES = 8;
/** Section id (u8) + payload length (u32). */
export const SECTION_HEADER_BYTES = 5;
/** The longest string (game id, game version, player name), in UTF-8 bytes. */
export const MAX_STRING_BYTES = 255;

/** Section ids. 0x80–0xFF are ancillary: a reader skips those it does not know. */
export const Section = {
  GAME: 0x01,
  TICKS: 0x02,
  INPUTS: 0x03,
  CHECKPOINTS: 0x04,
  KEYFRAMES: 0x05,
  TICK_HASHES: 0x06,
} as const;

/** A section's name, for messages. */
export function sectionName(id: number): string {
  switch (id) {
    case Section.GAME:
      return 'GAME';
    case Section.TICKS:
      return 'TICKS';
    case Section.INPUTS:
      return 'INPUTS';
    case Section.CHECKPOINTS:
      return 'CHECKPOINTS';
    case Section.KEYFRAMES:
      return 'KEYFRAMES';
    case Section.TICK_HASHES:
      return 'TICK_HASHES';
    default:
      return id >= 0x80 ? `ancillary 0x${id.toString(16)}` : `unknown 0x${id.toString(16)}`;
  }
}

/** A growable little-endian byte buffer; grows by doubling, so appends are amortised O(1). */
export class ByteSink {
  private buf: Uint8Array;
  private view: DataView;
  private pos = 0;

  constructor(initialCapacity = 64) {
    this.buf = new Uint8Array(Math.max(16, initialCapacity));
    this.view = new DataView(this.buf.buffer);
  }

  get length(): number {
    return this.pos;
  }

  private ensure(n: number): void {
    if (this.pos + n <= this.buf.length) return;
    let cap = this.buf.length * 2;
    while (cap < this.pos + n) cap *= 2;
    const next = new Uint8Array(cap);
    next.set(this.buf.subarray(0, this.pos));
    this.buf = next;
    this.view = new DataView(next.buffer);
  }

  u8(v: number): void {
    this.ensure(1);
    this.buf[this.pos++] = v & 0xff;
  }

  u32(v: number): void {
    this.ensure(4);
    this.view.setUint32(this.pos, v >>> 0, true);
    this.pos += 4;
  }

  u64(v: bigint): void {
    this.ensure(8);
    this.view.setBigUint64(this.pos, BigInt.asUintN(64, v), true);
    this.pos += 8;
  }

  /** Unsigned LEB128 of a u32: 7 bits a byte, low first, high bit = more; minimal length. */
  varint(v: number): void {
    this.ensure(5);
    let x = v >>> 0;
    while (x >= 0x80) {
      this.buf[this.pos++] = (x & 0x7f) | 0x80;
      x >>>= 7;
    }
    this.buf[this.pos++] = x;
  }

  bytes(b: Uint8Array): void {
    this.ensure(b.length);
    this.buf.set(b, this.pos);
    this.pos += b.length;
  }

  /** A string as varint byte length + UTF-8. */
  str(s: string): void {
    const b = utf8Encoder.encode(s);
    this.varint(b.length);
    this.bytes(b);
  }

  /** A view of the bytes written (valid until the next write). */
  view8(): Uint8Array {
    return this.buf.subarray(0, this.pos);
  }
}

/** How many bytes {@link ByteSink.varint} writes for `v`. */
export function varintSize(v: number): number {
  let x = v >>> 0;
  let n = 1;
  while (x >= 0x80) {
    x >>>= 7;
    n++;
  }
  return n;
}

const utf8Encoder = new TextEncoder();
const utf8Decoder = new TextDecoder('utf-8', { fatal: true, ignoreBOM: true });

/** UTF-8 length of a string, in bytes. */
export function utf8Length(s: string): number {
  return utf8Encoder.encode(s).length;
}

/**
 * A bounds-checked reader over `[start, end)` of a file. Every failure is a {@link ReplayError}
 * (`CORRUPT` by default: inside a checksummed file, running out of bytes means a wrong length
 * field, not a short file) naming the field and the absolute offset.
 */
export class Cursor {
  pos: number;
  private readonly view: DataView;

  constructor(
    readonly buf: Uint8Array,
    start: number,
    readonly end: number,
    /** What is being read, e.g. "section INPUTS": prefixed to messages. */
    readonly where: string,
  ) {
    this.pos = start;
    this.view = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  }

  get remaining(): number {
    return this.end - this.pos;
  }

  fail(message: string, at = this.pos): never {
    throw new ReplayError('CORRUPT', `${this.where}: ${message}`, at);
  }

  need(n: number, what: string): void {
    if (n > this.end - this.pos) {
      this.fail(`${what} needs ${n} bytes, ${this.end - this.pos} left`);
    }
  }

  u8(what: string): number {
    this.need(1, what);
    return this.buf[this.pos++]!;
  }

  u32(what: string): number {
    this.need(4, what);
    const v = this.view.getUint32(this.pos, true);
    this.pos += 4;
    return v;
  }

  u64(what: string): bigint {
    this.need(8, what);
    const v = this.view.getBigUint64(this.pos, true);
    this.pos += 8;
    return v;
  }

  /** A canonical unsigned LEB128 u32: at most 5 bytes, value below 2^32, no redundant 0x00 tail. */
  varint(what: string): number {
    const at = this.pos;
    let result = 0;
    let scale = 1; // 128^i, exact in a double
    for (let i = 0; i < 5; i++) {
      if (this.pos >= this.end) this.fail(`${what}: varint runs past the end`, at);
      const b = this.buf[this.pos++]!;
      if (i === 4 && b > 0x0f) this.fail(`${what}: varint above 2^32 - 1`, at);
      result += (b & 0x7f) * scale;
      if ((b & 0x80) === 0) {
        if (b === 0 && i > 0) this.fail(`${what}: non-canonical varint (redundant zero byte)`, at);
        return result;
      }
      scale *= 128;
    }
    return this.fail(`${what}: varint longer than 5 bytes`, at);
  }

  bytes(n: number, what: string): Uint8Array {
    this.need(n, what);
    const b = this.buf.subarray(this.pos, this.pos + n);
    this.pos += n;
    return b;
  }

  /** A varint byte length (at most `max`), then that many bytes of valid UTF-8. */
  str(what: string, max = MAX_STRING_BYTES): string {
    const at = this.pos;
    const n = this.varint(`${what} length`);
    if (n > max) this.fail(`${what} is ${n} bytes, the format allows at most ${max}`, at);
    const b = this.bytes(n, what);
    try {
      return utf8Decoder.decode(b);
    } catch {
      return this.fail(`${what} is not valid UTF-8`, at);
    }
  }

  /** Throws unless every byte up to `end` was read. */
  done(): void {
    if (this.pos !== this.end) this.fail(`${this.end - this.pos} unexpected bytes left over`);
  }
}

// --------------------------------------------------------------------------- input bit interleave

function spread16(v: number): number {
  let x = v & 0xffff;
  x = (x | (x << 8)) & 0x00ff00ff;
  x = (x | (x << 4)) & 0x0f0f0f0f;
  x = (x | (x << 2)) & 0x33333333;
  x = (x | (x << 1)) & 0x55555555;
  return x;
}

function compact16(v: number): number {
  let x = v & 0x55555555;
  x = (x | (x >>> 1)) & 0x33333333;
  x = (x | (x >>> 2)) & 0x0f0f0f0f;
  x = (x | (x >>> 4)) & 0x00ff00ff;
  x = (x | (x >>> 8)) & 0x0000ffff;
  return x;
}

/**
 * Bit b of the low half → bit 2b, bit b of the high half → bit 2b+1. For a ButtonInput this puts
 * each button's "down" and "pressed" bits side by side, so the low buttons of a game land in the
 * low bits and their changes fit one varint byte. A bijection on u32.
 */
export function interleave(v: number): number {
  return (spread16(v) | (spread16(v >>> 16) << 1)) >>> 0;
}

/** The inverse of {@link interleave}. */
export function deinterleave(w: number): number {
  return (compact16(w) | (compact16(w >>> 1) << 16)) >>> 0;
}

/** The low 32 bits of a 64-bit hash (what the per-tick hash section stores). */
export function low32(h: bigint): number {
  return Number(BigInt.asUintN(32, h));
}

/** Greatest common divisor of two non-negative integers. */
export function gcd(a: number, b: number): number {
  while (b !== 0) {
    const t = a % b;
    a = b;
    b = t;
  }
  return a;
}
