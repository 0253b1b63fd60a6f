import { mkdtemp, readdir, readFile, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterEach, beforeEach, describe, expect, it } from 'vitest';
import { startServer, type RunningServer } from '../src/serve.js';
import {
  HighscoreStore,
  checkSubmission,
  highscoreApi,
  type HighscoreEntry,
} from '../src/highscores.js';
import { recordBot, recordRunner } from './replay-fixtures.js';

let dir: string;
beforeEach(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-hs-'));
});
afterEach(async () => {
  await rm(dir, { recursive: true, force: true });
});

const table = () => path.join(dir, 'data', 'highscores.json');

describe('checkSubmission', () => {
  const honest = recordRunner(1800);
  const score = honest.game.hud().score!;

  it('accepts a replay that reproduces the claimed score', () => {
    const entry = checkSubmission(honest.bytes, score, new Date(0));
    expect(entry).toMatchObject({ game: 'runner', name: 'ada', score, ticks: 1800, seed: 7 });
    expect(score).toBeGreaterThan(0);
  });

  it.each(['ctf', 'survival'])('ranks %s by kills', (id) => {
    const match = recordBot(id, 3600);
    const kills = match.game.hud().kills!;
    expect(checkSubmission(match.bytes, kills, new Date(0))).toMatchObject({
      game: id,
      score: kills,
      name: 'bot0',
    });
    expect(() => checkSubmission(match.bytes, kills + 1, new Date(0))).toThrow(/claimed/);
  });

  it.each([
    [
      'an edited score',
      () => checkSubmission(honest.bytes, score + 1, new Date(0)),
      'SCORE_MISMATCH',
    ],
    [
      'edited inputs',
      () => checkSubmission(recordRunner(1800, { editTick: 700 }).bytes, score, new Date(0)),
      'DOES_NOT_REPRODUCE',
    ],
    [
      'a replay of another seed',
      () => checkSubmission(recordRunner(1800, { claimSeed: 9 }).bytes, score, new Date(0)),
      'DOES_NOT_REPRODUCE',
    ],
    [
      'a damaged file',
      () => checkSubmission(honest.bytes.slice(0, 100), score, new Date(0)),
      'TRUNCATED',
    ],
  ])('refuses %s', (_, submit, code) => {
    expect(submit).toThrow(expect.objectContaining({ code, status: 422 }) as Error);
  });
});

describe('HighscoreStore', () => {
  const entry = (score: number, game = 'runner'): HighscoreEntry => ({
    game,
    name: 'x',
    score,
    ticks: 60,
    seed: 1,
    finalHash: '0'.repeat(16),
    replayId: `id-${game}-${score}`,
    at: new Date(score).toISOString(),
  });

  it('ranks per game and survives a restart', async () => {
    const { store } = await HighscoreStore.open(table());
    expect(await store.add(entry(100))).toBe(1);
    expect(await store.add(entry(300))).toBe(1);
    expect(await store.add(entry(200))).toBe(2);
    expect(await store.add(entry(50, 'ctf'))).toBe(1);
    const { store: again } = await HighscoreStore.open(table());
    expect(again.top('runner').map((e) => e.score)).toEqual([300, 200, 100]);
    expect(again.top('ctf')).toHaveLength(1);
  });

  it('survives a crash in the middle of a write: the old table stays, the half-written file goes', async () => {
    const { store } = await HighscoreStore.open(table());
    await store.add(entry(100));
    // A crash mid-write leaves a temporary file next to an intact table.
    await writeFile(`${table()}.tmp-999-1`, '{"format":"fixedstep-highscores","entr');
    const { store: again, recovered } = await HighscoreStore.open(table());
    expect(recovered).toBeUndefined();
    expect(again.top('runner').map((e) => e.score)).toEqual([100]);
    expect((await readdir(path.dirname(table()))).filter((f) => f.includes('.tmp-'))).toEqual([]);
  });

  it('keeps a corrupt table aside instead of losing it', async () => {
    await HighscoreStore.open(table());
    await writeFile(table(), 'not json at all');
    const { store, recovered } = await HighscoreStore.open(table());
    expect(recovered).toMatch(/could not be read.*kept as .*corrupt-/);
    expect(store.top('runner')).toEqual([]);
    const aside = (await readdir(path.dirname(table()))).find((f) => f.includes('.corrupt-'))!;
    expect(await readFile(path.join(path.dirname(table()), aside), 'utf8')).toBe('not json at all');
  });

  it('keeps the best 100 per game', async () => {
    const { store } = await HighscoreStore.open(table());
    for (let s = 1; s <= 105; s++) await store.add(entry(s));
    expect(store.top('runner', 100)).toHaveLength(100);
    expect(store.top('runner', 100).at(-1)!.score).toBe(6);
    expect(await store.add(entry(0.5))).toBe(0);
  });
});

describe('the highscore API', () => {
  let server: RunningServer;
  let base: string;
  beforeEach(async () => {
    const { store } = await HighscoreStore.open(table());
    await writeFile(path.join(dir, 'index.html'), 'lab');
    server = await startServer({ port: 0, root: dir, api: highscoreApi({ store, perMinute: 5 }) });
    base = server.url.replace('localhost', '127.0.0.1');
  });
  afterEach(async () => {
    await server.close();
  });

  const post = (bytes: Uint8Array, score: string) =>
    fetch(`${base}api/highscores?score=${score}`, {
      method: 'POST',
      body: Buffer.from(bytes),
      headers: { 'content-type': 'application/octet-stream' },
    });

  it('accepts a verified score, refuses a duplicate and a forgery, and lists the table', async () => {
    const honest = recordRunner(1200, {}, 'grace');
    const score = String(honest.game.hud().score);
    const ok = await post(honest.bytes, score);
    expect(ok.status).toBe(201);
    expect(await ok.json()).toMatchObject({ rank: 1, entry: { name: 'grace', game: 'runner' } });
    expect((await post(honest.bytes, score)).status).toBe(409);
    const forged = await post(recordRunner(1200, { editTick: 300 }).bytes, score);
    expect(forged.status).toBe(422);
    expect(await forged.json()).toMatchObject({ code: 'DOES_NOT_REPRODUCE' });
    const list = (await (await fetch(`${base}api/highscores?game=runner`)).json()) as {
      entries: HighscoreEntry[];
    };
    expect(list.entries.map((e) => e.name)).toEqual(['grace']);
    // The static lab is still served next to the API.
    expect(await (await fetch(base)).text()).toBe('lab');
  });

  it('answers bad requests clearly and limits the rate', async () => {
    expect((await fetch(`${base}api/highscores?game=chess`)).status).toBe(400);
    expect((await post(new Uint8Array(10), 'lots')).status).toBe(400);
    const big = await post(new Uint8Array(2 * 1024 * 1024), '1');
    expect(big.status).toBe(413);
    const garbage = await post(new Uint8Array(64), '1');
    expect(garbage.status).toBe(422);
    expect(await garbage.json()).toMatchObject({ code: 'BAD_MAGIC' });
    // Five submissions a minute from one address: the 4th and 5th are judged, the 6th is not.
    expect((await post(new Uint8Array(64), '1')).status).toBe(422);
    expect((await post(new Uint8Array(64), '1')).status).toBe(422);
    const limited = await post(new Uint8Array(64), '1');
    expect(limited.status).toBe(429);
    expect(await limited.json()).toMatchObject({ code: 'RATE_LIMITED' });
    expect((await fetch(`${base}api/highscores`, { method: 'DELETE' })).status).toBe(405);
  });
});
