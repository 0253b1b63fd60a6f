/**
 * A state schema: what a game's `save()` bytes are, column by column, and how precisely each
 * number needs to reach a state-sync client. With one, a state-sync room sends each entity's
 * changed fields as small integers instead of the raw bytes (see `net/state-sync/schema-codec.ts`),
 * and snaps its own world to exactly what it sent — so the client's prediction starts from the
 * server's state, bit for bit. Without one, nothing changes: rooms send the bytes as before.
 *
 * The schema describes the layout the game already writes: a list of columns in byte order, each
 * a run of `count` little-endian numbers of one type (a scalar is a column of one). A column
 * names
 * - its **group** — the entity it belongs to: columns of one group have one count, and an entity is
 *   the row `i` of every column of its group (player `i`'s x, y, health …). Change masks are per
 *   row: an entity that did not change costs a bit, or less;
 * - its **precision** (floats only) — the value is sent as a whole multiple of it, within `min` …
 *   `max`, and the server's own state is set to that multiple (snapped) when it sends;
 * - **local** — not sent, not checked: each side keeps its own (a solver's warm-start cache, a
 *   derived index). The client's copy comes from its own prediction.
 *
 * Our own format rather than a general one (protobuf, FlatBuffers) because it must describe the
 * bytes a game already saves, byte for byte, and quantise the same way in every engine.
 * @module
 */

/** A column's number type, little-endian: integers, or IEEE floats. */
export type StateColumnType = 'u8' | 'i8' | 'u16' | 'i16' | 'u32' | 'i32' | 'f32' | 'f64';

/** How many numbers a column holds when an earlier column says so. */
export interface StateColumnCount {
  /** The name of an earlier integer column of one number whose value is the count. */
  of: string;
  /** The count is that value times this (e.g. bytes per wall). Default 1. */
  times?: number;
  /** The most numbers the column may hold: a decoder allocates no more. */
  max: number;
}

/** One column of a {@link StateSchemaDefinition}. */
export interface StateColumn {
  /** A name, unique in the schema (for messages and counts). */
  name: string;
  type: StateColumnType;
  /** Numbers in the column: a constant (default 1), or another column's value. */
  count?: number | StateColumnCount;
  /**
   * The entity the column belongs to; its columns share a count and a change mask per row.
   * Default: the column's own name (a group of one column).
   */
  group?: string;
  /**
   * Floats only: send the value as a whole multiple of this (units of the value), between `min`
   * and `max` (both required). The server's state is snapped to it; a value outside the range is
   * clamped and counted. Without it a float is sent as its exact bits (fine for values that rarely
   * change; costly for ones that move).
   */
  precision?: number;
  min?: number;
  max?: number;
  /**
   * How a quantised value rounds: `'nearest'` (default: error ≤ half a step), or `'away'` from
   * zero (error < one step; a value that is not 0 never becomes 0 — for timers a game checks with
   * `> 0`).
   */
  rounding?: 'nearest' | 'away';
  /**
   * Not sent, not in the hash: each side keeps its own (`true`), or the state a side loads has 0
   * here (`'zero'`: a value the game's step works out afresh before it reads it, such as a
   * velocity steered anew every tick — zero is always a value the game's `load` takes). Default
   * false.
   */
  local?: boolean | 'zero';
  /**
   * A quantised column only: the name of a quantised column of the same group that is this one's
   * rate of change per second (a position's velocity; it may not have a rate itself). The codec
   * then sends the difference from a prediction rather than from the base: over `n` ticks of `Δt`,
   * `base + Δt × (baseRate × (n − 1) + rate × (n + 1)) / 2`, with `rate` the value this snapshot
   * brings — exact for a body under constant acceleration stepped as games step (velocity first,
   * then position: semi-implicit Euler), and over one tick simply `base + rate × Δt`. A body that
   * kept its velocity costs nothing. Default none.
   */
  rate?: string;
  /**
   * A quantised column without a `rate` only: predicted from the two snapshots before this one
   * that both ends hold — `b1 + (b1 − b2) × n1 / n2` (`n1` ticks from `b1` to this snapshot, `n2`
   * from `b2` to `b1`): a position whose velocity is not sent, as Glenn Fiedler's cubes are sent.
   * Default false.
   */
  extrapolate?: boolean;
}

