import { readFile } from 'node:fs/promises';
import path from 'node:path';
import type { Queryable, Row, SqlDriver } from './driver.js';
import { claimDataDir, openPglite, type ClaimedDataDir } from './pglite.js';
import { describeDatabaseUrl, openPostgres } from './pg.js';
import { cleanName } from '../text.js';

/** One row of a game's table, as the API sends it. */
export interface HighscoreEntry {
  game: string;
  /** The game's version the run was played on (null for rows imported from the old JSON table). */
  version: string | null;
  /** The player's name, from the replay (printable, at most 32 characters). */
  name: string;
  score: number;
  /** Ticks the run lasted. */
  ticks: number;
  seed: number;
  /** The replay's final state hash, 16 hex digits. */
  finalHash: string;
  /**
   * The run's identity, 16 hex digits (see `runId`): the same run — same game, version, seed,
   * options and inputs, whatever the name — is accepted once. Rows imported from the old JSON table
   * keep their file hash, prefixed `v1-`.
   */
  replayId: string;
  /** When it was accepted (server time, ISO 8601). */
  at: string;
}

/** What storing a verified run did. */
export type StoreOutcome =
  /** New: stored with its replay, in one transaction. `rank` is 1 for the best of its game. */
  | { readonly kind: 'added'; readonly rank: number; readonly entry: HighscoreEntry }
  /** This run was already stored under this name: the same answer again (an idempotent retry). */
  | { readonly kind: 'same'; readonly rank: number; readonly entry: HighscoreEntry }
  /** This run was already stored under another name: refused. */
  | { readonly kind: 'taken'; readonly entry: HighscoreEntry };

/** The most rows {@link HighscoreStore.top} returns. */
export const TABLE_SIZE = 100;

/**
 * The migrations, in order: each runs once, in a transaction, under an advisory lock, so two
 * processes starting on one database apply them once. Never edit one that has shipped: add another.
 */
const MIGRATIONS: readonly string[] = [
  `create table highscores (
     run_id text primary key,
     game text not null,
     game_version text,
     name text not null,
     score bigint not null,
     ticks integer not null,
     seed bigint not null,
     final_hash text not null,
     submitted_at timestamptz not null
   );
   create index highscores_rank on highscores (game, score desc, ticks, submitted_at, run_id);
   create table replays (
     run_id text primary key references highscores (run_id) on delete cascade,
     bytes bytea not null
   );
   create table fixedstep_meta (key text primary key, value text not null);`,
];

/** The database was written by a newer server: retrying cannot help, upgrading the server does. */
export class SchemaError extends Error {
  override readonly name = 'SchemaError';
}

/** Any 64-bit number that identifies fixedstep's migration lock among a database's advisory locks. */
const MIGRATION_LOCK = 0x66786473; // "fxds"

const COLUMNS = 'run_id, game, game_version, name, score, ticks, seed, final_hash, submitted_at';

function toEntry(row: Row): HighscoreEntry {
  const at = row.submitted_at;
  return {
    game: String(row.game),
    version: typeof row.game_version === 'string' ? row.game_version : null,
    name: String(row.name),
    score: Number(row.score),
    ticks: Number(row.ticks),
    seed: Number(row.seed),
    finalHash: String(row.final_hash),
    replayId: String(row.run_id),
    at: (at instanceof Date ? at : new Date(String(at))).toISOString(),
  };
}

/**
 * Highscores and their replays in PostgreSQL — embedded (PGlite) or a server (`pg`), the same SQL
 * for both. Every submission is one transaction; a run is unique by its identity (not its name), so
 * two processes sharing one database accept a run once, and a failed write fails only itself.
 */
export class HighscoreStore {
  private constructor(
    private readonly db: SqlDriver,
    /** Messages from opening it (a JSON table imported, …), for the server's log. */
    readonly notes: readonly string[],
  ) {}

  /** Which database this is, for messages (no password). */
  get description(): string {
    return this.db.description;
  }

