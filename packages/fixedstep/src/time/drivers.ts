/**
 * Clocks and frame schedulers are injected, never global: a loop in a browser tab, a loop in a
 * Node server, and a loop in a test each get their own, and several can run at once.
 */

/** A source of time in milliseconds. Only differences between readings matter. */
export interface Clock {
  now(): number;
}

/** The platform's monotonic clock (`performance.now()`), in browsers and in Node. */
export function performanceClock(): Clock {
  return { now: () => performance.now() };
}

/** A clock that only moves when told to: for tests and simulated displays. */
export class ManualClock implements Clock {
  private t: number;
  /** A clock that reads `startMs` (ms) until it is moved. */
  constructor(startMs = 0) {
    this.t = startMs;
  }
  /** The current reading, in ms. */
  now(): number {
    return this.t;
  }
  /** Move the clock by `ms` (may be negative, to fake a clock that jumps back). */
  advance(ms: number): number {
    this.t += ms;
    return this.t;
  }
  /** Set the reading to `ms` (earlier than now fakes a clock that jumps back). */
  set(ms: number): void {
    this.t = ms;
  }
}

/** Called once per display frame with a clock reading in ms. */
export type FrameCallback = (nowMs: number) => void;

/** Asks for the next display frame. */
export interface FrameScheduler {
  request(callback: FrameCallback): number;
  cancel(handle: number): void;
}

interface AnimationFrameHost {
  requestAnimationFrame(callback: (time: number) => void): number;
  cancelAnimationFrame(handle: number): void;
}

/** Frames from `requestAnimationFrame` (the timestamp it passes is the reading). */
export function animationFrameScheduler(host: AnimationFrameHost = globalThis): FrameScheduler {
  if (typeof host.requestAnimationFrame !== 'function') {
    throw new TypeError(
      'animationFrameScheduler: requestAnimationFrame is not available here (use timerScheduler in Node)',
    );
  }
  return {
    request: (cb) => host.requestAnimationFrame(cb),
    cancel: (h) => {
      host.cancelAnimationFrame(h);
    },
  };
}

/**
 * Frames from timers, for Node (a server running a simulation) or any place without a display.
 * Aims at `intervalMs` between frames, correcting for timer lateness against `clock`.
 */
export function timerScheduler(
  intervalMs: number,
  clock: Clock = performanceClock(),
): FrameScheduler {
  if (!(Number.isFinite(intervalMs) && intervalMs > 0)) {
    throw new RangeError(
      `timerScheduler: interval must be a positive number of ms, got ${String(intervalMs)}`,
    );
  }
  let next = clock.now();
  const timers = new Map<number, ReturnType<typeof setTimeout>>();
  let id = 0;
  return {
    request(cb) {
      const handle = ++id;
      next += intervalMs;
      const now = clock.now();
      if (next < now - intervalMs) next = now; // fell far behind: do not fire a burst
      const timer = setTimeout(
        () => {
          timers.delete(handle);
          cb(clock.now());
        },
        Math.max(0, next - now),
      );
      timers.set(handle, timer);
      return handle;
    },
    cancel(handle) {
      const t = timers.get(handle);
      if (t !== undefined) clearTimeout(t);
      timers.delete(handle);
    },
  };
}

/** A scheduler driven by hand: `fire(now)` delivers the pending frame, if any. */
export class ManualScheduler implements FrameScheduler {
  private pending: FrameCallback | undefined;
  private id = 0;
  request(callback: FrameCallback): number {
    this.pending = callback;
    return ++this.id;
  }
  cancel(): void {
    this.pending = undefined;
  }
  /** Deliver one frame at `nowMs`. Returns false when nothing was waiting for a frame. */
  fire(nowMs: number): boolean {
    const cb = this.pending;
    if (!cb) return false;
    this.pending = undefined;
    cb(nowMs);
    return true;
  }
}

/**
 * Calls `onFrame` on every frame of `scheduler` between {@link start} and {@link stop}, with the
 * frame's clock reading in ms (the `requestAnimationFrame` timestamp for
 * {@link animationFrameScheduler}): pass it to `FixedLoop.frame` or `FrameStepper.frame` as it is.
 */
export class FrameDriver {
  private handle: number | undefined;
  private readonly tickCb: FrameCallback = (now) => {
    this.handle = this.scheduler.request(this.tickCb);
    this.onFrame(now);
  };
  constructor(
    private readonly scheduler: FrameScheduler,
    private readonly onFrame: FrameCallback,
  ) {}
  /** Ask for frames (again). Calling it while running does nothing. */
  start(): void {
    this.handle ??= this.scheduler.request(this.tickCb);
  }
  /** Stop asking for frames: no `onFrame` call after this one returns. */
  stop(): void {
    if (this.handle !== undefined) this.scheduler.cancel(this.handle);
    this.handle = undefined;
  }
  /** Whether a frame has been asked for. */
  get running(): boolean {
    return this.handle !== undefined;
  }
}

interface VisibilityHost {
  readonly hidden: boolean;
  addEventListener(type: 'visibilitychange', listener: () => void): void;
  removeEventListener(type: 'visibilitychange', listener: () => void): void;
}

/** Keeps `loop.setHidden` in step with the page's visibility. Returns a function that stops it. */
export function trackVisibility(
  doc: VisibilityHost,
  loop: { setHidden(hidden: boolean): void },
): () => void {
  const listener = () => {
    loop.setHidden(doc.hidden);
  };
  listener();
  doc.addEventListener('visibilitychange', listener);
  return () => {
    doc.removeEventListener('visibilitychange', listener);
  };
}
