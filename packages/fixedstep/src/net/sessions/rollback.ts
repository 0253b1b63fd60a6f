/**
 * Rollback over a relay: predict the other players' inputs and run ahead; when the confirmed
 * inputs differ from a prediction, load the first wrong tick's state and resimulate to the
 * present.
 * @module
 */
import type { ButtonInput } from '../../sim/buttons.js';
import { LeadTicks } from '../clock-sync.js';
import { diffSnapshots } from '../forensics.js';
import { InputRing, type SavesInto } from '../history.js';
import { NetSession } from './base.js';
import type { NetSessionOptions } from './relay-options.js';

/** What a rollback changed at the current tick: for the renderer's smoothing. */
export interface Correction {
  /** The tick whose state was corrected (the current tick when the rollback ran). */
  tick: number;
  /** Ticks resimulated: from the first mispredicted tick to the current one. */
  depth: number;
  /** Bytes of the current state that the correction changed (0: the prediction was right in effect). */
  bytesChanged: number;
  /** The predicted state at `tick` and the corrected one (`save()` bytes; do not modify). */
  before: Uint8Array;
  after: Uint8Array;
}

/** Options of a {@link RollbackSession}. */
export interface RollbackSessionOptions<I = ButtonInput> extends NetSessionOptions<I> {
  /** Local input delay in ticks (fewer, shallower rollbacks for a little lag). Default 1. */
  inputDelay?: number;
  /**
   * The most ticks the simulation may run ahead of the confirmed inputs (the prediction window).
   * Beyond it the session stalls. Default 30 (0.5 s at 60 Hz).
   */
  maxPrediction?: number;
  /**
   * How far ahead of the server clock to simulate, in ticks, so local inputs reach the server
   * before their tick closes. `'auto'` (default): half a high RTT plus a tick, minus the input
   * delay; it moves by one tick at a time, every 250 ms.
   */
  lead?: number | 'auto';
  /**
   * Predicted input of a remote player from their last confirmed one. Default: the schema's
   * `missing` rule — held buttons stay held, presses are not repeated, axes keep their value.
   */
  predict?: (last: I, player: number) => I;
  /** Called after every rollback with what it changed at the current tick. */
  onCorrection?: (correction: Correction) => void;
}

/**
 * Rollback over a server relay: remote inputs are predicted (their last confirmed input, held
 * buttons only) so the simulation runs ahead of the confirmed ticks by up to `maxPrediction`
 * ticks with no input lag beyond `inputDelay`. Every state is saved in a ring; when confirmed
 * inputs differ from a prediction, the session loads the state of the first wrong tick and
 * resimulates up to the present, once per frame however many messages arrived.
 *
 * It reports rollbacks, their depth and the size of each correction; visual smoothing of a
 * correction is the renderer's job ({@link RollbackSessionOptions.onCorrection}).
 */
export class RollbackSession<I = ButtonInput> extends NetSession<I> {
  /** The last rollback's correction. */
  lastCorrection: Correction | undefined;

  private inputDelay: number;
  /** Sessions of other players on this machine, whose issued inputs this one uses. */
  private localPeers: readonly RollbackSession<I>[] = [];
  private pendingDelay: { delay: number; atTick: number } | undefined;
  private readonly maxPrediction: number;
  private readonly autoLead: boolean;
  private readonly predict: ((last: I, player: number) => I) | undefined;
  private readonly lead = new LeadTicks();
  private used = new InputRing(1, 1);
  private pendingRollback = Infinity;
  private row: I[] = [];
  private rowWords = new Uint32Array(0);

  constructor(options: RollbackSessionOptions<I>) {
    super(options, 'player');
    this.inputDelay = options.inputDelay ?? 1;
    this.maxPrediction = options.maxPrediction ?? 30;
    if (!(Number.isInteger(this.inputDelay) && this.inputDelay >= 0 && this.inputDelay <= 60)) {
      throw new RangeError(`inputDelay must be an integer from 0 to 60, got ${this.inputDelay}`);
    }
    if (!(
      Number.isInteger(this.maxPrediction) &&
      this.maxPrediction >= 1 &&
      this.maxPrediction <= 600
    )) {
      throw new RangeError(
        `maxPrediction must be an integer from 1 to 600, got ${this.maxPrediction}`,
      );
    }
    this.autoLead = options.lead === undefined || options.lead === 'auto';
    if (typeof options.lead === 'number') this.lead.ticks = options.lead;
    this.predict = options.predict;
  }

