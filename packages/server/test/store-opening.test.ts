/**
 * The server while its store opens (issue 23: "start-up freezes the process"). The embedded
 * database opens in a thread of its own; these tests hold that opening on a gate — a module the
 * database's thread imports first, which blocks its thread until the test creates a file — and
 * meanwhile `/healthz` answers, `/readyz` says the store is opening, the highscore API answers 503
 * `STORE_STARTING`, and a relay match plays to its end. Were the database opened on the event loop,
 * nothing would answer while the gate is shut and the test would hang. No timing is involved.
 *
 * Then the store's failures: a PostgreSQL server that is down when the server starts (retried
 * until it is up, liveness failing meanwhile), a damaged PGlite folder (set aside, a new one made,
 * the rest of the server running).
 */
import { readFileSync } from 'node:fs';
import { mkdtemp, readFile, readdir, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, afterEach, beforeAll, describe, expect, it } from 'vitest';
import { createServer, type FixedstepServer } from '../src/app.js';
import { openStore, prepareStore } from '../src/store/store.js';
import { PgCluster, pgBin } from './pg-cluster.js';
import { recordRunner } from './replay-fixtures.js';
import { ctfBotsOnRelay } from './session-frames.js';

const gateModule = fileURLToPath(new URL('./store-gate.ts', import.meta.url));
let dir: string;
let server: FixedstepServer | undefined;
beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-opening-'));
  process.env.FIXEDSTEP_TEST_STORE_GATE = path.join(dir, 'open');
});
afterEach(async () => {
  await writeFile(path.join(dir, 'open'), ''); // never leave a thread at the gate
  await server?.close();
  server = undefined;
});
afterAll(async () => {
  delete process.env.FIXEDSTEP_TEST_STORE_GATE;
  await rm(dir, { recursive: true, force: true });
});

const get = async (p: string) => {
  const res = await fetch(`http://127.0.0.1:${server!.port}${p}`);
  return { status: res.status, body: (await res.json()) as Record<string, unknown> };
};

/** Two bots play a 120-tick capture-the-flag match through the server's relay; their final hashes. */
function relayMatch(port: number, room: string): Promise<[string, string]> {
  return ctfBotsOnRelay({
    url: `ws://127.0.0.1:${port}/ws/${room}`,
    room,
    ticks: 120,
    seed: 7,
    timeoutMs: 60_000,
  });
}

describe('while the store opens', () => {
  it('answers /healthz, /readyz and the API, and plays a relay match, with the database held at a gate', async () => {
    const data = path.join(dir, 'gated');
    const prepared = await prepareStore({ dataDir: data, preload: [gateModule] });
    server = await createServer({ port: 0, store: prepared, log: () => undefined });
    // The database's thread is blocked at the gate; the event loop is not.
    expect(await get('/healthz')).toEqual({ status: 200, body: { status: 'ok' } });
    expect(await get('/readyz')).toEqual({
      status: 503,
      body: { ready: false, reasons: ['the store is opening'] },
    });
    const list = await fetch(`http://127.0.0.1:${server.port}/api/highscores?game=runner`);
    expect(list.status).toBe(503);
    expect(list.headers.get('retry-after')).toBe('5');
    expect(await list.json()).toMatchObject({ code: 'STORE_STARTING' });
    const [a, b] = await relayMatch(server.port, 'gated');
    expect(a).toBe(b);
    expect((await get('/readyz')).body).toEqual({
      ready: false,
      reasons: ['the store is opening'],
    });

    await writeFile(path.join(dir, 'open'), '');
    await server.storeReady;
    expect(await get('/readyz')).toEqual({ status: 200, body: { ready: true, reasons: [] } });
    const run = recordRunner(4242, {}, 'ada');
    const posted = await fetch(
      `http://127.0.0.1:${server.port}/api/highscores?score=${run.game.hud().score!}`,
      { method: 'POST', body: Buffer.from(run.bytes) },
    );
    expect(posted.status).toBe(201);
  }, 120_000);

  it('closes cleanly while the database is still at the gate, and gives the folder up', async () => {
    await rm(path.join(dir, 'open'), { force: true });
    const data = path.join(dir, 'closed-early');
    const prepared = await prepareStore({ dataDir: data, preload: [gateModule] });
    server = await createServer({ port: 0, store: prepared, log: () => undefined });
    expect((await get('/healthz')).status).toBe(200);
    const closing = server.close();
    await writeFile(path.join(dir, 'open'), '');
    await closing;
    server = undefined;
    expect(await readdir(data)).not.toContain('pglite.lock');
  }, 120_000);
});

