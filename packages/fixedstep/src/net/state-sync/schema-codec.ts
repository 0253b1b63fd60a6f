/**
 * The schema codec: a state's words (see `StateSchema.quantise`) against a base's, as bits —
 * Glenn Fiedler's *Snapshot Compression* in general form.
 *
 * For each group (entity type) of the schema, in order:
 *
 *     any changed row?                      1 bit
 *     which rows (when the group has > 1):  1 bit mode, then a bitmap (1 bit a row), or the count
 *                                           and the gaps between changed rows (exp-Golomb, order k)
 *     per column word ("lane"):             1 bit: any change in it;
 *                                           then 1 bit mode + 5 bits k, and per changed row either
 *                                           EG_k(zigzag(next − base)), or a flag bit and, when set,
 *                                           EG_k(zigzag(next − base) − 1)
 *
 * where `base` is the base snapshot's word (0 for a row it did not have, or without a base: a full
 * snapshot is a delta against nothing) — for a column that has a rate, moved by it: over `n` ticks,
 * `base + round(scale × (baseRate × (n − 1) + rate × (n + 1)) / (2 × tickRate))`, where `rate` is
 * the value this snapshot brings (a group's columns without a rate are coded first, see
 * `StateGroup.codeOrder`) — and the encoder picks, for every choice, the cheaper by counting bits. Exp-Golomb with a per-lane order chosen from the data is the entropy coder: it
 * costs 6 bits a lane and adapts to how far that field moved since the base. A value that did not
 * change costs nothing beyond its row's bit, or its lane's.
 *
 * Our own format because it is a wire format: the same bits in every engine, bounded before
 * anything is allocated, and decoded without trusting the sender.
 * @module
 */
import type { StateSchema } from '../../sim/state-schema.js';
import { ProtocolError } from '../wire/error.js';

/** Appends bits, most significant first, to a growing buffer. */
export class BitWriter {
  private buf = new Uint8Array(256);
  private bytePos = 0;
  /** Bits pending in `acc` (0–7 after each write). */
  private bits = 0;
  private acc = 0;

  reset(): this {
    this.bytePos = 0;
    this.bits = 0;
    this.acc = 0;
    return this;
  }

  /** Write the low `n` bits of `v` (n ≤ 32). */
  write(v: number, n: number): void {
    if (n > 24) {
      this.write(Math.floor(v / 65536) & 0xffff, n - 16);
      this.write(v & 0xffff, 16);
      return;
    }
    this.acc = ((this.acc << n) | (v & ((1 << n) - 1))) >>> 0;
    this.bits += n;
    while (this.bits >= 8) {
      this.bits -= 8;
      this.put((this.acc >>> this.bits) & 0xff);
    }
    this.acc &= (1 << this.bits) - 1;
  }

  bit(b: boolean): void {
    this.write(b ? 1 : 0, 1);
  }

  /** Exp-Golomb of order k for an integer 0 ≤ v < 2^32. */
  expGolomb(v: number, k: number): void {
    const x = v + POW2[k]!;
    const len = bitLength(x);
    this.write(0, len - k - 1);
    if (len > 32) {
      this.write(1, 1);
      this.write(x - TWO_32, 32);
    } else {
      this.write(x, len);
    }
  }

  /** The bytes written (padded with zero bits to a byte), copied. */
  finish(): Uint8Array {
    if (this.bits > 0) this.put((this.acc << (8 - this.bits)) & 0xff);
    this.bits = 0;
    this.acc = 0;
    return this.buf.slice(0, this.bytePos);
  }

  private put(b: number): void {
    if (this.bytePos === this.buf.length) {
      const next = new Uint8Array(this.buf.length * 2);
      next.set(this.buf);
      this.buf = next;
    }
    this.buf[this.bytePos++] = b;
  }
}

/** Reads what a {@link BitWriter} wrote; past the end it throws a `TRUNCATED` ProtocolError. */
export class BitReader {
  private pos = 0;
  constructor(private readonly buf: Uint8Array) {}

  read(n: number): number {
    let v = 0;
    for (let i = 0; i < n; i++) v = v * 2 + this.one();
    return v;
  }

  bit(): boolean {
    return this.one() === 1;
  }

