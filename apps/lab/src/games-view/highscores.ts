/**
 * The highscore client of chapters 5 and 9: submit a replay with the score it claims
 * (`POST api/highscores?score=N`) and read a game's table (`GET api/highscores?game=…`). The server
 * re-simulates the replay and ranks only a score the replay reaches. No DOM here.
 */
import { fetchWithRetry, type FetchRetryOptions } from 'fixedstep';

/** A highscore entry as the server sends it. */
export interface HighscoreRow {
  game: string;
  name: string;
  score: number;
  ticks: number;
  seed: number;
  finalHash: string;
  replayId: string;
  at: string;
}

export type SubmitResult =
  | { kind: 'accepted'; rank: number; entry: HighscoreRow }
  | { kind: 'refused'; status: number; code: string; error: string }
  | { kind: 'unavailable'; reason: string };

export type TableResult =
  | { kind: 'ok'; entries: HighscoreRow[] }
  | { kind: 'refused'; status: number; code: string; error: string }
  | { kind: 'unavailable'; reason: string };

/** The API's address, relative to the page (so a lab served under a prefix still finds it). */
export const HIGHSCORE_PATH = 'api/highscores';

type FetchLike = (url: string, init?: RequestInit) => Promise<Response>;

const UNAVAILABLE =
  'This copy of the lab has no highscore server (a static host?). Run `fixedstep serve` to rank scores.';

async function jsonBody(res: Response): Promise<Record<string, unknown> | undefined> {
  const type = res.headers.get('content-type') ?? '';
  if (!type.includes('application/json')) return undefined;
  try {
    const body: unknown = await res.json();
    return typeof body === 'object' && body !== null
      ? (body as Record<string, unknown>)
      : undefined;
  } catch {
    return undefined;
  }
}

function refusal(status: number, body: Record<string, unknown>) {
  return {
    kind: 'refused' as const,
    status,
    code: typeof body.code === 'string' ? body.code : 'ERROR',
    error: typeof body.error === 'string' ? body.error : `HTTP ${status}`,
  };
}

/**
 * Submit a replay with the score it claims: `POST api/highscores?score=N`, the replay as the
 * body. The server re-simulates the replay and accepts the score only if the replay reaches it;
 * while it is busy, the submission waits and is sent again ({@link fetchWithRetry}).
 */
export async function submitScore(
  bytes: Uint8Array,
  score: number,
  fetchFn: FetchLike = (u, i) => fetch(u, i),
  retry: Omit<FetchRetryOptions, 'fetch'> = {},
): Promise<SubmitResult> {
  let res: Response;
  try {
    // A busy server (503 BUSY: its verification queue is full) or a rate limit (429) asks again
    // after its Retry-After, with jitter; `retry.onRetry` tells the player the score is queued.
    res = await fetchWithRetry(
      `${HIGHSCORE_PATH}?score=${encodeURIComponent(String(score))}`,
      {
        method: 'POST',
        headers: { 'Content-Type': 'application/octet-stream' },
        body: bytes as Uint8Array<ArrayBuffer>,
      },
      { ...retry, fetch: fetchFn },
    );
  } catch (e) {
    return { kind: 'unavailable', reason: `The highscore server cannot be reached: ${String(e)}` };
  }
  const body = await jsonBody(res);
  if (!body) return { kind: 'unavailable', reason: UNAVAILABLE };
  if (res.status === 201 && typeof body.rank === 'number' && typeof body.entry === 'object') {
    return { kind: 'accepted', rank: body.rank, entry: body.entry as HighscoreRow };
  }
  return refusal(res.status, body);
}

/** The best `limit` scores of a game: `GET api/highscores?game=…&limit=…`. */
export async function fetchHighscores(
  game: string,
  limit = 10,
  fetchFn: FetchLike = (u, i) => fetch(u, i),
): Promise<TableResult> {
  let res: Response;
  try {
    res = await fetchFn(`${HIGHSCORE_PATH}?game=${encodeURIComponent(game)}&limit=${limit}`, {
      headers: { Accept: 'application/json' },
    });
  } catch (e) {
    return { kind: 'unavailable', reason: `The highscore server cannot be reached: ${String(e)}` };
  }
  const body = await jsonBody(res);
  if (!body) return { kind: 'unavailable', reason: UNAVAILABLE };
  if (res.ok && Array.isArray(body.entries)) {
    return { kind: 'ok', entries: body.entries as HighscoreRow[] };
  }
  return refusal(res.status, body);
}
