/**
 * NTP-style estimate of the server's clock from ping/pong round trips.
 *
 * A sample is (client send time, server time, client receive time). Its round trip is
 * `receive - send`; assuming the two directions took equally long, the server read its clock
 * at the client's `(send + receive) / 2`, so `offset = server - (send + receive) / 2`. The error
 * of that assumption is at most half the round trip, so of the last {@link window} samples the
 * one with the smallest round trip is trusted (the min-RTT filter): a delayed pong — a congested
 * link, or a background tab whose timers and handlers ran late — cannot drag the estimate away.
 *
 * The estimate never runs backwards: a new best sample with a smaller offset holds the estimated
 * server time still until the client clock has caught up with the previous reading.
 */
export class ClockSync {
  /** How many recent samples are kept. */
  readonly window: number;
  private readonly rtts: Float64Array;
  private readonly offsets: Float64Array;
  private count = 0;
  private next = 0;
  private best = -1;
  private lastEstimate = -Infinity;

  constructor(window = 16) {
    if (!(Number.isInteger(window) && window >= 1 && window <= 1024)) {
      throw new RangeError(`ClockSync: window must be an integer from 1 to 1024, got ${window}`);
    }
    this.window = window;
    this.rtts = new Float64Array(window);
    this.offsets = new Float64Array(window);
  }

  /**
   * Add a round trip: the client's clock when the ping left (`sentAt`) and when the pong arrived
   * (`receivedAt`), and the server's clock when it answered. Samples that go backwards in time are
   * ignored. Returns whether the sample was used.
   */
  addSample(sentAt: number, serverTime: number, receivedAt: number): boolean {
    if (
      !(Number.isFinite(sentAt) && Number.isFinite(serverTime) && Number.isFinite(receivedAt)) ||
      receivedAt < sentAt
    ) {
      return false;
    }
    this.rtts[this.next] = receivedAt - sentAt;
    this.offsets[this.next] = serverTime - (sentAt + receivedAt) / 2;
    this.next = (this.next + 1) % this.window;
    if (this.count < this.window) this.count++;
    let best = 0;
    for (let i = 1; i < this.count; i++) if (this.rtts[i]! < this.rtts[best]!) best = i;
    this.best = best;
    return true;
  }

  /** Samples held (up to the window). */
  get samples(): number {
    return this.count;
  }

  /** Whether there is an estimate yet. */
  get ready(): boolean {
    return this.count > 0;
  }

  /** Server clock minus client clock, in ms (0 before the first sample). */
  get offset(): number {
    return this.best < 0 ? 0 : this.offsets[this.best]!;
  }

  /** The smallest round trip in the window, in ms (0 before the first sample). */
  get rtt(): number {
    return this.best < 0 ? 0 : this.rtts[this.best]!;
  }

  /**
   * A high round trip in the window, in ms: the second largest (the largest, with fewer than four
   * samples) — about the 90th percentile of 16 samples, robust to one outlier. Input delay is sized
   * from it.
   */
  get rttHigh(): number {
    if (this.count === 0) return 0;
    const sorted = Array.from(this.rtts.subarray(0, this.count)).sort((a, b) => a - b);
    return sorted[this.count >= 4 ? this.count - 2 : this.count - 1]!;
  }

  /** The estimated server clock at client time `clientNow`, in ms; never decreasing. */
  serverTime(clientNow: number): number {
    const t = clientNow + this.offset;
    if (t > this.lastEstimate) this.lastEstimate = t;
    return this.lastEstimate;
  }
}

/**
 * How many ticks ahead of the server's clock a predicting session runs (rollback, state sync):
 * the first lead it wants is taken at once; after that the lead follows the wanted one a tick at
 * a time, at most once every 250 ms (up: every `riseEveryMs`), so a noisy round trip does not
 * jerk the simulation.
 * Negative while unset.
 */
export class LeadTicks {
  private lastMove = -Infinity;

  constructor(
    /** The lead now, ticks (negative: not set yet). */
    public ticks = -1,
    /** The least time between two moves up, ms (down: always 250). */
    private readonly riseEveryMs = 250,
  ) {}

  /** Moves the lead towards `want` ticks at `now` (ms on the session's clock). */
  follow(want: number, now: number): void {
    if (this.ticks < 0) {
      this.ticks = want;
      this.lastMove = now;
    } else if (
      want !== this.ticks &&
      now - this.lastMove >= (want > this.ticks ? this.riseEveryMs : 250)
    ) {
      this.ticks += want > this.ticks ? 1 : -1;
      this.lastMove = now;
    }
  }
}
