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
 *
 * When the host runs behind another stage — a worker thread fed by the main thread that reads the
 * sockets — that stage's stalls leave the clients' messages unread too: once told of it
 * ({@link upstream}), the clock also stops while that stage has not been heard from for more than
 * `toleranceMs`.
 */
export class LivenessClock {
  private last: number | undefined;
  private responsive = 0;
  /** When the stage in front last showed it was responsive; undefined: no such stage. */
  private upstreamAt: number | undefined;
  /** Time the server lost to stalls so far, in ms. */
  stalledMs = 0;

  constructor(readonly toleranceMs: number) {}

  /** The responsive time at real time `now` (ms). */
  at(now: number): number {
    if (this.last === undefined) return this.responsive;
    return this.responsive + this.counted(this.last, now);
  }

  /** The host's periodic call: advances the responsive time to `now`. */
  update(now: number): void {
    if (this.last !== undefined) {
      const counted = this.counted(this.last, now);
      this.stalledMs += Math.max(0, now - this.last) - counted;
      this.responsive += counted;
    }
    this.last = now;
  }

  /**
   * The stage in front of the host (what reads the sockets and hands the host their bytes) was
   * responsive at `now`: call it every few hundred ms at most — well within `toleranceMs` — once
   * you call it at all.
   */
  upstream(now: number): void {
    this.upstreamAt = now;
  }

  /**
   * How much of the real time from `from` (the last update) to `to` counts: no more than
   * `toleranceMs` past the host's last update, nor past the stage in front's last sign of life.
   */
  private counted(from: number, to: number): number {
    let end = Math.min(to, from + this.toleranceMs);
    if (this.upstreamAt !== undefined) end = Math.min(end, this.upstreamAt + this.toleranceMs);
    return Math.max(0, end - from);
  }
}
