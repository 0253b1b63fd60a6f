import {
  Fnv1a64,
  ReplayError,
  hex64,
  readReplay,
  replayFactory,
  setupFromReplayHeader,
  verifyReplay,
  type AnyGameDefinition,
  type Replay,
  type ReplayLimits,
  type Simulation,
} from 'fixedstep';
import { cleanName } from '../text.js';

/**
 * Checking a highscore submission, in two steps: {@link precheckSubmission} (cheap — parse the
 * file, a known game of the same version and input schema, within the limits, a score the game
 * can rank — done on the event loop before any simulation) and {@link resimulate} (the re-simulation
 * itself, done in a verification worker). Both are pure functions of the bytes and the games.
 */

/** Why a submission was refused: an HTTP status, a stable code and a sentence for people. */
export class SubmissionError extends Error {
  override readonly name = 'SubmissionError';
  constructor(
    /** The HTTP status to answer with (4xx, or 503 when the server is busy or its store is down). */
    readonly status: number,
    /** A stable code for programs, e.g. `DOES_NOT_REPRODUCE`, `RUN_TAKEN`. */
    readonly code: string,
    message: string,
    /** Seconds after which a retry may succeed (sent as `Retry-After`), for 429 and 503. */
    readonly retryAfter?: number,
  ) {
    super(message);
  }
}

/** The most ticks a submitted replay may have: one hour at 60 Hz (bounds the re-simulation). */
export const MAX_SUBMITTED_TICKS = 216_000;
/** The largest submitted replay, in bytes (1 MiB). */
export const MAX_SUBMITTED_BYTES = 1024 * 1024;
/** The most keyframes a submitted replay may hold (a played run needs a few hundred). */
export const MAX_SUBMITTED_KEYFRAMES = 4096;
/** The highest score a submission may claim (scores are stored as 53-bit integers). */
export const MAX_CLAIMED_SCORE = 2 ** 31 - 1;

/** The replay limits a submission is parsed under. */
export function submissionLimits(
  maxTicks = MAX_SUBMITTED_TICKS,
  maxBytes = MAX_SUBMITTED_BYTES,
): Partial<ReplayLimits> {
  return {
    maxTicks,
    maxFileBytes: maxBytes,
    maxKeyframes: MAX_SUBMITTED_KEYFRAMES,
    maxPlayers: 64,
  };
}

/** What the pre-check learned from a submission that looks honest. */
export interface Precheck {
  readonly game: AnyGameDefinition;
  readonly replay: Replay;
  /** The run's identity (16 hex digits): see {@link runId}. */
  readonly runId: string;
  /** The first player's name, cleaned (no control characters, ≤ 32 characters). */
  readonly name: string;
  readonly seed: number;
  readonly ticks: number;
}

/**
 * The identity of a run: FNV-1a 64 over everything that decides the simulation — game id and
 * version, step, seeds, option bytes, player count, input schema, and every player's input at every
 * tick — and nothing that does not: not the player names, not how often hashes or keyframes were
 * stored. A run renamed, or recorded again with other checkpoint settings, has the same identity.
 */
export function runId(replay: Replay): string {
  const h = replay.header;
  const text = new TextEncoder();
  const h64 = new Fnv1a64();
  const field = (bytes: Uint8Array) => {
    h64.update(u32(bytes.length)).update(bytes);
  };
  field(text.encode('fixedstep-run/1'));
  field(text.encode(h.gameId));
  field(text.encode(h.gameVersion));
  h64.update(u32(h.stepNumerator)).update(u32(h.stepDenominator));
  h64.update(u32(h.seeds.length));
  for (const s of h.seeds) h64.update(u32(s));
  field(h.config);
  h64.update(u32(h.players.length));
  field(text.encode(h.input.id));
  h64.update(u32(replay.tickCount));
  // Inputs tick by tick, in chunks of ticks, as little-endian words.
  const per = replay.playerCount * replay.words;
  const chunkTicks = 1024;
  const chunk = new Uint32Array(per * chunkTicks);
  const tick = new Uint32Array(per);
  const cursor = replay.inputCursor();
  let filled = 0;
  for (let t = 0; t < replay.tickCount; t++) {
    cursor.nextWords(tick);
    chunk.set(tick, filled * per);
    if (++filled === chunkTicks) {
      h64.update(littleEndian(chunk, filled * per));
      filled = 0;
    }
  }
  if (filled > 0) h64.update(littleEndian(chunk, filled * per));
  return h64.hex();
}

const LITTLE = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

function littleEndian(words: Uint32Array, count: number): Uint8Array {
  if (LITTLE) return new Uint8Array(words.buffer, words.byteOffset, count * 4);
  const out = new Uint8Array(count * 4);
  const view = new DataView(out.buffer);
  for (let i = 0; i < count; i++) view.setUint32(i * 4, words[i]!, true);
  return out;
}

function u32(n: number): Uint8Array {
  const b = new Uint8Array(4);
  new DataView(b.buffer).setUint32(0, n >>> 0, true);
  return b;
}

/**
 * The cheap checks, before any simulation: the file parses under the submission limits, its game
 * is one of `games` with the same version, tick rate, input schema and a player count it takes, the
 * game ranks scores, and the claimed score is a whole number it could rank. Throws a
 * {@link SubmissionError} (422, or 400 for the claim) naming what is wrong. Costs O(file size).
 */
