/**
 * A per-client byte budget for schema-coded snapshots, with Glenn Fiedler's priority accumulator
 * (*State Synchronization*): when a snapshot's delta would be larger than the budget, only some
 * rows of the largest group (the entities: bodies, enemies) go in it. Every other changed row is
 * sent as the client will predict it anyway — its value in the base moved by its rate (dead
 * reckoning) — which costs nothing. Rows of the other groups (the head, scores, players) always
 * go. The client holds what it was sent, so its hash check and its next base agree with the
 * server's copy of it.
 *
 * Which rows: over datagrams a delta is against the snapshot the client acknowledged, so a row
 * refreshed after that base goes again in every snapshot until the client acknowledges one that
 * has it (left out, it would fall back to the base's prediction); over a reliable transport the
 * base is the snapshot sent before, and nothing is in flight. Then the highest priorities: a changed row's
 * priority grows every snapshot by one and by how far the client's prediction of it is off, in
 * steps of its columns, and drops to 0 when it is sent — so the rows whose error grows fastest go
 * first, and none waits for ever.
 * @module
 */
import type { StateSchema } from '../../sim/state-schema.js';
import {
  BitWriter,
  encodeSchemaDelta,
  predictedWords,
  starts,
  type Elapsed,
} from './schema-codec.js';

/** What {@link PriorityAccumulator.limit} decided. */
export interface Limited {
  /** The words the client will hold (what is hashed and kept as its base). */
  words: Int32Array;
  /** Their delta's bits. */
  payload: Uint8Array;
  /** Changed rows left out (sent as predicted). */
  deferred: number;
}

/** One client's priorities: how long each row of the largest group has waited. */
export class PriorityAccumulator {
  private waited = new Float64Array(0);
  /**
   * Per row: the tick of the snapshot that refreshed it by priority (-1: none). Until the client
   * acknowledges that snapshot or a later one, the row is in flight.
   */
  private sentAt = new Float64Array(0);
  private readonly bits = new BitWriter();

  /**
   * The words to send for `next` against `base` within `budget` bytes of payload (or `next`
   * itself when its delta fits). Without a base (a full snapshot) nothing is left out.
   */
  limit(
    schema: StateSchema,
    base: Int32Array | undefined,
    next: Int32Array,
    elapsed: Elapsed,
    budget: number,
    tick: number,
    baseTick: number,
  ): Limited {
    const encode = (words: Int32Array): Uint8Array => {
      encodeSchemaDelta(schema, base, words, this.bits.reset(), elapsed);
      return this.bits.finish();
    };
    const whole = encode(next);
    if (whole.length <= budget || base === undefined) {
      // Every row goes: each is now as good as sent.
      this.sentAt.fill(tick);
      return { words: next, payload: whole, deferred: 0 };
    }
    // The largest group: where the entities are.
    let gi = 0;
    const n = starts(schema, next);
    for (let g = 1; g < schema.groups.length; g++) if (n.rows[g]! > n.rows[gi]!) gi = g;
    const group = schema.groups[gi]!;
    const rows = n.rows[gi]!;
    // What the client holds of a row left out: the base moved by the base's rates (the row brings
    // no new rate) — `next` with every rate column (a column others move by) as in the base.
    const rateColumns = new Set<number>();
    for (const s of group.columns)
      if (schema.sent[s]!.rate >= 0) rateColumns.add(schema.sent[s]!.rate);
    const b = starts(schema, base);
    const baseRates = next.slice();
    for (const s of rateColumns) {
      const kept = Math.min(rows, b.rows[gi]!);
      baseRates.set(base.subarray(b.col[s], b.col[s]! + kept), n.col[s]);
    }
    const expected = predictedWords(schema, base, baseRates, elapsed);
    if (this.waited.length !== rows) {
      this.waited = new Float64Array(rows);
      this.sentAt = new Float64Array(rows).fill(-1);
    }
    // A changed row's priority grows by one a snapshot, plus how far the client's prediction of it
    // is off (in steps of its columns, each capped).
    const changed: number[] = [];
    for (let r = 0; r < rows; r++) {
      let off = 0;
      for (const s of group.columns) {
        const lanes = schema.sent[s]!.lanes;
        const at = n.col[s]! + r * lanes;
        for (let l = 0; l < lanes; l++) {
          if (next[at + l] !== expected[at + l]) {
            off += lanes === 1 ? Math.min(1e6, Math.abs(next[at + l]! - expected[at + l]!)) : 1;
          }
        }
      }
      if (off > 0) {
        changed.push(r);
        this.waited[r]! += 1 + off;
      }
    }
    // In flight (sent after the base) first, then the highest priority; ties by row.
    const flying = (r: number): number => (this.sentAt[r]! > baseTick ? 1 : 0);
    changed.sort((a, b) => flying(b) - flying(a) || this.waited[b]! - this.waited[a]! || a - b);
    const build = (keep: number): Int32Array => {
      const words = next.slice();
      for (let i = keep; i < changed.length; i++) {
        const r = changed[i]!;
        for (const s of group.columns) {
          const lanes = schema.sent[s]!.lanes;
          const at = n.col[s]! + r * lanes;
          for (let l = 0; l < lanes; l++) words[at + l] = expected[at + l]!;
        }
      }
      return words;
    };
    // What the rest costs with no row of the group in it, and a row on average.
    const floor = encode(build(0)).length;
    const perRow = (whole.length - floor) / Math.max(1, changed.length);
    let keep = Math.max(0, Math.min(changed.length, Math.floor((budget - floor) / perRow)));
    let words = build(keep);
    let payload = encode(words);
    // The estimate is an average: shrink until it fits (the rows in flight first are kept longest).
    for (let tries = 0; payload.length > budget && keep > 0 && tries < 8; tries++) {
      const scaled = Math.floor((keep * (budget - floor)) / (payload.length - floor));
      keep = Math.max(0, Math.min(keep - 1, scaled));
      words = build(keep);
      payload = encode(words);
    }
    for (let i = 0; i < keep; i++) {
      const r = changed[i]!;
      // A resend of a row in flight keeps its refresh's tick: acknowledged, it is in the base.
      if (!(this.sentAt[r]! > baseTick)) this.sentAt[r] = tick;
      this.waited[r] = 0;
    }
    return { words, payload, deferred: changed.length - keep };
  }
}
