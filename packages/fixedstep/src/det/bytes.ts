/**
 * Canonical bytes: little-endian, every float written with -0 as +0 and every NaN as the one
 * quiet NaN (0x7ff8000000000000), so two states that are equal as numbers are equal as bytes and
 * hash the same in every engine. Used by every `Simulation.save()`, and — with the canonical
 * LEB128 varints below — by the replay format and the network protocol, which add their own
 * bounds-checked readers on top of {@link readVarint}.
 */

const CANONICAL_NAN_HI = 0x7ff80000;
const utf8Encoder = new TextEncoder();

/** How many bytes {@link ByteWriter.varint} writes for `v` (a u32). */
export function varintSize(v: number): number {
  let x = v >>> 0;
  let n = 1;
  while (x >= 0x80) {
    x >>>= 7;
    n++;
  }
  return n;
}

/** {@link readVarint}: the bytes end inside the varint. */
export const VARINT_TRUNCATED = -1;
/**
 * {@link readVarint}: the fifth byte carries bits above 2^32 − 1 (a fifth byte with its "more"
 * bit set does too, so no varint is ever longer than 5 bytes).
 */
export const VARINT_TOO_LARGE = -2;
/** {@link readVarint}: a redundant zero last byte (the same value has a shorter form). */
export const VARINT_NOT_CANONICAL = -3;

/**
 * Reads a canonical unsigned LEB128 u32 from `buf[at.pos … end)` and moves `at.pos` past it.
 * Returns the value (≥ 0), or one of the negative `VARINT_*` codes, for which
 * {@link varintProblem} gives the words; the caller turns that into its own error type. Allocates
 * nothing.
 */
export function readVarint(at: { pos: number }, buf: Uint8Array, end: number): number {
  let result = 0;
  let scale = 1; // 128^i, exact in a double
  for (let i = 0; ; i++) {
    if (at.pos >= end) return VARINT_TRUNCATED;
    const b = buf[at.pos++]!;
    if (i === 4 && b > 0x0f) return VARINT_TOO_LARGE;
    result += (b & 0x7f) * scale;
    if ((b & 0x80) === 0) return b === 0 && i > 0 ? VARINT_NOT_CANONICAL : result;
    scale *= 128;
  }
}

/** What a negative {@link readVarint} result means, e.g. `varint runs past the end`. */
export function varintProblem(code: number): string {
  switch (code) {
    case VARINT_TRUNCATED:
      return 'varint runs past the end';
    case VARINT_TOO_LARGE:
      return 'varint above 2^32 - 1';
    default:
      return 'non-canonical varint (redundant zero byte)';
  }
}

/** The u32 at `p` of `b`, little-endian. */
function littleU32(b: Uint8Array, p: number): number {
  return (b[p]! | (b[p + 1]! << 8) | (b[p + 2]! << 16) | (b[p + 3]! << 24)) >>> 0;
}

// One float64's bytes, for reading a single value without a DataView.
const F64 = new Float64Array(1);
const F64_BYTES = new Uint8Array(F64.buffer);
const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
/**
 * Arrays of at least this many elements are copied whole by {@link ByteWriter.f64s} and
 * {@link ByteWriter.ints} (a view of their memory costs about as much as writing a few elements).
 */
const BULK_FROM = 16;

/** Appends canonical little-endian values to a growing buffer. Reuse one writer to avoid allocation. */
export class ByteWriter {
  private buf: Uint8Array;
  // Made on first use: a message of bytes and varints never needs one, and a DataView costs as
  // much to create as the rest of a small message's encoding.
  private dataView: DataView | undefined;
  private pos = 0;

  constructor(initialCapacity = 256) {
    this.buf = new Uint8Array(Math.max(16, initialCapacity));
  }

  private get view(): DataView {
    return (this.dataView ??= new DataView(this.buf.buffer));
  }

  /** Bytes written so far. */
  get length(): number {
    return this.pos;
  }

  /** Forget what was written (keeps the buffer). */
  reset(): this {
    this.pos = 0;
    return this;
  }

  private ensure(n: number): void {
    if (this.pos + n <= this.buf.length) return;
    let cap = this.buf.length * 2;
    while (cap < this.pos + n) cap *= 2;
    const next = new Uint8Array(cap);
    next.set(this.buf.subarray(0, this.pos));
    this.buf = next;
    this.dataView = undefined;
  }

