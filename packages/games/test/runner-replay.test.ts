import { describe, expect, it } from 'vitest';
import {
  ReplayPlayer,
  ReplayRecorder,
  hex64,
  isReplayError,
  readReplay,
  verifyReplay,
  type ReplayRecorderOptions,
} from 'fixedstep';
import {
  RunnerGame,
  gameFromReplayHeader,
  replayOptionsFor,
  runnerBot,
  runnerGame,
  type GameConfig,
} from '@fixedstep/games';

const MINUTES = 10;
const TICKS = MINUTES * 60 * 60;
const SEED = 21;
const KEYFRAME_EVERY = 3600;

interface Recorded {
  bytes: Uint8Array;
  /** inputs[t]: the input of tick t. */
  inputs: Uint32Array;
  /** hashes[t]: the state hash after tick t. */
  hashes: BigUint64Array;
  saves: Map<number, Uint8Array>;
  score: number;
}

function options(config: GameConfig): ReplayRecorderOptions {
  return replayOptionsFor(runnerGame, config, ['bot'], { keyframeEvery: KEYFRAME_EVERY });
}

/** The bot plays `ticks` ticks and a recorder takes it down (every hash kept, for forgeries). */
function recordBot(seed: number, ticks: number): Recorded {
  const config = { seed, players: 1 };
  const game = new RunnerGame(config);
  const rec = new ReplayRecorder(options(config));
  rec.start(game);
  const inputs = new Uint32Array(ticks);
  const hashes = new BigUint64Array(ticks + 1);
  const saves = new Map<number, Uint8Array>();
  hashes[0] = game.hash();
  const frame = [0];
  for (let t = 0; t < ticks; t++) {
    frame[0] = inputs[t] = runnerBot(game, 0);
    game.step(frame);
    rec.record(frame, game);
    hashes[t + 1] = game.hash();
    if ((t + 1) % KEYFRAME_EVERY === 0) saves.set(t + 1, game.save());
  }
  return { bytes: rec.finish(), inputs, hashes, saves, score: game.score };
}

/**
 * A forger's file: a recorder fed by a puppet that reports the recorded run's hashes and
 * snapshots, with other inputs or another header. Checksum and structure are perfect; only
 * re-simulation can tell.
 */
function forge(run: Recorded, config: GameConfig, inputs: Uint32Array): Uint8Array {
  const puppet = {
    tick: 0,
    hash: () => run.hashes[puppet.tick]!,
    save: () => run.saves.get(puppet.tick)!,
  };
  const rec = new ReplayRecorder(options(config));
  rec.start(puppet);
  const frame = [0];
  for (let t = 0; t < inputs.length; t++) {
    frame[0] = inputs[t]!;
    puppet.tick++;
    rec.record(frame, puppet);
  }
  return rec.finish();
}

const run = recordBot(SEED, TICKS);
const replay = readReplay(run.bytes, { gameId: 'runner' });

describe('runner replays: a 10-minute bot game', () => {
  it('records and verifies by re-simulation', () => {
    expect(replay.tickCount).toBe(TICKS);
    expect(replay.header.seeds).toEqual([SEED]);
    expect(runnerGame.decodeConfig(replay.header.config)).toEqual({ seed: SEED, players: 1 });
    expect(run.score).toBeGreaterThan(110_000);
    const result = verifyReplay(run.bytes, gameFromReplayHeader, {
      gameId: 'runner',
      gameVersion: String(runnerGame.info.version),
    });
    expect(result).toMatchObject({ ok: true, ticks: TICKS, simulated: TICKS, lastGoodTick: TICKS });
    expect(replay.finalHash).toBe(run.hashes[TICKS]);
  });

  it('takes a few hundred bytes a minute', () => {
    const section = (name: string) => replay.sections.find((s) => s.name === name)!.length;
    const inputsPerMinute = section('INPUTS') / MINUTES;
    const filePerMinute = run.bytes.length / MINUTES;
    expect(inputsPerMinute).toBeLessThan(400);
    expect(filePerMinute).toBeLessThan(1200);
    // A checkpoint (8 bytes) every 10 s (the default), and one at tick 0.
    expect(replay.checkpointEvery).toBe(600);
    expect(section('CHECKPOINTS')).toBe(8 * (TICKS / 600 + 1));
  });

  it('an edited input is caught at the next checkpoint, even in a well-formed file', () => {
    // Drop one of the bot's jumps: the player stays on the ground and the states part at once.
    let t = 20_000;
    while (run.inputs[t] === 0) t++;
    const inputs = run.inputs.slice();
    inputs[t] = 0;
    const forged = forge(run, { seed: SEED, players: 1 }, inputs);
    expect(readReplay(forged).tickCount).toBe(TICKS); // parses: checksum and structure are fine
    const result = verifyReplay(forged, gameFromReplayHeader);
    const every = replay.checkpointEvery;
    const next = Math.ceil((t + 1) / every) * every;
    expect(result).toMatchObject({ ok: false, kind: 'checkpoint', firstMismatchTick: next });
    expect(result.lastGoodTick).toBe(next - every);
    // The untouched original still verifies.
    expect(
      verifyReplay(forge(run, { seed: SEED, players: 1 }, run.inputs), gameFromReplayHeader).ok,
    ).toBe(true);
  });

  it('a flipped byte is caught by the checksum before any simulation', () => {
    const inputsAt = replay.sections.find((s) => s.name === 'INPUTS')!.offset;
    const damaged = run.bytes.slice();
    damaged[inputsAt + 20] = damaged[inputsAt + 20]! ^ 1;
    let error: unknown;
    try {
      verifyReplay(damaged, gameFromReplayHeader);
    } catch (e) {
      error = e;
    }
    expect(isReplayError(error) && error.code).toBe('BAD_CHECKSUM');
  });

  it('a replay from another seed fails at tick 0', () => {
    // The right file, the wrong game: a factory that ignores the header's seed.
    const wrongFactory = () => new RunnerGame({ seed: SEED + 1, players: 1 });
    expect(verifyReplay(run.bytes, wrongFactory)).toMatchObject({
      ok: false,
      kind: 'checkpoint',
      firstMismatchTick: 0,
      lastGoodTick: -1,
    });
    // A file whose header claims another seed, with this run's inputs and hashes.
    const claimed = forge(run, { seed: SEED + 1, players: 1 }, run.inputs);
    expect(readReplay(claimed).header.seeds).toEqual([SEED + 1]);
    expect(verifyReplay(claimed, gameFromReplayHeader)).toMatchObject({
      ok: false,
      firstMismatchTick: 0,
    });
    // That seed's own bot game is a different run altogether.
    const other = recordBot(SEED + 1, 600);
    expect(other.hashes[600]).not.toBe(run.hashes[600]);
  });

  it('the player seeks through keyframes to the recorded states', () => {
    const player = new ReplayPlayer(replay, gameFromReplayHeader);
    for (const tick of [25_000, 7_201, 35_999, 3_600]) {
      player.seek(tick);
      expect(hex64(player.sim.hash()), `tick ${tick}`).toBe(hex64(run.hashes[tick]!));
    }
    expect(player.firstMismatch).toBeNull();
  });
});
