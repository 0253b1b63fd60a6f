/**
 * Admission by client address: how many of a thing (connections, rooms, tickets) each address
 * holds, against a cap per address and a cap in all.
 * @module
 */
import type { NetErrorCode } from '../wire/common.js';

/** Counts of one resource by client address (an IPv4 address, an IPv6 /64, a proxy's header). */
export class AddressTally {
  private readonly counts = new Map<string, number>();
  private count = 0;

  /**
   * @param what — the resource in refusals: `connections`, `rooms`, `tickets`.
   * @param perAddress — most one address may hold.
   * @param max — most in all.
   */
  constructor(
    readonly what: string,
    readonly perAddress: number,
    readonly max: number,
  ) {}

  /** How many `address` holds. */
  of(address: string): number {
    return this.counts.get(address) ?? 0;
  }

  /** How many in all. */
  get total(): number {
    return this.count;
  }

  /** Distinct addresses holding one or more. */
  get addresses(): number {
    return this.counts.size;
  }

  /** Whether every place is taken. */
  get full(): boolean {
    return this.count >= this.max;
  }

  /** Why `address` may not take one more (its share, or the whole), or undefined. */
  refusal(address: string): [NetErrorCode, string] | undefined {
    if (this.of(address) >= this.perAddress) {
      return ['ADDRESS_LIMIT', `at most ${this.perAddress} ${this.what} from one address`];
    }
    if (this.count >= this.max) return ['SERVER_FULL', `${this.max} ${this.what} already`];
    return undefined;
  }

  add(address: string): void {
    this.counts.set(address, this.of(address) + 1);
    this.count++;
  }

  remove(address: string): void {
    const n = this.of(address) - 1;
    if (n < 0) return;
    if (n === 0) this.counts.delete(address);
    else this.counts.set(address, n);
    this.count--;
  }
}
