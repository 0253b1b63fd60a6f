/**
 * The field kinds a wire message is declared with. Each kind knows how to write a value, read it
 * back (checking every size against the bytes left and the protocol's limits before allocating),
 * say why a value cannot be sent, how many bytes it may take, and how to make a valid random
 * value — so a protocol's encoder, decoder, size limits and fuzz test all follow from its
 * declaration (see `protocol.ts`).
 *
 * Integers are canonical unsigned LEB128 varints of at most 32 bits, fixed-width values are
 * little-endian, times are finite float64 milliseconds (never -0), strings and byte fields carry a
 * varint length.
 * @module
 */
import { ByteReader, ByteWriter, varintSize, type ByteReadProblem } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import { deinterleave, interleave } from '../../sim/buttons.js';
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
function describe(b: Bound): string {
  return typeof b === 'function' ? 'a limit' : String(b);
}

/** Room names and game ids: 1–32 of `A–Z a–z 0–9 _ - .`. */
export const NAME_PATTERN = /^[A-Za-z0-9_.-]{1,32}$/;
// eslint-disable-next-line no-control-regex
const CONTROL = /[\u0000-\u001f\u007f]/;
// eslint-disable-next-line no-control-regex
const CONTROLS = /[\u0000-\u001f\u007f]/g;
const encoder = new TextEncoder();

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
  /** Present or not, per a presence bit (see {@link optional}). */
  readonly optional?: boolean;
  /** Written inside another field's bytes (see {@link packed}, {@link inputs}): writes nothing itself. */
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

function isInt(v: unknown): v is number {
  return typeof v === 'number' && Number.isInteger(v);
}

