import { ReplayRecorder } from 'fixedstep';
import { findGame, replayOptionsFor, type Game } from '@fixedstep/games';

export interface Recorded {
  bytes: Uint8Array;
  game: Game;
}

/**
 * A runner replay of `ticks` ticks played by the bot. `lie` makes a dishonest file: the inputs
 * written are changed at one tick (`editTick`), or the header claims another seed (`claimSeed`),
 * while the hashes come from the honest game.
 */
export function recordRunner(
  ticks: number,
  lie: { editTick?: number; claimSeed?: number } = {},
  name = 'ada',
): Recorded {
  const def = findGame('runner');
  if (!def) throw new Error('the runner game is not registered');
  const config = { seed: 7, players: 1 };
  const game = def.create(config);
  const header = replayOptionsFor(
    def,
    lie.claimSeed === undefined ? config : { ...config, seed: lie.claimSeed },
    [name],
    {
      checkpointEvery: 60,
    },
  );
  const rec = new ReplayRecorder(header);
  rec.start(game);
  // The edit removes the first jump at or after editTick from the file: a jump the bot needed,
  // so the recorded inputs now crash into an obstacle. (Editing a tick that changes nothing
  // lasting — a duck while running — is harmless, and the verifier rightly accepts it.)
  let removing = false;
  let removed = false;
  for (let t = 0; t < ticks; t++) {
    const input = def.bot(game, 0);
    game.step([input]);
    const jump = (input & 1) !== 0;
    if (lie.editTick !== undefined && t >= lie.editTick && !removed && jump) removing = true;
    if (removing && !jump) {
      removing = false;
      removed = true;
    }
    rec.record([removing ? input & ~0x10001 : input], game);
  }
  return { bytes: rec.finish(), game };
}

/**
 * A bot match of any registered game: every player driven by the game's bot. Honest, unless
 * `lie.hashAt` is given: then the hash stored for that tick is not the state's.
 */
export function recordBot(
  gameId: string,
  ticks: number,
  players = 1,
  lie: { hashAt?: number } = {},
): Recorded {
  const def = findGame(gameId);
  if (!def) throw new Error(`the ${gameId} game is not registered`);
  const config = { seed: 3, players };
  const game = def.create(config);
  const names = Array.from({ length: players }, (_, i) => `bot${i}`);
  const rec = new ReplayRecorder(replayOptionsFor(def, config, names, { checkpointEvery: 60 }));
  const seen = {
    get tick() {
      return game.tick;
    },
    hash: () => (game.tick === lie.hashAt ? ~game.hash() : game.hash()),
    save: () => game.save(),
  };
  rec.start(seen);
  const inputs = new Array<number>(players).fill(0);
  for (let t = 0; t < ticks; t++) {
    for (let p = 0; p < players; p++) inputs[p] = def.bot(game, p);
    game.step(inputs);
    rec.record(inputs, seen);
  }
  return { bytes: rec.finish(), game };
}
