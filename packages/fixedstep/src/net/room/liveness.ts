/**
 * Liveness that does not blame clients for the server's own stalls.
 * @module
 */

/**
 * The server's responsive time: a clock that runs with the real one while the server keeps up, and
 * stops while its event loop is stalled (a long garbage collection, a blocking call, a suspended
 * VM). The host calls {@link update} every few milliseconds; a gap between two calls longer than
 * `toleranceMs` is a stall, and only `toleranceMs` of it counts. A member's silence is measured on
 * this clock, so when a stalled server wakes up to a backlog of its players' messages, it does not
 * close them as "silent" before it has read what they sent.
 */
export class LivenessClock {
  private last: number | undefined;
  private responsive = 0;
  /** Time the server lost to stalls so far, in ms. */
  stalledMs = 0;

  constructor(readonly toleranceMs: number) {}

  /** The responsive time at real time `now` (ms). */
  at(now: number): number {
    if (this.last === undefined) return this.responsive;
    return this.responsive + Math.min(Math.max(0, now - this.last), this.toleranceMs);
  }

  /** The host's periodic call: advances the responsive time to `now`. */
  update(now: number): void {
    if (this.last !== undefined) {
      const gap = Math.max(0, now - this.last);
      if (gap > this.toleranceMs) this.stalledMs += gap - this.toleranceMs;
    }
    this.responsive = this.at(now);
    this.last = now;
  }
}