describe('a damaged embedded database', () => {
  it('is set aside with a message naming the folder and the cause; a new one opens and the server runs', async () => {
    const data = path.join(dir, 'damaged');
    const first = await openStore({ dataDir: data });
    const before = recordRunner(77, {}, 'bob');
    await first.add(
      {
        game: 'runner',
        version: '1',
        name: 'bob',
        score: 1,
        ticks: 60,
        seed: 77,
        finalHash: '0'.repeat(16),
        replayId: 'a'.repeat(16),
        at: new Date(0).toISOString(),
      },
      before.bytes,
    );
    await first.close();
    const control = path.join(data, 'pglite', 'global', 'pg_control');
    const garbage = Buffer.alloc(8192, 0x5a);
    await writeFile(control, garbage);

    const logged: string[] = [];
    const prepared = await prepareStore({ dataDir: data });
    server = await createServer({
      port: 0,
      store: {
        ...prepared,
        open: async () => {
          const opened = await prepared.open();
          logged.push(...opened.notes);
          return opened;
        },
      },
      log: (m) => logged.push(m),
    });
    await server.storeReady;
    const aside = (await readdir(data)).find((f) => f.startsWith('pglite.corrupt-'));
    expect(aside).toBeDefined();
    const where = path.join(data, 'pglite');
    expect(logged).toHaveLength(1);
    expect(logged[0]).toContain(`the embedded database in ${where} could not be opened`);
    expect(logged[0]).toMatch(/PostgreSQL said: .*FATAL/);
    expect(logged[0]).toContain(`move ${path.join(data, aside!)} back to ${where}`);
    // Set aside unchanged.
    expect(readFileSync(path.join(data, aside!, 'global', 'pg_control'))).toEqual(garbage);
    // A new, empty table; the server is ready and plays.
    expect(await get('/readyz')).toEqual({ status: 200, body: { ready: true, reasons: [] } });
    expect((await get('/api/highscores?game=runner')).body).toEqual({
      game: 'runner',
      entries: [],
    });
    const [a, b] = await relayMatch(server.port, 'after-damage');
    expect(a).toBe(b);
    expect(await readFile(path.join(data, 'pglite', 'PG_VERSION'), 'utf8')).toMatch(/^\d+/);
  }, 180_000);
});

describe.skipIf(pgBin === undefined)('PostgreSQL down when the server starts', () => {
  let cluster: PgCluster | undefined;
  afterAll(() => {
    cluster?.remove();
  });

  it('retries with a backoff, fails liveness after the allowed time, and becomes ready once it is up', async () => {
    cluster = await PgCluster.create(pgBin!);
    const logged: string[] = [];
    server = await createServer({
      port: 0,
      relay: false,
      store: await prepareStore({ databaseUrl: cluster.url }),
      storeRetry: { firstMs: 20, maxMs: 200 },
      storeLivenessMs: 1,
      log: (m) => logged.push(m),
    });
    // Down: not ready, saying why; and once it has failed for longer than allowed, not alive.
    await expect
      .poll(async () => (await get('/readyz')).body.reasons, { timeout: 60_000 })
      .toEqual([
        expect.stringMatching(
          /^the store could not be opened \(attempt \d+: cannot reach PostgreSQL at 127\.0\.0\.1:\d+\/postgres: .*\); trying again/,
        ),
      ]);
    await expect.poll(async () => (await get('/healthz')).status, { timeout: 60_000 }).toBe(503);
    expect((await get('/healthz')).body).toMatchObject({ status: 'store-unavailable' });
    // Each failure is logged, with the attempt and the wait before the next.
    await expect
      .poll(() => logged.some((m) => m.includes('could not be opened (attempt 2; trying again in')))
      .toBe(true);

    cluster.start();
    await server.storeReady;
    expect(await get('/readyz')).toEqual({ status: 200, body: { ready: true, reasons: [] } });
    expect(await get('/healthz')).toEqual({ status: 200, body: { status: 'ok' } });
    const run = recordRunner(5150, {}, 'cy');
    const posted = await fetch(
      `http://127.0.0.1:${server.port}/api/highscores?score=${run.game.hud().score!}`,
      { method: 'POST', body: Buffer.from(run.bytes) },
    );
    expect(posted.status).toBe(201);
  }, 180_000);

  it('stops retrying when the server closes', async () => {
    cluster ??= await PgCluster.create(pgBin!);
    cluster.stop();
    server = await createServer({
      port: 0,
      relay: false,
      store: await prepareStore({ databaseUrl: cluster.url }),
      storeRetry: { firstMs: 20, maxMs: 50 },
      log: () => undefined,
    });
    await expect
      .poll(async () => String((await get('/readyz')).body.reasons))
      .toMatch(/could not be opened/);
    await server.close();
    server = undefined;
  }, 60_000);
});
