/**
 * What a wire message is declared with: a {@link Field} (one kind of value: how to write it, read
 * it back — checking every size against the bytes left and the protocol's limits before
 * allocating —, say why a value cannot be sent, how many bytes it may take, and how to make a
 * valid random value). A `Layout` (`layout.ts`) holds the fields of one message or struct, in wire
 * order. So a protocol's encoder, decoder, size limits and fuzz test all follow from its
 * declaration (see `protocol.ts`). The kinds themselves are in `scalars.ts` and `compound.ts`.
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

/**
 * A scalar kind a `Layout` handles by a `switch` on `op`, calling the kind's own module functions
 * directly. Every message field goes through one loop; calling each field's functions through its
 * object makes that loop's call sites megamorphic, which cost more than the rest of a small
 * message. One object shape for every kind keeps the loop's own property loads monomorphic.
 */
export interface Fast {
  readonly op: number;
  /** `uint`: the smallest value (the wire holds `v − min`). */
  readonly min: number;
  /** `uint`: the largest; `bytes`: the longest. */
  readonly max: Bound;
  /** `oneOf`: the values, by index. */
  readonly values: readonly string[] | undefined;
  /** `bytes`: the only lengths allowed. */
  readonly sizes: readonly number[] | undefined;
}

/** One field kind: see the module's comment. */
export interface Field<T> {
  /** What it is on the wire, in words (`varint 1–16`, `name`, `bytes ≤ maxSnapshotBytes`). */
  readonly kind: string;
  /** Present or not, per a presence bit (see the `optional` kind). */
  readonly optional?: boolean;
  /** Written inside another field's bytes (the `packed` and `inputs` kinds): writes nothing itself. */
  readonly carried?: boolean;
  /**
   * For the common scalar kinds: which one, so a `Layout` reads, writes and checks it with a direct
   * call (see `Fast`) instead of through this object's functions.
   * @internal
   */
  readonly fast?: Fast;
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
