import { spawn, spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { cp, mkdtemp, readFile, rm, utimes, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { run } from '@fixedstep/cli';
import { createServer } from '../src/app.js';
import { HighscoreStore, openStore, type HighscoreEntry } from '../src/store/store.js';
import { claimDataDir, openPglite } from '../src/store/pglite.js';
import type { SqlDriver } from '../src/store/driver.js';
import { template } from './helpers.js';
import { recordRunner } from './replay-fixtures.js';

let dir: string;
beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-store-'));
});
afterAll(async () => {
  await rm(dir, { recursive: true, force: true });
});

const entry = (score: number, name = 'x', id = score): HighscoreEntry => ({
  game: 'runner',
  version: '1',
  name,
  score,
  ticks: 60,
  seed: 1,
  finalHash: '0'.repeat(16),
  replayId: id.toString(16).padStart(16, '0'),
  at: new Date(1_000_000 + score).toISOString(),
});

/** A driver whose next `failures` transactions fail the way a full file table fails. */
function flaky(driver: SqlDriver): SqlDriver & { failures: number } {
  const wrapped = {
    failures: 0,
    description: driver.description,
    query: (sql: string, params?: readonly unknown[]) => driver.query(sql, params),
    transaction: <T>(work: Parameters<SqlDriver['transaction']>[0]) => {
      if (wrapped.failures > 0) {
        wrapped.failures--;
        return Promise.reject(
          Object.assign(new Error('EMFILE: too many open files'), { code: 'EMFILE' }),
        );
      }
      return driver.transaction(work) as Promise<T>;
    },
    close: () => driver.close(),
  };
  return wrapped;
}

