/**
 * An HTTP request that copes with a busy server: `503` (the server's verification queue is full,
 * `BUSY`; the store is opening) and `429` (a rate limit) are answered again after the server's
 * `Retry-After`, or after an exponential back-off when it names none, each wait stretched by a
 * random jitter so that a burst of clients refused together does not come back together. A request
 * that cannot reach the server at all (a restart, a lost connection) is retried the same way.
 * Every other answer — success or refusal — is returned at once.
 * @module
 */
import {
  abortReason,
  type AbortSignalLike,
  type FetchInit,
  type FetchResponse,
} from './platform.js';

/** One wait before another attempt, as {@link FetchRetryOptions.onRetry} is told of it. */
export interface FetchRetry {
  /** The attempt about to be made after the wait: 2 for the first retry. */
  readonly attempt: number;
  /** How long this wait is, in ms (the server's `Retry-After` or the back-off, with jitter). */
  readonly delayMs: number;
  /** The status that asked for the wait, or 0 when the server could not be reached. */
  readonly status: number;
  /** The server's `Retry-After`, in ms, when it sent one. */
  readonly retryAfterMs?: number;
}

/** Options of {@link fetchWithRetry}. */
export interface FetchRetryOptions {
  /** Attempts after the first (default 4); then the last answer is returned, or the error thrown. */
  readonly retries?: number;
  /** The first back-off when the server names no `Retry-After`, in ms (default 1,000); doubled each attempt. */
  readonly baseDelayMs?: number;
  /** The longest wait, in ms (default 30,000), also for a `Retry-After` beyond it. */
  readonly maxDelayMs?: number;
  /** A uniform number in [0, 1) for the jitter (default `Math.random`; a test passes its own). */
  readonly random?: () => number;
  /** Waits `ms` (default a timer); rejects when `signal` aborts. */
  readonly sleep?: (ms: number, signal?: AbortSignalLike) => Promise<void>;
  /** Told before each wait: a page says "the server is busy: your score is queued". */
  readonly onRetry?: (retry: FetchRetry) => void;
  /** The request's `fetch` (default the global one). */
  readonly fetch?: (url: string, init?: FetchInit) => Promise<FetchResponse>;
}

/** The statuses that mean "the same request may succeed later". */
const RETRYABLE = new Set([429, 503]);

/** A wait is stretched by up to this fraction of itself, at random. */
const JITTER = 0.5;

/**
 * `fetch(url, init)`, answered again after a wait while the server says it is busy (503) or
 * rate-limited (429), or cannot be reached. The body must be re-sendable (a string, bytes, not a
 * stream). Aborting `init.signal` stops the waiting too.
 */
export async function fetchWithRetry(
  url: string,
  init: FetchInit = {},
  options: FetchRetryOptions = {},
): Promise<FetchResponse> {
  const retries = options.retries ?? 4;
  const base = options.baseDelayMs ?? 1000;
  const max = options.maxDelayMs ?? 30_000;
  const random = options.random ?? Math.random;
  const sleep = options.sleep ?? wait;
  const doFetch = options.fetch ?? ((u: string, i?: FetchInit) => fetch(u, i));
  if (!Number.isInteger(retries) || retries < 0) {
    throw new RangeError(`fetchWithRetry: retries must be a whole number ≥ 0, got ${retries}`);
  }
  for (let attempt = 1; ; attempt++) {
    let response: FetchResponse | undefined;
    let failure: unknown;
    try {
      response = await doFetch(url, init);
    } catch (error) {
      if (init.signal?.aborted) throw error;
      failure = error;
    }
    if (response !== undefined && !RETRYABLE.has(response.status)) return response;
    if (attempt > retries) {
      if (response !== undefined) return response;
      throw failure;
    }
    const retryAfterMs = response
      ? parseRetryAfter(response.headers.get('retry-after'))
      : undefined;
    const backoff = Math.min(max, base * 2 ** (attempt - 1));
    const delayMs = Math.round(Math.min(max, retryAfterMs ?? backoff) * (1 + JITTER * random()));
    // The refused answer's body is not read: release it before waiting.
    await response?.body?.cancel().catch(() => undefined);
    options.onRetry?.({
      attempt: attempt + 1,
      delayMs,
      status: response?.status ?? 0,
      ...(retryAfterMs !== undefined ? { retryAfterMs } : {}),
    });
    await sleep(delayMs, init.signal ?? undefined);
  }
}

/**
 * A `Retry-After` header in ms: delay-seconds (RFC 9110 §10.2.3; the HTTP-date form is not used
 * by fixedstep's server and is ignored), or undefined.
 */
export function parseRetryAfter(value: string | null): number | undefined {
  if (value === null || !/^\s*\d+\s*$/.test(value)) return undefined;
  return Number(value) * 1000;
}

function wait(ms: number, signal?: AbortSignalLike): Promise<void> {
  return new Promise((resolve, reject) => {
    if (signal?.aborted) {
      reject(abortReason(signal));
      return;
    }
    const timer = setTimeout(() => {
      signal?.removeEventListener('abort', onAbort);
      resolve();
    }, ms);
    const onAbort = () => {
      clearTimeout(timer);
      reject(abortReason(signal!));
    };
    signal?.addEventListener('abort', onAbort, { once: true });
  });
}