  expGolomb(k: number): number {
    let zeros = 0;
    while (this.one() === 0) {
      if (++zeros > 32) fail('BAD_VALUE', 'an exp-Golomb code longer than 33 bits', this.pos >> 3);
    }
    // A value below 2^32 has at most 33 bits with its leading 1.
    if (zeros + k > 32) fail('BAD_VALUE', 'an exp-Golomb value above 2^32 - 1', this.pos >> 3);
    const x = POW2[zeros + k]! + this.read(zeros + k);
    const v = x - POW2[k]!;
    if (v > 0xffffffff) fail('BAD_VALUE', 'an exp-Golomb value above 2^32 - 1', this.pos >> 3);
    return v;
  }

  /** Bits left. */
  get remaining(): number {
    return this.buf.length * 8 - this.pos;
  }

  private one(): number {
    const p = this.pos;
    if (p >= this.buf.length * 8) fail('TRUNCATED', 'the schema delta ends early', p >> 3);
    this.pos = p + 1;
    return (this.buf[p >> 3]! >> (7 - (p & 7))) & 1;
  }
}

function fail(
  code: 'TRUNCATED' | 'BAD_VALUE' | 'TOO_LARGE',
  message: string,
  offset: number,
): never {
  throw new ProtocolError(code, message, {
    protocol: 'state sync',
    messageType: 'snapshot',
    field: 'payload (schema delta)',
    offset,
  });
}

/** 2^k for k = 0 … 33, by multiplication (exact; no `**`, which is `Math.pow`). */
const POW2: readonly number[] = (() => {
  const out = [1];
  for (let k = 1; k <= 33; k++) out.push(out[k - 1]! * 2);
  return out;
})();
const TWO_32 = POW2[32]!;

/** Bits of x ≥ 1 (x < 2^33). */
function bitLength(x: number): number {
  return x >= TWO_32 ? 33 : 32 - Math.clz32(x);
}

/** Bits of EG_k(v). */
function egBits(v: number, k: number): number {
  return 2 * bitLength(v + POW2[k]!) - k - 1;
}

const K_BITS = 5;
const MAX_K = 31;

/**
 * How far a snapshot is from its base — whole ticks, and the game's ticks a second — and, for
 * columns that `extrapolate`, the snapshot before the base that both ends hold.
 */
export interface Elapsed {
  readonly ticks: number;
  readonly tickRate: number;
  /** The words of a snapshot older than the base (none: extrapolating columns keep the base's). */
  readonly older?: Int32Array;
  /** Ticks from `older` to the base (> 0 with `older`). */
  readonly olderTicks?: number;
}

/** No base (a full snapshot): nothing elapsed. */
const NO_TIME: Elapsed = { ticks: 0, tickRate: 1 };

/**
 * A word moved over `e` by its rate, from `was` at the base with rate `r0` to the snapshot with
 * rate `rn`: `was + round(scale × (r0 × (n − 1) + rn × (n + 1)) / (2 × tickRate))` — where a body
 * stepped `v += a·Δt; x += v·Δt` under a constant `a` is after `n` ticks. In 32-bit arithmetic,
 * the same IEEE operations in the same order and `Math.round` in every engine, so both ends
 * predict alike.
 */
function predict(was: number, r0: number, rn: number, scale: number, e: Elapsed): number {
  const n = e.ticks;
  if (n <= 0) return was;
  return (was + Math.round((scale * (r0 * (n - 1) + rn * (n + 1))) / (2 * e.tickRate))) | 0;
}

/**
 * A word at the base (`b1`) and at the older snapshot (`b2`) carried on in a straight line:
 * `b1 + round((b1 − b2) × n1 / n2)`, in 32-bit arithmetic (the same in every engine).
 */
function extrapolate(b1: number, b2: number, e: Elapsed): number {
  const n2 = e.olderTicks!;
  if (!(n2 > 0) || e.ticks <= 0) return b1;
  return (b1 + Math.round(((b1 - b2) * e.ticks) / n2)) | 0;
}

/** zigzag of a 32-bit difference, as an unsigned number. */
function zigzag(d: number): number {
  return ((d << 1) ^ (d >> 31)) >>> 0;
}

function unzigzag(z: number): number {
  return (z >>> 1) ^ -(z & 1);
}

