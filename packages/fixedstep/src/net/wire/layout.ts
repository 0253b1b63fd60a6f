/**
 * The fields of a message or struct in wire order, read, written and checked in one loop: the
 * common scalar kinds by a direct call (`fastRead` …, see `Fast`), the others through their own
 * functions.
 * @module
 */
import type { ByteWriter } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import {
  bound,
  type Fast,
  type Field,
  type Fields,
  type Limits,
  type WireReader,
} from './field.js';
import { failUint, fastProblem, fastRead, fastWrite, isInlineUint } from './scalars.js';

/** Node (or a runtime like it): where {@link Layout} compiles its codecs. */
const SERVER_RUNTIME =
  (globalThis as { process?: { versions?: { node?: string } } }).process?.versions?.node !==
  undefined;

/**
 * The fields of one message or struct, in wire order. Up to eight optional fields share one
 * presence byte, written just before the first of them.
 */
export class Layout {
  readonly entries: readonly (readonly [string, Field<unknown>])[];
  // The same, as parallel arrays for the hot loops (every message of a match goes through them):
  // the keys, the fields, and each field's presence bit (0: always there; -1: carried).
  private readonly keys: readonly string[];
  private readonly fields: readonly Field<unknown>[];
  private readonly bits: readonly number[];
  private readonly fasts: readonly (Fast | undefined)[];
  private readonly optionals: readonly string[];
  private readonly firstOptional: number;
  // Most bytes under the limits last asked about (a protocol asks with the same limits each time).
  private maxLimits: Limits | undefined;
  private maxCached = 0;
  // This layout's own reader and encoder, compiled from its fields (see `compile`), or null where
  // it cannot be (optional fields, or no code generation: a page whose CSP forbids it).
  private compiledRead: ((r: WireReader, m: Fields) => Fields) | null | undefined;
  private compiledEncode:
    ((w: ByteWriter, m: Fields, limits: Limits) => [string, string] | undefined) | null | undefined;

  constructor(fields: Readonly<Record<string, Field<unknown>>>) {
    this.entries = Object.entries(fields);
    this.optionals = this.entries.filter(([, f]) => f.optional).map(([k]) => k);
    if (this.optionals.length > 8) throw new RangeError('wire: at most 8 optional fields');
    this.firstOptional = this.entries.findIndex(([, f]) => f.optional);
    this.keys = this.entries.map(([k]) => k);
    this.fields = this.entries.map(([, f]) => f);
    this.bits = this.entries.map(([k, f]) =>
      f.carried ? -1 : f.optional ? 1 << this.optionals.indexOf(k) : 0,
    );
    this.fasts = this.fields.map((f) => (f.optional ? undefined : f.fast));
  }

  /** The first field that cannot be written and why, or undefined. */
  problem(m: Fields, limits: Limits): [string, string] | undefined {
    const { keys, fields, fasts } = this;
    for (let i = 0; i < keys.length; i++) {
      const f = fields[i]!;
      const v = m[keys[i]!];
      const fast = fasts[i];
      if (v === undefined && f.optional) continue;
      const p = fast !== undefined ? fastProblem(fast, v, limits) : f.problem(v, m, limits);
      if (p !== undefined) return [keys[i]!, p];
    }
    return undefined;
  }

  write(w: ByteWriter, m: Fields, limits: Limits): void {
    const { keys, fields, bits } = this;
    for (let i = 0; i < keys.length; i++) {
      if (i === this.firstOptional) w.u8(this.presence(m));
      const bit = bits[i]!;
      if (bit < 0) continue;
      const v = m[keys[i]!];
      const fast = this.fasts[i];
      if (fast !== undefined) fastWrite(fast, w, v);
      else if (bit === 0 || v !== undefined) fields[i]!.write(w, v, m, limits);
    }
  }

  /** The presence byte of `m`: a bit for each optional field it has. */
  private presence(m: Fields): number {
    const { keys, bits } = this;
    let present = 0;
    for (let j = this.firstOptional; j < keys.length; j++) {
      if (bits[j]! > 0 && m[keys[j]!] !== undefined) present |= bits[j]!;
    }
    return present;
  }

  /**
   * Checks each field and writes it, in one pass (a message's hot path). Returns the first field
   * that cannot be written and why — the bytes written so far are then to be dropped — or
   * undefined when all of `m` was written.
   */
  encode(w: ByteWriter, m: Fields, limits: Limits): [string, string] | undefined {
    const { keys, fields, bits, fasts } = this;
    for (let i = 0; i < keys.length; i++) {
      if (i === this.firstOptional) w.u8(this.presence(m));
      const f = fields[i]!;
      const v = m[keys[i]!];
      const fast = fasts[i];
      const bit = bits[i]!;
      if (bit > 0 && v === undefined) continue;
      const p = fast !== undefined ? fastProblem(fast, v, limits) : f.problem(v, m, limits);
      if (p !== undefined) return [keys[i]!, p];
      if (fast !== undefined) fastWrite(fast, w, v);
      else if (bit >= 0) f.write(w, v, m, limits);
    }
    return undefined;
  }

  /**
   * A message's fields read into a new object whose first property is `type`: by the compiled
   * reader where there is one (see {@link compile}), else as {@link read} does.
   */
  readMessage(r: WireReader, type: string): Fields {
    if (this.compiledRead === undefined) this.compile();
    const read = this.compiledRead;
    return read ? read(r, { type }) : this.read(r, { type });
  }

  /** As {@link encode}, by the compiled encoder where there is one. */
  encodeMessage(w: ByteWriter, m: Fields, limits: Limits): [string, string] | undefined {
    if (this.compiledEncode === undefined) this.compile();
    const encode = this.compiledEncode;
    return encode ? encode(w, m, limits) : this.encode(w, m, limits);
  }

