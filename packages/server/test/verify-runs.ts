/**
 * A server with the verification-pool test games (verify-games.ts) and its gate, runs of those
 * games recorded as a player would submit them, and the server's gauges read back from /metrics.
 */
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import {
  BUTTON_WORD,
  ReplayRecorder,
  gameSetup,
  type AnyGameDefinition,
  type Simulation,
} from 'fixedstep';
import { createServer, type FixedstepServer, type ServerOptions } from '../src/app.js';
import { loadGames } from '../src/games/load.js';
import { memoryStore } from './helpers.js';

/** A 120-tick one-player run of `id` by `name` (its seed makes it a distinct run), and its score. */
export function recordRun(
  games: readonly AnyGameDefinition[],
  id: string,
  seed: number,
  name = 'ada',
): { bytes: Uint8Array; score: number } {
  const game = games.find((g) => g.id === id)!;
  const setup = gameSetup(game, 1, seed);
  const sim = game.create(setup) as Simulation;
  const recorder = ReplayRecorder.forGame(
    game as AnyGameDefinition & { input: typeof BUTTON_WORD },
    setup,
    [name],
    { checkpointEvery: 30 },
  );
  recorder.start(sim);
  for (let t = 0; t < 120; t++) {
    const inputs = [t % 3 === 0 ? 1 : 0];
    sim.step(inputs);
    recorder.record(inputs, sim);
  }
  return { bytes: recorder.finish(), score: game.score!(sim) };
}

/** A gauge's value from the /metrics of the server at `port` (NaN when it is missing). */
export async function gaugeOf(port: number, name: string): Promise<number> {
  const text = await (await fetch(`http://127.0.0.1:${port}/metrics`)).text();
  const line = text.split('\n').find((l) => l.startsWith(`${name} `));
  return Number(line?.split(' ')[1]);
}

/**
 * A server with the verification test games (verify-games.ts), one verifier and a queue of one,
 * whose `gate` game's verification waits in its worker until {@link GatedServer.openGate}: the
 * test decides when a verification may finish, with no timing. `options` add to the server's.
 */
export async function startGatedServer(
  name: string,
  options: Partial<ServerOptions> = {},
): Promise<GatedServer> {
  const dir = mkdtempSync(path.join(os.tmpdir(), `fixedstep-${name}-`));
  const gateFile = path.join(dir, 'open');
  // Read by the `gate` game in the workers (they inherit the environment when they start).
  process.env.FIXEDSTEP_TEST_GATE = gateFile;
  writeFileSync(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
  const loaded = await loadGames([fileURLToPath(new URL('./verify-games.ts', import.meta.url))]);
  const server = await createServer({
    port: 0,
    root: dir,
    games: loaded,
    store: await memoryStore(),
    verification: { workers: 1, maxQueue: 1 },
    ...options,
  });
  await server.storeReady;
  const openGate = () => {
    writeFileSync(gateFile, '');
  };
  return {
    server,
    games: loaded.games,
    openGate,
    closeGate: () => {
      rmSync(gateFile, { force: true });
    },
    async close() {
      openGate(); // never leave a worker waiting
      await server.close();
      delete process.env.FIXEDSTEP_TEST_GATE;
      rmSync(dir, { recursive: true, force: true });
    },
  };
}

/** What {@link startGatedServer} started. */
export interface GatedServer {
  readonly server: FixedstepServer;
  readonly games: readonly AnyGameDefinition[];
  /** Lets the held verifications of the `gate` game finish (and every later one). */
  openGate(): void;
  /** Holds the next verifications of the `gate` game again. */
  closeGate(): void;
  /** Opens the gate, closes the server, removes its folder. */
  close(): Promise<void>;
}
