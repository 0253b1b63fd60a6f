/**
 * Replays of the talk's games as chapters 5 and 9 both need them: how a game is recorded, a bot
 * game recorded headless (the replays chapter's sample), a replay given another player name, and
 * what a file holds, section by section — so every sentence about a replay's size is read from the
 * file itself. No DOM here.
 */
import { ReplayRecorder, readReplay, type Replay, type ReplayRecorderOptions } from 'fixedstep';
import {
  gameFromReplayHeader,
  replayOptionsFor,
  type GameConfig,
  type RegisteredGame,
} from '@fixedstep/games';
import { bytesPerMinute, cleanName } from './games.js';

/**
 * The recorder options every game of the lab records with: the inputs, the seed and a state hash
 * every 10 s (the recorder's default) — no stored snapshots: a player re-simulates to seek, as the
 * talk says a replay is just the inputs and the seeds.
 */
export function labRecording(
  def: RegisteredGame,
  config: GameConfig,
  player: string,
): ReplayRecorderOptions {
  return replayOptionsFor(def, config, [cleanName(player)]);
}

/**
 * `ticks` ticks of `def`'s game with seed `seed`, played by its bot and recorded as the lab
 * records a game. Deterministic: the same arguments give the same bytes.
 */
export function recordBotGame(
  def: RegisteredGame,
  seed: number,
  ticks: number,
  player = 'bot',
): Uint8Array {
  if (!(Number.isInteger(ticks) && ticks >= 0 && ticks <= 216_000)) {
    throw new RangeError(`recordBotGame: ticks must be an integer from 0 to 216000, got ${ticks}`);
  }
  const config = { seed: seed >>> 0, players: 1 };
  const game = def.create(config);
  const recorder = new ReplayRecorder(labRecording(def, config, player));
  recorder.start(game);
  const inputs = [0];
  for (let t = 0; t < ticks && !game.over; t++) {
    inputs[0] = def.bot(game, 0);
    game.step(inputs);
    recorder.record(inputs, game);
  }
  return recorder.finish();
}

/**
 * The same replay with `name` as its player: the game is rebuilt from the header and stepped with
 * the file's inputs into a new recording (same game, seed, inputs, hashes and keyframe spacing),
 * so a name typed after the game still reaches the highscore table. Returns `bytes` itself when
 * the name is already the file's. Throws a ReplayError for a file it cannot read.
 */
export function withPlayerName(bytes: Uint8Array, name: string): Uint8Array {
  const replay = readReplay(bytes);
  const clean = cleanName(name);
  const header = replay.header;
  if (header.players.length === 1 && header.players[0] === clean) return bytes;
  const game = gameFromReplayHeader(header);
  const recorder = new ReplayRecorder({
    gameId: header.gameId,
    gameVersion: header.gameVersion,
    tickRate: game.info.tickRate,
    seeds: header.seeds,
    config: header.config,
    players: header.players.map((p, i) => (i === 0 ? clean : p)),
    checkpointEvery: replay.checkpointEvery,
    keyframeEvery: replay.keyframeEvery,
    tickHashes: replay.tickHashes !== null,
    input: header.input,
  });
  recorder.start(game);
  const cursor = replay.inputCursor();
  const words = new Uint32Array(replay.playerCount * replay.words);
  const inputs: number[] = [];
  for (let t = 0; t < replay.tickCount; t++) {
    cursor.nextWords(words);
    for (let p = 0; p < replay.playerCount; p++) inputs[p] = words[p * replay.words]!;
    game.step(inputs);
    recorder.recordWords(words, game);
  }
  return recorder.finish();
}

/** What a replay file holds, from its own sections. Bytes. */
export interface ReplayContents {
  /** The whole file. */
  total: number;
  /** The INPUTS section: every tick's input, run-length coded. */
  inputs: number;
  /** CHECKPOINTS and TICK_HASHES: the hashes that prove the replay. */
  hashes: number;
  /** KEYFRAMES: snapshots of the state, for seeking (0 when the file has none). */
  keyframes: number;
  /** The rest: header, game and tick sections, section headers, checksum. */
  header: number;
  /** Keyframes stored. */
  keyframeCount: number;
  /** Ticks recorded, and the step's rate. */
  ticks: number;
  tickRate: number;
  /** The whole file per minute of play (NaN for an empty replay). */
  bytesPerMinute: number;
}

/** The section sizes of a parsed replay. */
export function replayContents(replay: Replay): ReplayContents {
  const size = (...names: string[]) =>
    replay.sections.filter((s) => names.includes(s.name)).reduce((n, s) => n + s.length, 0);
  const inputs = size('INPUTS');
  const hashes = size('CHECKPOINTS', 'TICK_HASHES');
  const keyframes = size('KEYFRAMES');
  const h = replay.header;
  const tickRate = h.stepDenominator / h.stepNumerator;
  return {
    total: replay.byteLength,
    inputs,
    hashes,
    keyframes,
    header: replay.byteLength - inputs - hashes - keyframes,
    keyframeCount: replay.keyframes.length,
    ticks: replay.tickCount,
    tickRate,
    bytesPerMinute: bytesPerMinute(replay.byteLength, replay.tickCount, tickRate),
  };
}

/**
 * One sentence on what the file holds, every number from its sections:
 * "28 019 bytes: the inputs of 2 345 ticks in 319 B, 40 state hashes in 330 B, 8 keyframes in
 * 27 428 B (98 % of the file, for seeking) and 60 B of header".
 */
export function describeContents(c: ReplayContents, count: (n: number) => string): string {
  const share = (n: number) => (c.total > 0 ? Math.round((100 * n) / c.total) : 0);
  const parts = [
    `the inputs of ${count(c.ticks)} ticks in ${count(c.inputs)} B (${share(c.inputs)} %)`,
    `the state hashes in ${count(c.hashes)} B`,
    c.keyframes > 0
      ? `${count(c.keyframeCount)} keyframe${c.keyframeCount === 1 ? '' : 's'} for seeking in ${count(c.keyframes)} B (${share(c.keyframes)} %)`
      : 'no keyframes (seeking re-simulates from the inputs)',
    `${count(c.header)} B of header and checksum`,
  ];
  return `${count(c.total)} bytes: ${parts.slice(0, -1).join(', ')} and ${parts[parts.length - 1]!}`;
}
