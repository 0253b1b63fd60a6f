/**
 * Lockstep over a relay: a tick is stepped only once every player's confirmed input for it is
 * here, so nothing is ever predicted or rolled back; the price is input delay.
 * @module
 */
import type { ButtonInput } from '../../sim/buttons.js';
import { NetSession } from './base.js';
import type { NetSessionOptions } from './relay-options.js';

/** Options of a {@link LockstepSession}. */
export interface LockstepSessionOptions<I = ButtonInput> extends NetSessionOptions<I> {
  /**
   * Input delay in ticks: the local input sampled now is for the tick this many ticks ahead of
   * the server clock. `'auto'` (the default) sizes it from the measured round trip — a high
   * percentile of recent RTTs plus a tick and a half — so confirmed inputs are back before their
   * tick is due; it grows at once and shrinks by one tick a second.
   */
  inputDelay?: number | 'auto';
  /** Most the adaptive input delay may grow to, in ticks. Default 60. */
  maxInputDelay?: number;
}

/** Keeps the last `n` values and their maximum. */
class WindowMax {
  private readonly values: Float64Array;
  private i = 0;
  private n = 0;
  constructor(size: number) {
    this.values = new Float64Array(size);
  }
  add(v: number): void {
    this.values[this.i] = v;
    this.i = (this.i + 1) % this.values.length;
    if (this.n < this.values.length) this.n++;
  }
  get max(): number {
    let m = -Infinity;
    for (let k = 0; k < this.n; k++) if (this.values[k]! > m) m = this.values[k]!;
    return m;
  }
}

/**
 * Lockstep over a server relay: a tick is stepped only once the confirmed inputs of every player
 * for it are here, so the state is never predicted and never rolled back. The local input is
 * sent `inputDelay` ticks ahead (adaptive to the RTT) so it is back, confirmed, in time; the
 * display runs `playoutDelay` ticks behind the server clock, a jitter buffer sized from how late
 * confirmed ticks have actually arrived. A spectator is a lockstep session without inputs
 * ({@link SpectatorSession}).
 */
export class LockstepSession<I = ButtonInput> extends NetSession<I> {
  private delay: number;
  private readonly autoDelay: boolean;
  private readonly maxDelay: number;
  private lastDelayDrop = 0;
  private playout = 0;
  private lastPlayoutDrop = 0;
  private readonly lateness = new WindowMax(600);
  private row: I[] = [];
  private rowWords = new Uint32Array(0);

  constructor(options: LockstepSessionOptions<I>, role: 'player' | 'spectator' = 'player') {
    super(options, role);
    this.autoDelay = options.inputDelay === undefined || options.inputDelay === 'auto';
    this.delay = typeof options.inputDelay === 'number' ? options.inputDelay : 4;
    this.maxDelay = options.maxInputDelay ?? 60;
    if (!(Number.isInteger(this.delay) && this.delay >= 0 && this.delay <= 600)) {
      throw new RangeError(
        `inputDelay must be 'auto' or an integer from 0 to 600, got ${this.delay}`,
      );
    }
  }

  confirmedStateTick(): number {
    return this.sim?.tick ?? 0;
  }

  protected override onConfirmed(from: number, _to: number, now: number): void {
    // How late the first newly confirmed tick arrived against the server clock (the one the
    // display may have been waiting for): the jitter buffer's input.
    const s = this.serverTick(now);
    if (Number.isFinite(s)) this.lateness.add(s - from);
  }

  protected displayTime(now: number): number {
    return this.serverTick(now) - this.playout;
  }

  protected advance(serverTick: number, now: number): number {
    const sim = this.sim!;
    if (!Number.isFinite(serverTick)) return 0;
    this.adapt(now);
    const clockTick = Math.floor(serverTick);
    this.issueUntil(clockTick + 1 + this.delay);
    const target = Math.min(clockTick - this.playout, this.stopAt);
    let n = 0;
    if (this.rowWords.length !== this.players * this.words) {
      this.rowWords = new Uint32Array(this.players * this.words);
      this.row = new Array<I>(this.players);
    }
    const row = this.row;
    while (sim.tick < target && sim.tick < this.confirmedEnd && n < this.maxTicksPerFrame) {
      const t = sim.tick;
      this.confirmed.copy(t, this.rowWords);
      this.decodeRow(this.rowWords, row);
      sim.step(row);
      this.remember();
      n++;
    }
    this.markStall(sim.tick < target && sim.tick >= this.confirmedEnd);
    return n;
  }

  private adapt(now: number): void {
    const tickMs = this.tickMs;
    if (this.autoDelay && this.slot >= 0 && this.clockSync.ready) {
      const want = Math.min(
        this.maxDelay,
        // The round trip, plus the room's network rate: inputs wait for their group here and
        // confirmed ticks for theirs at the server, up to `sendEvery − 1` ticks each.
        Math.ceil((this.clockSync.rttHigh + 1.5 * tickMs) / tickMs) +
          2 * ((this.welcomeMsg?.sendEvery ?? 1) - 1),
      );
      if (want > this.delay) {
        this.delay = want;
        this.lastDelayDrop = now;
      } else if (want < this.delay && now - this.lastDelayDrop >= 1000) {
        this.delay--;
        this.lastDelayDrop = now;
      }
    }
    // Confirmed tick t is needed once the display passes t + 1.
    const late = this.lateness.max;
    const wantPlayout = Number.isFinite(late) ? Math.max(0, Math.min(120, Math.ceil(late - 1))) : 0;
    if (wantPlayout > this.playout) {
      this.playout = wantPlayout;
      this.lastPlayoutDrop = now;
    } else if (wantPlayout < this.playout && now - this.lastPlayoutDrop >= 2000) {
      this.playout--;
      this.lastPlayoutDrop = now;
    }
    this.stats.inputDelay = this.slot >= 0 ? this.delay : 0;
    this.stats.playoutDelay = this.playout;
  }
}
