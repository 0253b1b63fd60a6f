import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { GAMES } from '@fixedstep/games';
import { createServer, type FixedstepServer } from '../src/app.js';
import { precheckSubmission, resimulate, runId } from '../src/verify/check.js';
import { readReplay } from 'fixedstep';
import { closed, connect, memoryStore, request } from './helpers.js';
import { recordBot, recordRunner } from './replay-fixtures.js';

describe('checking a submission', () => {
  const honest = recordRunner(1800);
  const score = honest.game.hud().score!;

  it('accepts a replay that reproduces the claimed score', () => {
    const pre = precheckSubmission(honest.bytes, score, GAMES);
    expect(pre).toMatchObject({ name: 'ada', seed: 7, ticks: 1800 });
    expect(pre.runId).toMatch(/^[0-9a-f]{16}$/);
    expect(resimulate(honest.bytes, score, GAMES)).toMatchObject({ ok: true, score, ticks: 1800 });
    expect(score).toBeGreaterThan(0);
  });

  it.each(['ctf', 'survival'])('ranks %s by kills', (id) => {
    const match = recordBot(id, 3600);
    const kills = match.game.hud().kills!;
    expect(resimulate(match.bytes, kills, GAMES)).toMatchObject({ ok: true, score: kills });
    expect(resimulate(match.bytes, kills + 1, GAMES)).toMatchObject({
      ok: false,
      code: 'SCORE_MISMATCH',
    });
  });

  it('checks a survival run past its end: the claimed kills, and every hash after the end', () => {
    // Survival is over when the bot has lost its lives (6 to 7 minutes); the file runs on for a
    // minute. The verifier skips those ticks (the state is frozen) but not their hashes.
    const ticks = 9 * 60 * 60;
    const honest = recordBot('survival', ticks);
    expect(honest.game.over).toBe(true);
    const kills = honest.game.hud().kills!;
    expect(resimulate(honest.bytes, kills, GAMES)).toMatchObject({ ok: true, score: kills });
    expect(resimulate(honest.bytes, kills + 1, GAMES)).toMatchObject({
      ok: false,
      code: 'SCORE_MISMATCH',
    });
    const forged = recordBot('survival', ticks, 1, { hashAt: ticks - 60 });
    expect(resimulate(forged.bytes, kills, GAMES)).toMatchObject({
      ok: false,
      code: 'DOES_NOT_REPRODUCE',
      message: expect.stringContaining(`${ticks - 120}, ${ticks - 60}]`) as string,
    });
  });

  it('gives a renamed run the same identity, and another run another', () => {
    const renamed = recordRunner(1800, {}, 'mallory');
    expect(readReplay(renamed.bytes).header.players).toEqual(['mallory']);
    expect(runId(readReplay(renamed.bytes))).toBe(runId(readReplay(honest.bytes)));
    expect(runId(readReplay(recordRunner(1799).bytes))).not.toBe(runId(readReplay(honest.bytes)));
    expect(runId(readReplay(recordRunner(1800, { claimSeed: 9 }).bytes))).not.toBe(
      runId(readReplay(honest.bytes)),
    );
  });

  it.each([
    ['an edited score', () => resimulate(honest.bytes, score + 1, GAMES), 'SCORE_MISMATCH'],
    [
      'edited inputs',
      () => resimulate(recordRunner(1800, { editTick: 700 }).bytes, score, GAMES),
      'DOES_NOT_REPRODUCE',
    ],
    [
      'another seed',
      () => resimulate(recordRunner(1800, { claimSeed: 9 }).bytes, score, GAMES),
      'DOES_NOT_REPRODUCE',
    ],
  ])('refuses %s when re-simulating', (_, check, code) => {
    expect(check()).toMatchObject({ ok: false, status: 422, code });
  });

  it.each([
    [
      'a damaged file',
      () => precheckSubmission(honest.bytes.slice(0, 100), score, GAMES),
      'TRUNCATED',
    ],
    [
      'a game the server lacks',
      () => precheckSubmission(honest.bytes, score, GAMES.slice(1)),
      'UNKNOWN_GAME',
    ],
    ['an impossible claim', () => precheckSubmission(honest.bytes, -1, GAMES), 'BAD_SCORE'],
    [
      'too many ticks',
      () => precheckSubmission(honest.bytes, score, GAMES, { maxTicks: 100 }),
      'TOO_LARGE',
    ],
  ])('refuses %s before any simulation', (_, check, code) => {
    expect(check).toThrow(expect.objectContaining({ code }) as Error);
  });
});

