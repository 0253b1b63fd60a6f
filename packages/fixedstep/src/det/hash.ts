/**
 * FNV-1a, 64-bit, over bytes: the canonical state hash. Computed on two 32-bit halves with exact
 * integer arithmetic (no BigInt in the loop), so it is fast and identical in every JS engine.
 */
export class Fnv1a64 {
  private hi = 0xcbf29ce4;
  private lo = 0x84222325;

  /** Mix in bytes. */
  update(bytes: Uint8Array): this {
    let hi = this.hi;
    let lo = this.lo;
    for (let i = 0; i < bytes.length; i++) {
      lo ^= bytes[i]!;
      // h × 0x100000001b3 mod 2^64 = h × 0x1b3 + (h << 40)
      const a = (lo >>> 0) * 0x1b3;
      const carry = Math.floor(a / 4294967296);
      hi = (Math.imul(hi, 0x1b3) + (lo << 8) + carry) >>> 0;
      lo = a >>> 0;
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
