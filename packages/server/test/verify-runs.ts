/**
 * Runs of the verification-pool test games (verify-games.ts) recorded as a player would submit
 * them, and the server's gauges read back from /metrics.
 */
import {
  BUTTON_WORD,
  ReplayRecorder,
  gameSetup,
  type AnyGameDefinition,
  type Simulation,
} from 'fixedstep';

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