/** What {@link defineStateSchema} takes. */
export interface StateSchemaDefinition {
  /** Every column of the state's bytes, in byte order: together they are the whole state. */
  columns: readonly StateColumn[];
}

/** A group of sent columns (an entity type) as the codec walks it. */
export interface StateGroup {
  readonly name: string;
  /** A constant count, or the index (in {@link StateSchema.sent}) of the column that holds it. */
  readonly count: number | { column: number; times: number; max: number };
  /** Indices into {@link StateSchema.sent}, in order. */
  readonly columns: readonly number[];
  /**
   * The same columns in the order the codec codes them: those without a rate first, then those
   * with one — so a position is predicted from the velocity the snapshot brings, not only the
   * base's.
   */
  readonly codeOrder: readonly number[];
}

/** A sent column as the codec walks it. */
export interface SentColumn {
  readonly name: string;
  /** Words per number: 2 for an exact f64, else 1. */
  readonly lanes: number;
  /** Its group's index in {@link StateSchema.groups}. */
  readonly group: number;
  /** The sent column that is its rate of change per second, or -1 (it has no rate of its own). */
  readonly rate: number;
  /** Its rate column's precision ÷ its own: rate words × this × seconds = its words. */
  readonly rateScale: number;
  /** Predicted from the two snapshots before (see {@link StateColumn.extrapolate}). */
  readonly extrapolate: boolean;
}

/** Where a byte of a state is: see {@link StateSchema.locate}. */
export interface StateLocation {
  /** The column's name. */
  readonly column: string;
  /** The number within the column (the entity's row), from 0. */
  readonly row: number;
  /** Numbers the column holds in this state. */
  readonly count: number;
  readonly type: StateColumnType;
  /** The byte offset of that number in the state. */
  readonly offset: number;
  /** Whether the column is local (not sent by state sync). */
  readonly local: boolean;
}

/** What quantising one state found (for benchmarks and metrics). */
export interface QuantiseReport {
  /**
   * Largest |value − sent value| over the quantised columns, in units of each column's precision
   * (≤ 0.5; < 1 for columns that round away from zero).
   */
  maxError: number;
  /** Values outside their column's range (sent clamped). */
  clamped: number;
}

const SIZES: Readonly<Record<StateColumnType, number>> = {
  u8: 1,
  i8: 1,
  u16: 2,
  i16: 2,
  u32: 4,
  i32: 4,
  f32: 4,
  f64: 8,
};
const INTEGER: ReadonlySet<StateColumnType> = new Set(['u8', 'i8', 'u16', 'i16', 'u32', 'i32']);
const NAME = /^[A-Za-z_][A-Za-z0-9_.]{0,63}$/;
const MAX_COLUMNS = 1024;
const MAX_COUNT = 1 << 20;
/** Largest |word| of a quantised number (2^31 − 1). */
const Q_LIMIT = 2147483647;

interface Column {
  readonly name: string;
  readonly type: StateColumnType;
  readonly size: number;
  readonly count: number | { column: number; times: number; max: number };
  readonly local: boolean;
  /** A local column that a merged state has zeros in. */
  readonly zero: boolean;
  /** Index among the sent columns (-1: local). */
  readonly sent: number;
  readonly precision: number;
  readonly qmin: number;
  readonly qmax: number;
  readonly away: boolean;
  /** Predicted from the two snapshots before (see {@link StateColumn.extrapolate}). */
  readonly extrapolate: boolean;
}