describe('the highscore API under hostile traffic', () => {
  let server: FixedstepServer;
  let base: string;
  beforeAll(async () => {
    server = await createServer({
      port: 0,
      relay: false,
      store: memoryStore(),
      submissionsPerMinute: 3,
      trustProxy: 'x-forwarded-for',
      limits: { requestTimeoutMs: 400, headersTimeoutMs: 400 },
    });
    await server.storeReady;
    base = `http://127.0.0.1:${server.port}`;
  }, 120_000);
  afterAll(async () => {
    await server.close();
  });

  const post = (bytes: Uint8Array, score: number | string, from = '203.0.113.1') =>
    fetch(`${base}/api/highscores?score=${score}`, {
      method: 'POST',
      body: Buffer.from(bytes),
      headers: {
        'content-type': 'application/octet-stream',
        'x-forwarded-for': `10.0.0.1, ${from}`,
      },
    });

  it('accepts a verified run once: a retry gets the same answer, a renamed copy and a stolen run 409', async () => {
    const honest = recordRunner(1200, {}, 'grace');
    const score = honest.game.hud().score!;
    const first = await post(honest.bytes, score, '198.51.100.7');
    expect(first.status).toBe(201);
    const accepted = (await first.json()) as {
      rank: number;
      entry: { replayId: string; name: string };
    };
    expect(accepted).toMatchObject({ rank: 1, entry: { name: 'grace', game: 'runner', score } });
    // The same submission again (a client retrying after a lost answer): the same entry.
    const retry = await post(honest.bytes, score, '198.51.100.7');
    expect(retry.status).toBe(201);
    expect(await retry.json()).toMatchObject({ repeated: true, rank: 1, entry: accepted.entry });
    // Renamed twelve times, by its author or by someone else: refused every time, no simulation.
    for (let i = 0; i < 12; i++) {
      const renamed = await post(recordRunner(1200, {}, `grace${i}`).bytes, score, `192.0.2.${i}`);
      expect(renamed.status).toBe(409);
      expect(await renamed.json()).toMatchObject({ code: 'RUN_TAKEN' });
    }
    const list = (await (await fetch(`${base}/api/highscores?game=runner&limit=100`)).json()) as {
      entries: { name: string }[];
    };
    expect(list.entries.map((e) => e.name)).toEqual(['grace']);
    // The stored replay comes back byte for byte.
    const replay = await fetch(`${base}/api/highscores/${accepted.entry.replayId}/replay`);
    expect(Buffer.from(await replay.arrayBuffer())).toEqual(Buffer.from(honest.bytes));
  });

  it('charges the rate limit after the pre-check: junk never locks out an honest score', async () => {
    const from = '198.51.100.20';
    for (let i = 0; i < 20; i++) {
      const junk = await post(new Uint8Array(64), 1, from);
      expect(junk.status).toBe(422);
    }
    const honest = recordRunner(900, {}, 'ada');
    expect((await post(honest.bytes, honest.game.hud().score!, from)).status).toBe(201);
    // Honest-looking submissions are charged: 3 a minute per client address (from the proxy header).
    const forged = recordRunner(1500, { editTick: 300 }, 'eve');
    expect((await post(forged.bytes, 1, from)).status).toBe(422);
    expect((await post(forged.bytes, 2, from)).status).toBe(422);
    const limited = await post(forged.bytes, 3, from);
    expect(limited.status).toBe(429);
    expect(Number(limited.headers.get('retry-after'))).toBeGreaterThan(0);
    expect(await limited.json()).toMatchObject({ code: 'RATE_LIMITED' });
    // Another address behind the same proxy has its own quota.
    const other = recordRunner(700, {}, 'bob');
    expect((await post(other.bytes, other.game.hud().score!, '198.51.100.21')).status).toBe(201);
  });

  it('refuses a declared 1 GiB body at once and closes the connection without reading it', async () => {
    const socket = await connect(server.port);
    const done = closed(socket);
    socket.write(
      'POST /api/highscores?score=1 HTTP/1.1\r\nHost: x\r\nContent-Type: application/octet-stream\r\n' +
        `Content-Length: ${1024 ** 3}\r\n\r\n`,
    );
    // Keep sending until the server hangs up: it must not read the gigabyte.
    let sent = 0;
    const chunk = Buffer.alloc(64 * 1024);
    const pump = () => {
      while (!socket.destroyed && sent < 64 * 1024 * 1024 && socket.write(chunk))
        sent += chunk.length;
      if (!socket.destroyed && sent < 64 * 1024 * 1024) socket.once('drain', pump);
    };
    pump();
    const answer = await done;
    expect(answer).toMatch(/^HTTP\/1\.1 413/);
    expect(answer.toLowerCase()).toContain('connection: close');
    expect(sent).toBeLessThan(64 * 1024 * 1024);
  });

  it('cuts a slow body (408) and keeps answering', async () => {
    const socket = await connect(server.port);
    const done = closed(socket);
    socket.write(
      'POST /api/highscores?score=1 HTTP/1.1\r\nHost: x\r\nContent-Length: 1000\r\n\r\nab',
    );
    expect(await done).toMatch(/^HTTP\/1\.1 408/);
    const idle = await connect(server.port);
    // A connection that never sends its headers is answered 408 and closed too.
    expect(await closed(idle)).toMatch(/^HTTP\/1\.1 408/);
    expect((await fetch(`${base}/api/highscores?game=runner`)).status).toBe(200);
  });

  it('answers bad requests clearly', async () => {
    expect((await fetch(`${base}/api/highscores?game=chess`)).status).toBe(400);
    expect((await post(new Uint8Array(10), 'lots')).status).toBe(400);
    const big = await post(new Uint8Array(2 * 1024 * 1024), '1');
    expect(big.status).toBe(413);
    expect(await big.json()).toMatchObject({ code: 'TOO_LARGE' });
    const garbage = await post(new Uint8Array(64), '1');
    expect(await garbage.json()).toMatchObject({ code: 'BAD_MAGIC' });
    expect((await fetch(`${base}/api/highscores`, { method: 'DELETE' })).status).toBe(405);
    expect((await request(server.port, '/api/highscores/zzz/replay')).status).toBe(404);
  });
});
