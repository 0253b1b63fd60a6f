/**
 * A state-sync client's snapshots: the states it holds by tick — its delta bases — with their
 * schema words for a schema-coded room, and how a new snapshot is rebuilt from them: decoded
 * against its base (and the older snapshot its extrapolating columns need), checked against the
 * server's hash, and merged with this client's own local columns. What the session then does with
 * the state (load it, reconcile, draw) is the session's.
 * @module
 */
import { fnv1a64 } from '../../det/hash.js';
import { StateSchema } from '../../sim/state-schema.js';
import { SnapshotRing } from '../history.js';
import { applyDelta } from '../state-sync/delta.js';
import type { ResyncReason, StateSnapshotMessage } from '../state-sync/messages.js';
import { decodeSchemaDelta } from '../state-sync/schema-codec.js';
import { ProtocolError } from '../wire/error.js';

/** A rebuilt snapshot's state (and words), or why it cannot be used. */
export type Rebuilt =
  | { ok: true; state: Uint8Array; words: Uint8Array | undefined }
  | { ok: false; reason: ResyncReason; message: string };

const WRONG_HASH = (tick: number): string =>
  `the state rebuilt for tick ${tick} does not have the server's hash (a damaged delta, or the wrong base)`;

/** The snapshots a client holds, by tick, and the rebuilding of the next one. */
export class SnapshotBases {
  private readonly states: SnapshotRing;
  private readonly words: SnapshotRing;

  constructor(history: number) {
    this.states = new SnapshotRing(history);
    this.words = new SnapshotRing(history);
  }

  /** The state held for `tick`, if any. */
  state(tick: number): Uint8Array | undefined {
    return this.states.get(tick);
  }

  /** Keep a snapshot that loaded: its state and (schema codec) its words. */
  put(tick: number, state: Uint8Array, words: Uint8Array | undefined): void {
    this.states.put(tick, state);
    if (words !== undefined) this.words.put(tick, words);
  }

  /**
   * The state snapshot `m` makes of the bases held here. `schema` is the game's (required for a
   * schema-coded snapshot), `own` this client's state now (its local columns go into a schema-coded
   * one). Never throws for bad bytes: they come back as a resync reason.
   */
  rebuild(
    m: StateSnapshotMessage,
    schema: StateSchema | undefined,
    tickRate: number,
    own: () => Uint8Array,
  ): Rebuilt {
    if (m.codec === 'schema') return this.rebuildWords(m, schema!, tickRate, own);
    let state: Uint8Array;
    if (m.base < 0) {
      state = m.payload;
    } else {
      const base = this.states.get(m.base);
      if (base === undefined) return noBase(m.base, 'apply a delta to');
      try {
        state = applyDelta(base, m.payload, m.size);
      } catch (e) {
        if (!(e instanceof ProtocolError)) throw e;
        return { ok: false, reason: 'bad-delta', message: e.message };
      }
    }
    if (fnv1a64(state) !== m.hash) {
      return { ok: false, reason: 'hash-mismatch', message: WRONG_HASH(m.tick) };
    }
    return { ok: true, state, words: undefined };
  }

  private rebuildWords(
    m: StateSnapshotMessage,
    schema: StateSchema,
    tickRate: number,
    own: () => Uint8Array,
  ): Rebuilt {
    const base = m.base >= 0 ? this.words.get(m.base) : undefined;
    if (m.base >= 0 && base === undefined) return noBase(m.base, 'apply a delta to');
    const older = m.older >= 0 ? this.words.get(m.older) : undefined;
    if (m.older >= 0 && older === undefined) return noBase(m.older, 'extrapolate from');
    let decoded: Int32Array;
    try {
      decoded = decodeSchemaDelta(
        schema,
        base && wordsOf(base),
        m.payload,
        Math.min(schema.maxWords, m.size >> 2),
        {
          ticks: base ? m.tick - m.base : 0,
          tickRate,
          older: older && wordsOf(older),
          olderTicks: older ? m.base - m.older : 0,
        },
      );
    } catch (e) {
      if (!(e instanceof ProtocolError)) throw e;
      return { ok: false, reason: 'bad-delta', message: e.message };
    }
    const words = StateSchema.bytesOf(decoded);
    if (words.length !== m.size || fnv1a64(words) !== m.hash) {
      return { ok: false, reason: 'hash-mismatch', message: WRONG_HASH(m.tick) };
    }
    try {
      // Local columns (not sent) come from this client's own world.
      return { ok: true, state: schema.merge(own(), decoded), words };
    } catch (e) {
      if (!(e instanceof RangeError)) throw e;
      return {
        ok: false,
        reason: 'unloadable',
        message: `the state does not fit the schema: ${e.message}`,
      };
    }
  }
}

function noBase(tick: number, what: string): Rebuilt {
  return { ok: false, reason: 'no-base', message: `no snapshot of tick ${tick} here to ${what}` };
}

/** Schema words stored as bytes, as words again. */
function wordsOf(bytes: Uint8Array): Int32Array {
  return new Int32Array(bytes.buffer, bytes.byteOffset, bytes.length >> 2);
}
