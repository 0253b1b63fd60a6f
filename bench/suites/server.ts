/**
 * The server under forged submissions: does verification stay off the event loop?
 *
 * - **Latency while forged replays arrive** (20 a second): `GET /` and a WebSocket ping to the
 *   relay, p50 and p99 in ms, with verification in the worker pool and inline on the event loop,
 *   side by side in one run. Each forged replay is a capture-the-flag bot match that passes the
 *   pre-check (a real file of a known game) and claims a score it does not reach, so the server
 *   re-simulates all of it before refusing it. Target: p99 < 50 ms with the pool.
 * - **Verification throughput**, replays a second: the same honest replays through a
 *   `VerifierPool` (cores − 1 workers, at least 1) and inline, one after another.
 */
import { availableParallelism } from 'node:os';
import WebSocket from 'ws';
import { decodeMessage, encodeMessage } from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { createServer, openStore, VerifierPool, loadGames } from '@fixedstep/server';
import { defineSuite } from '../lib/suite.js';
import { recordBotGame } from './replay.js';

function percentile(values: readonly number[], p: number): number {
  if (values.length === 0) return NaN;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.ceil((p / 100) * sorted.length) - 1)]!;
}

interface LoadResult {
  get: number[];
  ping: number[];
  answered: Record<number, number>;
}

/** Serves with `workers` verification workers (0: inline) while forged replays arrive at `rate`/s. */
async function underLoad(
  workers: number,
  forged: Uint8Array,
  seconds: number,
  rate: number,
): Promise<LoadResult> {
  const games = await loadGames();
  const server = await createServer({
    port: 0,
    store: openStore(),
    games,
    verification: { workers, maxQueue: 32 },
    submissionsPerMinute: 1_000_000,
    log: () => undefined,
  });
  await server.storeReady;
  const base = `http://127.0.0.1:${server.port}`;
  // The relay probe: a player waiting in a capture-the-flag room for a second player (the relay
  // drops a connection that sends no hello within 5 s), timing the relay protocol's ping → pong.
  const ws = new WebSocket(`ws://127.0.0.1:${server.port}/ws`);
  await new Promise((resolve) => ws.once('open', resolve));
  ws.send(
    encodeMessage({
      type: 'hello',
      room: 'probe',
      role: 'player',
      game: 'ctf',
      gameVersion: ctfGame.info.version,
      input: ctfGame.input.id,
      players: 2,
      name: 'probe',
    }),
  );
  let answered: ((error?: Error) => void) | undefined;
  ws.on('message', (data: Buffer) => {
    if (decodeMessage(new Uint8Array(data)).type === 'pong') answered?.();
  });
  ws.once('close', (code, reason) => {
    answered?.(new Error(`the relay closed the probe (${code} ${reason.toString()})`));
  });
  const relayPing = (id: number): Promise<void> =>
    new Promise<void>((resolve, reject) => {
      answered = (error) => {
        answered = undefined;
        if (error) reject(error);
        else resolve();
      };
      ws.send(encodeMessage({ type: 'ping', id, time: 0 }));
    });
  // Warm-up: a few forged submissions and probes, not counted.
  for (let i = 0; i < 3; i++) {
    await (
      await fetch(`${base}/api/highscores?score=999`, { method: 'POST', body: Buffer.from(forged) })
    ).arrayBuffer();
    await (await fetch(`${base}/healthz`)).arrayBuffer();
  }
  const result: LoadResult = { get: [], ping: [], answered: {} };
  const end = performance.now() + seconds * 1000;
  const pending: Promise<unknown>[] = [];
  // Forged submissions at a steady rate.
  const submit = setInterval(() => {
    pending.push(
      fetch(`${base}/api/highscores?score=999`, { method: 'POST', body: Buffer.from(forged) })
        .then(async (r) => {
          result.answered[r.status] = (result.answered[r.status] ?? 0) + 1;
          await r.arrayBuffer();
        })
        .catch(() => undefined),
    );
  }, 1000 / rate);
  // Probes: GET / and a WebSocket ping, one of each every 20 ms.
  while (performance.now() < end) {
    const t0 = performance.now();
    await (await fetch(`${base}/healthz`)).arrayBuffer();
    result.get.push(performance.now() - t0);
    const t1 = performance.now();
    await relayPing(result.ping.length);
    result.ping.push(performance.now() - t1);
    await new Promise((resolve) => setTimeout(resolve, 20));
  }
  clearInterval(submit);
  await Promise.all(pending);
  ws.close();
  await server.close();
  return result;
}

export default defineSuite({
  name: 'server',
  description:
    'GET / and relay ping p99 while forged replays arrive (worker pool vs inline); verification throughput',
  async run(ctx) {
    const seconds = ctx.quick ? 2 : 10;
    const rate = 20;
    const forgedTicks = ctx.quick ? 600 : 1800;
    const forged = recordBotGame(ctfGame, forgedTicks).bytes;
    const rows: string[][] = [];
    for (const [label, workers] of [
      ['worker pool', Math.max(1, availableParallelism() - 1)],
      ['inline', 0],
    ] as const) {
      const r = await underLoad(workers, forged, seconds, rate);
      const f = (v: number) => v.toFixed(1);
      rows.push([
        label,
        String(workers),
        f(percentile(r.get, 50)),
        f(percentile(r.get, 99)),
        f(percentile(r.ping, 50)),
        f(percentile(r.ping, 99)),
        Object.entries(r.answered)
          .map(([status, n]) => `${n}×${status}`)
          .join(' '),
      ]);
    }
    ctx.table(
      `Latency while ${rate} forged CTF replays (${forgedTicks} ticks each) arrive per second, for ${seconds} s`,
      [
        'verification',
        'workers',
        'GET p50 ms',
        'GET p99 ms',
        'ping p50 ms',
        'ping p99 ms',
        'answers',
      ],
      rows,
    );

    // Throughput: honest replays through the pool and inline.
    const games = await loadGames();
    const count = ctx.quick ? 6 : 24;
    const honest = recordBotGame(ctfGame, ctx.quick ? 600 : 1800);
    const game = honest.def.create(honest.config);
    const players = honest.config.players;
    const frame = new Array<number>(players).fill(0);
    for (let t = 0; t < honest.ticks; t++) {
      for (let p = 0; p < players; p++) frame[p] = honest.inputs[t * players + p]!;
      game.step(frame);
    }
    const claimed = ctfGame.score!(game);
    const through: string[][] = [];
    const workers = Math.max(1, availableParallelism() - 1);
    for (const [label, n] of [
      ['worker pool', workers],
      ['inline', 0],
    ] as const) {
      const pool = new VerifierPool({
        modules: games.modules,
        games: games.games,
        workers: n,
        maxQueue: count,
      });
      await pool.ready();
      await Promise.all([pool.verify(honest.bytes, claimed), pool.verify(honest.bytes, claimed)]); // warm-up
      const t0 = performance.now();
      const verdicts = await Promise.all(
        Array.from({ length: count }, () => pool.verify(honest.bytes, claimed)),
      );
      const s = (performance.now() - t0) / 1000;
      await pool.close();
      if (!verdicts.every((v) => v.ok))
        throw new Error('server suite: an honest replay did not verify');
      through.push([
        label,
        String(n),
        String(count),
        (count / s).toFixed(1),
        ((count * honest.ticks) / s / 1000).toFixed(0),
      ]);
    }
    ctx.table(
      `Verification throughput: ${count} honest CTF replays of ${honest.ticks} ticks`,
      ['verification', 'workers', 'replays', 'replays/s', 'k ticks/s'],
      through,
    );
  },
});
