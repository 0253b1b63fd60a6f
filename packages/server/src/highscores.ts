import type http from 'node:http';
import type { FastifyPluginAsync, FastifyReply } from 'fastify';
import type { AnyGameDefinition } from 'fixedstep';
import { requestAddress, type TrustedProxy } from './http/admission.js';
import type { ServerMetrics } from './http/metrics.js';
import { RateLimiter } from './http/rate-limit.js';
import type { HighscoreStore, HighscoreEntry } from './store/store.js';
import { TABLE_SIZE } from './store/store.js';
import {
  MAX_SUBMITTED_BYTES,
  SubmissionError,
  submissionLimits,
  type PrecheckSummary,
} from './verify/check.js';
import { VerifierPool } from './verify/pool.js';
import type { LoadedGames } from './games/load.js';

/**
 * The highscore API: a score is accepted only with the replay that produced it, re-simulated from
 * its inputs and seed alone, and stored with that replay.
 *
 * - `GET /api/highscores?game=<id>&limit=10` → 200 `{ game, entries }`
 * - `POST /api/highscores?score=<n>`, the replay file as the body → 201 `{ rank, entry }`; the same
 *   submission again → 201 with the same entry and `repeated: true`; refusals are
 *   `{ error, code }`: 400 bad request, 409 `RUN_TAKEN` (this run is already in the table under
 *   another name), 413 too large, 422 refused (invalid replay, unknown game or version, does not
 *   reproduce, score mismatch), 429 too many submissions, 503 busy / store unavailable (with
 *   `Retry-After`).
 * - `GET /api/highscores/<replayId>/replay` → the stored replay file.
 *
 * Usable three ways: {@link HighscoreApi.plugin} (fastify; what `createServer` uses),
 * {@link HighscoreApi.handler} (plain `node:http`, and express as middleware).
 */

/** Options of {@link highscoreApi}. */
export interface HighscoreApiOptions {
  /**
   * The games: the definitions, or what {@link loadGames} returned (its module URLs let the
   * verification workers import the same games). With definitions alone and no `verifier`,
   * verification runs inline on the event loop.
   */
  games: LoadedGames | readonly AnyGameDefinition[];
  /** Where accepted scores and their replays go. */
  store: HighscoreStore;
  /** Re-simulates submissions. Default: a {@link VerifierPool} over the games' modules. */
  verifier?: VerifierPool;
  /** Submissions that passed the pre-check allowed per client address per minute. Default 20. */
  perMinute?: number;
  /**
   * Submissions of any kind (before the pre-check, which runs in a verification worker) allowed
   * per client address per minute. Default 60, or 3 × `perMinute` when that is more.
   */
  attemptsPerMinute?: number;
  /**
   * A trusted reverse proxy (see `TrustedProxy`), or just the header it puts the client's address
   * in (`x-forwarded-for`, `x-real-ip`) for a proxy on loopback: its header is believed only from
   * it. Unset: the socket's address.
   */
  trustProxy?: string | TrustedProxy;
  /** Largest replay accepted, in bytes. Default 1 MiB. */
  maxBodyBytes?: number;
  /** A body must arrive within this many ms (plain `node:http` handler). Default 10 000. */
  bodyTimeoutMs?: number;
  /** The clock for rate limits and timestamps, in ms. Default `Date.now`. */
  now?: () => number;
  /** Metrics to count into. */
  metrics?: ServerMetrics;
  /** Where unexpected errors are reported. Default `console.error`. */
  log?: (message: string, error: unknown) => void;
  /** Worker threads of the verifier this API creates (see `VerifierPoolOptions.workers`). */
  workers?: number;
  /** Submissions that may wait for a worker (see `VerifierPoolOptions.maxQueue`). Default 32. */
  maxQueue?: number;
}

/** An answer of the API, before it is written to a response. */
export interface ApiAnswer {
  status: number;
  body: unknown;
  headers?: Record<string, string>;
}

/** A `node:http` request handler that answers the API's paths and resolves false for any other. */
export type ApiHandler = (req: http.IncomingMessage, res: http.ServerResponse) => Promise<boolean>;