/** Scratch for one encode: changed rows and a lane's residuals. */
const scratch = { rows: new Int32Array(64), zig: new Float64Array(64) };
function grow(n: number): void {
  if (scratch.rows.length < n) {
    let m = scratch.rows.length;
    while (m < n) m *= 2;
    scratch.rows = new Int32Array(m);
    scratch.zig = new Float64Array(m);
  }
}

/** Where each sent column's words start, and each group's row count, for a state's words. */
export function starts(
  schema: StateSchema,
  words: Int32Array | undefined,
): { col: number[]; rows: number[] } {
  const col: number[] = new Array<number>(schema.sent.length).fill(0);
  const rows: number[] = new Array<number>(schema.groups.length).fill(0);
  if (!words) return { col, rows };
  let w = 0;
  for (const [gi, g] of schema.groups.entries()) {
    const n = typeof g.count === 'number' ? g.count : words[col[g.count.column]!]! * g.count.times;
    rows[gi] = n;
    for (const s of g.columns) {
      col[s] = w;
      w += n * schema.sent[s]!.lanes;
    }
  }
  return { col, rows };
}

/**
 * Write the delta that turns `base`'s words (none: a full snapshot) into `next`'s to `out`. Both
 * must be words of `schema` (from `quantise`).
 */
export function encodeSchemaDelta(
  schema: StateSchema,
  base: Int32Array | undefined,
  next: Int32Array,
  out: BitWriter,
  elapsed: Elapsed = NO_TIME,
): void {
  const n = starts(schema, next);
  const expected = predictInto(schema, base, next, elapsed, scratchWords(next.length));
  for (const [gi, g] of schema.groups.entries()) {
    const count = n.rows[gi]!;
    grow(count);
    const rows = scratch.rows;
    let changed = 0;
    for (let r = 0; r < count; r++) {
      let differs = false;
      for (const s of g.columns) {
        const lanes = schema.sent[s]!.lanes;
        const at = n.col[s]! + r * lanes;
        for (let l = 0; l < lanes; l++) {
          if (next[at + l] !== expected[at + l]) differs = true;
        }
        if (differs) break;
      }
      if (differs) rows[changed++] = r;
    }
    out.bit(changed > 0);
    if (changed === 0) continue;
    if (count > 1) writeRows(out, rows, changed, count);
    for (const s of g.codeOrder) {
      const lanes = schema.sent[s]!.lanes;
      const start = n.col[s]!;
      for (let l = 0; l < lanes; l++) {
        const zig = scratch.zig;
        let nonZero = 0;
        for (let i = 0; i < changed; i++) {
          const at = start + rows[i]! * lanes + l;
          const z = zigzag((next[at]! - expected[at]!) | 0);
          zig[i] = z;
          if (z !== 0) nonZero++;
        }
        out.bit(nonZero > 0);
        if (nonZero === 0) continue;
        writeLane(out, zig, changed);
      }
    }
  }
}

/**
 * What a decoder predicts, word for word in `next`'s layout: `base`'s words (0 for rows it did
 * not have), the columns with a rate moved by it — the base's and `next`'s (a rate is decoded
 * before what it moves). A row whose words equal these costs nothing.
 */
export function predictedWords(
  schema: StateSchema,
  base: Int32Array | undefined,
  next: Int32Array,
  elapsed: Elapsed,
): Int32Array {
  return predictInto(schema, base, next, elapsed, new Int32Array(next.length));
}

function predictInto(
  schema: StateSchema,
  base: Int32Array | undefined,
  next: Int32Array,
  elapsed: Elapsed,
  expected: Int32Array,
): Int32Array {
  const b = starts(schema, base);
  const n = starts(schema, next);
  const o = elapsed.older && starts(schema, elapsed.older);
  for (const [gi, g] of schema.groups.entries()) {
    const rows = Math.min(n.rows[gi]!, b.rows[gi]!);
    for (const s of g.columns) {
      const col = schema.sent[s]!;
      const from = b.col[s]!;
      const to = n.col[s]!;
      const words = n.rows[gi]! * col.lanes;
      const kept = rows * col.lanes;
      if (kept > 0) expected.set(base!.subarray(from, from + kept), to);
      expected.fill(0, to + kept, to + words);
      if (col.rate >= 0) {
        const was = b.col[col.rate]!;
        const now = n.col[col.rate]!;
        for (let r = 0; r < rows; r++) {
          expected[to + r] = predict(
            expected[to + r]!,
            base![was + r]!,
            next[now + r]!,
            col.rateScale,
            elapsed,
          );
        }
      } else if (col.extrapolate && o) {
        const from = o.col[s]!;
        const both = Math.min(rows, o.rows[gi]!);
        for (let r = 0; r < both; r++) {
          expected[to + r] = extrapolate(expected[to + r]!, elapsed.older[from + r]!, elapsed);
        }
      }
    }
  }
  return expected;
}

