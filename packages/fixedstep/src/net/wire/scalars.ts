/**
 * The scalar field kinds: integers (canonical unsigned LEB128 varints of at most 32 bits, or
 * fixed-width little-endian), times (finite float64 milliseconds, never -0), flags, enums, text and
 * names (a varint byte length, then UTF-8), and byte strings.
 * @module
 */
import { varintSize, type ByteWriter } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import {
  bound,
  describe,
  isInt,
  pick,
  type Bound,
  type Fast,
  type Field,
  type Fields,
  type Limits,
  type WireReader,
} from './field.js';

/** Room names and game ids: 1–32 of `A–Z a–z 0–9 _ - .`. */
export const NAME_PATTERN = /^[A-Za-z0-9_.-]{1,32}$/;
// eslint-disable-next-line no-control-regex
const CONTROL = /[\u0000-\u001f\u007f]/;
// eslint-disable-next-line no-control-regex
const CONTROLS = /[\u0000-\u001f\u007f]/g;
const encoder = new TextEncoder();
/** {@link NAME_PATTERN} in words. */
const NAME_RULE = '1–32 of A–Z a–z 0–9 _ - .';

// ------------------------------------------------------------------------------------ fast kinds

// The scalar kinds a Layout handles with one direct call (see `Fast`): each kind's reading,
// writing and checking is here, once, and its Field's functions are these too.
const OP_UINT = 1;
const OP_U32 = 2;
const OP_U64 = 3;
const OP_TIME = 4;
const OP_FLAG = 5;
const OP_ONE_OF = 6;
const OP_BYTES = 7;
const OP_NAME = 8;

/** A fast kind's description; every field of it is set, so all share one shape. */
function fastKind(
  op: number,
  more: { min?: number; max?: Bound; values?: readonly string[]; sizes?: readonly number[] } = {},
): Fast {
  return {
    op,
    min: more.min ?? 0,
    max: more.max ?? 0,
    values: more.values,
    sizes: more.sizes,
  };
}

/**
 * Whether fast kind `f` is a `uint` with a numeric max: a compiled layout reads and writes it
 * inline (see `Layout`), with {@link failUint} and {@link fastProblem} for its refusals.
 */
export function isInlineUint(f: Fast): f is Fast & { readonly max: number | string } {
  return f.op === OP_UINT && (typeof f.max === 'number' || typeof f.max === 'string');
}

/** A `uint` read `v` above its `max`: the refusal {@link fastRead} throws. */
export function failUint(r: WireReader, v: number, max: number, at: number): never {
  return r.fail('too-large', `${v}, at most ${max}`, at);
}

/** Reads a value of fast kind `f`. */
export function fastRead(f: Fast, r: WireReader): unknown {
  const at = r.pos;
  switch (f.op) {
    case OP_UINT: {
      const v = r.varint(r.fieldName) + f.min;
      const hi = typeof f.max === 'number' ? f.max : bound(f.max, r.limits);
      return v > hi ? r.fail('too-large', `${v}, at most ${hi}`, at) : v;
    }
    case OP_U32:
      return r.u32(r.fieldName);
    case OP_U64:
      return r.u64(r.fieldName);
    case OP_TIME: {
      const v = r.f64(r.fieldName);
      if (!Number.isFinite(v)) r.fail('invalid', 'not a finite number', at);
      return Object.is(v, -0) ? r.fail('invalid', '-0 (not canonical: +0)', at) : v;
    }
    case OP_FLAG: {
      const v = r.u8(r.fieldName);
      return v > 1 ? r.fail('invalid', `${v} is not 0 or 1`, at) : v === 1;
    }
    case OP_ONE_OF:
      return f.values![r.u8(r.fieldName)] ?? r.fail('invalid', `unknown value ${r.buf[at]}`, at);
    case OP_BYTES: {
      const b = r.field(r.fieldName, bound(f.max, r.limits));
      if (f.sizes && !f.sizes.includes(b.length)) {
        r.fail('invalid', `${b.length} bytes, not ${f.sizes.join(' or ')}`, at);
      }
      return b;
    }
    default: {
      const s = r.str(r.fieldName, 32);
      return NAME_PATTERN.test(s) ? s : r.fail('invalid', `must be ${NAME_RULE}`, at);
    }
  }
}

/** Writes `v` as fast kind `f` (it passed {@link fastProblem}). */
export function fastWrite(f: Fast, w: ByteWriter, v: unknown): void {
  switch (f.op) {
    case OP_UINT:
      w.varint((v as number) - f.min);
      return;
    case OP_U32:
      w.u32(v as number);
      return;
    case OP_U64:
      w.u64(v as bigint);
      return;
    case OP_TIME:
      w.f64(v as number);
      return;
    case OP_FLAG:
      w.u8(v ? 1 : 0);
      return;
    case OP_ONE_OF:
      w.u8(f.values!.indexOf(v as string));
      return;
    case OP_BYTES:
      w.varint((v as Uint8Array).length).bytes(v as Uint8Array);
      return;
    default:
      w.str(v as string);
  }
}