/** The highscore API over a store and games (see the module's description). */
export interface HighscoreApi {
  /** The fastify plugin: registers the routes (with their own body parser and limit). */
  readonly plugin: FastifyPluginAsync;
  /** For `node:http` and express: answers `/api/highscores…` and resolves true, else resolves false. */
  readonly handler: ApiHandler;
  /** The verifier in use. */
  readonly verifier: VerifierPool;
  /** Lists a game's table. */
  list(game: string, limitText: string | null): Promise<ApiAnswer>;
  /** Judges one submission: `scoreText` as in the query, `client` the rate-limit key. */
  submit(bytes: Uint8Array, scoreText: string | null, client: string): Promise<ApiAnswer>;
  /** Answers a stored replay's bytes. */
  replay(runId: string): Promise<ApiAnswer>;
  /** Refuses new submissions (503) and waits for the ones being verified. */
  drain(): Promise<void>;
  /** Drains, then stops the verifier if this API made it (the store is the caller's to close). */
  close(): Promise<void>;
}

function refusal(error: SubmissionError): ApiAnswer {
  return {
    status: error.status,
    body: { error: error.message, code: error.code },
    ...(error.retryAfter !== undefined
      ? { headers: { 'Retry-After': String(error.retryAfter) } }
      : {}),
  };
}

