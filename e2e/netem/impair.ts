/**
 * What the loss harness's proxies do to traffic, in one place: delay ± jitter and loss per
 * direction, decided by a seeded generator (a run's losses repeat with its seed), on an injectable
 * timer so tests can drive a simulated clock.
 */
import { Random } from 'fixedstep';

/** Conditions of one direction. */
export interface Impairment {
  /** Mean one-way delay, ms. */
  latencyMs: number;
  /** Each packet's delay is `latency ± jitter`, uniform. */
  jitterMs: number;
  /** Probability a datagram is dropped (UDP) or a segment is "lost" and retransmitted (TCP model). */
  loss: number;
}

export const CLEAN: Impairment = Object.freeze({ latencyMs: 0, jitterMs: 0, loss: 0 });

/** Runs `fn` after `ms` (setTimeout by default; a test passes a simulated scheduler). */
export type Schedule = (fn: () => void, ms: number) => void;

export const realSchedule: Schedule = (fn, ms) => {
  if (ms <= 0) queueMicrotask(fn);
  else setTimeout(fn, ms);
};

/** Counters of one direction. */
export interface DirectionStats {
  packets: number;
  bytes: number;
  /** UDP: datagrams dropped. TCP: segments held for a retransmission timeout (retransmissions). */
  lost: number;
}

export function newStats(): DirectionStats {
  return { packets: 0, bytes: 0, lost: 0 };
}

export function checkImpairment(c: Impairment): Impairment {
  if (!(Number.isFinite(c.latencyMs) && c.latencyMs >= 0)) {
    throw new RangeError(`latencyMs must be >= 0, got ${String(c.latencyMs)}`);
  }
  if (!(Number.isFinite(c.jitterMs) && c.jitterMs >= 0 && c.jitterMs <= c.latencyMs)) {
    throw new RangeError(`jitterMs must be from 0 to latencyMs, got ${String(c.jitterMs)}`);
  }
  if (!(c.loss >= 0 && c.loss < 1))
    throw new RangeError(`loss must be in [0, 1), got ${String(c.loss)}`);
  return { ...c };
}

/** A seeded source of delays and losses for one direction. */
export class Dice {
  private readonly rng: Random;
  constructor(seed: number) {
    this.rng = new Random(seed >>> 0);
  }
  lost(c: Impairment): boolean {
    return c.loss > 0 && this.rng.next() < c.loss;
  }
  delay(c: Impairment): number {
    return c.jitterMs > 0 ? c.latencyMs + (this.rng.next() * 2 - 1) * c.jitterMs : c.latencyMs;
  }
}
