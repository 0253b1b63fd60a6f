import { mkdir, open, readFile, readdir, rename, unlink } from 'node:fs/promises';
import type http from 'node:http';
import path from 'node:path';
import { ReplayError, fnv1a64Hex, hex64, verifyReplay, type Simulation } from 'fixedstep';
import { findGame, gameFromReplayHeader, type Game } from '@fixedstep/games';

/**
 * Highscores that cannot be faked: a score is accepted only with the replay that produced it,
 * re-simulated here from the inputs and seed alone; the table is kept durably in one JSON file.
 *
 * Why one file and not an embedded database: the table is small (the best 100 per game), written
 * rarely (a verified submission) and read whole; one file written atomically — write a temporary
 * file, fsync it, rename it over the old one, fsync the directory — survives a restart and a crash
 * at any point of a write (the old table or the new one is on disk, never half of one), needs no
 * native module, and can be read with any text editor.
 */

export interface HighscoreEntry {
  game: string;
  /** The player's name, from the replay (trimmed to 32 printable characters). */
  name: string;
  score: number;
  /** Ticks the game lasted. */
  ticks: number;
  seed: number;
  /** The replay's final state hash, 16 hex digits. */
  finalHash: string;
  /** FNV-1a 64 of the replay file, 16 hex digits: the same file is accepted once. */
  replayId: string;
  /** When it was accepted (server time, ISO 8601). */
  at: string;
}

/** How many entries each game's table keeps. */
export const TABLE_SIZE = 100;

/** A table of highscores per game, persisted atomically to one JSON file. */
export class HighscoreStore {
  private entries: HighscoreEntry[] = [];
  private writing: Promise<void> = Promise.resolve();
  private tmpCount = 0;

  private constructor(readonly file: string) {}

  /**
   * Opens (or creates) the table at `file`. A file that cannot be parsed is kept aside as
   * `<file>.corrupt-<time>` — never deleted — and the table starts empty; `recovered` says so.
   */
  static async open(file: string): Promise<{ store: HighscoreStore; recovered?: string }> {
    const store = new HighscoreStore(path.resolve(file));
    await mkdir(path.dirname(store.file), { recursive: true });
    await store.removeStaleTemporaries();
    let text: string;
    try {
      text = await readFile(store.file, 'utf8');
    } catch (error) {
      if ((error as NodeJS.ErrnoException).code === 'ENOENT') return { store };
      throw error;
    }
    try {
      store.entries = parseTable(text);
      return { store };
    } catch (error) {
      const aside = `${store.file}.corrupt-${new Date().toISOString().replace(/[:.]/g, '-')}`;
      await rename(store.file, aside);
      return {
        store,
        recovered: `${store.file} could not be read (${(error as Error).message}); kept as ${aside}`,
      };
    }
  }

  /** The best entries of `game`, best first. */
  top(game: string, limit = 10): HighscoreEntry[] {
    return this.entries.filter((e) => e.game === game).slice(0, limit);
  }

  /** Whether a replay file with this id was already accepted. */
  has(replayId: string): boolean {
    return this.entries.some((e) => e.replayId === replayId);
  }

  /**
   * Adds an entry and writes the table to disk before resolving. Returns its rank (1 = best) in
   * its game's table, or 0 if it did not make the table.
   */
  async add(entry: HighscoreEntry): Promise<number> {
    const all = [...this.entries, entry].sort(compareEntries);
    const kept: HighscoreEntry[] = [];
    const perGame = new Map<string, number>();
    for (const e of all) {
      const n = perGame.get(e.game) ?? 0;
      if (n < TABLE_SIZE) kept.push(e);
      perGame.set(e.game, n + 1);
    }
    this.entries = kept;
    const rank = kept.filter((e) => e.game === entry.game).indexOf(entry) + 1;
    await this.persist();
    return rank;
  }

  private persist(): Promise<void> {
    const text = `${JSON.stringify({ format: 'fixedstep-highscores', version: 1, entries: this.entries }, null, 1)}\n`;
    // Writes run one after another; each writes the whole table as it was when it was asked for.
    this.writing = this.writing.then(() => this.writeAtomically(text));
    return this.writing;
  }

