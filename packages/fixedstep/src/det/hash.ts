/**
 * FNV-1a, 64-bit, over bytes: the canonical state hash. Computed on two 32-bit halves with exact
 * 32-bit integer arithmetic (no BigInt, no floating point in the loop), so it is fast and
 * identical in every JS engine.
 *
 * A run of zero bytes is taken in one step. FNV-1a mixes a byte as `h = (h ^ b) × P mod 2^64`;
 * for b = 0 that is `h × P`, so k zero bytes are `h × P^k mod 2^64` — one 64-bit multiplication
 * by a power of P instead of k steps, and exactly the same value. State snapshots are mostly
 * zero bytes (empty pool slots, zero floats, the high bytes of small counters: 92–95 % in the
 * shooters), which makes a checkpoint hash several times cheaper. Runs are found a 32-bit word at
 * a time where the bytes allow it (little-endian engines, four bytes aligned): the bytes hashed
 * and their order never change, only how they are read.
 */
export class Fnv1a64 {
  private hi = 0xcbf29ce4 | 0;
  private lo = 0x84222325 | 0;

  /** Mix in bytes. */
  update(bytes: Uint8Array): this {
    const n = bytes.length;
    // Word-at-a-time scanning needs an aligned Uint32Array view of the bytes (a small
    // allocation); below a few dozen bytes the plain byte loop is cheaper.
    if (!LITTLE_ENDIAN || n < WORDS_FROM) return this.bytesFrom(bytes, 0, n);
    const head = (4 - (bytes.byteOffset & 3)) & 3;
    this.bytesFrom(bytes, 0, head);
    const count = (n - head) >>> 2;
    const words = new Uint32Array(bytes.buffer, bytes.byteOffset + head, count);
    let hi = this.hi;
    let lo = this.lo;
    let zeros = 0;
    for (let i = 0; i < count; i++) {
      // Four zero words at once where they are (most of a snapshot), then one at a time.
      if (i + 4 <= count && (words[i]! | words[i + 1]! | words[i + 2]! | words[i + 3]!) === 0) {
        zeros += 16;
        i += 3;
        continue;
      }
      const w = words[i]!;
      if (w === 0) {
        zeros += 4;
        continue;
      }
      if (zeros !== 0) {
        timesPowerOfPrime(hi, lo, zeros);
        hi = product[0]!;
        lo = product[1]!;
        zeros = 0;
      }
      // The word's four bytes, lowest address first (little-endian): four FNV-1a steps.
      for (let k = 0, b = w; k < 4; k++, b >>>= 8) {
        lo ^= b & 0xff;
        // h × P mod 2^64 with P = 2^40 + 0x1b3: h × 0x1b3 + (h << 40). lo × 0x1b3 is up to 41
        // bits: computed on 16-bit halves, its low 32 bits and its carry into hi stay exact.
        const a = (lo & 0xffff) * 0x1b3;
        const c = (lo >>> 16) * 0x1b3 + (a >>> 16);
        hi = (Math.imul(hi, 0x1b3) + (lo << 8) + (c >>> 16)) | 0;
        lo = (c << 16) | (a & 0xffff);
      }
    }
    if (zeros !== 0) {
      timesPowerOfPrime(hi, lo, zeros);
      hi = product[0]!;
      lo = product[1]!;
    }
    this.hi = hi;
    this.lo = lo;
    return this.bytesFrom(bytes, head + count * 4, n);
  }

  /** Mix in `bytes[from … to)` one byte at a time. */
  private bytesFrom(bytes: Uint8Array, from: number, to: number): this {
    let hi = this.hi;
    let lo = this.lo;
    for (let i = from; i < to; i++) {
      lo ^= bytes[i]!;
      const a = (lo & 0xffff) * 0x1b3;
      const c = (lo >>> 16) * 0x1b3 + (a >>> 16);
      hi = (Math.imul(hi, 0x1b3) + (lo << 8) + (c >>> 16)) | 0;
      lo = (c << 16) | (a & 0xffff);
    }
    this.hi = hi;
    this.lo = lo;
    return this;
  }

  /** The hash as an unsigned 64-bit BigInt. */
  digest(): bigint {
    return (BigInt(this.hi >>> 0) << 32n) | BigInt(this.lo >>> 0);
  }

  /** The hash as 16 lowercase hex digits. */
  hex(): string {
    return (
      (this.hi >>> 0).toString(16).padStart(8, '0') + (this.lo >>> 0).toString(16).padStart(8, '0')
    );
  }
}

const LITTLE_ENDIAN = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;
/** Inputs shorter than this are hashed a byte at a time (see {@link Fnv1a64.update}). */
const WORDS_FROM = 64;

/** {@link multiply64}'s answer: hi, lo. */
const product = new Int32Array(2);

/**
 * The FNV-1a 64 prime's powers P^k mod 2^64 for k < {@link POWERS}, as hi and lo halves (32 KB,
 * built once).
 */
const POWERS = 4096;
const powerHi = new Int32Array(POWERS);
const powerLo = new Int32Array(POWERS);
powerLo[0] = 1;
for (let i = 1; i < POWERS; i++) {
  multiply64(powerHi[i - 1]!, powerLo[i - 1]!, 0x100, 0x1b3);
  powerHi[i] = product[0]!;
  powerLo[i] = product[1]!;
}

/** product = (hi, lo) × P^k mod 2^64. */
function timesPowerOfPrime(hi: number, lo: number, k: number): void {
  for (; k >= POWERS; k -= POWERS - 1) {
    multiply64(hi, lo, powerHi[POWERS - 1]!, powerLo[POWERS - 1]!);
    hi = product[0]!;
    lo = product[1]!;
  }
  multiply64(hi, lo, powerHi[k]!, powerLo[k]!);
}

/** product = (ah, al) × (bh, bl) mod 2^64, on 32-bit halves (16-bit pieces for the low product). */
function multiply64(ah: number, al: number, bh: number, bl: number): void {
  const a0 = al & 0xffff;
  const a1 = al >>> 16;
  const b0 = bl & 0xffff;
  const b1 = bl >>> 16;
  // al × bl = a1·b1·2^32 + (a1·b0 + a0·b1)·2^16 + a0·b0; its high 32 bits, exactly:
  const mid = a1 * b0 + a0 * b1 + ((a0 * b0) >>> 16); // < 2^34: exact in a double
  const high = a1 * b1 + Math.floor(mid / 65536);
  product[0] = (high + Math.imul(ah, bl) + Math.imul(al, bh)) | 0;
  product[1] = Math.imul(al, bl);
}

/** FNV-1a 64 of `bytes`, as 16 hex digits. */
export function fnv1a64Hex(bytes: Uint8Array): string {
  return new Fnv1a64().update(bytes).hex();
}

/** FNV-1a 64 of `bytes`, as a BigInt. */
export function fnv1a64(bytes: Uint8Array): bigint {
  return new Fnv1a64().update(bytes).digest();
}

/** A 64-bit hash as 16 lowercase hex digits (what golden tests and logs print). */
export function hex64(h: bigint): string {
  return BigInt.asUintN(64, h).toString(16).padStart(16, '0');
}