/** Why `v` cannot be written as fast kind `f`, or undefined. */
export function fastProblem(f: Fast, v: unknown, limits: Limits): string | undefined {
  switch (f.op) {
    case OP_UINT: {
      if (!isInt(v)) return `${String(v)} is not an integer`;
      const hi = typeof f.max === 'number' ? f.max : bound(f.max, limits);
      if (v < f.min || v > hi) return `${v} is not from ${f.min} to ${hi}`;
      return v - f.min > 0xffffffff ? `${v} is above 2^32` : undefined;
    }
    case OP_U32:
      return isInt(v) && v >= 0 && v <= 0xffffffff ? undefined : `${String(v)} is not a u32`;
    case OP_U64:
      return typeof v === 'bigint' && v >= 0n && v < 1n << 64n
        ? undefined
        : `${String(v)} is not a u64`;
    case OP_TIME:
      return typeof v === 'number' && Number.isFinite(v)
        ? undefined
        : `${String(v)} is not a finite time`;
    case OP_FLAG:
      return typeof v === 'boolean' ? undefined : `${String(v)} is not a boolean`;
    case OP_ONE_OF:
      return f.values!.includes(v as string)
        ? undefined
        : `"${String(v)}" is not one of ${f.values!.join(', ')}`;
    case OP_BYTES: {
      if (!(v instanceof Uint8Array)) return 'is not a Uint8Array';
      const max = bound(f.max, limits);
      if (v.length > max) return `${v.length} bytes, at most ${max}`;
      if (f.sizes && !f.sizes.includes(v.length)) {
        return `${v.length} bytes, not ${f.sizes.join(' or ')}`;
      }
      return undefined;
    }
    default:
      return typeof v === 'string' && NAME_PATTERN.test(v)
        ? undefined
        : `"${String(v)}" is not ${NAME_RULE}`;
  }
}

/** A Field of fast kind `f`: its read, write and problem are the functions above. */
function fastField<T>(
  kind: string,
  minBytes: number,
  f: Fast,
  sample: (rng: Random, m: Fields, limits: Limits) => T,
  maxBytes: (limits: Limits) => number,
): Field<T> {
  return {
    kind,
    minBytes,
    fast: f,
    problem: (v, _m, limits) => fastProblem(f, v, limits),
    write: (w, v) => {
      fastWrite(f, w, v);
    },
    read: (r) => fastRead(f, r) as T,
    sample,
    maxBytes,
  };
}

// ------------------------------------------------------------------------------------ integers

/** Options of {@link uint}. */
export interface UintOptions {
  /** Smallest value (may be -1: the wire then carries `v + 1`). Default 0. */
  min?: number;
  /** Largest value. Default 2^32 − 1 + min. */
  max?: Bound;
  /**
   * Carried relative to this (the wire holds `v − base(m)`, never negative): e.g. an ack as the
   * distance past the message's last tick, one byte however long the match.
   */
  base?: (m: Fields) => number;
}

/** An integer as a canonical varint (see {@link UintOptions}). */
export function uint(options: UintOptions = {}): Field<number> {
  const min = options.min ?? 0;
  const max = options.max ?? 0xffffffff + min;
  const base = options.base;
  const kind =
    max === 0xffffffff + min
      ? min === 0
        ? 'varint'
        : `varint ≥ ${min}`
      : `varint ${min}–${describe(max)}`;
  const top = (limits: Limits) => bound(max, limits);
  if (base === undefined) {
    return fastField(
      kind,
      1,
      fastKind(OP_UINT, { min, max }),
      (rng, _m, limits) => pick(rng, min, Math.min(top(limits), min + 0xffffffff)),
      (limits) => varintSize(Math.min(0xffffffff, top(limits) - min)),
    );
  }
  return {
    kind,
    minBytes: 1,
    problem(v, m, limits) {
      if (!isInt(v)) return `${String(v)} is not an integer`;
      if (v < min || v > top(limits)) return `${v} is not from ${min} to ${top(limits)}`;
      const b = base(m);
      return v < b || v - b > 0xffffffff ? `${v} is before ${b}` : undefined;
    },
    write(w, v, m) {
      w.varint(v - base(m));
    },
    read(r, m) {
      const at = r.pos;
      const v = r.varint(r.fieldName) + base(m);
      const hi = top(r.limits);
      if (v > hi) r.fail('too-large', `${v}, at most ${hi}`, at);
      return v;
    },
    sample(rng, m, limits) {
      const lo = Math.max(min, base(m));
      return pick(rng, lo, Math.min(top(limits), lo + 0xffffffff));
    },
    maxBytes: () => 5,
  };
}

