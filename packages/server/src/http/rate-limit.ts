/**
 * A per-address rate limit with bounded memory: at most `limit` charges per address per window.
 *
 * Hand-written, not a library, for two properties the server needs and the rate-limit packages we
 * looked at do not give together: a separate *check* and *charge* (the highscore API charges only a
 * submission that passed its pre-check, so junk cannot spend an honest player's quota), and a hard
 * bound on memory whatever the number of addresses (two generations of at most `maxAddresses`
 * entries; a full generation is forgotten early, which can only let someone through, never lock
 * anyone out).
 */
export class RateLimiter {
  private current = new Map<string, number>();
  private previous = new Map<string, number>();
  private windowStart: number;

  /**
   * @param limit — charges allowed per address per window.
   * @param windowMs — the window, in ms. Default 60 000.
   * @param now — the clock, in ms (injected for tests). Default `Date.now`.
   * @param maxAddresses — addresses remembered per generation. Default 100 000.
   */
  constructor(
    readonly limit: number,
    readonly windowMs = 60_000,
    private readonly now: () => number = Date.now,
    readonly maxAddresses = 100_000,
  ) {
    if (!Number.isInteger(limit) || limit < 1)
      throw new RangeError(`RateLimiter: limit must be an integer ≥ 1, got ${String(limit)}`);
    if (!(windowMs > 0))
      throw new RangeError(`RateLimiter: windowMs must be > 0, got ${String(windowMs)}`);
    this.windowStart = now();
  }

  /** Addresses remembered right now (at most 2 × maxAddresses). */
  get size(): number {
    return this.current.size + this.previous.size;
  }

  /**
   * Seconds until `key` may be charged again, or 0 if it may be now. The count of a key is a sliding
   * estimate: this window's charges plus the previous window's, weighted by how much of it overlaps.
   */
  check(key: string): number {
    this.rotate();
    const elapsed = (this.now() - this.windowStart) / this.windowMs;
    const count = (this.current.get(key) ?? 0) + (this.previous.get(key) ?? 0) * (1 - elapsed);
    if (count < this.limit) return 0;
    return Math.max(1, Math.ceil(((1 - elapsed) * this.windowMs) / 1000));
  }

  /** Charges `key` once (call after {@link check} said 0). */
  charge(key: string): void {
    this.rotate();
    if (!this.current.has(key) && this.current.size >= this.maxAddresses) {
      this.previous = this.current;
      this.current = new Map();
    }
    this.current.set(key, (this.current.get(key) ?? 0) + 1);
  }

  private rotate(): void {
    const t = this.now();
    const windows = Math.floor((t - this.windowStart) / this.windowMs);
    if (windows <= 0) return;
    this.previous = windows === 1 ? this.current : new Map<string, number>();
    this.current = new Map<string, number>();
    this.windowStart += windows * this.windowMs;
  }
}
