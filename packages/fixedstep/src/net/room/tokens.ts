/**
 * Secrets of a room: reconnect tokens, invites.
 * @module
 */
import { TOKEN_BYTES } from '../wire/common.js';

/** A u32 from the platform's cryptographic source (browsers, Node). */
export function cryptoU32(): number {
  return globalThis.crypto.getRandomValues(new Uint32Array(1))[0]!;
}

/** A new token of {@link TOKEN_BYTES} bytes from `randomU32`. */
export function newToken(randomU32: () => number): Uint8Array {
  const t = new Uint8Array(TOKEN_BYTES);
  const v = new DataView(t.buffer);
  for (let i = 0; i < TOKEN_BYTES; i += 4) v.setUint32(i, randomU32() >>> 0);
  return t;
}

/** Whether two tokens are equal, in time that does not depend on where they differ. */
export function sameToken(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  let d = 0;
  for (let i = 0; i < a.length; i++) d |= a[i]! ^ b[i]!;
  return d === 0;
}
