/**
 * How a state-sync room turns its world into snapshot payloads: the bytes or schema words of each
 * view, the server's own world snapped to what the schema sends, and each member's payload —
 * whole, a byte delta, a schema delta, or one held to a byte budget — shared by the members that
 * see the same state and acknowledged the same base. The room decides when and to whom; this
 * decides what.
 * @module
 */
import { ByteWriter } from '../../det/bytes.js';
import { fnv1a64 } from '../../det/hash.js';
import type { AnyGameDefinition } from '../../sim/game.js';
import type { Simulation } from '../../sim/simulation.js';
import { StateSchema, type QuantiseReport } from '../../sim/state-schema.js';
import type { SnapshotRing } from '../history.js';
import { encodeDelta } from './delta.js';
import type { PriorityAccumulator } from './priority.js';
import { BitWriter, encodeSchemaDelta, type Elapsed } from './schema-codec.js';

/** What one snapshot tick computes once and shares among members: views, words, hashes, deltas. */
export interface SnapshotRound {
  /** By view key (a slot, or -2 for the whole state): its bytes. */
  views: Map<number, Uint8Array>;
  /** Schema codec: by view, its words (as bytes). */
  words: Map<Uint8Array, Uint8Array>;
  hashes: Map<Uint8Array, bigint>;
  /** By state, then by base, then by the older snapshot: the delta's bytes. */
  deltas: Map<Uint8Array, Map<Uint8Array, Map<Uint8Array, Uint8Array>>>;
}

/** The view key of the whole state (no `view` function). */
export const WHOLE_VIEW = -2;

/** What a member is sent, and what it will hold. */
export interface CodedSnapshot {
  /** The state (bytes or words) the member will hold: its next base. */
  state: Uint8Array;
  hash: bigint;
  payload: Uint8Array;
  /** Rows left out by the byte budget. */
  deferred: number;
}

/** Counters the coder adds to (the room's stats). */
export interface CoderStats {
  quantisationError: number;
  clampedValues: number;
  deferredRows: number;
}

/** A room's snapshot coding. */
export class SnapshotCoder {
  private readonly writer = new ByteWriter(4096);
  private readonly bits = new BitWriter();

  constructor(
    /** The game's schema when snapshots are schema-coded, else undefined (byte deltas). */
    readonly schema: StateSchema | undefined,
    private readonly tickRate: number,
    /** Payload bytes a member's snapshot may take (schema codec), Infinity for no budget. */
    private readonly maxSnapshotBytes: number,
    private readonly stats: CoderStats,
  ) {}

  newRound(): SnapshotRound {
    return { views: new Map(), words: new Map(), hashes: new Map(), deltas: new Map() };
  }

  /**
   * Schema codec: set `sim` to what is sent — every quantised number to its multiple of the
   * precision — so clients that load a snapshot start from the server's state exactly. With
   * `whole` (no view function) the round gets the snapped state and its words, so nothing is saved
   * or quantised twice.
   */
  snap(sim: Simulation<unknown>, round: SnapshotRound, whole: boolean): void {
    const schema = this.schema;
    if (schema === undefined) return;
    const own = sim.save();
    const report: QuantiseReport = { maxError: 0, clamped: 0 };
    const words = schema.quantise(own, report);
    const snapped = schema.merge(own, words);
    sim.load(snapped);
    if (whole) {
      round.views.set(WHOLE_VIEW, snapped);
      round.words.set(snapped, StateSchema.bytesOf(words));
    }
    if (report.maxError > this.stats.quantisationError) {
      this.stats.quantisationError = report.maxError;
    }
    this.stats.clampedValues += report.clamped;
  }

  /** Whether the schema has columns that `extrapolate` (then a delta wants an older snapshot too). */
  get extrapolates(): boolean {
    return this.schema?.sent.some((c) => c.extrapolate) === true;
  }