/** Creates the highscore API (see {@link HighscoreApiOptions}). */
export function highscoreApi(options: HighscoreApiOptions): HighscoreApi {
  const loaded: LoadedGames = Array.isArray(options.games)
    ? { modules: [], games: options.games as readonly AnyGameDefinition[] }
    : (options.games as LoadedGames);
  const games = loaded.games;
  const maxBody = options.maxBodyBytes ?? MAX_SUBMITTED_BYTES;
  const limits = submissionLimits(undefined, maxBody);
  const metrics = options.metrics;
  const ownVerifier = options.verifier === undefined;
  const verifier =
    options.verifier ??
    new VerifierPool({
      modules: loaded.modules,
      games,
      limits,
      ...(loaded.modules.length === 0
        ? { workers: 0 }
        : options.workers !== undefined
          ? { workers: options.workers }
          : {}),
      ...(options.maxQueue !== undefined ? { maxQueue: options.maxQueue } : {}),
      ...(metrics
        ? {
            onDone: (seconds: number, outcome: string) => {
              metrics.verificationSeconds.observe(seconds);
              metrics.verificationOutcomes.inc({ outcome });
            },
          }
        : {}),
    });
  const perMinute = options.perMinute ?? 20;
  const limiter = new RateLimiter(perMinute, 60_000, options.now ?? Date.now);
  const attempts = new RateLimiter(
    options.attemptsPerMinute ?? Math.max(60, 3 * perMinute),
    60_000,
    options.now ?? Date.now,
  );
  const now = options.now ?? Date.now;
  const log =
    options.log ??
    ((message, error) => {
      console.error(`fixedstep: ${message}`, error);
    });
  let draining = false;

  const storeFailed = (error: unknown): ApiAnswer => {
    metrics?.storeErrors.inc();
    log('the highscore store failed', error);
    return refusal(
      new SubmissionError(
        503,
        'STORE_UNAVAILABLE',
        'the highscore table cannot be written right now; nothing was saved, try again',
        5,
      ),
    );
  };
  const count = (answer: ApiAnswer, result: string): ApiAnswer => {
    metrics?.submissions.inc({ result });
    return answer;
  };
  const gauges = () => {
    metrics?.verificationQueue.set(verifier.queued);
    metrics?.verificationRunning.set(verifier.running);
  };

  const list = async (game: string, limitText: string | null): Promise<ApiAnswer> => {
    if (!games.some((g) => g.id === game)) {
      return refusal(
        new SubmissionError(400, 'UNKNOWN_GAME', `unknown game "${game.slice(0, 40)}"`),
      );
    }
    const limit = Number(limitText ?? '10');
    if (!Number.isInteger(limit) || limit < 1 || limit > TABLE_SIZE) {
      return refusal(
        new SubmissionError(400, 'BAD_LIMIT', `limit must be an integer from 1 to ${TABLE_SIZE}`),
      );
    }
    try {
      return { status: 200, body: { game, entries: await options.store.top(game, limit) } };
    } catch (error) {
      return storeFailed(error);
    }
  };

  const submit = async (
    bytes: Uint8Array,
    scoreText: string | null,
    client: string,
  ): Promise<ApiAnswer> => {
    if (draining)
      return count(
        refusal(new SubmissionError(503, 'DRAINING', 'the server is shutting down', 5)),
        'DRAINING',
      );
    if (scoreText === null || !/^\d{1,10}$/.test(scoreText)) {
      return count(
        refusal(new SubmissionError(400, 'BAD_SCORE', 'score must be a whole number ≥ 0')),
        'BAD_SCORE',
      );
    }
    const claimed = Number(scoreText);
    // Before a byte is decoded: a looser cap on attempts per address, so one address cannot keep
    // the workers busy with pre-checks (junk refused by them is not charged to the limit below).
    const attemptWait = attempts.check(client);
    if (attemptWait > 0) {
      return count(
        refusal(
          new SubmissionError(
            429,
            'RATE_LIMITED',
            `at most ${attempts.limit} submission attempts a minute from one address`,
            attemptWait,
          ),
        ),
        'RATE_LIMITED',
      );
    }
    attempts.charge(client);
    // The pre-check in a worker: its cost follows the ticks the file declares, not its size.
    let pre: PrecheckSummary;
    try {
      const pending = verifier.precheck(bytes, claimed);
      gauges();
      const checked = await pending;
      if (!checked.ok)
        return count(
          refusal(new SubmissionError(checked.status, checked.code, checked.message)),
          checked.code,
        );
      pre = checked.summary;
    } catch (error) {
      if (error instanceof SubmissionError) return count(refusal(error), error.code);
      throw error;
    } finally {
      gauges();
    }
    // A run already in the table is answered from the table, with no simulation.
    let known: HighscoreEntry | undefined;
    try {
      known = await options.store.find(pre.runId);
    } catch (error) {
      return count(storeFailed(error), 'STORE_UNAVAILABLE');
    }
    if (known !== undefined) return count(await answerKnown(known, pre.name, claimed), 'KNOWN');
    // Honest-looking: only now is the submission charged to its address.
    const wait = limiter.check(client);
    if (wait > 0) {
      return count(
        refusal(
          new SubmissionError(
            429,
            'RATE_LIMITED',
            `at most ${limiter.limit} submissions a minute from one address`,
            wait,
          ),
        ),
        'RATE_LIMITED',
      );
    }
    limiter.charge(client);
    let verdict;
    try {
      const pending = verifier.verify(bytes, claimed);
      gauges();
      verdict = await pending;
    } catch (error) {
      if (error instanceof SubmissionError) return count(refusal(error), error.code);
      throw error;
    } finally {
      gauges();
    }
    if (!verdict.ok)
      return count(
        refusal(new SubmissionError(verdict.status, verdict.code, verdict.message)),
        verdict.code,
      );
    const entry: HighscoreEntry = {
      game: pre.gameId,
      version: pre.gameVersion,
      name: pre.name,
      score: verdict.score,
      ticks: verdict.ticks,
      seed: pre.seed,
      finalHash: verdict.finalHash,
      replayId: pre.runId,
      at: new Date(now()).toISOString(),
    };
    let outcome;
    try {
      outcome = await options.store.add(entry, bytes);
    } catch (error) {
      return count(storeFailed(error), 'STORE_UNAVAILABLE');
    }
    if (outcome.kind === 'taken') return count(taken(outcome.entry), 'RUN_TAKEN');
    return count(
      {
        status: 201,
        body: {
          rank: outcome.rank,
          entry: outcome.entry,
          ...(outcome.kind === 'same' ? { repeated: true } : {}),
        },
      },
      outcome.kind === 'added' ? 'added' : 'repeated',
    );
  };

  const taken = (entry: HighscoreEntry): ApiAnswer =>
    refusal(
      new SubmissionError(
        409,
        'RUN_TAKEN',
        `this run (the same game, seed and inputs) is already in the table under the name "${entry.name}"; a run is ranked once, whatever its name`,
      ),
    );

  const answerKnown = async (
    known: HighscoreEntry,
    name: string,
    claimed: number,
  ): Promise<ApiAnswer> => {
    if (known.name !== name) return taken(known);
    if (known.score !== claimed) {
      return refusal(
        new SubmissionError(
          422,
          'SCORE_MISMATCH',
          `claimed ${claimed}, the replay scores ${known.score}`,
        ),
      );
    }
    try {
      return {
        status: 201,
        body: { rank: await options.store.rank(known), entry: known, repeated: true },
      };
    } catch (error) {
      return storeFailed(error);
    }
  };

  const replay = async (runId: string): Promise<ApiAnswer> => {
    if (!/^(v1-)?[0-9a-f]{16}$/.test(runId)) {
      return refusal(new SubmissionError(404, 'NOT_FOUND', 'no such replay'));
    }
    let bytes;
    try {
      bytes = await options.store.replay(runId);
    } catch (error) {
      return storeFailed(error);
    }
    if (bytes === undefined)
      return refusal(new SubmissionError(404, 'NOT_FOUND', 'no such replay'));
    return {
      status: 200,
      body: bytes,
      headers: {
        'Content-Type': 'application/octet-stream',
        'Content-Disposition': `attachment; filename="${runId}.fsr"`,
      },
    };
  };

  const plugin = highscoreRoutes(() => api, {
    maxBodyBytes: maxBody,
    ...(options.trustProxy !== undefined ? { trustProxy: options.trustProxy } : {}),
  });

  const handler: ApiHandler = async (req, res) => {
    const url = new URL(req.url ?? '/', 'http://localhost');
    const replayPath = /^\/api\/highscores\/([^/]+)\/replay$/.exec(url.pathname);
    if (url.pathname !== '/api/highscores' && replayPath === null) return false;
    let answer: ApiAnswer;
    try {
      if (replayPath !== null && (req.method === 'GET' || req.method === 'HEAD'))
        answer = await replay(replayPath[1]!);
      else if (replayPath === null && (req.method === 'GET' || req.method === 'HEAD')) {
        answer = await list(url.searchParams.get('game') ?? '', url.searchParams.get('limit'));
      } else if (replayPath === null && req.method === 'POST') {
        const bytes = await readBody(req, maxBody, options.bodyTimeoutMs ?? 10_000);
        answer = await submit(
          bytes,
          url.searchParams.get('score'),
          requestAddress(req, options.trustProxy),
        );
      } else {
        res.setHeader('Allow', 'GET, HEAD, POST');
        answer = refusal(new SubmissionError(405, 'METHOD', 'use GET to read or POST to submit'));
      }
    } catch (error) {
      if (!(error instanceof SubmissionError)) throw error;
      answer = refusal(error);
      // The body was not read to its end: close the connection rather than read the rest.
      if (error.status === 413 || error.status === 408) res.setHeader('Connection', 'close');
    }
    writeAnswer(res, answer);
    return true;
  };

  const api: HighscoreApi = {
    plugin,
    handler,
    verifier,
    list,
    submit,
    replay,
    async drain() {
      draining = true;
      await verifier.drain();
    },
    async close() {
      draining = true;
      await verifier.drain();
      if (ownVerifier) await verifier.close();
    },
  };
  return api;
}

