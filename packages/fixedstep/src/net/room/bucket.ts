/**
 * Token buckets: how many messages and bytes a connection may send.
 * @module
 */

/** Rates of a {@link TokenBucket}: sustained per second, and the burst on top. */
export interface RateLimits {
  /** Sustained messages per second. */
  messagesPerSecond: number;
  /** Messages a connection may send at once after a quiet spell. */
  messageBurst: number;
  /** Sustained bytes per second. */
  bytesPerSecond: number;
  /** Bytes a connection may send at once (one full snapshot must fit). */
  byteBurst: number;
}

/** Counts down messages and bytes, refilling at the sustained rates up to the bursts. */
export class TokenBucket {
  private messages: number;
  private bytes: number;
  private at: number;

  constructor(
    private readonly rate: Readonly<RateLimits>,
    now: number,
  ) {
    this.messages = rate.messageBurst;
    this.bytes = rate.byteBurst;
    this.at = now;
  }

  /** Takes one message of `size` bytes at time `now` (ms); false when over either rate. */
  take(size: number, now: number): boolean {
    const r = this.rate;
    const dt = Math.max(0, now - this.at) / 1000;
    this.at = now;
    this.messages = Math.min(r.messageBurst, this.messages + dt * r.messagesPerSecond) - 1;
    this.bytes = Math.min(r.byteBurst, this.bytes + dt * r.bytesPerSecond) - size;
    return this.messages >= 0 && this.bytes >= 0;
  }
}