/** A checked {@link StateSchemaDefinition}: the layout, and quantising and merging of states. */
export class StateSchema {
  /** The sent columns, in the order of the words (group by group). */
  readonly sent: readonly SentColumn[];
  /** The groups of sent columns, in the order the codec walks them. */
  readonly groups: readonly StateGroup[];
  /** The most words a state can have (bounds a decoder). */
  readonly maxWords: number;
  private readonly columns: readonly Column[];
  /** Byte-order column index of each sent column. */
  private readonly sentToColumn: readonly number[];
  /** The one layout of a schema whose counts are all constants. */
  private readonly fixed: Layout | undefined;

  /** Use {@link defineStateSchema}. */
  constructor(definition: StateSchemaDefinition) {
    const bad = (why: string): never => {
      throw new RangeError(`defineStateSchema: ${why}`);
    };
    const list = (definition as { columns?: unknown }).columns;
    if (!Array.isArray(list) || list.length === 0 || list.length > MAX_COLUMNS) {
      throw new RangeError(
        `defineStateSchema: columns must be an array of 1 to ${MAX_COLUMNS} columns`,
      );
    }
    const byName = new Map<string, number>();
    const columns: Column[] = [];
    const groupOf: string[] = [];
    for (const [i, item] of (list as unknown[]).entries()) {
      if (typeof item !== 'object' || item === null) bad(`column ${i} is not an object`);
      const c = item as StateColumn;
      const named: unknown = c.name;
      const at = `column ${i} (${typeof named === 'string' ? named : '?'})`;
      if (typeof named !== 'string' || !NAME.test(named)) {
        bad(`${at}: name must be 1-64 of A-Z a-z 0-9 _ . (not starting with a digit or .)`);
      }
      if (byName.has(c.name)) bad(`${at}: the name is used twice`);
      const size = (SIZES as Partial<Record<string, number>>)[c.type];
      if (size === undefined) bad(`${at}: type must be one of ${Object.keys(SIZES).join(', ')}`);
      const localValue: unknown = c.local;
      if (localValue !== undefined && typeof localValue !== 'boolean' && localValue !== 'zero') {
        bad(`${at}: local must be true, false or 'zero'`);
      }
      const local = localValue === true || localValue === 'zero';
      let count: Column['count'] = 1;
      if (typeof c.count === 'number') {
        if (!Number.isInteger(c.count) || c.count < 0 || c.count > MAX_COUNT) {
          bad(`${at}: count must be an integer from 0 to ${MAX_COUNT}`);
        }
        count = c.count;
      } else if (c.count !== undefined) {
        const ref = byName.get(c.count.of);
        const times = c.count.times ?? 1;
        if (ref === undefined) bad(`${at}: count.of names no earlier column ("${c.count.of}")`);
        const src = columns[ref!]!;
        if (!INTEGER.has(src.type) || src.count !== 1) {
          bad(`${at}: count.of must name an integer column of one number`);
        }
        if (src.local && !local) bad(`${at}: a sent column cannot take its count from a local one`);
        if (!Number.isInteger(times) || times < 1 || times > 4096) {
          bad(`${at}: count.times must be an integer from 1 to 4096`);
        }
        if (!Number.isInteger(c.count.max) || c.count.max < 0 || c.count.max > MAX_COUNT) {
          bad(`${at}: count.max must be an integer from 0 to ${MAX_COUNT}`);
        }
        count = { column: ref!, times, max: c.count.max };
      }
      let precision = 0;
      let qmin = 0;
      let qmax = 0;
      if (c.precision !== undefined) {
        if (c.type !== 'f32' && c.type !== 'f64') bad(`${at}: precision is for f32 and f64 only`);
        if (!(typeof c.precision === 'number' && c.precision > 0 && Number.isFinite(c.precision))) {
          bad(`${at}: precision must be a finite number > 0`);
        }
        if (!(Number.isFinite(c.min) && Number.isFinite(c.max) && c.min! < c.max!)) {
          bad(`${at}: a quantised column needs finite min < max`);
        }
        precision = c.precision;
        qmin = Math.round(c.min! / precision);
        qmax = Math.round(c.max! / precision);
        if (qmin < -Q_LIMIT || qmax > Q_LIMIT) {
          bad(
            `${at}: (max or min) / precision must be within ±2^31: a coarser precision, or a smaller range`,
          );
        }
      } else if (c.min !== undefined || c.max !== undefined || c.rounding !== undefined) {
        bad(`${at}: min, max and rounding go with precision`);
      }
      const extrapolate: unknown = c.extrapolate;
      if (extrapolate !== undefined && typeof extrapolate !== 'boolean') {
        bad(`${at}: extrapolate must be true or false`);
      }
      if (extrapolate === true && (precision === 0 || c.rate !== undefined)) {
        bad(`${at}: extrapolate is for quantised columns without a rate`);
      }
      const rounding: unknown = c.rounding;
      if (rounding !== undefined && rounding !== 'nearest' && rounding !== 'away') {
        bad(`${at}: rounding must be 'nearest' or 'away'`);
      }
      byName.set(c.name, i);
      const group: unknown = c.group ?? c.name;
      if (typeof group !== 'string' || group.length === 0) bad(`${at}: group must be a name`);
      groupOf.push(group as string);
      columns.push({
        name: c.name,
        type: c.type,
        size: size!,
        count,
        local,
        zero: localValue === 'zero',
        sent: -1,
        precision,
        qmin,
        qmax,
        away: c.rounding === 'away',
        extrapolate: extrapolate === true,
      });
    }
    // Groups of sent columns, in order of first appearance; a group is all sent or all local.
    const groupIndex = new Map<string, number>();
    const groupColumns: number[][] = [];
    const groupLocal = new Map<string, boolean>();
    for (const [i, c] of columns.entries()) {
      const g = groupOf[i]!;
      const was = groupLocal.get(g);
      if (was !== undefined && was !== c.local) {
        bad(`group "${g}" mixes local and sent columns (column ${c.name})`);
      }
      groupLocal.set(g, c.local);
      if (c.local) continue;
      let gi = groupIndex.get(g);
      if (gi === undefined) {
        gi = groupColumns.length;
        groupIndex.set(g, gi);
        groupColumns.push([]);
      }
      const first = groupColumns[gi]![0];
      if (first !== undefined && !sameCount(columns[first]!.count, c.count)) {
        bad(`group "${g}": column ${c.name} has another count than ${columns[first]!.name}`);
      }
      groupColumns[gi]!.push(i);
    }
    // Sent columns are numbered group by group (the order of the words).
    const sentToColumn: number[] = [];
    const sent: SentColumn[] = [];
    const patched = columns.slice();
    for (const [gi, cols] of groupColumns.entries()) {
      for (const ci of cols) {
        const c = columns[ci]!;
        patched[ci] = { ...c, sent: sent.length };
        sentToColumn.push(ci);
        sent.push({
          name: c.name,
          lanes: c.type === 'f64' && c.precision === 0 ? 2 : 1,
          group: gi,
          rate: -1,
          rateScale: 0,
          extrapolate: c.extrapolate,
        });
      }
    }
    // Rates: a quantised column of the same group.
    for (const [i, c] of (list as StateColumn[]).entries()) {
      if (c.rate === undefined) continue;
      const own = patched[i]!;
      const ri = byName.get(c.rate);
      const rc = ri === undefined ? undefined : patched[ri];
      if (own.precision === 0) bad(`column ${c.name}: rate is for quantised columns`);
      if (rc === undefined || rc.precision === 0 || rc.local || groupOf[ri!] !== groupOf[i]) {
        bad(`column ${c.name}: rate must name a quantised column of its group, got "${c.rate}"`);
      }
      // One level: the codec codes rates before the columns that move by them.
      if ((list as StateColumn[])[ri!]!.rate !== undefined) {
        bad(`column ${c.name}: its rate ${c.rate} has a rate of its own (one level only)`);
      }
      sent[own.sent] = {
        ...sent[own.sent]!,
        rate: rc!.sent,
        rateScale: rc!.precision / own.precision,
      };
    }
    const groups: StateGroup[] = [];
    let maxWords = 0;
    for (const [gi, cols] of groupColumns.entries()) {
      const c = patched[cols[0]!]!;
      let count: StateGroup['count'];
      if (typeof c.count === 'number') {
        count = c.count;
      } else {
        const src = patched[c.count.column]!;
        // The count's column is sent earlier in the words than this group (it precedes in bytes,
        // and a group of one scalar column is numbered at its first appearance).
        if (src.sent < 0 || sent[src.sent]!.group >= gi) {
          bad(
            `group "${[...groupIndex.keys()][gi]!}": its count column ${src.name} must be sent in an earlier group`,
          );
        }
        count = { column: src.sent, times: c.count.times, max: c.count.max };
      }
      const n = typeof count === 'number' ? count : count.max * count.times;
      for (const ci of cols) maxWords += n * sent[patched[ci]!.sent]!.lanes;
      const columns = cols.map((ci) => patched[ci]!.sent);
      groups.push({
        name: [...groupIndex.keys()][gi]!,
        count,
        columns,
        codeOrder: [
          ...columns.filter((s) => sent[s]!.rate < 0),
          ...columns.filter((s) => sent[s]!.rate >= 0),
        ],
      });
    }
    if (maxWords > MAX_COUNT * 4)
      bad(`the state can have ${maxWords} words, at most ${MAX_COUNT * 4}`);
    this.columns = patched;
    this.sent = sent;
    this.groups = groups;
    this.maxWords = maxWords;
    this.sentToColumn = sentToColumn;
    if (patched.every((c) => typeof c.count === 'number')) {
      let bytes = 0;
      for (const c of patched) bytes += (c.count as number) * c.size;
      this.fixed = this.layoutOf(new Uint8Array(bytes), undefined);
    }
  }