  u8(v: number): this {
    this.ensure(1);
    this.buf[this.pos++] = v & 0xff;
    return this;
  }

  u16(v: number): this {
    this.ensure(2);
    this.view.setUint16(this.pos, v, true);
    this.pos += 2;
    return this;
  }

  u32(v: number): this {
    this.ensure(4);
    this.view.setUint32(this.pos, v >>> 0, true);
    this.pos += 4;
    return this;
  }

  i32(v: number): this {
    this.ensure(4);
    this.view.setInt32(this.pos, v | 0, true);
    this.pos += 4;
    return this;
  }

  /** A float64, canonical: -0 → +0, any NaN → the quiet NaN. */
  f64(v: number): this {
    this.ensure(8);
    if (v !== v) {
      this.view.setUint32(this.pos, 0, true);
      this.view.setUint32(this.pos + 4, CANONICAL_NAN_HI, true);
    } else {
      this.view.setFloat64(this.pos, v === 0 ? 0 : v, true);
    }
    this.pos += 8;
    return this;
  }

  /**
   * Every element of a Float64Array, canonical. On a little-endian engine an array's memory is
   * already those bytes but for -0 and NaNs: a longer one is copied whole, then those elements
   * are rewritten (what {@link f64} would write). Same bytes, a fraction of the time.
   */
  f64s(values: Float64Array): this {
    const n = values.length;
    this.ensure(n * 8);
    if (!LITTLE_ENDIAN || n < BULK_FROM) {
      for (let i = 0; i < n; i++) this.f64(values[i]!);
      return this;
    }
    const at = this.pos;
    this.buf.set(new Uint8Array(values.buffer, values.byteOffset, n * 8), at);
    for (let i = 0; i < n; i++) {
      const v = values[i]!;
      if (v === 0 ? 1 / v < 0 : v !== v) {
        this.pos = at + i * 8;
        this.f64(v);
      }
    }
    this.pos = at + n * 8;
    return this;
  }

  /**
   * Every element of an integer typed array, as little-endian of its own width. On a
   * little-endian engine that is the array's memory (two's complement for the signed ones): a
   * longer array is copied whole.
   */
  ints(values: Int32Array | Uint32Array | Uint16Array | Uint8Array | Int8Array | Int16Array): this {
    const w = values.BYTES_PER_ELEMENT;
    this.ensure(values.length * w);
    if (LITTLE_ENDIAN && values.length >= BULK_FROM) {
      this.buf.set(new Uint8Array(values.buffer, values.byteOffset, values.byteLength), this.pos);
      this.pos += values.byteLength;
      return this;
    }
    const view = this.view;
    for (let i = 0; i < values.length; i++) {
      const v = values[i]!;
      if (w === 1) this.buf[this.pos] = v & 0xff;
      else if (w === 2) view.setUint16(this.pos, v & 0xffff, true);
      else view.setUint32(this.pos, v >>> 0, true);
      this.pos += w;
    }
    return this;
  }

  /** A u64 from a bigint (its low 64 bits). */
  u64(v: bigint): this {
    this.ensure(8);
    this.view.setBigUint64(this.pos, BigInt.asUintN(64, v), true);
    this.pos += 8;
    return this;
  }

  /**
   * An unsigned LEB128 varint of a u32: 7 bits a byte, low first, high bit = more; always the
   * shortest form (what {@link readVarint} insists on). Throws a RangeError for anything that is
   * not an integer from 0 to 2^32 − 1.
   */
  varint(v: number): this {
    if (!(v >= 0 && v <= 0xffffffff && v === Math.floor(v))) {
      throw new RangeError(`ByteWriter: cannot write ${String(v)} as a u32 varint`);
    }
    this.ensure(5);
    let x = v >>> 0;
    while (x >= 0x80) {
      this.buf[this.pos++] = (x & 0x7f) | 0x80;
      x >>>= 7;
    }
    this.buf[this.pos++] = x;
    return this;
  }

  /** A string as a varint byte length, then its UTF-8. */
  str(s: string): this {
    const b = utf8Encoder.encode(s);
    this.varint(b.length);
    return this.bytes(b);
  }

  /** Raw bytes. */
  bytes(b: Uint8Array): this {
    this.ensure(b.length);
    this.buf.set(b, this.pos);
    this.pos += b.length;
    return this;
  }