  confirmedStateTick(): number {
    if (!this.sim) return 0;
    return Math.min(this.confirmedEnd, this.sim.tick, this.pendingRollback);
  }

  /** The local input delay in force, in ticks. */
  get inputDelayTicks(): number {
    return this.inputDelay;
  }

  /**
   * Change the local input delay during a match, from the frame on which the simulation reaches
   * `atTick` (default: the next frame). Give every player the same `atTick` — e.g. a tick derived
   * from a confirmed game event — and their delays change together.
   *
   * Deterministic whatever the tick: the delay only decides which tick a local input is sent for,
   * and the relay's confirmed inputs are what every machine simulates. Growing the delay by k
   * issues k more ticks at once (each asks `localInput`, so a press lands on the first of them and
   * is never doubled); shrinking it by k issues nothing for k ticks (inputs wait; none is lost).
   */
  setInputDelay(delay: number, atTick = this.tick): void {
    if (!(Number.isInteger(delay) && delay >= 0 && delay <= 60)) {
      throw new RangeError(`setInputDelay: delay must be an integer from 0 to 60, got ${delay}`);
    }
    if (!(Number.isInteger(atTick) && atTick >= 0)) {
      throw new RangeError(`setInputDelay: atTick must be a tick (an integer >= 0), got ${atTick}`);
    }
    this.pendingDelay = { delay, atTick };
  }

  /**
   * Several players on one machine (a shared keyboard, two gamepads): give each its own session —
   * its own transport to the relay, so its own slot — and link them. Each linked session then
   * simulates the others' locally issued inputs (sampling one early, if its session has not yet
   * issued it this frame) instead of predicting them and rolling back when they are confirmed:
   * rollbacks come only from remote players.
   *
   * Deterministic: only predictions change; every machine still simulates the relay's confirmed
   * inputs (an issued input the relay replaced, e.g. one that arrived after its tick's deadline,
   * is corrected by a rollback like any misprediction). Each session still runs its own
   * simulation and receives the confirmed stream, so the cost is one simulation and one
   * connection per local player; draw any one of them. Every session must be in the same room and
   * game; linking again replaces the links.
   */
  static linkLocalPlayers<I>(sessions: readonly RollbackSession<I>[]): void {
    if (new Set(sessions).size !== sessions.length) {
      throw new RangeError('linkLocalPlayers: a session is listed twice');
    }
    for (const s of sessions) s.localPeers = sessions.filter((o) => o !== s);
  }

  /** Ticks the simulation is ahead of the confirmed inputs. */
  get predictedTicks(): number {
    return Math.max(0, this.tick - this.confirmedEnd);
  }

  protected override ringCapacity(): number {
    return this.maxPrediction + Math.max(1, this.forensicsWindow) + 2;
  }

  protected override keepInputsFrom(): number {
    const t = this.sim?.tick ?? 0;
    return Math.min(t, this.confirmedEnd, this.pendingRollback);
  }

  protected override onConfirmed(from: number, to: number): void {
    const sim = this.sim!;
    this.ensureRows();
    const end = Math.min(to, sim.tick);
    const lanes = this.players * this.words;
    for (let t = from; t < end; t++) {
      if (!this.used.has(t)) {
        this.pendingRollback = Math.min(this.pendingRollback, t);
        return;
      }
      for (let p = 0; p < lanes; p++) {
        if (this.used.get(t, p) !== this.confirmed.get(t, p)) {
          this.pendingRollback = Math.min(this.pendingRollback, t);
          return;
        }
      }
    }
  }

  protected displayTime(now: number): number {
    return this.serverTick(now) + Math.max(0, this.lead.ticks);
  }

  protected advance(serverTick: number, now: number): number {
    const sim = this.sim!;
    this.ensureRows();
    if (!Number.isFinite(serverTick)) return 0;
    const pending = this.pendingDelay;
    if (pending && sim.tick >= pending.atTick) {
      this.inputDelay = pending.delay;
      this.pendingDelay = undefined;
    }
    this.adaptLead(now);
    const target = Math.min(Math.floor(serverTick) + this.lead.ticks, this.stopAt);
    this.issueUntil(target + this.inputDelay);
    this.rollback();
    let n = 0;
    const limit = this.confirmedEnd + this.maxPrediction;
    while (sim.tick < target && sim.tick < limit && n < this.maxTicksPerFrame) {
      this.stepOne();
      n++;
    }
    this.markStall(sim.tick < target && sim.tick >= limit);
    return n;
  }