  /**
   * The words a state-sync room sends for `state` (the game's `save()` bytes): every sent
   * column's numbers as 32-bit words, group by group — integers as they are, quantised floats as
   * their multiple of the precision, other floats as their bits. Throws a RangeError when the bytes
   * do not have the schema's layout.
   */
  quantise(state: Uint8Array, report?: QuantiseReport): Int32Array {
    const layout = this.layout(state, undefined);
    const out = new Int32Array(layout.words);
    const view = new DataView(state.buffer, state.byteOffset, state.byteLength);
    for (const [ci, c] of this.columns.entries()) {
      if (c.local) continue;
      const n = layout.counts[ci]!;
      let at = layout.offsets[ci]!;
      let w = layout.wordStart[c.sent]!;
      for (let i = 0; i < n; i++, at += c.size) {
        if (c.precision > 0) {
          const v = c.type === 'f64' ? view.getFloat64(at, true) : view.getFloat32(at, true);
          const r = v / c.precision;
          let q = !c.away ? Math.round(r) : r > 0 ? Math.ceil(r) : r < 0 ? -Math.ceil(-r) : 0;
          if (!(q >= c.qmin && q <= c.qmax)) {
            q = q > c.qmax ? c.qmax : c.qmin; // NaN too: to min
            if (report) report.clamped++;
          } else if (report) {
            const e = Math.abs(v - q * c.precision) / c.precision;
            if (e > report.maxError) report.maxError = e;
          }
          out[w++] = q;
        } else if (c.type === 'f64') {
          out[w++] = view.getInt32(at, true);
          out[w++] = view.getInt32(at + 4, true);
        } else {
          out[w++] = readInt(view, at, c.type);
        }
      }
    }
    return out;
  }

