/**
 * What a wire message is declared with: a {@link Field} (one kind of value: how to write it, read
 * it back — checking every size against the bytes left and the protocol's limits before
 * allocating —, say why a value cannot be sent, how many bytes it may take, and how to make a
 * valid random value), and a {@link Layout} (the fields of one message or struct, in wire order).
 * So a protocol's encoder, decoder, size limits and fuzz test all follow from its declaration (see
 * `protocol.ts`). The kinds themselves are in `scalars.ts` and `compound.ts`.
 * @module
 */
import { ByteReader, type ByteReadProblem, type ByteWriter } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import { PROBLEM_CODES, ProtocolError } from './error.js';

/** A protocol's limits: named bounds its fields refer to. */
export type Limits = Readonly<Record<string, number>>;
/** A message as the codec sees it: field name → value. */
export type Fields = Record<string, unknown>;
/** A bound: a number, the name of one of the protocol's limits, or a function of them. */
export type Bound = number | string | ((limits: Limits) => number);

/** The value of `b` under `limits`. */
export function bound(b: Bound, limits: Limits): number {
  if (typeof b === 'number') return b;
  if (typeof b === 'function') return b(limits);
  const v = limits[b];
  if (v === undefined) throw new RangeError(`wire: no limit named "${b}"`);
  return v;
}

/** `b` in words: a number, a limit's name, or `a limit` for a function of them. */
export function describe(b: Bound): string {
  return typeof b === 'function' ? 'a limit' : String(b);
}

/** The reader every declared message is read with: a failure is a {@link ProtocolError} naming the place. */
export class WireReader extends ByteReader {
  /** The message type being read. */
  messageType = '';
  /** The field being read (`groups[1].peers` inside lists and structs). */
  fieldName = '';
  constructor(
    buf: Uint8Array,
    readonly protocol: string,
    readonly limits: Limits,
  ) {
    super(buf, { start: 2 });
  }
  override fail(problem: ByteReadProblem, message: string, at = this.pos): never {
    throw new ProtocolError(PROBLEM_CODES[problem], message, {
      protocol: this.protocol,
      messageType: this.messageType,
      field: this.fieldName,
      offset: at,
    });
  }
}

/** One field kind: see the module's comment. */
export interface Field<T> {
  /** What it is on the wire, in words (`varint 1–16`, `name`, `bytes ≤ maxSnapshotBytes`). */
  readonly kind: string;
  /** Present or not, per a presence bit (see the `optional` kind). */
  readonly optional?: boolean;
  /** Written inside another field's bytes (the `packed` and `inputs` kinds): writes nothing itself. */
  readonly carried?: boolean;
  /** Fewest bytes it takes (bounds what a count may allocate). */
  readonly minBytes: number;
  /** Why `v` cannot be written (undefined: it can). `m` holds the message's other fields. */
  problem(v: unknown, m: Fields, limits: Limits): string | undefined;
  write(w: ByteWriter, v: T, m: Fields, limits: Limits): void;
  /** Reads the value; `m` holds the fields read before it. */
  read(r: WireReader, m: Fields): T;
  /** A valid random value, given the fields sampled before it (the fuzz test). */
  sample(rng: Random, m: Fields, limits: Limits): T;
  /** Most bytes it takes. */
  maxBytes(limits: Limits): number;
}

/** Whether `v` is an integer. */
export function isInt(v: unknown): v is number {
  return typeof v === 'number' && Number.isInteger(v);
}

/** A random integer in [lo, hi], often an end of the range (where bugs live). */
export function pick(rng: Random, lo: number, hi: number): number {
  const r = rng.int(8);
  if (r === 0 || hi <= lo) return lo;
  if (r === 1) return hi;
  const span = Math.min(hi - lo, 4000);
  return lo + rng.int(span + 1);
}

/**
 * The fields of one message or struct, in wire order. Up to eight optional fields share one
 * presence byte, written just before the first of them.
 */
export class Layout {
  readonly entries: readonly (readonly [string, Field<unknown>])[];
  private readonly optionals: readonly string[];
  private readonly firstOptional: number;

  constructor(fields: Readonly<Record<string, Field<unknown>>>) {
    this.entries = Object.entries(fields);
    this.optionals = this.entries.filter(([, f]) => f.optional).map(([k]) => k);
    if (this.optionals.length > 8) throw new RangeError('wire: at most 8 optional fields');
    this.firstOptional = this.entries.findIndex(([, f]) => f.optional);
  }

  /** The first field that cannot be written and why, or undefined. */
  problem(m: Fields, limits: Limits): [string, string] | undefined {
    for (const [key, f] of this.entries) {
      const v = m[key];
      if (v === undefined && f.optional) continue;
      const p = f.problem(v, m, limits);
      if (p !== undefined) return [key, p];
    }
    return undefined;
  }

  write(w: ByteWriter, m: Fields, limits: Limits): void {
    const entries = this.entries;
    for (let i = 0; i < entries.length; i++) {
      if (i === this.firstOptional) {
        let bits = 0;
        this.optionals.forEach((k, b) => {
          if (m[k] !== undefined) bits |= 1 << b;
        });
        w.u8(bits);
      }
      const [key, f] = entries[i]!;
      const v = m[key];
      if (f.carried || (f.optional && v === undefined)) continue;
      f.write(w, v, m, limits);
    }
  }

  /** Reads the fields into `m` (which may hold a `type`); field names in errors start with `prefix`. */
  read(r: WireReader, m: Fields, prefix = ''): Fields {
    const entries = this.entries;
    let present = 0;
    for (let i = 0; i < entries.length; i++) {
      if (i === this.firstOptional) {
        r.fieldName = `${prefix}(presence)`;
        const at = r.pos;
        present = r.u8(r.fieldName);
        if (present >>> this.optionals.length !== 0) {
          r.fail('invalid', `presence bits 0x${present.toString(16)}`, at);
        }
      }
      const [key, f] = entries[i]!;
      r.fieldName = prefix + key;
      // A carried field's value was set by its carrier.
      if (f.carried) continue;
      if (f.optional && (present & (1 << this.optionals.indexOf(key))) === 0) continue;
      m[key] = f.read(r, m);
    }
    return m;
  }

  sample(rng: Random, m: Fields, limits: Limits): Fields {
    for (const [key, f] of this.entries) {
      if (f.carried) continue;
      const v = f.sample(rng, m, limits);
      if (v !== undefined) m[key] = v;
    }
    return m;
  }

  maxBytes(limits: Limits): number {
    let n = this.firstOptional >= 0 ? 1 : 0;
    for (const [, f] of this.entries) n += f.maxBytes(limits);
    return n;
  }

  get minBytes(): number {
    let n = this.firstOptional >= 0 ? 1 : 0;
    for (const [, f] of this.entries) n += f.minBytes;
    return n;
  }
}
