/**
 * Ten minutes of every registered game, as a server sees a submission: a bot match taken down by
 * the recorder, then re-simulated from the file's own inputs — by `verifyReplay`, and by a plain
 * loop that hashes the state every 10 s. The final hash and the digest of those hashes are golden:
 * they were computed by the games before the speed work (the broad phase of the walls, the bots'
 * searches, the register forms) and must never change with it. Correctness, not speed: nothing
 * here is timed.
 */
import { describe, expect, it } from 'vitest';
import {
  ReplayRecorder,
  fnv1a64Hex,
  hex64,
  readReplay,
  verifyReplay,
  type ButtonInput,
} from 'fixedstep';
import {
  GAMES,
  gameFromReplayHeader,
  replayOptionsFor,
  type RegisteredGame,
} from '@fixedstep/games';

const SEED = 20261201;
const MINUTES = 10;
/** A hash every 10 s of play (at 60 Hz) goes into the digest. */
const HASH_EVERY = 600;

/**
 * Per game: the hash after ten minutes, the FNV-1a 64 of the hashes every 10 s (as hex, one after
 * another), and the tick at which the match ended (-1: it runs on).
 */
const GOLDEN: Record<string, { final: string; digest: string; overAt: number }> = {
  runner: { final: '210bc5f1ab9993f4', digest: 'b2ca213a1be5ff1e', overAt: -1 },
  ctf: { final: '026f2ad40b435ae0', digest: 'a4edfb293b101c6f', overAt: 36000 },
  // The bots lose their 15 lives each in wave 28, 6.9 minutes in; the rest is a finished match.
  survival: { final: '55d4a2a4ae75b23f', digest: '148d58c625a574f1', overAt: 24818 },
};

/** A bot match of `ticks` ticks on two seats (or what the game allows), recorded. */
function recordBotMatch(def: RegisteredGame, ticks: number): Uint8Array {
  const players = Math.min(def.info.maxPlayers, Math.max(def.info.minPlayers, 2));
  const config = { seed: SEED, players };
  const names = Array.from({ length: players }, (_, p) => `bot ${String(p + 1)}`);
  const recorder = new ReplayRecorder(replayOptionsFor(def, config, names));
  const game = def.create(config);
  recorder.start(game);
  const frame = new Array<ButtonInput>(players).fill(0);
  for (let t = 0; t < ticks; t++) {
    for (let p = 0; p < players; p++) frame[p] = def.bot(game, p);
    game.step(frame);
    recorder.record(frame, game);
  }
  return recorder.finish();
}

describe.each(GAMES.map((def) => ({ id: def.info.id, def })))(
  'a 10-minute bot match of $id, re-simulated from its replay',
  ({ id, def }) => {
    const ticks = MINUTES * 60 * def.info.tickRate;
    const bytes = recordBotMatch(def, ticks);
    const golden = GOLDEN[id];

    it('has golden numbers', () => {
      expect(golden, `no golden numbers for ${id}: add them`).toBeDefined();
    });

    it('verifies, and ends in the golden state', () => {
      const result = verifyReplay(bytes, gameFromReplayHeader);
      expect(result.ok).toBe(true);
      expect(result.simulated).toBe(ticks);
      // A finished match is not stepped to the end of the file (every hash still compared):
      // from the first tick checked at or after the end on.
      const overAt = golden?.overAt ?? -1;
      const lag = result.frozenFrom - overAt;
      const every = readReplay(bytes).checkpointEvery;
      expect(
        overAt < 0 ? result.frozenFrom === -1 : lag >= 0 && lag < every,
        `frozen from ${result.frozenFrom}, over at ${overAt}`,
      ).toBe(true);
      const final = hex64(readReplay(bytes).finalHash);
      if (final !== golden?.final) console.log(`${id} 10-minute final hash: ${final}`);
      expect(final).toBe(golden?.final);
    });

    it('goes through the golden states every 10 s, tick for tick from the file’s inputs', () => {
      const replay = readReplay(bytes);
      expect(replay.tickCount).toBe(ticks);
      const game = gameFromReplayHeader(replay.header);
      const cursor = replay.inputCursor();
      const inputs: number[] = [];
      let hashes = '';
      let overAt = -1;
      for (let t = 1; t <= ticks; t++) {
        cursor.next(inputs);
        game.step(inputs);
        if (overAt < 0 && game.over) overAt = t;
        if (t % HASH_EVERY === 0) hashes += hex64(game.hash());
      }
      const actual = {
        final: hex64(game.hash()),
        digest: fnv1a64Hex(new TextEncoder().encode(hashes)),
        overAt,
      };
      if (JSON.stringify(actual) !== JSON.stringify(golden)) {
        console.log(`${id} 10-minute golden numbers: ${JSON.stringify(actual)}`);
      }
      expect(actual).toEqual(golden);
    });
  },
);