  /**
   * The state whose sent columns are `words` and whose local columns are `own`'s (a state of
   * the same game; rows a count adds are zero): what a client loads, and what the server snaps
   * to. Throws a RangeError when `own` does not have the schema's layout or `words` is not a
   * state's words.
   */
  merge(own: Uint8Array, words: Int32Array): Uint8Array {
    const mine = this.layout(own, undefined);
    const theirs = this.layout(undefined, words);
    // The merged layout: sent columns' counts from the words, local ones from `own` unless a sent
    // count governs them.
    const counts = this.columns.map((c, ci) => {
      if (typeof c.count === 'number') return c.count;
      const src = this.columns[c.count.column]!;
      if (src.local) return mine.counts[ci]!;
      return words[theirs.wordStart[src.sent]!]! * c.count.times;
    });
    let size = 0;
    for (const [ci, c] of this.columns.entries()) size += counts[ci]! * c.size;
    const out = new Uint8Array(size);
    const view = new DataView(out.buffer);
    let at = 0;
    for (const [ci, c] of this.columns.entries()) {
      const n = counts[ci]!;
      if (c.zero) {
        // Left as the zeros the buffer was made with.
      } else if (c.local) {
        const from = mine.offsets[ci]!;
        const bytes = Math.min(n, mine.counts[ci]!) * c.size;
        out.set(own.subarray(from, from + bytes), at);
      } else {
        let w = theirs.wordStart[c.sent]!;
        for (let i = 0, a = at; i < n; i++, a += c.size) {
          if (c.precision > 0) {
            const v = words[w++]! * c.precision;
            if (c.type === 'f64') view.setFloat64(a, v, true);
            else view.setFloat32(a, v, true);
          } else if (c.type === 'f64') {
            view.setInt32(a, words[w++]!, true);
            view.setInt32(a + 4, words[w++]!, true);
          } else {
            writeInt(view, a, c.type, words[w++]!);
          }
        }
      }
      at += n * c.size;
    }
    return out;
  }