  private async writeAtomically(text: string): Promise<void> {
    const tmp = `${this.file}.tmp-${process.pid}-${++this.tmpCount}`;
    const handle = await open(tmp, 'w');
    try {
      await handle.writeFile(text, 'utf8');
      await handle.sync();
    } finally {
      await handle.close();
    }
    await rename(tmp, this.file);
    const dir = await open(path.dirname(this.file), 'r');
    try {
      await dir.sync();
    } finally {
      await dir.close();
    }
  }

  private async removeStaleTemporaries(): Promise<void> {
    const base = path.basename(this.file);
    for (const name of await readdir(path.dirname(this.file))) {
      if (name.startsWith(`${base}.tmp-`)) await unlink(path.join(path.dirname(this.file), name));
    }
  }
}

function compareEntries(a: HighscoreEntry, b: HighscoreEntry): number {
  if (a.game !== b.game) return a.game < b.game ? -1 : 1;
  if (a.score !== b.score) return b.score - a.score;
  if (a.ticks !== b.ticks) return a.ticks - b.ticks;
  return a.at < b.at ? -1 : a.at > b.at ? 1 : 0;
}

function parseTable(text: string): HighscoreEntry[] {
  const data = JSON.parse(text) as { format?: unknown; entries?: unknown };
  if (data.format !== 'fixedstep-highscores' || !Array.isArray(data.entries))
    throw new Error('not a highscore table');
  const ok = (e: Record<string, unknown>) =>
    typeof e.game === 'string' &&
    typeof e.name === 'string' &&
    Number.isFinite(e.score) &&
    Number.isInteger(e.ticks) &&
    typeof e.replayId === 'string' &&
    typeof e.at === 'string';
  const entries = data.entries as Record<string, unknown>[];
  if (!entries.every(ok)) throw new Error('an entry is malformed');
  return (entries as unknown as HighscoreEntry[]).sort(compareEntries);
}

/** Why a submission was refused. */
export class SubmissionError extends Error {
  constructor(
    readonly status: number,
    readonly code: string,
    message: string,
  ) {
    super(message);
  }
}

/** The most ticks a submitted replay may have: one hour at 60 Hz (bounds the re-simulation). */
export const MAX_SUBMITTED_TICKS = 216_000;
/** The largest submitted replay, in bytes. */
export const MAX_SUBMITTED_BYTES = 1024 * 1024;

/**
 * Checks a submission: the replay must parse, be of a game this server has (same version),
 * re-simulate to every stored hash, and end with exactly the claimed score. Returns the entry to
 * store (not stored yet).
 */
export function checkSubmission(
  bytes: Uint8Array,
  claimedScore: number,
  now: Date,
): HighscoreEntry {
  let game: Game | undefined;
  const factory = (header: Parameters<typeof gameFromReplayHeader>[0]): Simulation => {
    game = gameFromReplayHeader(header);
    return game;
  };
  let result;
  try {
    result = verifyReplay(bytes, factory, {
      limits: { maxTicks: MAX_SUBMITTED_TICKS, maxFileBytes: MAX_SUBMITTED_BYTES },
    });
  } catch (error) {
    if (error instanceof ReplayError)
      throw new SubmissionError(422, error.code, `invalid replay: ${error.message}`);
    if (error instanceof RangeError) throw new SubmissionError(422, 'WRONG_GAME', error.message);
    throw error;
  }
  if (!result.ok || !game) {
    throw new SubmissionError(
      422,
      'DOES_NOT_REPRODUCE',
      `the replay does not reproduce: the state first differs after a tick in (${result.lastGoodTick}, ${result.firstMismatchTick}]`,
    );
  }
  const header = result.replay.header;
  const key = findGame(header.gameId)?.info.scoreKey ?? 'score';
  const score = game.hud()[key];
  if (score === undefined)
    throw new SubmissionError(422, 'NO_SCORE', `${header.gameId} has no "${key}" to rank by`);
  if (score !== claimedScore) {
    throw new SubmissionError(
      422,
      'SCORE_MISMATCH',
      `claimed ${claimedScore}, the replay scores ${score}`,
    );
  }
  return {
    game: header.gameId,
    name: cleanName(header.players[0] ?? ''),
    score,
    ticks: result.ticks,
    seed: header.seeds[0] ?? 0,
    finalHash: hex64(result.replay.finalHash),
    replayId: fnv1a64Hex(bytes),
    at: now.toISOString(),
  };
}

function cleanName(name: string): string {
  const printable = Array.from(name)
    .filter((ch) => ch >= ' ' && ch !== '\u007f')
    .join('');
  const clean = printable.trim().slice(0, 32);
  return clean === '' ? 'anonymous' : clean;
}

