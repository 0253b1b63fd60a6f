/**
 * Low-level pieces of the replay format (see docs/replay-format.md): constants, a bounds-checked
 * cursor that throws {@link ReplayError}s. Bytes are written
 * with det/bytes.ts's `ByteWriter` and its canonical LEB128 varints.
 * @internal
 */
import { ByteReader } from '../det/bytes.js';
import { ReplayError } from './errors.js';

/** "FSREPLAY" in ASCII. */
export const MAGIC = Uint8Array.of(0x46, 0x53, 0x52, 0x45, 0x50, 0x4c, 0x41, 0x59);
/**
 * The format version this code writes. It reads this one and every earlier one: version 1 (no
 * input schema: one 32-bit button word per player per tick) reads as the `BUTTON_WORD` schema.
 */
export const FORMAT_VERSION = 2;
/** The oldest format version this code reads. */
export const OLDEST_FORMAT_VERSION = 1;
/** Longest input schema descriptor, in bytes. */
export const MAX_DESCRIPTOR_BYTES = 1024;
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

/** UTF-8 length of a string, in bytes. */
export function utf8Length(s: string): number {
  return utf8Encoder.encode(s).length;
}

/**
 * The shared {@link ByteReader} over `[start, end)` of a file, failing with {@link ReplayError}s:
 * `CORRUPT` for every problem (inside a checksummed file, running out of bytes means a wrong length
 * field, not a short file), each message prefixed with what is being read (`where`) and carrying
 * the absolute offset.
 */
export class Cursor extends ByteReader {
  constructor(
    buf: Uint8Array,
    start: number,
    end: number,
    /** What is being read, e.g. "section INPUTS": prefixed to messages. */
    readonly where: string,
  ) {
    super(buf, {
      start,
      end,
      fail: (_problem, message, offset) => {
        throw new ReplayError('CORRUPT', `${where}: ${message}`, offset);
      },
    });
  }

  /** Refuse the file as `CORRUPT` with `message` at `at`. */
  corrupt(message: string, at = this.pos): never {
    return this.fail('invalid', message, at);
  }

  /** A varint byte length (at most `max`, the format's string limit by default), then valid UTF-8. */
  string(what: string, max = MAX_STRING_BYTES): string {
    const at = this.pos;
    const n = this.varint(`${what} length`);
    if (n > max) this.corrupt(`${what} is ${n} bytes, the format allows at most ${max}`, at);
    this.pos = at;
    return this.str(what, max);
  }

  /** Refuse unless every byte up to the cursor's end was read. */
  done(): void {
    if (this.pos !== this.limit) {
      this.corrupt(`${this.limit - this.pos} unexpected bytes left over`);
    }
  }
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
