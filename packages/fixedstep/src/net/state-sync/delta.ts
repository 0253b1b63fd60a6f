/**
 * Delta coding of world states: the bytes of one `save()` against an older one.
 *
 * A game's canonical bytes keep every field at a fixed offset, and from one snapshot to the next
 * most of them do not change (walls, scores, timers at rest, the high bytes of a float that moved a
 * little). A delta is a list of runs over `next XOR base` (the base is read as zeros past its end):
 *
 *     run = skip v, count v (≥ 1), count bytes of (next XOR base) at the cursor
 *
 * the cursor starting at 0 and moving by `skip`, then by `count`. The encoder closes a run after
 * three equal bytes (a new run costs two varints, so shorter gaps are cheaper to send inside the
 * run). The format is our own, not a general compressor's, because the bytes are a wire format that
 * must be the same in every engine and bounded before anything is allocated.
 * @module
 */
import { ByteReader, ByteWriter } from '../../det/bytes.js';
import { PROBLEM_CODES, ProtocolError } from '../wire/error.js';
import type { ByteReadProblem } from '../../det/bytes.js';

const NO_WORDS = new Int32Array(0);

/** Equal bytes after which the encoder closes a run. */
const GAP = 3;

/**
 * Writes the delta that turns `base` into `next` to `out` (appends; an empty delta when they are
 * equal). Allocates nothing beyond `out`'s growth.
 */
export function encodeDelta(base: Uint8Array, next: Uint8Array, out: ByteWriter): void {
  const n = next.length;
  const b = base;
  const shared = Math.min(b.length, n);
  const at = (i: number): number => (i < shared ? b[i]! : 0);
  // Most of a state does not change: skip equal stretches four bytes at a time when both arrays
  // sit on 4-byte boundaries (every fresh `save()` does).
  const aligned = (b.byteOffset & 3) === 0 && (next.byteOffset & 3) === 0;
  const words = aligned ? shared >> 2 : 0;
  const wa = aligned ? new Int32Array(b.buffer, b.byteOffset, words) : NO_WORDS;
  const wb = aligned ? new Int32Array(next.buffer, next.byteOffset, words) : NO_WORDS;
  /** The first index from `i` on where the states differ (n when none). */
  const nextDiff = (from: number): number => {
    let i = from;
    while (i < n && (i & 3) !== 0) {
      if (next[i] !== at(i)) return i;
      i++;
    }
    let w = i >> 2;
    while (w < words && wa[w] === wb[w]) w++;
    if (w << 2 > i) i = w << 2;
    while (i < n && next[i] === at(i)) i++;
    return i;
  };
  let cursor = 0;
  let i = 0;
  while (i < n) {
    i = nextDiff(i);
    if (i >= n) break;
    const start = i;
    let end = i + 1; // one past the last differing byte of the run
    let j = end;
    while (j < n) {
      if (next[j] !== at(j)) {
        end = j + 1;
        j++;
      } else if (j - end + 1 >= GAP) {
        break;
      } else {
        j++;
      }
    }
    out.varint(start - cursor);
    out.varint(end - start);
    for (let k = start; k < end; k++) out.u8(next[k]! ^ at(k));
    cursor = end;
    i = end;
  }
}

/** The delta from `base` to `next`, as bytes. */
export function deltaBytes(base: Uint8Array, next: Uint8Array): Uint8Array {
  const w = new ByteWriter(64);
  encodeDelta(base, next, w);
  return w.finish();
}

/**
 * The state of `size` bytes that `delta` makes of `base`. Throws a `ProtocolError` (`TRUNCATED`,
 * `BAD_VALUE`, `TOO_LARGE`) for runs that do not decode or reach past `size`; a loop over the delta
 * reads at least two bytes a run, so it ends. A delta that decodes but was made against another
 * base gives a wrong state: the caller compares its hash with the one the server sent.
 */
export function applyDelta(base: Uint8Array, delta: Uint8Array, size: number): Uint8Array {
  const out = new Uint8Array(size);
  out.set(base.length > size ? base.subarray(0, size) : base);
  const r = new ByteReader(delta, {
    fail: (problem: ByteReadProblem, message: string, offset: number) => {
      throw new ProtocolError(PROBLEM_CODES[problem], message, {
        protocol: 'state sync',
        messageType: 'snapshot',
        field: 'payload (delta)',
        offset,
      });
    },
  });
  let cursor = 0;
  while (r.remaining > 0) {
    const at = r.pos;
    const skip = r.varint('delta skip');
    const count = r.count('delta run length', size, 1);
    if (skip > size - cursor || count > size - cursor - skip) {
      r.fail(
        'too-large',
        `a delta run ends at ${cursor + skip + count}, past the ${size}-byte state`,
        at,
      );
    }
    cursor += skip;
    r.need(count, 'delta run');
    for (let k = 0; k < count; k++) out[cursor + k] = out[cursor + k]! ^ r.buf[r.pos + k]!;
    r.pos += count;
    cursor += count;
  }
  return out;
}