  /**
   * What member `m` is sent for `view` at `tick` against its base of `baseTick` (none: a whole
   * snapshot) and the older snapshot of `olderTick` (-1: none), and what it will hold.
   */
  code(
    m: { priority: PriorityAccumulator; sent: SnapshotRing },
    view: Uint8Array,
    tick: number,
    baseTick: number,
    olderTick: number,
    round: SnapshotRound,
  ): CodedSnapshot {
    const schema = this.schema;
    const base = baseTick >= 0 ? m.sent.get(baseTick) : undefined;
    const older = base && olderTick >= 0 ? m.sent.get(olderTick) : undefined;
    let state = this.wire(view, round);
    const elapsed: Elapsed = {
      ticks: base ? tick - baseTick : 0,
      tickRate: this.tickRate,
      older: older && wordsOf(older),
      olderTicks: older ? baseTick - olderTick : 0,
    };
    let payload: Uint8Array | undefined;
    let deferred = 0;
    if (schema && base && this.maxSnapshotBytes !== Infinity) {
      // Within the member's byte budget: what it will hold is its own.
      const l = m.priority.limit(
        schema,
        wordsOf(base),
        wordsOf(state),
        elapsed,
        this.maxSnapshotBytes,
        tick,
        baseTick,
      );
      if (l.deferred > 0) {
        state = StateSchema.bytesOf(l.words);
        payload = l.payload;
        deferred = l.deferred;
        this.stats.deferredRows += deferred;
      }
    }
    // Members that see the same state and acknowledged the same base share the work.
    let hash = round.hashes.get(state);
    if (hash === undefined) {
      hash = fnv1a64(state);
      round.hashes.set(state, hash);
    }
    payload ??= base || schema ? this.delta(state, base, older, elapsed, round) : state;
    return { state, hash, payload, deferred };
  }

  /** What is sent for a view: its bytes, or (schema codec) its schema words as bytes. */
  private wire(view: Uint8Array, round: SnapshotRound): Uint8Array {
    const schema = this.schema;
    if (schema === undefined) return view;
    let words = round.words.get(view);
    if (words === undefined) {
      words = StateSchema.bytesOf(schema.quantise(view));
      round.words.set(view, words);
    }
    return words;
  }

  /** The delta from `base` (none: from nothing, schema codec) to `state`, once a round. */
  private delta(
    state: Uint8Array,
    base: Uint8Array | undefined,
    older: Uint8Array | undefined,
    elapsed: Elapsed,
    round: SnapshotRound,
  ): Uint8Array {
    let byBase = round.deltas.get(state);
    if (byBase === undefined) {
      byBase = new Map();
      round.deltas.set(state, byBase);
    }
    let byOlder = byBase.get(base ?? NO_BASE);
    if (byOlder === undefined) {
      byOlder = new Map();
      byBase.set(base ?? NO_BASE, byOlder);
    }
    const key = older ?? NO_BASE;
    let delta = byOlder.get(key);
    if (delta === undefined) {
      if (this.schema) {
        encodeSchemaDelta(
          this.schema,
          base && wordsOf(base),
          wordsOf(state),
          this.bits.reset(),
          elapsed,
        );
        delta = this.bits.finish();
      } else {
        encodeDelta(base!, state, this.writer.reset());
        delta = this.writer.finish();
      }
      byOlder.set(key, delta);
    }
    return delta;
  }
}

/** The key of a full snapshot's payload among a round's deltas. */
const NO_BASE = new Uint8Array(0);

/** Schema words stored as bytes (a view of an Int32Array), as words again. */
function wordsOf(bytes: Uint8Array): Int32Array {
  return new Int32Array(bytes.buffer, bytes.byteOffset, bytes.length >> 2);
}

/** The schema a room of `game` codes snapshots with (`codec` checked), or undefined. */
export function schemaOf(
  game: AnyGameDefinition,
  codec: 'schema' | 'bytes' | undefined,
): StateSchema | undefined {
  if (codec === 'bytes') return undefined;
  if (codec === 'schema' && game.stateSchema === undefined) {
    throw new RangeError(
      `StateSyncRoom: codec 'schema' needs a game with a stateSchema; ${game.id} has none`,
    );
  }
  const given: unknown = codec;
  if (given !== undefined && given !== 'schema') {
    throw new RangeError(
      `StateSyncRoom: codec must be 'schema' or 'bytes', got ${typeof given === 'string' ? given : typeof given}`,
    );
  }
  return game.stateSchema;
}