/**
 * The API's fastify routes over whichever API `get` returns (503 `STORE_STARTING` while it returns
 * undefined, e.g. while the store opens): `GET|POST /api/highscores`, `GET /api/highscores/:id/replay`.
 * Replays are read as bytes whatever type the client claims; the limit is checked against
 * Content-Length before a byte is read (413, and the connection is closed).
 */
export function highscoreRoutes(
  get: () => HighscoreApi | undefined,
  options: { maxBodyBytes?: number; trustProxy?: string | TrustedProxy } = {},
): FastifyPluginAsync {
  const maxBody = options.maxBodyBytes ?? MAX_SUBMITTED_BYTES;
  // eslint-disable-next-line @typescript-eslint/require-await -- fastify's plugin signature
  return async (app) => {
    app.removeAllContentTypeParsers();
    app.addContentTypeParser('*', { parseAs: 'buffer', bodyLimit: maxBody }, (_req, body, done) => {
      done(null, body);
    });
    const send = async (reply: FastifyReply, answer: () => Promise<ApiAnswer> | ApiAnswer) => {
      const result = get() === undefined ? starting() : await answer();
      reply.code(result.status).header('Cache-Control', 'no-store');
      for (const [k, v] of Object.entries(result.headers ?? {})) reply.header(k, v);
      return reply.send(result.body instanceof Uint8Array ? Buffer.from(result.body) : result.body);
    };
    interface Query {
      Querystring: Record<string, string | undefined>;
    }
    app.get<Query>('/api/highscores', (request, reply) =>
      send(reply, () => get()!.list(request.query.game ?? '', request.query.limit ?? null)),
    );
    app.post<Query>('/api/highscores', (request, reply) => {
      const body = Buffer.isBuffer(request.body) ? new Uint8Array(request.body) : new Uint8Array(0);
      return send(reply, () =>
        get()!.submit(
          body,
          request.query.score ?? null,
          requestAddress(request.raw, options.trustProxy),
        ),
      );
    });
    app.get<{ Params: { id: string } }>('/api/highscores/:id/replay', (request, reply) =>
      send(reply, () => get()!.replay(request.params.id)),
    );
    app.route({
      method: ['PUT', 'DELETE', 'PATCH', 'OPTIONS'],
      url: '/api/highscores',
      handler: (_request, reply) =>
        send(reply.header('Allow', 'GET, HEAD, POST'), () =>
          refusal(new SubmissionError(405, 'METHOD', 'use GET to read or POST to submit')),
        ),
    });
  };
}