/** Handles one HTTP request if it is for the highscore API; resolves true when it answered. */
export type ApiHandler = (req: http.IncomingMessage, res: http.ServerResponse) => Promise<boolean>;

export interface HighscoreApiOptions {
  store: HighscoreStore;
  /** Submissions allowed per client address per minute. Default 20. */
  perMinute?: number;
  /** The clock for the rate limit and timestamps (injectable for tests). Default Date.now. */
  now?: () => number;
}

/**
 * `GET /api/highscores?game=runner&limit=10` → `{ game, entries }`.
 * `POST /api/highscores?score=N` with the replay file as the body → 201 `{ rank, entry }`, or
 * 4xx `{ error, code }`: 400 bad request, 409 already submitted, 413 too large, 422 refused
 * (invalid replay, does not reproduce, score mismatch), 429 too many submissions.
 */
export function highscoreApi(options: HighscoreApiOptions): ApiHandler {
  const perMinute = options.perMinute ?? 20;
  const now = options.now ?? Date.now;
  const recent = new Map<string, number[]>();
  return async (req, res) => {
    const url = new URL(req.url ?? '/', 'http://localhost');
    if (url.pathname !== '/api/highscores') return false;
    try {
      if (req.method === 'GET' || req.method === 'HEAD') {
        const game = url.searchParams.get('game') ?? '';
        if (!findGame(game))
          throw new SubmissionError(400, 'UNKNOWN_GAME', `unknown game "${game}"`);
        const limit = Number(url.searchParams.get('limit') ?? '10');
        if (!Number.isInteger(limit) || limit < 1 || limit > TABLE_SIZE) {
          throw new SubmissionError(
            400,
            'BAD_LIMIT',
            `limit must be an integer from 1 to ${TABLE_SIZE}`,
          );
        }
        json(res, 200, { game, entries: options.store.top(game, limit) });
        return true;
      }
      if (req.method !== 'POST') {
        res.setHeader('Allow', 'GET, HEAD, POST');
        throw new SubmissionError(405, 'METHOD', 'use GET to read or POST to submit');
      }
      const t = now();
      const who = req.socket.remoteAddress ?? '?';
      const times = (recent.get(who) ?? []).filter((x) => t - x < 60_000);
      if (times.length >= perMinute)
        throw new SubmissionError(429, 'RATE_LIMITED', `at most ${perMinute} submissions a minute`);
      times.push(t);
      recent.set(who, times);
      const scoreText = url.searchParams.get('score') ?? '';
      if (!/^\d{1,15}$/.test(scoreText))
        throw new SubmissionError(400, 'BAD_SCORE', 'score must be a whole number ≥ 0');
      const body = await readBody(req, MAX_SUBMITTED_BYTES);
      const entry = checkSubmission(body, Number(scoreText), new Date(t));
      if (options.store.has(entry.replayId))
        throw new SubmissionError(409, 'DUPLICATE', 'this replay was already submitted');
      const rank = await options.store.add(entry);
      json(res, 201, { rank, entry });
    } catch (error) {
      if (!(error instanceof SubmissionError)) throw error;
      json(res, error.status, { error: error.message, code: error.code });
    }
    return true;
  };
}

async function readBody(req: http.IncomingMessage, max: number): Promise<Uint8Array> {
  const declared = Number(req.headers['content-length'] ?? NaN);
  if (declared > max) {
    req.resume();
    throw new SubmissionError(413, 'TOO_LARGE', `a replay is at most ${max} bytes`);
  }
  const chunks: Buffer[] = [];
  let size = 0;
  for await (const chunk of req as AsyncIterable<Buffer>) {
    size += chunk.length;
    if (size > max) {
      req.destroy();
      throw new SubmissionError(413, 'TOO_LARGE', `a replay is at most ${max} bytes`);
    }
    chunks.push(chunk);
  }
  return new Uint8Array(Buffer.concat(chunks));
}

function json(res: http.ServerResponse, status: number, body: unknown): void {
  const text = JSON.stringify(body);
  res.statusCode = status;
  res.setHeader('Content-Type', 'application/json; charset=utf-8');
  res.setHeader('Cache-Control', 'no-store');
  res.setHeader('Content-Length', Buffer.byteLength(text));
  res.end(text);
}