export function precheckSubmission(
  bytes: Uint8Array,
  claimedScore: number,
  games: readonly AnyGameDefinition[],
  limits: Partial<ReplayLimits> = submissionLimits(),
): Precheck {
  if (!Number.isSafeInteger(claimedScore) || claimedScore < 0 || claimedScore > MAX_CLAIMED_SCORE) {
    throw new SubmissionError(
      400,
      'BAD_SCORE',
      `score must be a whole number from 0 to ${MAX_CLAIMED_SCORE}`,
    );
  }
  let replay: Replay;
  try {
    replay = readReplay(bytes, { limits });
  } catch (error) {
    if (error instanceof ReplayError) {
      throw new SubmissionError(422, error.code, `invalid replay: ${error.message}`);
    }
    throw error;
  }
  const header = replay.header;
  const game = games.find((g) => g.id === header.gameId);
  if (game === undefined) {
    throw new SubmissionError(
      422,
      'UNKNOWN_GAME',
      `this server has no game "${cleanName(header.gameId)}" (it has ${games.map((g) => g.id).join(', ')})`,
    );
  }
  try {
    setupFromReplayHeader(game, header);
  } catch (error) {
    throw new SubmissionError(
      422,
      'WRONG_GAME',
      error instanceof Error ? error.message : String(error),
    );
  }
  if (game.score === undefined) {
    throw new SubmissionError(422, 'NO_SCORE', `${game.id} keeps no score to rank`);
  }
  return {
    game,
    replay,
    runId: runId(replay),
    name: cleanName(header.players[0] ?? ''),
    seed: header.seeds[0] ?? 0,
    ticks: replay.tickCount,
  };
}

/**
 * What the pre-check learned, as plain data (it crosses from a worker thread): see
 * `precheckSubmission`.
 */
export interface PrecheckSummary {
  readonly gameId: string;
  readonly gameVersion: string;
  /** The run's identity (16 hex digits). */
  readonly runId: string;
  /** The first player's name, cleaned. */
  readonly name: string;
  readonly seed: number;
  readonly ticks: number;
}

/** A pre-check's answer: the summary, or the refusal. */
export type PrecheckResult =
  | { readonly ok: true; readonly summary: PrecheckSummary }
  | {
      readonly ok: false;
      readonly status: number;
      readonly code: string;
      readonly message: string;
    };

/** Runs the pre-check (see `precheckSubmission`), as plain data. */
export function precheckPlain(
  bytes: Uint8Array,
  claimedScore: number,
  games: readonly AnyGameDefinition[],
  limits: Partial<ReplayLimits>,
): PrecheckResult {
  try {
    const pre = precheckSubmission(bytes, claimedScore, games, limits);
    return {
      ok: true,
      summary: {
        gameId: pre.game.id,
        gameVersion: String(pre.game.version),
        runId: pre.runId,
        name: pre.name,
        seed: pre.seed,
        ticks: pre.ticks,
      },
    };
  } catch (error) {
    if (error instanceof SubmissionError)
      return { ok: false, status: error.status, code: error.code, message: error.message };
    return { ok: false, status: 500, code: 'VERIFIER_ERROR', message: String(error) };
  }
}

/** What re-simulating a submission found (plain data: it crosses from a worker thread). */
export type Resimulation =
  | {
      readonly ok: true;
      readonly score: number;
      readonly ticks: number;
      readonly finalHash: string;
    }
  | {
      readonly ok: false;
      readonly status: number;
      readonly code: string;
      readonly message: string;
    };

/**
 * Re-simulates a submission from its inputs and seed alone, checks every stored hash and that the
 * final state has exactly `claimedScore`. Never throws for a bad file: the refusal is the result.
 * Runs at most `limits.maxTicks` steps.
 */
export function resimulate(
  bytes: Uint8Array,
  claimedScore: number,
  games: readonly AnyGameDefinition[],
  limits: Partial<ReplayLimits> = submissionLimits(),
): Resimulation {
  const refuse = (status: number, code: string, message: string): Resimulation => ({
    ok: false,
    status,
    code,
    message,
  });
  const factory = replayFactory(games);
  let sim: Simulation<unknown> | undefined;
  let result;
  try {
    result = verifyReplay(bytes, (header) => (sim = factory(header)), {
      limits,
      checkKeyframes: true,
    });
  } catch (error) {
    if (error instanceof ReplayError)
      return refuse(422, error.code, `invalid replay: ${error.message}`);
    if (error instanceof RangeError) return refuse(422, 'WRONG_GAME', error.message);
    return refuse(422, 'GAME_REJECTED', `the game refused the replay: ${String(error)}`);
  }
  if (!result.ok || sim === undefined) {
    return refuse(
      422,
      'DOES_NOT_REPRODUCE',
      `the replay does not reproduce: the state first differs after a tick in (${result.lastGoodTick}, ${result.firstMismatchTick}]`,
    );
  }
  const game = games.find((g) => g.id === result.replay.header.gameId)!;
  const score = game.score?.(sim);
  if (score === undefined || !Number.isFinite(score)) {
    return refuse(422, 'NO_SCORE', `${game.id} keeps no score to rank`);
  }
  if (score !== claimedScore) {
    return refuse(422, 'SCORE_MISMATCH', `claimed ${claimedScore}, the replay scores ${score}`);
  }
  return { ok: true, score, ticks: result.ticks, finalHash: hex64(result.replay.finalHash) };
}
