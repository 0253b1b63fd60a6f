/**
 * Low-level pieces of the replay format (see docs/replay-format.md): constants, a bounds-checked
 * cursor that throws {@link ReplayError}s, the bit interleave of input words. Bytes are written
 * with det/bytes.ts's `ByteWriter` and its canonical LEB128 varints.
 * @internal
 */
import { readVarint, varintProblem } from '../det/bytes.js';
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
    const v = readVarint(this, this.buf, this.end);
    return v < 0 ? this.fail(`${what}: ${varintProblem(v)}`, at) : v;
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