  /**
   * Opens the store over `db`: applies the migrations, and imports the old JSON table
   * `importJson` (a `highscores.json` of earlier versions) the first time it finds one.
   */
  static async open(db: SqlDriver, options: { importJson?: string } = {}): Promise<HighscoreStore> {
    try {
      await migrate(db);
      const notes: string[] = [...(db.notes ?? [])];
      if (options.importJson !== undefined) {
        const note = await importJsonTable(db, options.importJson);
        if (note !== undefined) notes.push(note);
      }
      return new HighscoreStore(db, notes);
    } catch (error) {
      await db.close().catch(() => undefined);
      throw error;
    }
  }

  /** Checks the database answers (for readiness): resolves true, or false after `timeoutMs`. */
  async ping(timeoutMs = 2000): Promise<boolean> {
    let timer: NodeJS.Timeout | undefined;
    const timeout = new Promise<boolean>((resolve) => {
      timer = setTimeout(() => {
        resolve(false);
      }, timeoutMs);
      timer.unref();
    });
    try {
      return await Promise.race([
        this.db.query('select 1').then(
          () => true,
          () => false,
        ),
        timeout,
      ]);
    } finally {
      clearTimeout(timer);
    }
  }

  /** The best `limit` (1–{@link TABLE_SIZE}) entries of `game`, best first (score, then fewer ticks, then earlier). */
  async top(game: string, limit = 10): Promise<HighscoreEntry[]> {
    const rows = await this.db.query(
      `select ${COLUMNS} from highscores where game = $1
       order by score desc, ticks, submitted_at, run_id limit $2`,
      [game, Math.max(1, Math.min(TABLE_SIZE, Math.floor(limit)))],
    );
    return rows.map(toEntry);
  }

  /** The entry of a run, or undefined. */
  async find(runId: string): Promise<HighscoreEntry | undefined> {
    const rows = await this.db.query(`select ${COLUMNS} from highscores where run_id = $1`, [
      runId,
    ]);
    return rows[0] === undefined ? undefined : toEntry(rows[0]);
  }

  /** The rank of a stored entry in its game (1 = best). */
  rank(entry: HighscoreEntry): Promise<number> {
    return rankOf(this.db, entry);
  }

  /** The stored replay of a run, or undefined. */
  async replay(runId: string): Promise<Uint8Array | undefined> {
    const rows = await this.db.query('select bytes from replays where run_id = $1', [runId]);
    const bytes = rows[0]?.bytes;
    return bytes instanceof Uint8Array ? new Uint8Array(bytes) : undefined;
  }

  /** Every entry's run id (for tests and audits). */
  async runIds(): Promise<string[]> {
    return (await this.db.query('select run_id from highscores order by run_id')).map((r) =>
      String(r.run_id),
    );
  }

  /**
   * Stores a verified run and its replay in one transaction, unless the run is there already:
   * then the answer says whether it is the same submission again (same name) or another's run.
   */
  async add(entry: HighscoreEntry, replay: Uint8Array): Promise<StoreOutcome> {
    const stored = await this.db.transaction(async (tx) => {
      const inserted = await tx.query(
        `insert into highscores (${COLUMNS}) values ($1, $2, $3, $4, $5, $6, $7, $8, $9)
         on conflict (run_id) do nothing returning run_id`,
        [
          entry.replayId,
          entry.game,
          entry.version,
          entry.name,
          entry.score,
          entry.ticks,
          entry.seed,
          entry.finalHash,
          entry.at,
        ],
      );
      if (inserted.length === 1) {
        await tx.query('insert into replays (run_id, bytes) values ($1, $2)', [
          entry.replayId,
          replay,
        ]);
        return { added: true, entry };
      }
      const rows = await tx.query(`select ${COLUMNS} from highscores where run_id = $1`, [
        entry.replayId,
      ]);
      return { added: false, entry: toEntry(rows[0]!) };
    });
    if (!stored.added && stored.entry.name !== entry.name)
      return { kind: 'taken', entry: stored.entry };
    const rank = await rankOf(this.db, stored.entry);
    return { kind: stored.added ? 'added' : 'same', rank, entry: stored.entry };
  }

  /** Closes the database (the pool, or the embedded database and its folder lock). */
  close(): Promise<void> {
    return this.db.close();
  }
}