/** A random integer in [lo, hi], often an end of the range (where bugs live). */
function pick(rng: Random, lo: number, hi: number): number {
  const r = rng.int(8);
  if (r === 0 || hi <= lo) return lo;
  if (r === 1) return hi;
  const span = Math.min(hi - lo, 4000);
  return lo + rng.int(span + 1);
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
  const top = (limits: Limits) => bound(max, limits);
  return {
    kind: `varint ${min}–${describe(max)}`,
    minBytes: 1,
    problem(v, m, limits) {
      if (!isInt(v)) return `${String(v)} is not an integer`;
      if (v < min || v > top(limits)) return `${v} is not from ${min} to ${top(limits)}`;
      if (base !== undefined) {
        const b = base(m);
        if (v < b || v - b > 0xffffffff) return `${v} is before ${b}`;
      } else if (v - min > 0xffffffff) return `${v} is above 2^32`;
      return undefined;
    },
    write(w, v, m) {
      w.varint(base !== undefined ? v - base(m) : v - min);
    },
    read(r, m) {
      const at = r.pos;
      const n = r.varint(r.fieldName);
      const v = base !== undefined ? n + base(m) : n + min;
      const hi = top(r.limits);
      if (v > hi) r.fail('too-large', `${v}, at most ${hi}`, at);
      if (v > 0xffffffff + min) r.fail('invalid', `${v} is past 2^32`, at);
      return v;
    },
    sample(rng, m, limits) {
      const lo = base !== undefined ? Math.max(min, base(m)) : min;
      return pick(rng, lo, Math.min(top(limits), lo + 0xffffffff));
    },
    maxBytes: (limits) =>
      base !== undefined ? 5 : varintSize(Math.min(0xffffffff, top(limits) - min)),
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
  return {
    kind: `packed ${digits.map(([k, lo, hi]) => `${k} ${lo}–${describe(hi)}`).join(', ')}`,
    minBytes: 1,
    problem(_v, m, limits) {
      for (const [key, lo, hi] of digits) {
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
      digits.forEach(([key, lo], i) => {
        value += ((m[key] as number) - lo) * scale;
        scale *= spans[i] ?? 1;
      });
      w.varint(value);
    },
    read(r, m) {
      const at = r.pos;
      let rest = r.varint(r.fieldName);
      digits.forEach(([key, lo, hi], i) => {
        const span = spans[i];
        const v = (span === undefined ? rest : rest % span) + lo;
        if (span !== undefined) rest = Math.floor(rest / span);
        const max = bound(hi, r.limits);
        if (v > max) r.fail('too-large', `${key} ${v}, at most ${max}`, at);
        m[key] = v;
      });
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
  return {
    kind: 'u32',
    minBytes: 4,
    problem: (v) =>
      isInt(v) && v >= 0 && v <= 0xffffffff ? undefined : `${String(v)} is not a u32`,
    write: (w, v) => void w.u32(v),
    read: (r) => r.u32(r.fieldName),
    sample: (rng) => rng.nextU32(),
    maxBytes: () => 4,
  };
}

/** A u64 (a hash) in eight bytes. */
export function u64(): Field<bigint> {
  return {
    kind: 'u64',
    minBytes: 8,
    problem: (v) =>
      typeof v === 'bigint' && v >= 0n && v < 1n << 64n ? undefined : `${String(v)} is not a u64`,
    write: (w, v) => void w.u64(v),
    read: (r) => r.u64(r.fieldName),
    sample: (rng) => (BigInt(rng.nextU32()) << 32n) | BigInt(rng.nextU32()),
    maxBytes: () => 8,
  };
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
  return {
    kind: 'f64 ms',
    minBytes: 8,
    problem: (v) =>
      typeof v === 'number' && Number.isFinite(v) ? undefined : `${String(v)} is not a finite time`,
    write: (w, v) => void w.f64(v),
    read(r) {
      const at = r.pos;
      const v = r.f64(r.fieldName);
      if (!Number.isFinite(v)) r.fail('invalid', 'not a finite number', at);
      if (Object.is(v, -0)) r.fail('invalid', '-0 (not canonical: +0)', at);
      return v;
    },
    sample: (rng) => [0, 1e12 * rng.next(), -1e3 * rng.next(), 0.5][rng.int(4)]!,
    maxBytes: () => 8,
  };
}

/** A boolean as one byte, 0 or 1. */
export function flag(): Field<boolean> {
  return {
    kind: 'u8 0 | 1',
    minBytes: 1,
    problem: (v) => (typeof v === 'boolean' ? undefined : `${String(v)} is not a boolean`),
    write: (w, v) => void w.u8(v ? 1 : 0),
    read(r) {
      const at = r.pos;
      const v = r.u8(r.fieldName);
      if (v > 1) r.fail('invalid', `${v} is not 0 or 1`, at);
      return v === 1;
    },
    sample: (rng) => rng.int(2) === 1,
    maxBytes: () => 1,
  };
}

/** One of `values`, as its index in one byte. Appending values keeps old bytes meaning the same. */
export function oneOf<T extends string>(values: readonly T[]): Field<T> {
  if (values.length > 256) throw new RangeError('oneOf: at most 256 values');
  return {
    kind: `u8: ${values.join(' | ')}`,
    minBytes: 1,
    problem: (v) =>
      values.includes(v as T) ? undefined : `"${String(v)}" is not one of ${values.join(', ')}`,
    write: (w, v) => void w.u8(values.indexOf(v)),
    read(r) {
      const at = r.pos;
      const v = values[r.u8(r.fieldName)];
      return v ?? r.fail('invalid', `unknown value ${r.buf[at]}`, at);
    },
    sample: (rng) => values[rng.int(values.length)]!,
    maxBytes: () => 1,
  };
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
  return {
    kind: 'name',
    minBytes: 2,
    problem: (v) =>
      typeof v === 'string' && NAME_PATTERN.test(v)
        ? undefined
        : `"${String(v)}" is not 1–32 of A–Z a–z 0–9 _ - .`,
    write: (w, v) => void w.str(v),
    read(r) {
      const at = r.pos;
      const s = r.str(r.fieldName, 32);
      if (!NAME_PATTERN.test(s)) r.fail('invalid', 'must be 1–32 of A–Z a–z 0–9 _ - .', at);
      return s;
    },
    sample(rng) {
      const chars = 'abcXYZ019_.-';
      let s = '';
      for (let i = pick(rng, 1, 32); i > 0; i--) s += chars[rng.int(chars.length)]!;
      return s;
    },
    maxBytes: () => 33,
  };
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
  return {
    kind: sizes ? `bytes of ${sizes.join(' or ')}` : `bytes ≤ ${describe(max)}`,
    minBytes: 1,
    problem(v, _m, limits) {
      if (!(v instanceof Uint8Array)) return 'is not a Uint8Array';
      if (v.length > bound(max, limits)) return `${v.length} bytes, at most ${bound(max, limits)}`;
      if (sizes && !sizes.includes(v.length)) return `${v.length} bytes, not ${sizes.join(' or ')}`;
      return undefined;
    },
    write: (w, v) => void w.varint(v.length).bytes(v),
    read(r) {
      const at = r.pos;
      const b = r.field(r.fieldName, bound(max, r.limits));
      if (sizes && !sizes.includes(b.length)) {
        r.fail('invalid', `${b.length} bytes, not ${sizes.join(' or ')}`, at);
      }
      return b;
    },
    sample(rng, _m, limits) {
      const n = sizes
        ? sizes[rng.int(sizes.length)]!
        : pick(rng, 0, Math.min(bound(max, limits), 300));
      const b = new Uint8Array(n);
      for (let i = 0; i < n; i++) b[i] = rng.int(256);
      return b;
    },
    maxBytes: (limits) => varintSize(bound(max, limits)) + bound(max, limits),
  };
}

// ------------------------------------------------------------------------------------ structure

/** A field that may be absent; the message's (or struct's) presence byte says which are there. */
export function optional<T>(field: Field<T>): Field<T | undefined> {
  return {
    ...(field as Field<T | undefined>),
    kind: `optional ${field.kind}`,
    optional: true,
    minBytes: 0,
    sample: (rng, m, limits) => (rng.int(2) === 0 ? undefined : field.sample(rng, m, limits)),
  };
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

/** A nested object of fields (an ICE server, a group of peers). */
export function struct<T extends object>(fields: { [K in keyof T]-?: Field<T[K]> }): Field<T> {
  const layout = new Layout(fields);
  return {
    kind: `{ ${layout.entries.map(([k, f]) => `${k}: ${f.kind}`).join(', ')} }`,
    minBytes: layout.minBytes,
    problem(v, _m, limits) {
      if (typeof v !== 'object' || v === null) return 'is not an object';
      const p = layout.problem(v as Fields, limits);
      return p && `${p[0]}: ${p[1]}`;
    },
    write: (w, v, _m, limits) => {
      layout.write(w, v as Fields, limits);
    },
    read: (r) => layout.read(r, {}, `${r.fieldName}.`) as T,
    sample: (rng, _m, limits) => layout.sample(rng, {}, limits) as T,
    maxBytes: (limits) => layout.maxBytes(limits),
  };
}

/** Options of {@link list}. */
export interface ListOptions {
  /** Most items. */
  max: Bound;
  /** Fewest items. Default 0. */
  min?: number;
}

/** A varint count, then the items. */
export function list<T>(item: Field<T>, options: ListOptions): Field<T[]> {
  const { max, min = 0 } = options;
  return {
    kind: `list of ${min}–${describe(max)} ${item.kind}`,
    minBytes: 1 + min * item.minBytes,
    problem(v, m, limits) {
      if (!Array.isArray(v)) return 'is not an array';
      if (v.length < min || v.length > bound(max, limits)) {
        return `${v.length} items, not ${min} to ${bound(max, limits)}`;
      }
      for (let i = 0; i < v.length; i++) {
        const p = item.problem(v[i], m, limits);
        if (p !== undefined) return `[${i}]: ${p}`;
      }
      return undefined;
    },
    write(w, v, m, limits) {
      w.varint(v.length);
      for (const x of v) item.write(w, x, m, limits);
    },
    read(r, m) {
      const field = r.fieldName;
      const n = r.count(`${field} count`, bound(max, r.limits), min);
      r.need(n * item.minBytes, field);
      const out: T[] = [];
      for (let i = 0; i < n; i++) {
        r.fieldName = `${field}[${i}]`;
        out.push(item.read(r, m));
      }
      r.fieldName = field;
      return out;
    },
    sample(rng, m, limits) {
      const n = pick(rng, min, Math.min(bound(max, limits), 12));
      return Array.from({ length: n }, () => item.sample(rng, m, limits));
    },
    maxBytes: (limits) => 5 + bound(max, limits) * item.maxBytes(limits),
  };
}

/** A varint count, then that many u64s (hashes), as a BigUint64Array. */
export function u64s(options: { max: Bound }): Field<BigUint64Array> {
  return {
    kind: `u64 list ≤ ${describe(options.max)}`,
    minBytes: 1,
    problem(v, _m, limits) {
      if (!(v instanceof BigUint64Array)) return 'is not a BigUint64Array';
      const max = bound(options.max, limits);
      return v.length > max ? `${v.length} hashes, at most ${max}` : undefined;
    },
    write(w, v) {
      w.varint(v.length);
      for (const h of v) w.u64(h);
    },
    read(r) {
      const n = r.count(`${r.fieldName} count`, bound(options.max, r.limits));
      r.need(n * 8, r.fieldName);
      const out = new BigUint64Array(n);
      for (let i = 0; i < n; i++) out[i] = r.u64(r.fieldName);
      return out;
    },
    sample(rng, _m, limits) {
      const n = pick(rng, 0, Math.min(bound(options.max, limits), 20));
      const out = new BigUint64Array(n);
      for (let i = 0; i < n; i++) out[i] = (BigInt(rng.nextU32()) << 32n) | BigInt(rng.nextU32());
      return out;
    },
    maxBytes: (limits) => 5 + 8 * bound(options.max, limits),
  };
}

// ------------------------------------------------------------------------------------ inputs

/** Options of {@link inputs}. */
export interface InputsOptions {
  /** u32 words in one row: one player's words (an input message), or every player's (confirmed). */
  lanes: (m: Fields) => number;
  /** u32 words of one player's input (every `words`-th lane is a button word). */
  words: (m: Fields) => number;
  /** Most lanes a row may have under the limits (bounds the message's size). */
  maxLanes: (limits: Limits) => number;
  /** How many rows: `[fewest, most]`. */
  rows: readonly [number, Bound];
  /** A boolean field carried in the row count's low bit (it must be declared {@link carried}). */
  flag?: string;
}

/**
 * Rows of input words, each XOR-delta coded against the row before and every button word
 * bit-interleaved (its "down" and "pressed" bits side by side), so a held button costs one byte a
 * row: a varint row count (× 2 plus `flag`), then one varint per word.
 */
export function inputs(options: InputsOptions): Field<Uint32Array> {
  const { lanes, words, rows, maxLanes, flag: flagKey } = options;
  const [fewest, most] = rows;
  const countOf = (v: Uint32Array, m: Fields) => v.length / lanes(m);
  return {
    kind: `input rows ${fewest}–${describe(most)}`,
    minBytes: 1,
    problem(v, m, limits) {
      if (!(v instanceof Uint32Array)) return 'is not a Uint32Array';
      const n = countOf(v, m);
      const max = bound(most, limits);
      if (!Number.isInteger(n) || n < fewest || n > max) {
        return `${v.length} words is not ${fewest} to ${max} rows of ${lanes(m)}`;
      }
      if (flagKey !== undefined && typeof m[flagKey] !== 'boolean')
        return `${flagKey} is not a boolean`;
      return undefined;
    },
    write(w, v, m) {
      const n = countOf(v, m);
      w.varint(flagKey === undefined ? n : n * 2 + (m[flagKey] ? 1 : 0));
      const l = lanes(m);
      const k = words(m);
      for (let i = 0; i < v.length; i++) {
        const x = v[i]! >>> 0;
        const d = i < l ? x : (x ^ v[i - l]!) >>> 0;
        w.varint((i % l) % k === 0 ? interleave(d) : d);
      }
    },
    read(r, m) {
      const field = r.fieldName;
      const max = bound(most, r.limits);
      let n = r.count(`${field} rows`, flagKey === undefined ? max : max * 2 + 1, 0);
      if (flagKey !== undefined) {
        m[flagKey] = (n & 1) === 1;
        n >>>= 1;
      }
      if (n < fewest) r.fail('invalid', `${n} rows, at least ${fewest}`);
      const l = lanes(m);
      const k = words(m);
      // Each word takes at least one byte: check before allocating.
      r.need(n * l, field);
      const out = new Uint32Array(n * l);
      for (let i = 0; i < out.length; i++) {
        const v = r.varint(field);
        const d = (i % l) % k === 0 ? deinterleave(v) : v;
        out[i] = i < l ? d : (out[i - l]! ^ d) >>> 0;
      }
      return out;
    },
    sample(rng, m, limits) {
      const n = pick(rng, fewest, Math.min(bound(most, limits), 8));
      if (flagKey !== undefined) m[flagKey] = rng.int(2) === 1;
      const out = new Uint32Array(n * lanes(m));
      for (let i = 0; i < out.length; i++) out[i] = rng.int(3) === 0 ? rng.nextU32() : rng.int(4);
      return out;
    },
    maxBytes: (limits) => 5 + bound(most, limits) * maxLanes(limits) * 5,
  };
}