/**
 * Several small integers in one varint, low digit first: `[key, min, max]`, every max but the last
 * a number. Declared under `own` (one of the digits); the others are {@link carried}.
 */
export function packed(
  own: string,
  digits: readonly (readonly [string, number, Bound])[],
): Field<number> {
  if (digits.length < 2) throw new RangeError('packed: give two digits or more');
  if (!digits.some(([key]) => key === own)) throw new RangeError(`packed: ${own} is not a digit`);
  const spans = digits.slice(0, -1).map(([key, lo, hi]) => {
    if (typeof hi !== 'number') throw new RangeError(`packed: ${key}'s max must be a number`);
    return hi - lo + 1;
  });
  // The digits as parallel arrays: a message's hot path reads them with no destructuring.
  const keys = digits.map(([key]) => key);
  const mins = digits.map(([, lo]) => lo);
  const maxes = digits.map(([, , hi]) => hi);
  const count = digits.length;
  return {
    kind: `packed ${digits.map(([k, lo, hi]) => `${k} ${lo}–${describe(hi)}`).join(', ')}`,
    minBytes: 1,
    problem(_v, m, limits) {
      for (let i = 0; i < count; i++) {
        const key = keys[i]!;
        const lo = mins[i]!;
        const hi = maxes[i]!;
        const v = m[key];
        if (!isInt(v) || v < lo || v > bound(hi, limits)) {
          return `${key} ${String(v)} is not from ${lo} to ${bound(hi, limits)}`;
        }
      }
      return undefined;
    },
    write(w, _v, m) {
      let value = 0;
      let scale = 1;
      for (let i = 0; i < count; i++) {
        value += ((m[keys[i]!] as number) - mins[i]!) * scale;
        scale *= spans[i] ?? 1;
      }
      w.varint(value);
    },
    read(r, m) {
      const at = r.pos;
      let rest = r.varint(r.fieldName);
      for (let i = 0; i < count; i++) {
        const key = keys[i]!;
        const lo = mins[i]!;
        const hi = maxes[i]!;
        const span = spans[i];
        const v = (span === undefined ? rest : rest % span) + lo;
        if (span !== undefined) rest = Math.floor(rest / span);
        const max = typeof hi === 'number' ? hi : bound(hi, r.limits);
        if (v > max) r.fail('too-large', `${key} ${v}, at most ${max}`, at);
        m[key] = v;
      }
      return m[own] as number;
    },
    sample(rng, m, limits) {
      for (const [key, lo, hi] of digits) m[key] = pick(rng, lo, bound(hi, limits));
      return m[own] as number;
    },
    maxBytes: () => 5,
  };
}

/**
 * A field whose value rides in another field's bytes (a {@link packed} digit, the flag of
 * {@link inputs}); it must come after that field.
 */
export function carried<T>(): Field<T> {
  return {
    kind: 'carried',
    carried: true,
    minBytes: 0,
    problem: () => undefined,
    write: () => undefined,
    read: () => undefined as T,
    sample: () => undefined as T,
    maxBytes: () => 0,
  };
}

/** A u32 in four bytes (seeds: every value is as likely). */
export function u32(): Field<number> {
  return fastField(
    'u32',
    4,
    fastKind(OP_U32),
    (rng) => rng.nextU32(),
    () => 4,
  );
}

/** A u64 (a hash) in eight bytes. */
export function u64(): Field<bigint> {
  return fastField(
    'u64',
    8,
    fastKind(OP_U64),
    (rng) => (BigInt(rng.nextU32()) << 32n) | BigInt(rng.nextU32()),
    () => 8,
  );
}

/** A 64-bit id written as 16 lower-case hex digits (an input schema's `id`), sent as a u64. */
export function hex64(): Field<string> {
  return {
    kind: 'u64 as 16 hex digits',
    minBytes: 8,
    problem: (v) =>
      typeof v === 'string' && /^[0-9a-f]{16}$/.test(v)
        ? undefined
        : `"${String(v)}" is not 16 hex digits`,
    write: (w, v) => void w.u64(BigInt(`0x${v}`)),
    read: (r) => r.u64(r.fieldName).toString(16).padStart(16, '0'),
    sample: (rng) =>
      rng.nextU32().toString(16).padStart(8, '0') + rng.nextU32().toString(16).padStart(8, '0'),
    maxBytes: () => 8,
  };
}

/** A server or client clock reading in ms: a finite float64, never -0. */
export function time(): Field<number> {
  return fastField(
    'f64 ms',
    8,
    fastKind(OP_TIME),
    (rng) => [0, 1e12 * rng.next(), -1e3 * rng.next(), 0.5][rng.int(4)]!,
    () => 8,
  );
}