  /** A copy of the bytes written. */
  finish(): Uint8Array {
    return this.buf.slice(0, this.pos);
  }

  /** A view of the bytes written (valid until the next write). */
  peek(): Uint8Array {
    return this.buf.subarray(0, this.pos);
  }
}

/**
 * Why a {@link ByteReader} refused its bytes:
 * - `'truncated'` — a field needs more bytes than are left;
 * - `'invalid'` — a field breaks a rule (a non-canonical or too large varint, bad UTF-8 …);
 * - `'too-large'` — a count or length is above the bound the caller gave;
 * - `'trailing'` — bytes are left over after the last field.
 */
export type ByteReadProblem = 'truncated' | 'invalid' | 'too-large' | 'trailing';

/**
 * Turns a refusal into the caller's own error type; must throw. `offset` is absolute (in the
 * whole buffer), `message` names the field, e.g. `"seed needs 4 bytes, 2 left"`.
 */
export type ByteReadFailure = (problem: ByteReadProblem, message: string, offset: number) => never;

/** Options of a {@link ByteReader}. */
export interface ByteReaderOptions {
  /** First byte to read. Default 0. */
  start?: number;
  /** One past the last byte that may be read. Default: the buffer's length. */
  end?: number;
  /** How a refusal is thrown. Default: a RangeError `ByteReader: <message> (at byte <offset>)`. */
  fail?: ByteReadFailure;
}

const utf8Decoder = new TextDecoder('utf-8', { fatal: true, ignoreBOM: true });

const defaultFailure: ByteReadFailure = (problem, message, offset) => {
  throw new RangeError(
    `ByteReader: ${problem === 'truncated' ? 'truncated input: ' : ''}${message} (at byte ${offset})`,
  );
};

/**
 * The one bounds-checked reader of canonical bytes — states (`Simulation.load`), replay files and
 * network messages all read through it. Every read checks the bounds first and refuses through
 * {@link ByteReaderOptions.fail} (a RangeError by default; the replay reader throws
 * `ReplayError`s, the protocol `ProtocolError`s) naming the field and the byte offset, so no
 * input can make it read out of bounds, allocate more than the bytes allow, or loop.
 *
 * Field names (`what`) are optional: they only make messages clearer.
 */
export class ByteReader {
  /** The next byte to read (absolute offset in {@link buf}). May be moved by a caller that skips. */
  pos: number;
  /** One past the last readable byte (absolute offset in {@link buf}). */
  readonly limit: number;
  // Made on first use (see ByteWriter): most network messages are bytes and varints only.
  private dataView: DataView | undefined;
  private readonly failure: ByteReadFailure;

  constructor(
    readonly buf: Uint8Array,
    options: ByteReaderOptions = {},
  ) {
    this.pos = options.start ?? 0;
    this.limit = options.end ?? buf.length;
    this.failure = options.fail ?? defaultFailure;
    if (!(this.pos >= 0 && this.pos <= this.limit && this.limit <= buf.length)) {
      throw new RangeError(
        `ByteReader: range ${this.pos}–${this.limit} is outside a buffer of ${buf.length} bytes`,
      );
    }
  }

  private get view(): DataView {
    const b = this.buf;
    return (this.dataView ??= new DataView(b.buffer, b.byteOffset, b.byteLength));
  }

  /** Bytes read so far, from the start of the buffer. */
  get offset(): number {
    return this.pos;
  }

  /** Bytes left before {@link limit}. */
  get remaining(): number {
    return this.limit - this.pos;
  }

  /** Refuse the input: throws through the reader's failure function. */
  fail(problem: ByteReadProblem, message: string, at = this.pos): never {
    return this.failure(problem, message, at);
  }

  /** Refuse unless `n` more bytes are left. */
  need(n: number, what = 'field'): void {
    if (n > this.limit - this.pos) {
      this.fail('truncated', `${what} needs ${n} bytes, ${this.limit - this.pos} left`);
    }
  }

  u8(what = 'u8'): number {
    this.need(1, what);
    return this.buf[this.pos++]!;
  }

  // Single values are assembled from the bytes: a message of a few numbers would otherwise spend
  // more on creating its DataView than on everything else.

  u16(what = 'u16'): number {
    this.need(2, what);
    const b = this.buf;
    const p = this.pos;
    this.pos += 2;
    return b[p]! | (b[p + 1]! << 8);
  }