async function rankOf(db: Queryable, e: HighscoreEntry): Promise<number> {
  const rows = await db.query(
    `select count(*)::integer as better from highscores where game = $1 and (
       score > $2 or (score = $2 and (ticks < $3 or (ticks = $3 and (
         submitted_at < $4 or (submitted_at = $4 and run_id < $5))))))`,
    [e.game, e.score, e.ticks, e.at, e.replayId],
  );
  return Number(rows[0]?.better ?? 0) + 1;
}

async function migrate(db: SqlDriver): Promise<void> {
  await db.transaction(async (tx) => {
    await tx.query('select pg_advisory_xact_lock($1)', [MIGRATION_LOCK]);
    await tx.query(
      'create table if not exists fixedstep_migrations (version integer primary key, applied_at timestamptz not null default now())',
    );
    const rows = await tx.query(
      'select coalesce(max(version), 0)::integer as v from fixedstep_migrations',
    );
    const have = Number(rows[0]?.v ?? 0);
    if (have > MIGRATIONS.length) {
      throw new SchemaError(
        `the database is at schema version ${have}, newer than this server knows (${MIGRATIONS.length}): upgrade the server`,
      );
    }
    for (let v = have + 1; v <= MIGRATIONS.length; v++) {
      for (const statement of MIGRATIONS[v - 1]!.split(';')
        .map((s) => s.trim())
        .filter(Boolean)) {
        await tx.query(statement);
      }
      await tx.query('insert into fixedstep_migrations (version) values ($1)', [v]);
    }
  });
}

interface OldEntry {
  game: string;
  name: string;
  score: number;
  ticks: number;
  seed?: number;
  finalHash?: string;
  replayId: string;
  at: string;
}

/**
 * Imports the JSON table of earlier versions (`highscores.json`: `{ format: 'fixedstep-highscores',
 * version: 1, entries }`) once: its rows keep their names, scores and times, with `v1-` before their
 * file hash as run id, and no replay (the old table kept none). The file is left as it is.
 */
async function importJsonTable(db: SqlDriver, file: string): Promise<string | undefined> {
  const key = `imported:${path.resolve(file)}`;
  if ((await db.query('select 1 from fixedstep_meta where key = $1', [key])).length > 0)
    return undefined;
  let text: string;
  try {
    text = await readFile(file, 'utf8');
  } catch (error) {
    if ((error as NodeJS.ErrnoException).code === 'ENOENT') return undefined;
    return `the old highscore table ${file} could not be read (${(error as Error).message}); not imported`;
  }
  let entries: OldEntry[];
  try {
    const data = JSON.parse(text) as { format?: unknown; entries?: unknown };
    if (data.format !== 'fixedstep-highscores' || !Array.isArray(data.entries))
      throw new Error('not a highscore table');
    entries = data.entries as OldEntry[];
    const ok = (e: OldEntry) =>
      typeof e.game === 'string' &&
      typeof e.name === 'string' &&
      Number.isSafeInteger(e.score) &&
      Number.isInteger(e.ticks) &&
      typeof e.replayId === 'string' &&
      /^[0-9a-f]{16}$/.test(e.replayId) &&
      !Number.isNaN(Date.parse(e.at));
    const bad = entries.findIndex((e) => !ok(e));
    if (bad >= 0) throw new Error(`entry ${bad} is malformed`);
  } catch (error) {
    return `the old highscore table ${file} could not be read (${(error as Error).message}); not imported, left as it is`;
  }
  await db.transaction(async (tx) => {
    for (const e of entries) {
      await tx.query(
        `insert into highscores (${COLUMNS}) values ($1, $2, null, $3, $4, $5, $6, $7, $8) on conflict (run_id) do nothing`,
        [
          `v1-${e.replayId}`,
          e.game,
          cleanName(e.name),
          e.score,
          e.ticks,
          Number.isSafeInteger(e.seed) ? e.seed : 0,
          typeof e.finalHash === 'string' ? e.finalHash : '',
          new Date(e.at).toISOString(),
        ],
      );
    }
    await tx.query('insert into fixedstep_meta (key, value) values ($1, $2)', [
      key,
      new Date().toISOString(),
    ]);
  });
  return `imported ${entries.length} highscores from ${file} (the file is kept as it was)`;
}

