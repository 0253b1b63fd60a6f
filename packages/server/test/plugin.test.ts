import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import {
  LockstepSession,
  ReplayRecorder,
  hex64,
  performanceClock,
  type NetSession,
  readReplay,
  replayFactory,
  setupFromWelcome,
  verifyReplay,
  type AnyGameDefinition,
  type PlayerInput,
} from 'fixedstep';
import { createServer, type FixedstepServer } from '../src/app.js';
import { loadGames } from '../src/games/load.js';
import { connectNodeWebSocket } from '../src/relay/index.js';
import { memoryStore } from './helpers.js';
import { frameUntilFinished } from './session-frames.js';
import type { CoinDash } from '../../../examples/coin-dash/src/game.js';

/**
 * The example game of the packaging work (`examples/coin-dash`, a user's game on the published
 * package) hosted by the server as a plug-in: loaded from its module, played by two clients through
 * the relay, and the recorded match submitted as a highscore, verified in a worker thread that
 * imported the same module.
 */
const gameModule = fileURLToPath(
  new URL('../../../examples/coin-dash/src/game.ts', import.meta.url),
);

let server: FixedstepServer;
beforeAll(async () => {
  const games = await loadGames([path.relative(process.cwd(), gameModule)]);
  server = await createServer({
    port: 0,
    games,
    store: memoryStore(),
    verification: { workers: 1 },
  });
  await server.storeReady;
}, 120_000);
afterAll(async () => {
  await server.close();
});

describe('a user game as a plug-in', () => {
  it('is played through the relay, and its recorded run ranks as a verified highscore', async () => {
    const { games } = await loadGames([gameModule]);
    loaded = games;
    const coinDash = games[0]!;
    expect(coinDash.id).toBe('coin-dash');
    const ticks = 600;
    const clock = performanceClock();
    const recorders: ReplayRecorder<PlayerInput>[] = [];
    const sessions: NetSession<PlayerInput>[] = [];
    for (let p = 0; p < 2; p++) {
      const transport = await connectNodeWebSocket(`ws://127.0.0.1:${server.port}/ws`);
      let slot = 0;
      let real: CoinDash | undefined;
      const session = new LockstepSession<PlayerInput>({
        transport,
        clock,
        room: 'coin-room',
        game: coinDash,
        players: 2,
        seed: 31,
        stopAt: ticks,
        // The match is recorded as it is stepped (lockstep steps each tick once, in order).
        createSimulation: (welcome) => {
          slot = welcome.slot;
          const setup = setupFromWelcome(welcome);
          // eslint-disable-next-line @typescript-eslint/no-unsafe-class-instance-assignment -- the module's definition builds a CoinDash
          const sim = coinDash.create(setup) as CoinDash;
          real = sim;
          const recorder = ReplayRecorder.forGame(coinDash, setup, ['ada', 'bob'], {
            checkpointEvery: 60,
          });
          recorder.start(sim);
          recorders[slot] = recorder as ReplayRecorder<PlayerInput>;
          return {
            get tick() {
              return sim.tick;
            },
            step(inputs: readonly PlayerInput[]) {
              sim.step(inputs);
              recorder.record(inputs, sim);
            },
            save: () => sim.save(),
            load: (bytes: Uint8Array) => {
              sim.load(bytes);
            },
            hash: () => sim.hash(),
          };
        },
        localInput: () => coinDash.bot!(real!, slot) as PlayerInput,
      });
      sessions.push(session);
    }
    await frameUntilFinished(sessions);
    expect(new Set(sessions.map((s) => hex64(s.hashAt(ticks)!))).size).toBe(1);
    expect(server.relay!.relay.room('coin-room')!.desyncs).toHaveLength(0);

    const bytes = recorders[0]!.finish();
    const score = scoreOf(bytes);
    const res = await fetch(`http://127.0.0.1:${server.port}/api/highscores?score=${score}`, {
      method: 'POST',
      body: Buffer.from(bytes),
    });
    expect(res.status).toBe(201);
    expect(await res.json()).toMatchObject({
      rank: 1,
      entry: { game: 'coin-dash', version: '1', score, ticks },
    });
    const table = (await (
      await fetch(`http://127.0.0.1:${server.port}/api/highscores?game=coin-dash`)
    ).json()) as {
      entries: unknown[];
    };
    expect(table.entries).toHaveLength(1);
    // Only the hosted games: the built-in ones are not offered by this server.
    expect((await fetch(`http://127.0.0.1:${server.port}/api/highscores?game=runner`)).status).toBe(
      400,
    );
    for (const s of sessions) s.leave();
  });
});

/** The first player's score at the end of a replay, by re-simulating it here. */
function scoreOf(bytes: Uint8Array, games: readonly AnyGameDefinition[] = loaded): number {
  let sim: CoinDash | undefined;
  const factory = replayFactory(games);
  // eslint-disable-next-line @typescript-eslint/no-unsafe-class-instance-assignment -- the module's definition builds a CoinDash
  expect(verifyReplay(bytes, (h) => (sim = factory(h) as CoinDash)).ok).toBe(true);
  expect(readReplay(bytes).tickCount).toBe(600);
  return games[0]!.score!(sim!);
}
let loaded: readonly AnyGameDefinition[] = [];