  /**
   * Which column, and which row of it, byte `offset` of `state` (the game's `save()` bytes) is in:
   * to name the field where two states first differ. Undefined when the bytes do not have the
   * schema's layout or the offset is past their end.
   */
  locate(state: Uint8Array, offset: number): StateLocation | undefined {
    let layout: Layout;
    try {
      layout = this.layout(state, undefined);
    } catch {
      return undefined;
    }
    for (const [ci, c] of this.columns.entries()) {
      const start = layout.offsets[ci]!;
      const count = layout.counts[ci]!;
      if (offset >= start && offset < start + count * c.size) {
        const row = Math.floor((offset - start) / c.size);
        return {
          column: c.name,
          row,
          count,
          type: c.type,
          offset: start + row * c.size,
          local: c.local,
        };
      }
    }
    return undefined;
  }

  /** The byte length of the words of a state (for the wire's `size`). */
  static bytesOf(words: Int32Array): Uint8Array {
    return new Uint8Array(words.buffer, words.byteOffset, words.byteLength);
  }

  /**
   * Where each column is: from a state's bytes (byte offsets and counts), or from its words
   * (counts and word starts). Checks sizes and counts; RangeError on a mismatch.
   */
  private layout(state: Uint8Array | undefined, words: Int32Array | undefined): Layout {
    // A schema without counts taken from the state has one layout: work it out once.
    if (this.fixed !== undefined) {
      const f = this.fixed;
      if (state && state.length !== f.bytes) {
        throw new RangeError(
          `state schema: the state has ${state.length} bytes, the schema describes ${f.bytes}`,
        );
      }
      if (words && words.length !== f.words) {
        throw new RangeError(
          `state schema: ${words.length} words, the layout they describe has ${f.words}`,
        );
      }
      return f;
    }
    return this.layoutOf(state, words);
  }