/** A reused scratch vector of at least `n` words (the encoder's expected words). */
let expectedScratch = new Int32Array(1024);
function scratchWords(n: number): Int32Array {
  if (expectedScratch.length < n) {
    let m = expectedScratch.length;
    while (m < n) m *= 2;
    expectedScratch = new Int32Array(m);
  }
  return expectedScratch;
}

/** The changed rows of a group of `count`: a bitmap, or the gaps — whichever is shorter. */
function writeRows(out: BitWriter, rows: Int32Array, changed: number, count: number): void {
  let bestK = 0;
  let best = Infinity;
  for (let k = 0; k <= 16; k++) {
    let bits = egBits(changed - 1, 0) + K_BITS;
    let prev = -1;
    for (let i = 0; i < changed; i++) {
      bits += egBits(rows[i]! - prev - 1, k);
      prev = rows[i]!;
    }
    if (bits < best) {
      best = bits;
      bestK = k;
    }
  }
  if (count <= best) {
    out.bit(false);
    let i = 0;
    for (let r = 0; r < count; r++) {
      const set = i < changed && rows[i] === r;
      out.bit(set);
      if (set) i++;
    }
    return;
  }
  out.bit(true);
  out.expGolomb(changed - 1, 0);
  out.write(bestK, K_BITS);
  let prev = -1;
  for (let i = 0; i < changed; i++) {
    out.expGolomb(rows[i]! - prev - 1, bestK);
    prev = rows[i]!;
  }
}

/** One lane's residuals (zigzagged): plain EG_k, or a flag per row and EG_k of the non-zero. */
function writeLane(out: BitWriter, zig: Float64Array, n: number): void {
  let best = Infinity;
  let bestK = 0;
  let flagged = false;
  const largest = maxOf(zig, n);
  for (let k = 0; k <= MAX_K; k++) {
    let plain = 0;
    let sparse = n;
    for (let i = 0; i < n; i++) {
      const z = zig[i]!;
      plain += egBits(z, k);
      if (z !== 0) sparse += egBits(z - 1, k);
    }
    if (plain < best) {
      best = plain;
      bestK = k;
      flagged = false;
    }
    if (sparse < best) {
      best = sparse;
      bestK = k;
      flagged = true;
    }
    // Larger orders only pay while values are large: stop once k passes the largest value's bits.
    if (k > 0 && POW2[k]! > largest) break;
  }
  out.bit(flagged);
  out.write(bestK, K_BITS);
  for (let i = 0; i < n; i++) {
    const z = zig[i]!;
    if (flagged) {
      out.bit(z !== 0);
      if (z !== 0) out.expGolomb(z - 1, bestK);
    } else {
      out.expGolomb(z, bestK);
    }
  }
}

function maxOf(a: Float64Array, n: number): number {
  let m = 0;
  for (let i = 0; i < n; i++) if (a[i]! > m) m = a[i]!;
  return m;
}

/**
 * The words that `payload` makes of `base`'s (none: a full snapshot). Throws a
 * {@link ProtocolError} for bits that do not decode, a count above the schema's bounds, or more
 * than `maxWords` words; a payload made against another base decodes to wrong words — the caller
 * checks the hash.
 */
