import pg from 'pg';
import type { Queryable, Row, SqlDriver } from './driver.js';

/** A PostgreSQL server through a `pg` connection pool, as a {@link SqlDriver}. */
class PgDriver implements SqlDriver {
  constructor(
    private readonly pool: pg.Pool,
    readonly description: string,
  ) {}

  async query(sql: string, params: readonly unknown[] = []): Promise<Row[]> {
    return (await this.pool.query<Row>(sql, [...params])).rows;
  }

  async transaction<T>(work: (tx: Queryable) => Promise<T>): Promise<T> {
    const client = await this.pool.connect();
    let broken = false;
    try {
      await client.query('BEGIN');
      const result = await work({
        query: async (sql, params = []) => (await client.query<Row>(sql, [...params])).rows,
      });
      await client.query('COMMIT');
      return result;
    } catch (error) {
      try {
        await client.query('ROLLBACK');
      } catch {
        broken = true; // the connection is gone: do not return it to the pool
      }
      throw error;
    } finally {
      client.release(broken);
    }
  }

  async close(): Promise<void> {
    await this.pool.end();
  }
}

/** Where a connection string points, without its password (for messages and logs). */
export function describeDatabaseUrl(url: string): string {
  try {
    const u = new URL(url);
    return `PostgreSQL at ${u.hostname}${u.port ? `:${u.port}` : ''}${u.pathname}`;
  } catch {
    return 'PostgreSQL (an unparsable DATABASE_URL)';
  }
}

/**
 * Connects to the PostgreSQL server of `url` (`postgres://user:pass@host:5432/db`, as in
 * `DATABASE_URL`) with a pool of at most `max` connections, and checks it answers.
 * Statements time out after `statementTimeoutMs` (default 10 s), connecting after 5 s.
 */
export async function openPostgres(
  url: string,
  options: { max?: number; statementTimeoutMs?: number } = {},
): Promise<SqlDriver> {
  const pool = new pg.Pool({
    connectionString: url,
    max: options.max ?? 10,
    connectionTimeoutMillis: 5000,
    statement_timeout: options.statementTimeoutMs ?? 10_000,
    idleTimeoutMillis: 30_000,
  });
  // An idle client that loses its server emits 'error' on the pool: the next query reconnects.
  pool.on('error', () => undefined);
  const driver = new PgDriver(pool, describeDatabaseUrl(url));
  try {
    await driver.query('select 1');
  } catch (error) {
    await pool.end().catch(() => undefined);
    throw new Error(
      `cannot reach ${driver.description}: ${error instanceof Error ? error.message : String(error)}`,
      { cause: error },
    );
  }
  return driver;
}
