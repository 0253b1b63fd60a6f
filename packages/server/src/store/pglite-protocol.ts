/**
 * What the main thread and the embedded database's thread (`pglite-worker.ts`) share.
 * @module
 */

/** The worker's start: where the database is, and what to import first. */
export interface PgliteWorkerData {
  /** The database folder (`<data>/pglite`); undefined: in memory. */
  readonly dataDir?: string;
  /** For a database in memory: a `dumpDataDir()` to start from (skips `initdb`). */
  readonly template?: Uint8Array<ArrayBuffer>;
  /** Modules the thread imports before it opens the database (see `PgliteOptions.preload`). */
  readonly preload: readonly string[];
}

/** An error as it crosses from the worker: its name, message and (PostgreSQL or errno) code. */
export interface WorkerError {
  readonly name: string;
  readonly message: string;
  readonly code?: string;
}

/**
 * PostgreSQL settings added to PGlite's own start parameters. PGlite's default `shared_buffers` is
 * 128 MB of the WebAssembly heap, touched as pages are cached; the highscore queries read a few
 * index and heap pages (the rest comes from the operating system's file cache, as PGlite reads real
 * files), so 4 MB is plenty (measured, PGlite alone in a process after 2,000 inserts and top-10
 * reads: 164 MB with 4 MB, 175 MB with 16 MB, as fast).
 */
export const PGLITE_START_PARAMS: readonly string[] = ['-c', 'shared_buffers=4MB'];