  /**
   * Compiles this layout's reader and encoder — the loops of {@link read} and {@link encode}
   * unrolled, one statement a field — with `new Function`: each message then reads into an object
   * of one shape made at once, with named property access and a call site of its own per field,
   * where the generic loop's keyed stores and shared call sites cost more than the bytes (every
   * message of every match goes through here; the relay's benchmark holds it to the hand-written
   * codec it replaced). Generated from the declaration's own keys (quoted), calling the fields'
   * own functions: nothing but the order of calls is new. A layout with optional fields (whose
   * objects vary in shape) keeps the generic loops, and so does a browser (a page's
   * Content-Security-Policy forbids code generation, and says so on the console even when the
   * error is caught; a client decodes only its own session's messages): this is for servers.
   */
  private compile(): void {
    this.compiledRead = null;
    this.compiledEncode = null;
    if (this.firstOptional >= 0 || !SERVER_RUNTIME) return;
    const { keys, fasts } = this;
    const q = (k: string) => JSON.stringify(k);
    const init = keys.map((k) => `${q(k)}: undefined`).join(', ');
    // A uint with a numeric range (most fields of the hot messages) is read and checked inline:
    // the same calls and refusals as `fastRead` and `fastProblem`, without their switch.
    const reads = keys.map((k, i) => {
      if (this.bits[i]! < 0) return '';
      const f = fasts[i];
      if (f && isInlineUint(f)) {
        // A named limit is looked up as `bound` does (which throws for a missing one).
        const hi =
          typeof f.max === 'number'
            ? `hi = ${f.max};`
            : `hi = r.limits[${q(f.max)}]; if (hi === undefined) hi = bound(${q(f.max)}, r.limits);`;
        return (
          `r.fieldName = ${q(k)}; at = r.pos; v = r.varint(${q(k)}) + ${f.min}; ${hi} ` +
          `if (v > hi) failUint(r, v, hi, at); m[${q(k)}] = v;`
        );
      }
      const call = f ? `fastRead(fasts[${i}], r)` : `fields[${i}].read(r, m)`;
      return `r.fieldName = ${q(k)}; m[${q(k)}] = ${call};`;
    });
    const encodes = keys.map((k, i) => {
      const get = `v = m[${q(k)}];`;
      const f = fasts[i];
      if (f && isInlineUint(f)) {
        const hi =
          typeof f.max === 'number'
            ? `hi = ${f.max};`
            : `hi = limits[${q(f.max)}]; if (hi === undefined) hi = bound(${q(f.max)}, limits);`;
        return (
          `${get} ${hi} if (typeof v !== 'number' || !(v >= ${f.min} && v <= hi && v - ${f.min} <= 0xffffffff) || !Number.isInteger(v)) ` +
          `return [${q(k)}, fastProblem(fasts[${i}], v, limits)]; w.varint(v - ${f.min});`
        );
      }
      if (f) {
        return `${get} p = fastProblem(fasts[${i}], v, limits); if (p !== undefined) return [${q(k)}, p]; fastWrite(fasts[${i}], w, v);`;
      }
      const write = this.bits[i]! < 0 ? '' : `fields[${i}].write(w, v, m, limits);`;
      return `${get} p = fields[${i}].problem(v, m, limits); if (p !== undefined) return [${q(k)}, p]; ${write}`;
    });
    try {
      // eslint-disable-next-line @typescript-eslint/no-implied-eval -- see the comment above
      const make = new Function(
        'fastRead',
        'fastWrite',
        'fastProblem',
        'failUint',
        'bound',
        'fasts',
        'fields',
        `return [
          function read(r, m0) { const m = { type: m0.type, ${init} }; let at, v, hi; ${reads.join(' ')} return m; },
          function encode(w, m, limits) { let v, p, hi; ${encodes.join(' ')} return undefined; },
        ];`,
      ) as (
        ...args: unknown[]
      ) => [
        (r: WireReader, m: Fields) => Fields,
        (w: ByteWriter, m: Fields, limits: Limits) => [string, string] | undefined,
      ];
      [this.compiledRead, this.compiledEncode] = make(
        fastRead,
        fastWrite,
        fastProblem,
        failUint,
        bound,
        fasts,
        this.fields,
      );
    } catch {
      // No code generation here: the generic loops serve.
    }
  }

  /** Reads the fields into `m` (which may hold a `type`); field names in errors start with `prefix`. */
  read(r: WireReader, m: Fields, prefix = ''): Fields {
    const { keys, fields, bits } = this;
    let present = 0;
    for (let i = 0; i < keys.length; i++) {
      if (i === this.firstOptional) {
        r.fieldName = `${prefix}(presence)`;
        const at = r.pos;
        present = r.u8(r.fieldName);
        if (present >>> this.optionals.length !== 0) {
          r.fail('invalid', `presence bits 0x${present.toString(16)}`, at);
        }
      }
      const key = keys[i]!;
      r.fieldName = prefix === '' ? key : prefix + key;
      const fast = this.fasts[i];
      if (fast !== undefined) {
        m[key] = fastRead(fast, r);
        continue;
      }
      const bit = bits[i]!;
      // A carried field's value was set by its carrier.
      if (bit < 0 || (bit > 0 && (present & bit) === 0)) continue;
      m[key] = fields[i]!.read(r, m);
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
    if (limits === this.maxLimits) return this.maxCached;
    let n = this.firstOptional >= 0 ? 1 : 0;
    for (const f of this.fields) n += f.maxBytes(limits);
    this.maxLimits = limits;
    this.maxCached = n;
    return n;
  }

  get minBytes(): number {
    let n = this.firstOptional >= 0 ? 1 : 0;
    for (const [, f] of this.entries) n += f.minBytes;
    return n;
  }
}