/** Where the store lives: a data folder (embedded PGlite), a PostgreSQL server, or memory. */
export interface OpenStoreOptions {
  /**
   * A PostgreSQL connection string (`DATABASE_URL`): scores go to that server, and any number of
   * server processes may share it. Without it, the embedded database in `dataDir` is used.
   */
  databaseUrl?: string;
  /**
   * The data folder of the embedded database (`<dataDir>/pglite`), locked for this process; its
   * old `highscores.json`, if any, is imported once. Undefined with no `databaseUrl`: in memory.
   */
  dataDir?: string;
  /** For the embedded database in memory: a `dumpDataDir()` to start from (skips `initdb`; tests). */
  template?: Blob;
  /**
   * Modules (paths or URLs) the embedded database's thread imports before it opens the database
   * (a test holds the opening on a gate this way).
   */
  preload?: readonly string[];
}

/** A store whose location was checked, ready to be opened (see {@link prepareStore}). */
export interface PreparedStore {
  /** Where it will be: `PGlite in <dir>/pglite`, `PostgreSQL at host:port/db`, `PGlite in memory`. */
  readonly description: string;
  /**
   * Opens it (the slow part: PGlite's first `initdb` takes seconds; connecting to PostgreSQL). May
   * be called again after it failed (a database that was down): `createServer` retries it with a
   * backoff until it succeeds.
   */
  open(): Promise<HighscoreStore>;
  /** Gives up the data folder's lock, when the store is given up before it ever opened. */
  release(): Promise<void>;
}

/**
 * The fast part of {@link openStore}: checks and locks the data folder (the embedded database), so
 * a folder that cannot be used or is in use by another process fails at once with the reason; the
 * database itself is opened by `open()` — a server can listen meanwhile.
 */
export async function prepareStore(options: OpenStoreOptions = {}): Promise<PreparedStore> {
  const importJson =
    options.dataDir !== undefined
      ? { importJson: path.join(path.resolve(options.dataDir), 'highscores.json') }
      : {};
  const nothing = () => Promise.resolve();
  if (options.databaseUrl !== undefined && options.databaseUrl !== '') {
    const url = options.databaseUrl;
    return {
      description: describeDatabaseUrl(url),
      open: async () => HighscoreStore.open(await openPostgres(url), importJson),
      release: nothing,
    };
  }
  const preload = options.preload !== undefined ? { preload: options.preload } : {};
  if (options.dataDir === undefined) {
    return {
      description: 'PGlite in memory',
      open: async () =>
        HighscoreStore.open(
          await openPglite(undefined, {
            ...preload,
            ...(options.template ? { template: options.template } : {}),
          }),
        ),
      release: nothing,
    };
  }
  const dataDir = options.dataDir;
  let claimed: ClaimedDataDir | undefined = await claimDataDir(dataDir);
  const dir = claimed.dir;
  return {
    description: `PGlite in ${path.join(dir, 'pglite')}`,
    open: async () => {
      // A failed attempt that got as far as opening the database gave the lock up with it.
      const mine = (claimed ??= await claimDataDir(dataDir));
      const lock: ClaimedDataDir = {
        dir,
        release: async () => {
          if (claimed === mine) claimed = undefined;
          await mine.release();
        },
      };
      return HighscoreStore.open(await openPglite(dir, { claimed: lock, ...preload }), importJson);
    },
    release: async () => {
      await claimed?.release();
      claimed = undefined;
    },
  };
}

/**
 * Opens the highscore store: PostgreSQL at `databaseUrl` when given, else the embedded PGlite in
 * `dataDir` (or in memory). Migrates it, and imports `<dataDir>/highscores.json` once when present.
 */
export async function openStore(options: OpenStoreOptions = {}): Promise<HighscoreStore> {
  const prepared = await prepareStore(options);
  try {
    return await prepared.open();
  } catch (error) {
    await prepared.release();
    throw error;
  }
}
