import { existsSync, readFileSync } from 'node:fs';
import { mkdir, open, readFile, rm, stat, unlink } from 'node:fs/promises';
import path from 'node:path';
import { PGlite } from '@electric-sql/pglite';
import type { Queryable, Row, SqlDriver } from './driver.js';

/** The embedded PostgreSQL (PGlite) as a {@link SqlDriver}. */
class PgliteDriver implements SqlDriver {
  constructor(
    private readonly db: PGlite,
    readonly description: string,
    private readonly release: () => Promise<void>,
  ) {}

  async query(sql: string, params: readonly unknown[] = []): Promise<Row[]> {
    return (await this.db.query<Row>(sql, [...params])).rows;
  }

  transaction<T>(work: (tx: Queryable) => Promise<T>): Promise<T> {
    return this.db.transaction((tx) =>
      work({ query: async (sql, params = []) => (await tx.query<Row>(sql, [...params])).rows }),
    );
  }

  async close(): Promise<void> {
    try {
      await this.db.close();
    } finally {
      await this.release();
    }
  }
}

/** The data folder is in use by another process (or cannot be used at all). */
export class DataDirError extends Error {
  override readonly name = 'DataDirError';
}

/**
 * Takes `<dir>/pglite.lock` for this process: created exclusively with our identity in it (the
 * pid, and on Linux the process's start time). A lock whose process is gone is taken over. PGlite
 * is one process's database; two processes writing one data folder lose scores, so a second one is
 * refused with the owner's pid.
 */
async function lockDataDir(dir: string): Promise<() => Promise<void>> {
  const lock = path.join(dir, 'pglite.lock');
  for (let attempt = 0; attempt < 3; attempt++) {
    try {
      const handle = await open(lock, 'wx');
      await handle.writeFile(`${processIdentity(process.pid) ?? process.pid}\n`);
      await handle.close();
      return async () => {
        await unlink(lock).catch(() => undefined);
      };
    } catch (error) {
      if ((error as NodeJS.ErrnoException).code !== 'EEXIST') throw error;
    }
    const [pidText = '', started] = (await readFile(lock, 'utf8').catch(() => ''))
      .trim()
      .split(/\s+/);
    const owner = Number(pidText);
    if (owner === process.pid) {
      throw new DataDirError(`the data folder ${dir} is already open in this process`);
    }
    if (Number.isInteger(owner) && owner > 0 && lockHolderAlive(owner, started)) {
      throw new DataDirError(
        `the data folder ${dir} is in use by process ${owner}: the embedded database serves one process. ` +
          'To run several server processes, give them one PostgreSQL server with DATABASE_URL.',
      );
    }
    await rm(lock, { force: true }); // stale: its process is gone
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
  return `${pid} ${fields[19]}`;
}

/** Whether the process that wrote a lock (`pid`, and its start time if recorded) still runs. */
function lockHolderAlive(pid: number, started: string | undefined): boolean {
  if (existsSync('/proc/self/stat')) {
    const now = processIdentity(pid);
    return now !== undefined && (started === undefined || now === `${pid} ${started}`);
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
 * Opens (creating it the first time) the embedded PostgreSQL database in `<dataDir>/pglite`, or an
 * in-memory one when `dataDir` is undefined. The folder is locked for this process ({@link
 * claimDataDir}, unless `claimed` says it already is). The first open of a new folder runs `initdb`
 * (seconds); later opens take about a second.
 */
export async function openPglite(
  dataDir: string | undefined,
  options: { template?: Blob; claimed?: ClaimedDataDir } = {},
): Promise<SqlDriver> {
  if (dataDir === undefined) {
    const db = await PGlite.create(options.template ? { loadDataDir: options.template } : {});
    return new PgliteDriver(db, 'PGlite in memory', () => Promise.resolve());
  }
  const claimed = options.claimed ?? (await claimDataDir(dataDir));
  const where = path.join(claimed.dir, 'pglite');
  try {
    const db = await PGlite.create({ dataDir: where });
    return new PgliteDriver(db, `PGlite in ${where}`, () => claimed.release());
  } catch (error) {
    await claimed.release();
    throw error;
  }
}