/** A boolean as one byte, 0 or 1. */
export function flag(): Field<boolean> {
  return fastField(
    'u8 0 | 1',
    1,
    fastKind(OP_FLAG),
    (rng) => rng.int(2) === 1,
    () => 1,
  );
}

/**
 * One of `values`, as its index in one byte. Appending values keeps old bytes meaning the same.
 * `label` names a long list in the field's kind (`u8: an error code`) instead of spelling it out.
 */
export function oneOf<T extends string>(values: readonly T[], label?: string): Field<T> {
  if (values.length > 256) throw new RangeError('oneOf: at most 256 values');
  return fastField(
    `u8: ${label ?? values.join(' | ')}`,
    1,
    fastKind(OP_ONE_OF, { values }),
    (rng) => values[rng.int(values.length)]!,
    () => 1,
  );
}

// ------------------------------------------------------------------------------------ text, bytes

/** Options of {@link text}. */
export interface TextOptions {
  /** Most UTF-8 bytes. */
  max: Bound;
  /**
   * Cut a longer string to `max` bytes (on a character boundary) and blank control characters
   * when writing, instead of refusing it (error texts).
   */
  clip?: boolean;
  /** Allow control characters (line breaks in an SDP). Default false: names, messages. */
  controls?: boolean;
}

/** The string the encoder sends for `s` under a clipping text field. */
function clipText(s: string, max: number): string {
  const t = s.replace(CONTROLS, ' ');
  // Cut whole characters (a surrogate pair is one), never half of one.
  return encoder.encode(t).length <= max ? t : cutText(t, max);
}

/** Text: a varint byte length, then valid UTF-8 without control characters. */
export function text(options: TextOptions): Field<string> {
  const { max, clip = false, controls = false } = options;
  return {
    kind: `text ≤ ${describe(max)} bytes`,
    minBytes: 1,
    problem(v, _m, limits) {
      if (typeof v !== 'string') return `${String(v)} is not a string`;
      if (clip) return undefined;
      if (!controls && CONTROL.test(v)) return 'has control characters';
      const n = encoder.encode(v).length;
      return n > bound(max, limits) ? `${n} bytes, at most ${bound(max, limits)}` : undefined;
    },
    write: (w, v, _m, limits) => void w.str(clip ? clipText(v, bound(max, limits)) : v),
    read(r) {
      const at = r.pos;
      const s = r.str(r.fieldName, bound(max, r.limits));
      if (!controls && CONTROL.test(s)) r.fail('invalid', 'has control characters', at);
      return s;
    },
    sample(rng, _m, limits) {
      const alphabet = Array.from(controls ? 'aé€😀 Z9\r\n' : 'aé€😀 Z9');
      let s = '';
      const n = rng.int(Math.min(bound(max, limits), 40) + 1);
      while (encoder.encode(s).length < n) s += alphabet[rng.int(alphabet.length)]!;
      return controls ? cutText(s, bound(max, limits)) : clipText(s, bound(max, limits));
    },
    maxBytes: (limits) => varintSize(bound(max, limits)) + bound(max, limits),
  };
}

/** `s` cut to at most `max` UTF-8 bytes, whole characters. */
function cutText(s: string, max: number): string {
  const chars = Array.from(s);
  while (encoder.encode(chars.join('')).length > max) chars.pop();
  return chars.join('');
}

/** A room name or game id: 1–32 of `A–Z a–z 0–9 _ - .` (see {@link NAME_PATTERN}). */
export function name(): Field<string> {
  return fastField(
    'name',
    2,
    fastKind(OP_NAME),
    (rng) => {
      const chars = 'abcXYZ019_.-';
      let s = '';
      for (let i = pick(rng, 1, 32); i > 0; i--) s += chars[rng.int(chars.length)]!;
      return s;
    },
    () => 33,
  );
}

/** Options of {@link bytes}. */
export interface BytesOptions {
  /** Most bytes. */
  max: Bound;
  /** The only lengths allowed (e.g. `[0, 16]`: absent or a token). Default: any up to `max`. */
  sizes?: readonly number[];
}

/** Bytes: a varint length, then the bytes (a copy the receiver may keep). */
export function bytes(options: BytesOptions): Field<Uint8Array> {
  const { max, sizes } = options;
  return fastField(
    sizes ? `bytes of ${sizes.join(' or ')}` : `bytes ≤ ${describe(max)}`,
    1,
    fastKind(OP_BYTES, { max, ...(sizes ? { sizes } : {}) }),
    (rng, _m, limits) => {
      const n = sizes
        ? sizes[rng.int(sizes.length)]!
        : pick(rng, 0, Math.min(bound(max, limits), 300));
      const b = new Uint8Array(n);
      for (let i = 0; i < n; i++) b[i] = rng.int(256);
      return b;
    },
    (limits) => varintSize(bound(max, limits)) + bound(max, limits),
  );
}
