/**
 * Naming the bytes of a saved state: field maps, and the first difference between two states.
 *
 * When two engines disagree, the trace says *when* (the first tick whose hash differs); the field
 * map says *what*: the two `save()` byte arrays of that tick are compared byte by byte and the
 * first differing byte is named (`body[17].vy`, `dsin(x[3])`, …) with both values, floats as exact
 * hex floats (`0x1.921fb54442d18p+1`), so a 1-ulp difference is plain to see.
 */

/** How a field is stored (little-endian, as `ByteWriter` writes it). */
export type StateFieldType = 'u8' | 'u16' | 'u32' | 'i32' | 'f64';

/** One field of a saved state. */
export interface StateField {
  /** Byte offset in the state. */
  readonly offset: number;
  readonly type: StateFieldType;
  /** A name a person can find in the code, e.g. `body[17].vy`. */
  readonly name: string;
}

const SIZE: Readonly<Record<StateFieldType, number>> = { u8: 1, u16: 2, u32: 4, i32: 4, f64: 8 };

/** Bytes of one value of `type`. */
export function stateFieldSize(type: StateFieldType): number {
  return SIZE[type];
}

/** Builds a field map in write order, like a `ByteWriter` writes the state. */
export class StateLayout {
  readonly fields: StateField[] = [];
  private at = 0;

  /** Bytes laid out so far. */
  get length(): number {
    return this.at;
  }

  /** One field. */
  add(type: StateFieldType, name: string): this {
    this.fields.push({ offset: this.at, type, name });
    this.at += SIZE[type];
    return this;
  }

  /** `count` fields of one type, named by index. */
  array(type: StateFieldType, count: number, name: (i: number) => string): this {
    for (let i = 0; i < count; i++) this.add(type, name(i));
    return this;
  }

  /** The fields, if they cover exactly `bytes` bytes; otherwise undefined (the layout is stale). */
  covering(byteLength: number): StateField[] | undefined {
    return this.at === byteLength ? this.fields : undefined;
  }
}

/** The field containing byte `offset`, or undefined. `fields` must be in offset order. */
export function stateFieldAt(
  fields: readonly StateField[],
  offset: number,
): StateField | undefined {
  let lo = 0;
  let hi = fields.length - 1;
  while (lo <= hi) {
    const mid = (lo + hi) >>> 1;
    const f = fields[mid]!;
    if (offset < f.offset) hi = mid - 1;
    else if (offset >= f.offset + SIZE[f.type]) lo = mid + 1;
    else return f;
  }
  return undefined;
}

/** Reads a field's value (little-endian); undefined if the bytes are too short. */
export function readStateField(bytes: Uint8Array, field: StateField): number | undefined {
  if (field.offset + SIZE[field.type] > bytes.length) return undefined;
  const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  switch (field.type) {
    case 'u8':
      return v.getUint8(field.offset);
    case 'u16':
      return v.getUint16(field.offset, true);
    case 'u32':
      return v.getUint32(field.offset, true);
    case 'i32':
      return v.getInt32(field.offset, true);
    case 'f64':
      return v.getFloat64(field.offset, true);
  }
}

const bitsView = new DataView(new ArrayBuffer(8));

/**
 * The exact value of a double as a C99 hex float (`%a`): `0x1.921fb54442d18p+1` for π; `-0x0p+0`,
 * `Infinity`, `NaN` (with its bits when they are not the canonical quiet NaN). Two doubles that
 * differ print differently.
 */
export function hexFloat(x: number): string {
  bitsView.setFloat64(0, x);
  const hi = bitsView.getUint32(0);
  const lo = bitsView.getUint32(4);
  const sign = hi >>> 31 ? '-' : '';
  const exp = (hi >>> 20) & 0x7ff;
  const mant = (hi & 0xfffff).toString(16).padStart(5, '0') + lo.toString(16).padStart(8, '0');
  if (exp === 0x7ff) {
    if (mant === '0000000000000') return `${sign}Infinity`;
    return `NaN(0x${hi.toString(16).padStart(8, '0')}${lo.toString(16).padStart(8, '0')})`;
  }
  const digits = mant.replace(/0+$/, '');
  const frac = digits === '' ? '' : `.${digits}`;
  if (exp === 0) {
    return mant === '0000000000000' ? `${sign}0x0p+0` : `${sign}0x0${frac}p-1022`;
  }
  const e = exp - 1023;
  return `${sign}0x1${frac}p${e >= 0 ? '+' : ''}${e}`;
}

