/**
 * The fields of a message or struct in wire order, read, written and checked in one loop: the
 * common scalar kinds by a direct call (`fastRead` …, see `Fast`), the others through their own
 * functions.
 * @module
 */
import type { ByteWriter } from '../../det/bytes.js';
import type { Random } from '../../det/random.js';
import type { Fast, Field, Fields, Limits, WireReader } from './field.js';
import { fastProblem, fastRead, fastWrite } from './scalars.js';

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