function starting(): ApiAnswer {
  return {
    status: 503,
    body: {
      error: 'the highscore table is opening; try again in a few seconds',
      code: 'STORE_STARTING',
    },
    headers: { 'Retry-After': '5' },
  };
}

function writeAnswer(res: http.ServerResponse, answer: ApiAnswer): void {
  const binary = answer.body instanceof Uint8Array;
  const body = binary
    ? Buffer.from(answer.body as Uint8Array)
    : Buffer.from(JSON.stringify(answer.body));
  res.statusCode = answer.status;
  res.setHeader('Content-Type', 'application/json; charset=utf-8');
  res.setHeader('Cache-Control', 'no-store');
  for (const [k, v] of Object.entries(answer.headers ?? {})) res.setHeader(k, v);
  res.setHeader('Content-Length', body.length);
  res.end(body);
}

/**
 * Reads a request body of at most `max` bytes within `timeoutMs`. A declared length over the limit
 * is refused (413) before a byte is read; a body that grows past it, or is too slow (408), is
 * refused and the rest is never read (the connection is closed after the answer).
 */
export async function readBody(
  req: http.IncomingMessage,
  max: number,
  timeoutMs: number,
): Promise<Uint8Array> {
  const declared = Number(req.headers['content-length'] ?? NaN);
  if (declared > max)
    throw new SubmissionError(413, 'TOO_LARGE', `a replay is at most ${max} bytes`);
  const chunks: Buffer[] = [];
  let size = 0;
  return new Promise<Uint8Array>((resolve, reject) => {
    const timer = setTimeout(() => {
      cleanup();
      req.pause();
      reject(
        new SubmissionError(
          408,
          'BODY_TIMEOUT',
          `the body did not arrive within ${timeoutMs / 1000} s`,
        ),
      );
    }, timeoutMs);
    const onData = (chunk: Buffer) => {
      size += chunk.length;
      if (size > max) {
        cleanup();
        req.pause();
        reject(new SubmissionError(413, 'TOO_LARGE', `a replay is at most ${max} bytes`));
        return;
      }
      chunks.push(chunk);
    };
    const onEnd = () => {
      cleanup();
      resolve(new Uint8Array(Buffer.concat(chunks)));
    };
    const onError = (error: Error) => {
      cleanup();
      reject(error);
    };
    const cleanup = () => {
      clearTimeout(timer);
      req.off('data', onData);
      req.off('end', onEnd);
      req.off('error', onError);
    };
    req.on('data', onData);
    req.on('end', onEnd);
    req.on('error', onError);
  });
}
