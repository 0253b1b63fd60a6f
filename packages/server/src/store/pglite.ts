import { spawn } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { mkdir, open, readFile, readdir, rename, rm, stat, unlink } from 'node:fs/promises';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { Worker } from 'node:worker_threads';
import type { Queryable, Row, SqlDriver } from './driver.js';
import { PGLITE_START_PARAMS, type PgliteWorkerData, type WorkerError } from './pglite-protocol.js';
import { workerScript } from '../worker-script.js';

interface Pending {
  resolve: (rows: Row[]) => void;
  reject: (error: Error) => void;
}

/** An error of the database's thread, rebuilt on this one (name, message, code). */
function rebuild(error: WorkerError): Error {
  return Object.assign(new Error(error.message), {
    name: error.name,
    ...(error.code !== undefined ? { code: error.code } : {}),
  });
}

/**
 * The embedded PostgreSQL (PGlite) as a {@link SqlDriver}, in its own worker thread: every
 * statement is a message to it, so the event loop never waits for the database.
 */
class PgliteDriver implements SqlDriver {
  private readonly pending = new Map<number, Pending>();
  private nextId = 1;
  private stopped: Error | undefined;

  constructor(
    private readonly worker: Worker,
    readonly description: string,
    private readonly release: () => Promise<void>,
    readonly notes: readonly string[],
  ) {
    worker.on('message', (m: { id?: number; rows?: Row[]; error?: WorkerError }) => {
      const waiting = m.id === undefined ? undefined : this.pending.get(m.id);
      if (waiting === undefined) return;
      this.pending.delete(m.id!);
      if (m.error !== undefined) waiting.reject(rebuild(m.error));
      else waiting.resolve(m.rows ?? []);
    });
    worker.on('error', (error) => {
      this.stop(new Error(`the embedded database's thread failed: ${error.message}`));
    });
    worker.on('exit', () => {
      this.stop(new Error("the embedded database's thread has stopped"));
    });
  }

  private stop(error: Error): void {
    this.stopped ??= error;
    for (const waiting of this.pending.values()) waiting.reject(this.stopped);
    this.pending.clear();
  }

  private call(message: Record<string, unknown>): Promise<Row[]> {
    if (this.stopped !== undefined) return Promise.reject(this.stopped);
    const id = this.nextId++;
    return new Promise<Row[]>((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.worker.postMessage({ ...message, id });
    });
  }

  query(sql: string, params: readonly unknown[] = []): Promise<Row[]> {
    return this.call({ op: 'query', sql, params: [...params] });
  }

  async transaction<T>(work: (tx: Queryable) => Promise<T>): Promise<T> {
    const tx = this.nextId; // the id of the `begin` names the transaction
    await this.call({ op: 'begin' });
    let result: T;
    try {
      result = await work({
        query: (sql, params = []) => this.call({ op: 'query', sql, params: [...params], tx }),
      });
    } catch (error) {
      await this.call({ op: 'end', tx, commit: false }).catch(() => undefined);
      throw error;
    }
    await this.call({ op: 'end', tx, commit: true });
    return result;
  }

  async close(): Promise<void> {
    try {
      await this.call({ op: 'close' }).catch(() => undefined);
      await this.worker.terminate();
    } finally {
      await this.release();
    }
  }
}

/** Options of {@link openPglite}. */
export interface PgliteOptions {
  /** For a database in memory: a `dumpDataDir()` to start from (skips `initdb`; tests). */
  template?: Blob;
  /** The data folder, already claimed by {@link claimDataDir}. */
  claimed?: ClaimedDataDir;
  /**
   * Modules (URLs or paths) the database's thread imports before it opens the database — a test
   * holds the opening on a gate this way.
   */
  preload?: readonly string[];
}

/**
 * Starts the database's thread on `data` and resolves once it has opened the database (with the
 * worker), or rejects with the reason it could not: `opening` true when PGlite itself refused.
 */
function startWorker(
  data: PgliteWorkerData,
): Promise<{ worker: Worker } | { error: Error; opening: boolean }> {
  const { url, execArgv } = workerScript('./pglite-worker.js', import.meta.url);
  const worker = new Worker(url, { workerData: data, ...(execArgv ? { execArgv } : {}) });
  return new Promise((resolve) => {
    let failure: Error | undefined;
    const onMessage = (m: { opened?: boolean; error?: WorkerError }) => {
      if (m.opened === undefined) return;
      worker.off('message', onMessage);
      worker.off('exit', onExit);
      if (m.opened) {
        resolve({ worker });
      } else {
        void worker.terminate();
        resolve({
          error: rebuild(m.error ?? { name: 'Error', message: 'unknown' }),
          opening: true,
        });
      }
    };
    const onExit = () => {
      worker.off('message', onMessage);
      resolve({
        error: failure ?? new Error("the embedded database's thread stopped while opening"),
        opening: false,
      });
    };
    worker.on('message', onMessage);
    worker.on('error', (error) => (failure ??= error));
    worker.once('exit', onExit);
  });
}

