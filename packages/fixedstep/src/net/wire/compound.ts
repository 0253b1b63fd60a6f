/**
 * The compound field kinds: optional fields (a presence bit), structs, lists, hash lists, and the
 * packed input rows of a tick.
 * @module
 */
import { deinterleave, interleave } from '../../sim/buttons.js';
import { Layout } from './layout.js';
import {
  bound,
  describe,
  pick,
  type Bound,
  type Field,
  type Fields,
  type Limits,
} from './field.js';

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
      const n = r.count(field, bound(max, r.limits), min, ' count');
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
      const n = r.count(r.fieldName, bound(options.max, r.limits), 0, ' count');
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
      let n = r.count(field, flagKey === undefined ? max : max * 2 + 1, 0, ' rows');
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
