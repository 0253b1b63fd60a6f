/**
 * The one thing the highscore store needs from a database: run a parameterised statement, and run
 * several in one transaction. Two drivers implement it over the same SQL — embedded PostgreSQL
 * (PGlite, in the process) and a PostgreSQL server (`pg`) — so the migrations and the queries are
 * written once.
 * @module
 */

/** A row as the driver returns it (column name → value). */
export type Row = Record<string, unknown>;

/** Runs statements: `$1, $2, …` placeholders, parameters as JavaScript values. */
export interface Queryable {
  query(sql: string, params?: readonly unknown[]): Promise<Row[]>;
}

/** A database connection (a pool, or an embedded database). */
export interface SqlDriver extends Queryable {
  /** What this is, for messages: `PGlite at ./data/pglite`, `PostgreSQL at host:5432/db`. */
  readonly description: string;
  /** What opening it did that an operator should know (a damaged folder set aside, …). */
  readonly notes?: readonly string[];
  /**
   * Runs `work` in one transaction (BEGIN … COMMIT, ROLLBACK when it throws), on one connection.
   */
  transaction<T>(work: (tx: Queryable) => Promise<T>): Promise<T>;
  /** Closes the connection (the pool, the embedded database). */
  close(): Promise<void>;
}