/** Errors of the file system (a full disk, no permission): setting the folder aside cannot help. */
const FILE_SYSTEM_ERRORS = new Set([
  'EACCES',
  'EPERM',
  'EROFS',
  'ENOSPC',
  'EMFILE',
  'ENFILE',
  'EIO',
]);

/** Whether a folder exists and holds anything. */
async function hasFiles(dir: string): Promise<boolean> {
  try {
    return (await readdir(dir)).length > 0;
  } catch {
    return false;
  }
}

/** The data folder is in use by another process (or cannot be used at all). */
export class DataDirError extends Error {
  override readonly name = 'DataDirError';
}

/** The lock files this process holds (a lock naming this pid but not held here is stale). */
const held = new Set<string>();

/**
 * Takes `<dir>/pglite.lock` for this process: created exclusively with our identity in it — the
 * pid, and on Linux the process's start time and the machine's boot id. PGlite is one process's
 * database; two processes writing one data folder lose scores, so a second one is refused with the
 * owner's pid. A lock is stale, and taken over, when its process is gone, when the machine has
 * booted since (another boot id), when its pid now belongs to a process that started later (a pid
 * reused — after a reboot, or in a container, where the server is pid 1 every time), or when it
 * names this very process's pid without this process holding it.
 */
async function lockDataDir(dir: string): Promise<() => Promise<void>> {
  const lock = path.join(dir, 'pglite.lock');
  for (let attempt = 0; attempt < 3; attempt++) {
    try {
      const handle = await open(lock, 'wx');
      const me = processIdentity(process.pid);
      await handle.writeFile(
        `${me ?? process.pid}${me !== undefined ? ` ${bootId() ?? ''}` : ''}\n`,
      );
      await handle.close();
      held.add(lock);
      return async () => {
        held.delete(lock);
        await unlink(lock).catch(() => undefined);
      };
    } catch (error) {
      if ((error as NodeJS.ErrnoException).code !== 'EEXIST') throw error;
    }
    const [text, written] = await Promise.all([
      readFile(lock, 'utf8').catch(() => ''),
      stat(lock).then(
        (s) => s.mtimeMs,
        () => undefined,
      ),
    ]);
    const [pidText = '', started, boot] = text.trim().split(/\s+/);
    const owner = Number(pidText);
    if (held.has(lock)) {
      throw new DataDirError(`the data folder ${dir} is already open in this process`);
    }
    if (
      Number.isInteger(owner) &&
      owner > 0 &&
      owner !== process.pid &&
      lockHolderAlive(owner, started, boot, written)
    ) {
      throw new DataDirError(
        `the data folder ${dir} is in use by process ${owner}: the embedded database serves one process. ` +
          'To run several server processes, give them one PostgreSQL server with DATABASE_URL. ' +
          `If no server runs on this folder, process ${owner} is another program: delete ${lock}.`,
      );
    }
    await rm(lock, { force: true }); // stale
  }
  throw new DataDirError(`cannot take the lock ${lock}`);
}

/**
 * `<pid> <start time>` of a running process, from Linux's /proc (the start time in clock ticks
 * since boot tells a process from a later one that reuses its pid), or undefined when there is no
 * such process, it has exited (a zombie: a killed process whose parent has not reaped it still
 * answers `kill(pid, 0)`), or there is no /proc.
 */
function processIdentity(pid: number): string | undefined {
  const started = processStart(pid);
  return started === undefined ? undefined : `${pid} ${started}`;
}

/** A running process's start, in clock ticks since boot (see {@link processIdentity}). */
function processStart(pid: number): number | undefined {
  let stat: string;
  try {
    stat = readFileSync(`/proc/${pid}/stat`, 'utf8');
  } catch {
    return undefined;
  }
  // `pid (comm) state ppid …`: the name may hold spaces and parentheses, so read after the last ')'.
  const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
  const state = fields[0];
  if (state === 'Z' || state === 'X' || state === 'x') return undefined;
  return Number(fields[19]);
}

