/**
 * Opening the server's highscore store: a store or promise as given, or a prepared store opened —
 * and opened again after a growing, jittered wait while it fails for a reason that may pass — with
 * the liveness deadline `/healthz` reads. `createServer` holds one.
 * @module
 */
import { DataDirError } from './pglite.js';
import { SchemaError, type HighscoreStore, type PreparedStore } from './store.js';

/** What {@link StoreOpening} reads of the server's options (see `ServerOptions`). */
export interface StoreOpeningOptions {
  store?: HighscoreStore | Promise<HighscoreStore> | PreparedStore;
  storeRetry?: { firstMs?: number; maxMs?: number };
  storeLivenessMs?: number;
}

function isPrepared(store: StoreOpeningOptions['store']): store is PreparedStore {
  return (
    typeof store === 'object' &&
    typeof (store as Partial<PreparedStore>).open === 'function' &&
    typeof (store as Partial<PreparedStore>).release === 'function'
  );
}

/** A failure of opening that a retry cannot cure: another process holds the folder, a newer schema. */
function lasting(error: unknown): boolean {
  return error instanceof DataDirError || error instanceof SchemaError;
}

/** `FIXEDSTEP_STORE_LIVENESS_MS` read as a whole number of ms ≥ 0, or the default. */
function livenessFromEnv(env: Readonly<Record<string, string | undefined>>): number {
  const text = env.FIXEDSTEP_STORE_LIVENESS_MS;
  if (text === undefined || text === '') return 300_000;
  const ms = Number(text);
  if (!Number.isSafeInteger(ms) || ms < 0)
    throw new RangeError(
      `FIXEDSTEP_STORE_LIVENESS_MS must be a whole number of ms ≥ 0, got "${text}"`,
    );
  return ms;
}

/**
 * The store's opening: a store or promise as given, or a {@link PreparedStore} opened — and, while
 * it fails for a reason that may pass (a database that is down or slow to answer), opened again
 * after a growing, jittered wait — until it opens or {@link stop} is called.
 */
export class StoreOpening {
  /** Resolves with the open store (undefined: no store given). */
  readonly opened: Promise<HighscoreStore> | undefined;
  private readonly since = Date.now();
  private readonly livenessMs: number;
  private attempts = 0;
  private lastError: string | undefined;
  private nextTry: number | undefined;
  private stopped = false;
  private wake: (() => void) | undefined;

  constructor(
    private readonly options: StoreOpeningOptions,
    env: Readonly<Record<string, string | undefined>>,
    private readonly log: (message: string, error?: unknown) => void,
  ) {
    this.livenessMs = options.storeLivenessMs ?? livenessFromEnv(env);
    if (!Number.isSafeInteger(this.livenessMs) || this.livenessMs < 0) {
      throw new RangeError(
        `storeLivenessMs must be a whole number of ms ≥ 0, got ${String(options.storeLivenessMs)}`,
      );
    }
    const store = options.store;
    this.opened =
      store === undefined
        ? undefined
        : isPrepared(store)
          ? this.retry(store)
          : Promise.resolve(store);
  }

  private async retry(prepared: PreparedStore): Promise<HighscoreStore> {
    let wait = this.options.storeRetry?.firstMs ?? 1000;
    const longest = this.options.storeRetry?.maxMs ?? 30_000;
    for (;;) {
      this.attempts++;
      try {
        const store = await prepared.open();
        if (this.attempts > 1) this.log(`the highscore store is open (attempt ${this.attempts})`);
        return store;
      } catch (error) {
        if (lasting(error) || this.stopped) throw error;
        this.lastError = error instanceof Error ? error.message : String(error);
        const delay = Math.round(wait * (0.5 + Math.random() * 0.5));
        this.nextTry = Date.now() + delay;
        this.log(
          `the highscore store could not be opened (attempt ${this.attempts}; trying again in ${(delay / 1000).toFixed(1)} s)`,
          error,
        );
        await new Promise<void>((resolve) => {
          const timer = setTimeout(resolve, delay);
          this.wake = () => {
            clearTimeout(timer);
            resolve();
          };
        });
        this.wake = undefined;
        this.nextTry = undefined;
        if (this.isStopped()) {
          throw new Error('the server closed before the highscore store opened', { cause: error });
        }
        wait = Math.min(longest, wait * 2);
      }
    }
  }

  /** What `/readyz` says while the store is not open. */
  state(): string {
    if (this.lastError === undefined) return 'the store is opening';
    const next =
      this.nextTry === undefined
        ? 'trying again now'
        : `trying again in ${Math.max(0, (this.nextTry - Date.now()) / 1000).toFixed(1)} s`;
    return `the store could not be opened (attempt ${this.attempts}: ${this.lastError}); ${next}`;
  }

  /** Why liveness fails: the store has failed to open for longer than allowed (else undefined). */
  stuck(): string | undefined {
    if (this.livenessMs === 0 || this.lastError === undefined) return undefined;
    const waited = Date.now() - this.since;
    if (waited < this.livenessMs) return undefined;
    return `the highscore store has not opened for ${Math.round(waited / 1000)} s (${this.attempts} attempts; last: ${this.lastError})`;
  }

  private isStopped(): boolean {
    return this.stopped;
  }

  /** No more attempts (the server is closing). */
  stop(): void {
    this.stopped = true;
    this.wake?.();
  }

  /** Gives up a prepared store that never opened (its data folder's lock). */
  async release(): Promise<void> {
    if (isPrepared(this.options.store)) await this.options.store.release();
  }
}