  private layoutOf(state: Uint8Array | undefined, words: Int32Array | undefined): Layout {
    const cols = this.columns;
    const counts: number[] = new Array<number>(cols.length).fill(0);
    const offsets: number[] = new Array<number>(cols.length).fill(0);
    const wordStart: number[] = new Array<number>(this.sent.length).fill(0);
    const view = state ? new DataView(state.buffer, state.byteOffset, state.byteLength) : undefined;
    // Byte offsets (from the bytes), in byte order.
    let at = 0;
    for (const [ci, c] of cols.entries()) {
      let n = 0;
      if (typeof c.count === 'number') {
        n = c.count;
      } else if (view) {
        const src = cols[c.count.column]!;
        const v = readInt(view, offsets[c.count.column]!, src.type);
        n = v * c.count.times;
        if (!(v >= 0 && n <= c.count.max)) {
          throw new RangeError(
            `state schema: column ${c.name} would hold ${n} numbers (from ${src.name} = ${v}), at most ${c.count.max}`,
          );
        }
      }
      counts[ci] = n;
      if (view) {
        offsets[ci] = at;
        at += n * c.size;
        if (at > state!.length) {
          throw new RangeError(
            `state schema: the state's ${state!.length} bytes end inside column ${c.name} (it needs ${at})`,
          );
        }
      }
    }
    if (view && at !== state!.length) {
      throw new RangeError(
        `state schema: the state has ${state!.length - at} bytes after its last column ${cols[cols.length - 1]!.name}`,
      );
    }
    // Word starts, group by group. With words, counts of sent columns come from the words, read
    // group by group (a count's column is in an earlier group, so its word is placed).
    let w = 0;
    for (const g of this.groups) {
      let n: number;
      if (typeof g.count === 'number') {
        n = g.count;
      } else {
        const v = view
          ? counts[this.sentToColumn[g.columns[0]!]!]! / g.count.times
          : words![wordStart[g.count.column]!]!;
        n = v * g.count.times;
        if (!(v >= 0 && n <= g.count.max)) {
          throw new RangeError(
            `state schema: group ${g.name} would hold ${n} rows, at most ${g.count.max}`,
          );
        }
      }
      for (const s of g.columns) {
        wordStart[s] = w;
        counts[this.sentToColumn[s]!] = n;
        w += n * this.sent[s]!.lanes;
      }
    }
    if (words && words.length !== w) {
      throw new RangeError(
        `state schema: ${words.length} words, the layout they describe has ${w}`,
      );
    }
    return { counts, offsets, wordStart, words: w, bytes: at };
  }
}

/** Where each column is in a state's bytes and words. */
interface Layout {
  counts: number[];
  offsets: number[];
  wordStart: number[];
  /** Words of the state, and bytes (from a state's bytes; 0 from words). */
  words: number;
  bytes: number;
}

function sameCount(a: Column['count'], b: Column['count']): boolean {
  if (typeof a === 'number' || typeof b === 'number') return a === b;
  return a.column === b.column && a.times === b.times && a.max === b.max;
}

/** The number of `type` at byte `at` of `view`, little-endian, as a game's `save()` wrote it. */
export function readStateValue(view: DataView, at: number, type: StateColumnType): number {
  switch (type) {
    case 'u8':
      return view.getUint8(at);
    case 'i8':
      return view.getInt8(at);
    case 'u16':
      return view.getUint16(at, true);
    case 'i16':
      return view.getInt16(at, true);
    case 'u32':
      return view.getUint32(at, true);
    case 'i32':
      return view.getInt32(at, true);
    case 'f32':
      return view.getFloat32(at, true);
    default:
      return view.getFloat64(at, true);
  }
}

/** An integer column's value, or an f32's bits (a word of the wire). */
function readInt(view: DataView, at: number, type: StateColumnType): number {
  return type === 'f32' || type === 'f64'
    ? view.getInt32(at, true)
    : readStateValue(view, at, type);
}

function writeInt(view: DataView, at: number, type: StateColumnType, v: number): void {
  switch (type) {
    case 'u8':
    case 'i8':
      view.setUint8(at, v & 0xff);
      return;
    case 'u16':
    case 'i16':
      view.setUint16(at, v & 0xffff, true);
      return;
    default:
      view.setInt32(at, v, true);
  }
}

/**
 * Checks a state schema and returns it. Throws a RangeError naming the first column that is
 * wrong. Whether it matches the game's bytes is checked when a room first uses it (and in your
 * tests: `schema.merge(sim.save(), schema.quantise(sim.save()))` must load).
 */
export function defineStateSchema(definition: StateSchemaDefinition): StateSchema {
  return new StateSchema(definition);
}
