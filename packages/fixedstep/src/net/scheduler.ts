import { ManualClock } from '../time/drivers.js';

/** A cancellable scheduled event. */
export interface ScheduledEvent {
  cancel(): void;
}

interface Entry {
  time: number;
  seq: number;
  fn: () => void;
  cancelled: boolean;
}

/**
 * Discrete-event time for network tests and the lab: a {@link ManualClock} and a priority queue of
 * events (message deliveries, display frames, server ticks). {@link runUntil} pops events in time
 * order — ties in the order they were scheduled — moving the clock to each, so a 10-minute match
 * over a lossy link runs in seconds and gives the same result every time.
 */
export class EventScheduler {
  readonly clock: ManualClock;
  private heap: Entry[] = [];
  private seq = 0;
  private executed = 0;

  constructor(startMs = 0) {
    this.clock = new ManualClock(startMs);
  }

  /** The current time, in ms. */
  get now(): number {
    return this.clock.now();
  }

  /** Events run so far. */
  get eventsRun(): number {
    return this.executed;
  }

  /** Events waiting (including cancelled ones not yet popped). */
  get pending(): number {
    return this.heap.length;
  }

  /** Run `fn` at time `timeMs` (not before now: an earlier time runs it next, at now). */
  at(timeMs: number, fn: () => void): ScheduledEvent {
    const e: Entry = { time: Math.max(timeMs, this.now), seq: this.seq++, fn, cancelled: false };
    this.push(e);
    return {
      cancel: () => {
        e.cancelled = true;
      },
    };
  }

  /** Run `fn` after `ms` milliseconds. */
  after(ms: number, fn: () => void): ScheduledEvent {
    return this.at(this.now + Math.max(0, ms), fn);
  }

  /**
   * Run `fn` every `periodMs` ms, first at `firstAt` (default: now + period). `periodMs` may be a
   * function, read after each run (for a display whose rate changes, e.g. a hidden tab).
   */
  every(periodMs: number | (() => number), fn: () => void, firstAt?: number): ScheduledEvent {
    const period = typeof periodMs === 'function' ? periodMs : () => periodMs;
    let current: ScheduledEvent | undefined;
    let stopped = false;
    let next = firstAt ?? this.now + period();
    const run = () => {
      if (stopped) return;
      fn();
      next += period();
      current = this.at(next, run);
    };
    current = this.at(next, run);
    return {
      cancel: () => {
        stopped = true;
        current?.cancel();
      },
    };
  }

  /** Run every event due up to and including `timeMs`, then set the clock to `timeMs`. */
  runUntil(timeMs: number): void {
    for (;;) {
      const top = this.heap[0];
      if (top === undefined || top.time > timeMs) break;
      this.pop();
      if (top.cancelled) continue;
      if (top.time > this.now) this.clock.set(top.time);
      this.executed++;
      top.fn();
    }
    if (timeMs > this.now) this.clock.set(timeMs);
  }

  /** Run for `ms` milliseconds from now. */
  runFor(ms: number): void {
    this.runUntil(this.now + ms);
  }

  /**
   * Run events until `done()` holds (checked before each event) or `limitMs` passes. Returns
   * whether `done()` held.
   */
  runUntilDone(done: () => boolean, limitMs: number): boolean {
    const end = this.now + limitMs;
    while (!done()) {
      const top = this.heap[0];
      if (top === undefined || top.time > end) {
        if (end > this.now) this.clock.set(end);
        return done();
      }
      this.pop();
      if (top.cancelled) continue;
      if (top.time > this.now) this.clock.set(top.time);
      this.executed++;
      top.fn();
    }
    return true;
  }

  private less(a: Entry, b: Entry): boolean {
    return a.time < b.time || (a.time === b.time && a.seq < b.seq);
  }

  private push(e: Entry): void {
    const h = this.heap;
    h.push(e);
    let i = h.length - 1;
    while (i > 0) {
      const parent = (i - 1) >> 1;
      if (!this.less(h[i]!, h[parent]!)) break;
      [h[i], h[parent]] = [h[parent]!, h[i]!];
      i = parent;
    }
  }

  private pop(): void {
    const h = this.heap;
    const last = h.pop()!;
    if (h.length === 0) return;
    h[0] = last;
    let i = 0;
    for (;;) {
      const l = 2 * i + 1;
      const r = l + 1;
      let m = i;
      if (l < h.length && this.less(h[l]!, h[m]!)) m = l;
      if (r < h.length && this.less(h[r]!, h[m]!)) m = r;
      if (m === i) break;
      [h[i], h[m]] = [h[m]!, h[i]!];
      i = m;
    }
  }
}