  private ensureRows(): void {
    const lanes = this.players * this.words;
    if (this.used.capacity !== this.ring.capacity || this.used.lanes !== lanes) {
      this.used = new InputRing(this.ring.capacity, lanes);
    }
    if (this.rowWords.length !== lanes) {
      this.rowWords = new Uint32Array(lanes);
      this.row = new Array<I>(this.players);
    }
  }

  private stepOne(): void {
    const sim = this.sim!;
    const t = sim.tick;
    this.inputsFor(t, this.rowWords);
    this.decodeRow(this.rowWords, this.row);
    sim.step(this.row);
    this.used.set(t, this.rowWords);
    if (this.keepsBuffers) this.ring.putFrom(sim.tick, sim as SavesInto);
    else this.ring.put(sim.tick, sim.save());
  }

  /** Whether the simulation writes its snapshots into the ring's kept buffers (`saveInto`). */
  private get keepsBuffers(): boolean {
    const sim = this.sim!;
    return sim.saveInto !== undefined && sim.snapshotSize !== undefined;
  }

  /** Whether a linked local session has issued player `p`'s input for `tick` (copied to `out`). */
  private localPeerInput(p: number, tick: number, out: Uint32Array, at: number): boolean {
    const room = this.welcomeMsg?.room;
    for (const s of this.localPeers) {
      if (s.slot !== p || s.welcomeMsg?.room !== room || s.words !== this.words) continue;
      // Not issued yet (it frames after this one): sample it now. No further ahead than this
      // session's own issued inputs, so within what the relay accepts.
      if (s.phase === 'running') s.issueUntil(tick + 1);
      if (s.issuedInput(tick, out, at)) return true;
    }
    return false;
  }

  /** The words of `tick`: confirmed, else a local player's issued one, else predicted. */
  private inputsFor(tick: number, words: Uint32Array): void {
    if (tick < this.confirmedEnd) {
      this.confirmed.copy(tick, words);
      return;
    }
    const w = this.words;
    for (let p = 0; p < this.players; p++) {
      if (p === this.slot && this.issuedInput(tick, words, p * w)) continue;
      if (this.localPeers.length > 0 && this.localPeerInput(p, tick, words, p * w)) continue;
      if (this.predict) {
        const last = this.schema.decode(this.lastConfirmed, p * w);
        this.schema.encode(this.predict(last, p), words, p * w);
      } else {
        this.schema.missing(this.lastConfirmed, p * w, words, p * w);
      }
    }
  }

  private rollback(): void {
    const sim = this.sim!;
    const from = this.pendingRollback;
    this.pendingRollback = Infinity;
    const end = sim.tick;
    if (from >= end) return;
    const start = this.ring.get(from);
    const predicted = this.ring.get(end);
    if (!start || !predicted) {
      throw new Error(`RollbackSession: no snapshot of tick ${from} to roll back to`);
    }
    // Kept buffers are rewritten in place: the correction gets copies of both states.
    const kept = this.keepsBuffers;
    const before = kept ? predicted.slice() : predicted;
    sim.load(start);
    for (let t = from; t < end; t++) this.stepOne();
    const depth = end - from;
    const after = kept ? this.ring.get(end)!.slice() : this.ring.get(end)!;
    this.stats.rollbacks++;
    this.stats.resimulatedTicks += depth;
    if (depth > this.stats.maxRollbackDepth) this.stats.maxRollbackDepth = depth;
    const correction: Correction = {
      tick: end,
      depth,
      bytesChanged: diffSnapshots(before, after, 0).differingBytes,
      before,
      after,
    };
    this.lastCorrection = correction;
    (this.options as RollbackSessionOptions<I>).onCorrection?.(correction);
  }

  private adaptLead(now: number): void {
    if (this.autoLead && this.clockSync.ready) {
      const want = Math.max(
        0,
        Math.min(
          this.maxPrediction - 1,
          Math.ceil((this.clockSync.rttHigh / 2 + this.tickMs) / this.tickMs) - this.inputDelay,
        ),
      );
      this.lead.follow(want, now);
    }
    if (this.lead.ticks < 0) this.lead.ticks = 0;
    this.stats.lead = this.lead.ticks;
    this.stats.inputDelay = this.inputDelay;
  }
}
