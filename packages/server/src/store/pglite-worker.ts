/**
 * The embedded database's thread: opens PGlite (PostgreSQL compiled to WebAssembly) and runs the
 * statements the main thread sends, so neither its start (compiling the module, `initdb`, replaying
 * the WAL: seconds) nor a statement ever blocks the server's event loop. Started by `openPglite`;
 * not meant to be imported.
 *
 * Messages in: `{ id, op: 'query', sql, params, tx? }`, `{ id, op: 'begin' }` (answered once the
 * transaction holds the database; its statements then carry `tx: id`), `{ id, op: 'end', tx,
 * commit }`, `{ id, op: 'close' }`. Out: `{ opened: true }` or `{ opened: false, error }` once, then
 * `{ id, rows }` or `{ id, error }` per message.
 * @module
 */
import v8 from 'node:v8';
import { parentPort, workerData } from 'node:worker_threads';
import { PGlite, type Transaction } from '@electric-sql/pglite';
import { PGLITE_START_PARAMS, type PgliteWorkerData, type WorkerError } from './pglite-protocol.js';

const port = parentPort;
if (port === null) throw new Error('store/pglite-worker.js runs as a worker thread of openPglite');
const data = workerData as PgliteWorkerData;

type Message =
  | { id: number; op: 'query'; sql: string; params: unknown[]; tx?: number }
  | { id: number; op: 'begin' }
  | { id: number; op: 'end'; tx: number; commit: boolean }
  | { id: number; op: 'close' };

function describe(error: unknown): WorkerError {
  if (error instanceof Error) {
    const code = (error as { code?: unknown }).code;
    return {
      name: error.name,
      message: error.message,
      ...(typeof code === 'string' ? { code } : {}),
    };
  }
  return { name: 'Error', message: String(error) };
}

/** Thrown inside a transaction's callback to roll it back. */
const ROLLBACK = new Error('rolled back by the main thread');

/** PostgreSQL's last messages while opening (they name the cause PGlite's own error does not). */
const said: string[] = [];
function hear(text: string): boolean {
  if (/\b(PANIC|FATAL|ERROR)\b/.test(text)) said.push(text.trim());
  if (said.length > 3) said.shift();
  return false;
}

async function open(): Promise<PGlite> {
  for (const url of data.preload) await import(url);
  // PostgreSQL's WebAssembly module is large, and while it starts (WAL replay, catalog loads) V8
  // finds much of it hot and compiles it a second time with its optimising tier: ~40 MB of code
  // the highscore table's few queries never need (measured: RSS after opening 166 → 128 MB, the
  // queries after it as fast). So the module compiles with the baseline tier only; the flag is
  // V8's, process-wide, and is put back as soon as the database is open — functions that get hot
  // later still tier up, here and in every other thread.
  v8.setFlagsFromString('--liftoff-only');
  try {
    return await PGlite.create({
      onStderr: hear,
      onStdout: hear,
      ...(data.dataDir !== undefined ? { dataDir: data.dataDir } : {}),
      ...(data.template !== undefined ? { loadDataDir: new Blob([data.template]) } : {}),
      startParams: [...PGlite.defaultStartParams, ...PGLITE_START_PARAMS],
    });
  } finally {
    v8.setFlagsFromString('--no-liftoff-only');
  }
}

let db: PGlite;
try {
  db = await open();
} catch (error) {
  const described = describe(error);
  port.postMessage({
    opened: false,
    error:
      said.length === 0
        ? described
        : { ...described, message: `${described.message}; PostgreSQL said: ${said.join(' / ')}` },
  });
  // Nothing more to do: the main thread ends this thread.
  await new Promise(() => undefined);
  throw error;
}
port.postMessage({ opened: true });

/** Open transactions by the id of their `begin`: their handle, and how to end them. */
const transactions = new Map<number, { tx: Transaction; end: (commit: boolean) => void }>();
/** Each open transaction's end (settled once it has committed or rolled back). */
const ending = new Map<number, Promise<void>>();

port.on('message', (m: Message) => {
  void (async () => {
    try {
      switch (m.op) {
        case 'query': {
          const on = m.tx === undefined ? db : transactions.get(m.tx)?.tx;
          if (on === undefined) throw new Error(`no transaction ${m.tx}`);
          port.postMessage({ id: m.id, rows: (await on.query(m.sql, m.params)).rows });
          return;
        }
        case 'begin': {
          let ended: Promise<void> | undefined;
          await new Promise<void>((began, failed) => {
            ended = db
              .transaction(async (tx) => {
                const commit = await new Promise<boolean>((end) => {
                  transactions.set(m.id, { tx, end });
                  began();
                });
                transactions.delete(m.id);
                if (!commit) throw ROLLBACK;
              })
              .catch((error: unknown) => {
                if (error !== ROLLBACK) throw error;
              });
            ended.catch(failed);
          });
          ending.set(m.id, ended!);
          port.postMessage({ id: m.id, rows: [] });
          return;
        }
        case 'end': {
          const open = transactions.get(m.tx);
          const ended = ending.get(m.tx);
          ending.delete(m.tx);
          if (open === undefined || ended === undefined) throw new Error(`no transaction ${m.tx}`);
          open.end(m.commit);
          await ended;
          port.postMessage({ id: m.id, rows: [] });
          return;
        }
        case 'close':
          await db.close();
          port.postMessage({ id: m.id, rows: [] });
          return;
      }
    } catch (error) {
      port.postMessage({ id: m.id, error: describe(error) });
    }
  })();
});