  u32(what = 'u32'): number {
    this.need(4, what);
    const v = littleU32(this.buf, this.pos);
    this.pos += 4;
    return v;
  }

  i32(what = 'i32'): number {
    this.need(4, what);
    const v = littleU32(this.buf, this.pos) | 0;
    this.pos += 4;
    return v;
  }

  u64(what = 'u64'): bigint {
    this.need(8, what);
    const lo = littleU32(this.buf, this.pos);
    const hi = littleU32(this.buf, this.pos + 4);
    this.pos += 8;
    return (BigInt(hi) << 32n) | BigInt(lo);
  }

  f64(what = 'f64'): number {
    this.need(8, what);
    const b = this.buf;
    const p = this.pos;
    for (let i = 0; i < 8; i++) F64_BYTES[LITTLE_ENDIAN ? i : 7 - i] = b[p + i]!;
    this.pos += 8;
    return F64[0]!;
  }

  /** Fill `out` with float64s. */
  f64s(out: Float64Array, what = `${out.length} f64`): void {
    this.need(out.length * 8, what);
    const view = this.view;
    for (let i = 0; i < out.length; i++) {
      out[i] = view.getFloat64(this.pos, true);
      this.pos += 8;
    }
  }

  /** Fill an integer typed array, each element little-endian of its own width. */
  ints(
    out: Int32Array | Uint32Array | Uint16Array | Uint8Array | Int8Array | Int16Array,
    what = `${out.length} ints of ${out.BYTES_PER_ELEMENT} bytes`,
  ): void {
    const w = out.BYTES_PER_ELEMENT;
    this.need(out.length * w, what);
    const view = this.view;
    for (let i = 0; i < out.length; i++) {
      out[i] =
        w === 1
          ? this.buf[this.pos]!
          : w === 2
            ? view.getUint16(this.pos, true)
            : view.getUint32(this.pos, true);
      this.pos += w;
    }
  }

  /** The next `n` bytes, as a view into the buffer (copy it before keeping or changing it). */
  bytes(n: number, what = `${n} bytes`): Uint8Array {
    this.need(n, what);
    const b = this.buf.subarray(this.pos, this.pos + n);
    this.pos += n;
    return b;
  }

  /** A canonical unsigned LEB128 u32 (see {@link readVarint}). */
  varint(what = 'varint'): number {
    const at = this.pos;
    const v = readVarint(this, this.buf, this.limit);
    if (v === VARINT_TRUNCATED) this.fail('truncated', `${what}: ${varintProblem(v)}`, at);
    return v < 0 ? this.fail('invalid', `${what}: ${varintProblem(v)}`, at) : v;
  }

  /**
   * A varint from `min` to `max`: above `max` is `'too-large'`, below `min` `'invalid'`. A failure
   * names it `what` and then `noun` (`inputs` `rows`), joined only then.
   */
  count(what: string, max: number, min = 0, noun = ''): number {
    const at = this.pos;
    const n = this.varint(what);
    if (n > max) this.fail('too-large', `${what}${noun} is ${n}, at most ${max}`, at);
    if (n < min) this.fail('invalid', `${what}${noun} is ${n}, at least ${min}`, at);
    return n;
  }

  /** A varint byte length (at most `max`), then that many bytes: a copy the caller may keep. */
  field(what: string, max: number): Uint8Array {
    const n = this.count(what, max, 0, ' length');
    this.need(n, what);
    const b = this.buf.slice(this.pos, this.pos + n);
    this.pos += n;
    return b;
  }

  /** A varint byte length (at most `maxBytes`), then that many bytes of valid UTF-8. */
  str(what: string, maxBytes: number): string {
    const at = this.pos;
    const n = this.count(what, maxBytes, 0, ' length');
    this.need(n, what);
    try {
      const s = utf8Decoder.decode(this.buf.subarray(this.pos, this.pos + n));
      this.pos += n;
      return s;
    } catch {
      return this.fail('invalid', `${what} is not valid UTF-8`, at);
    }
  }

  /** Refuse (`'trailing'`) unless every byte up to {@link limit} was read. */
  end(): void {
    if (this.pos !== this.limit) {
      this.fail('trailing', `${this.limit - this.pos} unexpected trailing bytes`);
    }
  }
}