describe('the highscore store', () => {
  it('ranks per game, and keeps each run once whatever its name', async () => {
    const store = await HighscoreStore.open(
      await openPglite(undefined, { template: await template() }),
    );
    expect(await store.add(entry(100), new Uint8Array([1]))).toMatchObject({
      kind: 'added',
      rank: 1,
    });
    expect(await store.add(entry(300), new Uint8Array([3]))).toMatchObject({
      kind: 'added',
      rank: 1,
    });
    expect(await store.add(entry(200), new Uint8Array([2]))).toMatchObject({
      kind: 'added',
      rank: 2,
    });
    expect(await store.add(entry(200), new Uint8Array([2]))).toMatchObject({
      kind: 'same',
      rank: 2,
    });
    expect(await store.add(entry(200, 'thief'), new Uint8Array([2]))).toMatchObject({
      kind: 'taken',
      entry: { name: 'x' },
    });
    expect((await store.top('runner')).map((e) => e.score)).toEqual([300, 200, 100]);
    expect(await store.replay(entry(300).replayId)).toEqual(new Uint8Array([3]));
    await store.close();
  });

  it('a failed write (EMFILE) fails only itself: the score is not listed, a retry saves it, later ones too', async () => {
    const driver = flaky(await openPglite(undefined, { template: await template() }));
    const store = await HighscoreStore.open(driver);
    const server = await createServer({ port: 0, relay: false, store, log: () => undefined });
    const base = `http://127.0.0.1:${server.port}`;
    const post = (bytes: Uint8Array, score: number) =>
      fetch(`${base}/api/highscores?score=${score}`, { method: 'POST', body: Buffer.from(bytes) });
    const a = recordRunner(900, {}, 'ada');
    driver.failures = 1;
    const failed = await post(a.bytes, a.game.hud().score!);
    expect(failed.status).toBe(503);
    expect(failed.headers.get('retry-after')).toBe('5');
    expect(await failed.json()).toMatchObject({ code: 'STORE_UNAVAILABLE' });
    // Not acknowledged, so not listed — and not "already submitted" either.
    expect(await store.top('runner')).toEqual([]);
    expect((await post(a.bytes, a.game.hud().score!)).status).toBe(201);
    const b = recordRunner(1000, {}, 'bob');
    expect((await post(b.bytes, b.game.hud().score!)).status).toBe(201);
    expect((await store.top('runner')).map((e) => e.name).sort()).toEqual(['ada', 'bob']);
    expect(await (await fetch(`${base}/metrics`)).text()).toMatch(/fixedstep_store_errors_total 1/);
    await server.close();
  });

  it('imports the JSON table of earlier versions once, on first start, and keeps the file', async () => {
    const data = path.join(dir, 'old');
    await cp(new URL('./fixtures/highscores-v1', import.meta.url), data, { recursive: true });
    const before = await readFile(path.join(data, 'highscores.json'), 'utf8');
    const store = await openStore({ dataDir: data });
    expect(store.notes).toEqual([
      `imported 3 highscores from ${path.join(data, 'highscores.json')} (the file is kept as it was)`,
    ]);
    expect((await store.top('runner')).map((e) => [e.name, e.score, e.at])).toEqual([
      ['ada', 3450, '2026-11-21T11:30:00.000Z'],
      ['grace', 2200, '2026-11-20T10:00:00.000Z'],
    ]);
    expect((await store.top('ctf'))[0]).toMatchObject({
      name: 'bot0',
      score: 5,
      replayId: 'v1-aac47d467ea30332',
    });
    await store.close();
    expect(await readFile(path.join(data, 'highscores.json'), 'utf8')).toBe(before);
    // Reopened (the scores persisted in the folder): not imported again.
    const again = await openStore({ dataDir: data });
    expect(again.notes).toEqual([]);
    expect(await again.top('runner')).toHaveLength(2);
    await again.close();
  });

  it('refuses a second process on one data folder, and takes over a stale lock: its process dead, a reboot, its pid reused', async () => {
    const data = path.join(dir, 'locked');
    const mine = await claimDataDir(data);
    await expect(claimDataDir(data)).rejects.toThrow(/already open in this process/);
    await mine.release();
    const lockFile = path.join(data, 'pglite.lock');
    // The lock of a live process (the test runner's parent), as a lock of this version writes it
    // (pid and start time) and as an older one did (the pid alone): refused, naming it and the way out.
    const parent = readFileSync(`/proc/${process.ppid}/stat`, 'utf8');
    const parentStart = parent.slice(parent.lastIndexOf(')') + 2).split(' ')[19];
    for (const content of [`${process.ppid} ${parentStart}\n`, `${process.ppid}\n`]) {
      await writeFile(lockFile, content);
      await expect(claimDataDir(data)).rejects.toThrow(
        new RegExp(`in use by process ${process.ppid}.*DATABASE_URL`),
      );
    }
    const takesOver = async (content: string) => {
      await writeFile(lockFile, content);
      const taken = await claimDataDir(data);
      const [pid, start] = (await readFile(lockFile, 'utf8')).trim().split(' ');
      expect(pid).toBe(String(process.pid));
      expect(Number(start)).toBeGreaterThan(0);
      await taken.release();
    };
    // The lock of a process that has exited: taken over.
    const dead = spawnSync(process.execPath, [
      '-e',
      'process.stdout.write(String(process.pid))',
    ]).stdout.toString();
    await takesOver(`${dead}\n`);
    // The live parent's pid with another start time: a reboot, or the pid reused since.
    await takesOver(`${process.ppid} ${Number(parentStart) + 1}\n`);
    // The live parent's pid and start time, written in another boot of the machine.
    await takesOver(`${process.ppid} ${parentStart} 00000000-0000-4000-8000-000000000000\n`);
    // The live parent's pid alone (an older lock), written before the parent started: reused.
    await writeFile(lockFile, `${process.ppid}\n`);
    await utimes(lockFile, new Date(2000, 0, 1), new Date(2000, 0, 1));
    const reused = await claimDataDir(data);
    expect((await readFile(lockFile, 'utf8')).split(' ')[0]).toBe(String(process.pid));
    await reused.release();
    // This process's own pid, not held by it: a container restarted, its server pid 1 again.
    await takesOver(`${process.pid} ${Number(parentStart) - 1}\n`);
    await takesOver(`${process.pid}\n`);
    // A killed server whose parent never reaped it (a zombie still answers kill(pid, 0)): a
    // shell backgrounds a sleep and becomes a sleep itself, which never waits for its child.
    const shell = spawn('sh', ['-c', 'sleep 60 & echo $!; exec sleep 60'], {
      stdio: ['ignore', 'pipe', 'ignore'],
    });
    try {
      const zombie = Number(
        await new Promise<string>((resolve) => {
          shell.stdout.once('data', (d: Buffer) => {
            resolve(String(d));
          });
        }),
      );
      // Killed before the shell has become a sleep, the shell would reap it.
      await expect.poll(() => readFileSync(`/proc/${shell.pid}/comm`, 'utf8').trim()).toBe('sleep');
      process.kill(zombie, 'SIGKILL');
      for (
        let i = 0;
        i < 100 && !readFileSync(`/proc/${zombie}/stat`, 'utf8').includes(') Z ');
        i++
      ) {
        await new Promise((r) => setTimeout(r, 10));
      }
      expect(readFileSync(`/proc/${zombie}/stat`, 'utf8')).toMatch(/\) Z /);
      expect(() => process.kill(zombie, 0)).not.toThrow();
      await takesOver(`${zombie}\n`);
    } finally {
      shell.kill('SIGKILL');
    }
  });

  it('serve --data /proc/x fails at once with the reason', async () => {
    const root = path.join(dir, 'lab');
    await cp(new URL('./fixtures/highscores-v1', import.meta.url), root, { recursive: true });
    await writeFile(path.join(root, 'index.html'), 'lab');
    let err = '';
    const code = await run(
      ['serve', '--port', '0', '--root', root, '--data', '/proc/x'],
      {},
      {
        out: () => undefined,
        err: (t) => (err += t),
        stopSignal: new Promise(() => undefined),
      },
    );
    expect(code).toBe(1);
    expect(err).toMatch(/cannot use \/proc\/x as the data folder/);
  });
});