export function decodeSchemaDelta(
  schema: StateSchema,
  base: Int32Array | undefined,
  payload: Uint8Array,
  maxWords: number,
  elapsed: Elapsed = NO_TIME,
): Int32Array {
  const b = starts(schema, base);
  const o = elapsed.older && starts(schema, elapsed.older);
  const r = new BitReader(payload);
  // Counts come first in their own (earlier) groups: decode group by group into a growing vector.
  let words = new Int32Array(Math.min(maxWords, 1024));
  let used = 0;
  const col: number[] = new Array<number>(schema.sent.length).fill(0);
  for (const [gi, g] of schema.groups.entries()) {
    let count: number;
    if (typeof g.count === 'number') {
      count = g.count;
    } else {
      const v = words[col[g.count.column]!]!;
      count = v * g.count.times;
      if (!(v >= 0 && count <= g.count.max)) {
        fail('TOO_LARGE', `group ${g.name} would hold ${count} rows, at most ${g.count.max}`, 0);
      }
    }
    let groupWords = 0;
    for (const s of g.columns) groupWords += count * schema.sent[s]!.lanes;
    if (used + groupWords > maxWords) {
      fail('TOO_LARGE', `the state would have more than ${maxWords} words`, 0);
    }
    if (used + groupWords > words.length) {
      let m = words.length;
      while (m < used + groupWords) m *= 2;
      const bigger = new Int32Array(Math.min(m, maxWords));
      bigger.set(words.subarray(0, used));
      words = bigger;
    }
    const baseCount = b.rows[gi]!;
    // Start from the base (0 past its rows).
    for (const s of g.columns) {
      const lanes = schema.sent[s]!.lanes;
      col[s] = used;
      const copy = Math.min(count, baseCount) * lanes;
      if (copy > 0) words.set(base!.subarray(b.col[s], b.col[s]! + copy), used);
      words.fill(0, used + copy, used + count * lanes);
      used += count * lanes;
    }
    const kept = Math.min(count, baseCount);
    const changed = r.bit() ? changedRows(r, count) : NO_ROWS;
    for (const s of g.codeOrder) {
      const c = schema.sent[s]!;
      // Move the base's rows by their rates: the base's, and the snapshot's (decoded already).
      if (c.rate >= 0) {
        const was = b.col[c.rate]!;
        const now = col[c.rate]!;
        for (let row = 0; row < kept; row++) {
          const at = col[s]! + row;
          words[at] = predict(
            words[at]!,
            base![was + row]!,
            words[now + row]!,
            c.rateScale,
            elapsed,
          );
        }
      } else if (c.extrapolate && o) {
        const from = o.col[s]!;
        const both = Math.min(kept, o.rows[gi]!);
        for (let row = 0; row < both; row++) {
          const at = col[s]! + row;
          words[at] = extrapolate(words[at]!, elapsed.older[from + row]!, elapsed);
        }
      }
      if (changed.length === 0) continue;
      const rows = changed;
      const lanes = c.lanes;
      for (let l = 0; l < lanes; l++) {
        if (!r.bit()) continue;
        const flagged = r.bit();
        const k = r.read(K_BITS);
        for (const row of rows) {
          let z = 0;
          if (flagged) {
            if (r.bit()) z = r.expGolomb(k) + 1;
          } else {
            z = r.expGolomb(k);
          }
          if (z > 0xffffffff) fail('BAD_VALUE', 'a residual above 2^32 - 1', 0);
          const at = col[s]! + row * lanes + l;
          words[at] = (words[at]! + unzigzag(z)) | 0;
        }
      }
    }
  }
  if (r.remaining >= 8) fail('BAD_VALUE', `${r.remaining >> 3} bytes after the schema delta`, 0);
  return words.length === used ? words : words.slice(0, used);
}

const NO_ROWS: readonly number[] = [];

function changedRows(r: BitReader, count: number): number[] {
  if (count === 1) return [0];
  const rows: number[] = [];
  if (!r.bit()) {
    for (let i = 0; i < count; i++) if (r.bit()) rows.push(i);
    return rows;
  }
  const changed = r.expGolomb(0) + 1;
  if (changed > count) fail('BAD_VALUE', `${changed} changed rows of ${count}`, 0);
  const k = r.read(K_BITS);
  let prev = -1;
  for (let i = 0; i < changed; i++) {
    const row = prev + 1 + r.expGolomb(k);
    if (row >= count) fail('BAD_VALUE', `a changed row ${row} of ${count}`, 0);
    rows.push(row);
    prev = row;
  }
  return rows;
}