/** A field's value for a report: floats as hex float and shortest decimal, integers as both. */
export function formatStateValue(type: StateFieldType, value: number | undefined): string {
  if (value === undefined) return '(missing)';
  if (type === 'f64') return `${hexFloat(value)} (${String(value)})`;
  return `${value} (0x${(value >>> 0).toString(16)})`;
}

/** Where and how two saved states differ. */
export interface StateDiff {
  /** Whether the two byte arrays are identical. */
  readonly equal: boolean;
  /** The first differing byte (or the shorter length, when one is a prefix of the other); -1 if equal. */
  readonly offset: number;
  readonly lengthA: number;
  readonly lengthB: number;
  /** How many bytes differ (over the common length). */
  readonly differingBytes: number;
  /** The field holding the first differing byte, when the scene names its fields. */
  readonly field?: StateField;
  /** Both values of that field (or, without a field map, the doubles at the 8-aligned offset). */
  readonly a?: string;
  readonly b?: string;
  /** The first few differing fields, by name, in offset order. */
  readonly fields: readonly string[];
  /** One line for a report. */
  readonly summary: string;
}

function hexWindow(bytes: Uint8Array, offset: number): string {
  const from = Math.max(0, offset - 4);
  const to = Math.min(bytes.length, offset + 12);
  let s = '';
  for (let i = from; i < to; i++) {
    s +=
      (i === offset ? '[' : '') +
      bytes[i]!.toString(16).padStart(2, '0') +
      (i === offset ? ']' : '');
  }
  return `${from}: ${s}`;
}

/**
 * Compares two saved states of the same scene byte by byte and names the first difference:
 * the field (from `fields`, when given) and both values, else the byte offset, a hex window of
 * both sides and the doubles at the enclosing 8-byte boundary.
 */
export function diffStates(
  a: Uint8Array,
  b: Uint8Array,
  fields?: readonly StateField[],
): StateDiff {
  const n = Math.min(a.length, b.length);
  let first = -1;
  let count = 0;
  const names: string[] = [];
  let lastField: StateField | undefined;
  for (let i = 0; i < n; i++) {
    if (a[i] === b[i]) continue;
    if (first < 0) first = i;
    count++;
    if (fields && names.length < 8) {
      const f = stateFieldAt(fields, i);
      if (f && f !== lastField) {
        names.push(f.name);
        lastField = f;
      }
    }
  }
  if (first < 0 && a.length === b.length) {
    return {
      equal: true,
      offset: -1,
      lengthA: a.length,
      lengthB: b.length,
      differingBytes: 0,
      fields: [],
      summary: 'the states are byte-identical',
    };
  }
  const lengths =
    a.length === b.length
      ? `${a.length} bytes`
      : `lengths differ: ${a.length} vs ${b.length} bytes`;
  if (first < 0) {
    return {
      equal: false,
      offset: n,
      lengthA: a.length,
      lengthB: b.length,
      differingBytes: 0,
      fields: [],
      summary: `${lengths}; the shorter is a prefix of the longer (first extra byte at offset ${n})`,
    };
  }
  const differ = {
    equal: false,
    offset: first,
    lengthA: a.length,
    lengthB: b.length,
    differingBytes: count,
  };
  const field = fields ? stateFieldAt(fields, first) : undefined;
  if (field) {
    const va = formatStateValue(field.type, readStateField(a, field));
    const vb = formatStateValue(field.type, readStateField(b, field));
    return {
      ...differ,
      field,
      a: va,
      b: vb,
      fields: names,
      summary:
        `first difference at byte ${first}: ${field.name} (${field.type} at offset ${field.offset}) ` +
        `${va} vs ${vb}; ${count} bytes differ in ${lengths}` +
        (names.length > 1
          ? `; differing fields: ${names.join(', ')}${names.length === 8 ? ', …' : ''}`
          : ''),
    };
  }
  const aligned = first - (first % 8);
  const guess: StateField = { offset: aligned, type: 'f64', name: `f64 at ${aligned}` };
  const va = formatStateValue('f64', readStateField(a, guess));
  const vb = formatStateValue('f64', readStateField(b, guess));
  return {
    ...differ,
    a: va,
    b: vb,
    fields: [],
    summary:
      `first difference at byte ${first} (no field map): bytes ${hexWindow(a, first)} vs ${hexWindow(b, first)}; ` +
      `as doubles at ${aligned}: ${va} vs ${vb}; ${count} bytes differ in ${lengths}`,
  };
}