/** This boot of the machine (Linux), or undefined. */
function bootId(): string | undefined {
  try {
    return readFileSync('/proc/sys/kernel/random/boot_id', 'utf8').trim() || undefined;
  } catch {
    return undefined;
  }
}

/** When the machine booted, in ms since 1970 (Linux's /proc/stat `btime`), or undefined. */
function bootTime(): number | undefined {
  try {
    const line = /^btime (\d+)$/m.exec(readFileSync('/proc/stat', 'utf8'));
    return line === null ? undefined : Number(line[1]) * 1000;
  } catch {
    return undefined;
  }
}

/** Clock ticks a second in /proc's times (`USER_HZ`: 100 on every Linux architecture Node runs on). */
const USER_HZ = 100;

/**
 * Whether the process that wrote a lock still runs: `pid`, and if recorded its start time and the
 * boot it ran in; `writtenMs` is the lock file's modification time, which tells an old-style lock
 * (the pid alone) from a process that started after the lock was written.
 */
function lockHolderAlive(
  pid: number,
  started: string | undefined,
  boot: string | undefined,
  writtenMs: number | undefined,
): boolean {
  if (existsSync('/proc/self/stat')) {
    const now = processStart(pid);
    if (now === undefined) return false;
    if (boot !== undefined && boot !== '' && boot !== bootId()) return false;
    if (started !== undefined && started !== '') return String(now) === started;
    const booted = bootTime();
    // Started after the lock was written (with a second's slack for clock ticks): not its writer.
    if (booted !== undefined && writtenMs !== undefined)
      return booted + (now / USER_HZ) * 1000 <= writtenMs + 1000;
    return true;
  }
  try {
    process.kill(pid, 0);
    return true;
  } catch (error) {
    return (error as NodeJS.ErrnoException).code === 'EPERM';
  }
}

/**
 * `mkdir -p`, one level at a time. Node's own recursive mkdir never returns for a path under
 * `/proc` (each level answers ENOENT and it retries forever); this walks up to the first existing
 * ancestor and creates each missing level once, so it fails at once with the reason.
 */
export async function makeDirectory(dir: string): Promise<void> {
  const missing: string[] = [];
  let at = path.resolve(dir);
  for (;;) {
    try {
      if (!(await stat(at)).isDirectory()) throw new Error(`${at} is not a directory`);
      break;
    } catch (error) {
      const parent = path.dirname(at);
      if ((error as NodeJS.ErrnoException).code !== 'ENOENT' || parent === at) throw error;
      missing.push(at);
      at = parent;
    }
  }
  for (const level of missing.reverse()) {
    try {
      await mkdir(level);
    } catch (error) {
      if ((error as NodeJS.ErrnoException).code !== 'EEXIST') throw error;
    }
  }
}

/** A data folder checked and locked for this process (see {@link claimDataDir}). */
export interface ClaimedDataDir {
  /** The folder, absolute. */
  readonly dir: string;
  /** Gives the lock up (closing the database does it too). */
  release(): Promise<void>;
}

/**
 * Checks that `dataDir` can hold the embedded database (created if missing; a file can be created
 * in it — so `/proc/x` or a read-only mount fails at once, with the reason) and locks it for this
 * process. Fast: it does not open the database.
 */
export async function claimDataDir(dataDir: string): Promise<ClaimedDataDir> {
  const dir = path.resolve(dataDir);
  try {
    await makeDirectory(dir);
    const probe = path.join(dir, `.probe-${process.pid}`);
    await (await open(probe, 'w')).close();
    await unlink(probe);
  } catch (error) {
    throw new DataDirError(
      `cannot use ${dir} as the data folder: ${error instanceof Error ? error.message : String(error)}`,
    );
  }
  return { dir, release: await lockDataDir(dir) };
}

/**
 * Creates a new database folder (`initdb`) in a short-lived child process:
 * `initdb` leaves some hundred MB behind in whatever process runs it — a worker thread gives its
 * heap back when it ends, but not the C library's arenas — and a process gives everything back.
 * The child compiles PostgreSQL's module with V8's baseline tier only: `initdb` runs once, and
 * optimising the functions it finds hot cost more than it saved (measured: 4.0 s → 2.4 s, peak
 * memory 760 → 670 MB).
 */
async function initInChild(where: string): Promise<{ error: Error; opening: boolean } | undefined> {
  const pglite = import.meta.resolve('@electric-sql/pglite');
  const script = `
    const { PGlite } = await import(${JSON.stringify(pglite)});
    const db = await PGlite.create({
      dataDir: ${JSON.stringify(where)},
      startParams: [...PGlite.defaultStartParams, ...${JSON.stringify(PGLITE_START_PARAMS)}],
    });
    await db.close();`;
  const child = spawn(process.execPath, ['--liftoff-only', '--input-type=module', '-e', script], {
    stdio: ['ignore', 'ignore', 'pipe'],
  });
  let said = '';
  child.stderr.on('data', (d: Buffer) => {
    said = (said + d.toString()).slice(-4000);
  });
  const [code, signal] = await new Promise<[number | null, NodeJS.Signals | null]>((resolve) => {
    child.once('exit', (c, s) => {
      resolve([c, s]);
    });
    child.once('error', () => {
      resolve([null, null]);
    });
  });
  if (code === 0) return undefined;
  const fatal = said
    .split('\n')
    .filter((l) => /\b(PANIC|FATAL|ERROR|Error)\b/.test(l))
    .slice(-3)
    .join(' / ');
  return {
    error: new Error(
      `initdb failed (${signal ?? `exit ${String(code)}`})${fatal === '' ? '' : `: ${fatal.trim()}`}`,
    ),
    opening: true,
  };
}

/** Opens the database in `where` in a worker thread, creating it first if it is new. */
async function openFolder(
  where: string,
  preload: readonly string[],
): Promise<{ worker: Worker } | { error: Error; opening: boolean }> {
  if (!existsSync(path.join(where, 'PG_VERSION'))) {
    const failed = await initInChild(where);
    if (failed !== undefined) return failed;
  }
  return startWorker({ dataDir: where, preload });
}

/** A time for a file name: `2026-12-07T05-12-44Z`. */
function fileStamp(date: Date): string {
  return date
    .toISOString()
    .replace(/\.\d+Z$/, 'Z')
    .replaceAll(':', '-');
}

/**
 * Opens (creating it the first time) the embedded PostgreSQL database in `<dataDir>/pglite`, or an
 * in-memory one when `dataDir` is undefined, in a worker thread of its own. The folder is locked
 * for this process ({@link claimDataDir}, unless `claimed` says it already is — then the caller
 * keeps the lock whatever happens). The first open of a new folder runs `initdb` (seconds, in a
 * child process that ends after it, taking its memory along); later opens take about a second.
 *
 * A folder PGlite cannot open (a damaged file: PGlite says little more than `Aborted()`) is set
 * aside as `<dataDir>/pglite.corrupt-<time>` — kept as it was, never deleted — and a new, empty
 * database takes its place; {@link SqlDriver.notes} says so, naming both folders and the cause.
 * File-system errors (no permission, a full disk) are not set aside: they are thrown.
 */
export async function openPglite(
  dataDir: string | undefined,
  options: PgliteOptions = {},
): Promise<SqlDriver> {
  const preload = (options.preload ?? []).map((p) =>
    /^[a-z][a-z0-9+.-]*:/i.test(p) ? p : pathToFileURL(path.resolve(p)).href,
  );
  if (dataDir === undefined) {
    const template =
      options.template === undefined
        ? undefined
        : new Uint8Array(await options.template.arrayBuffer());
    const started = await startWorker({
      preload,
      ...(template !== undefined ? { template } : {}),
    });
    if ('error' in started) throw started.error;
    return new PgliteDriver(started.worker, 'PGlite in memory', () => Promise.resolve(), []);
  }
  const claimed = options.claimed ?? (await claimDataDir(dataDir));
  const where = path.join(claimed.dir, 'pglite');
  try {
    const notes: string[] = [];
    let started = await openFolder(where, preload);
    if (
      'error' in started &&
      started.opening &&
      !FILE_SYSTEM_ERRORS.has((started.error as NodeJS.ErrnoException).code ?? '') &&
      (await hasFiles(where))
    ) {
      const aside = `${where}.corrupt-${fileStamp(new Date())}`;
      await rename(where, aside);
      notes.push(
        `the embedded database in ${where} could not be opened (${started.error.message}); ` +
          `it was set aside, unchanged, as ${aside}, and a new, empty database was created in its place. ` +
          `To try the old one again: stop the server and move ${aside} back to ${where}.`,
      );
      started = await openFolder(where, preload);
    }
    if ('error' in started) {
      throw new Error(`cannot open the embedded database in ${where}: ${started.error.message}`, {
        cause: started.error,
      });
    }
    return new PgliteDriver(started.worker, `PGlite in ${where}`, () => claimed.release(), notes);
  } catch (error) {
    if (options.claimed === undefined) await claimed.release();
    throw error;
  }
}
