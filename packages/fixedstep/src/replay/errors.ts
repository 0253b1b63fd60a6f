/**
 * What went wrong with a replay file, as a stable machine-readable code:
 *
 * - `'TOO_LARGE'` — a size is above a {@link ReplayLimits} bound (the file, the tick count, the
 *   player count, a seed list, the configuration, a keyframe). Nothing that large was allocated.
 * - `'BAD_MAGIC'` — the file does not start with the replay magic: not a replay file.
 * - `'TRUNCATED'` — the file is shorter than it says it is (or than its header).
 * - `'TRAILING_DATA'` — the file is longer than it says it is.
 * - `'UNSUPPORTED_VERSION'` — a format version this reader does not know.
 * - `'BAD_CHECKSUM'` — the checksum at the end does not match the bytes: damaged in storage or
 *   transit, or edited.
 * - `'WRONG_GAME'` — a valid replay, but of another game id or game version than the caller expects.
 * - `'CORRUPT'` — the checksum matches but the content breaks a rule of the format (a section
 *   out of order or overrunning, an inconsistent count, a non-canonical number, bad UTF-8, …).
 * - `'GAME_REJECTED'` — the game itself refused the replay's data: its factory, `load()` or
 *   `step()` threw. The game's error is in `cause`.
 */
export type ReplayErrorCode =
  | 'TOO_LARGE'
  | 'BAD_MAGIC'
  | 'TRUNCATED'
  | 'TRAILING_DATA'
  | 'UNSUPPORTED_VERSION'
  | 'BAD_CHECKSUM'
  | 'WRONG_GAME'
  | 'CORRUPT'
  | 'GAME_REJECTED';

/**
 * The one error type a replay reader, player or verifier throws for bad data. `code` says what
 * kind of problem; `offset` (when known) is the byte offset in the file where it was found, and
 * the message names both what and where.
 *
 * Misuse of the API (a wrong argument, recording ticks out of order) throws a `RangeError` or an
 * `Error` instead: those are bugs in the caller, not in a file.
 */
export class ReplayError extends Error {
  /** What kind of problem: see {@link ReplayErrorCode}. */
  readonly code: ReplayErrorCode;
  /** Byte offset in the file where the problem was found, or -1 when it is not about one place. */
  readonly offset: number;

  /**
   * @param code — the kind of problem.
   * @param message — what and where, for a person.
   * @param offset — byte offset in the file, or -1.
   * @param cause — the underlying error, if any (e.g. what a game's `load()` threw).
   */
  constructor(code: ReplayErrorCode, message: string, offset = -1, cause?: unknown) {
    super(
      offset >= 0 ? `${code}: ${message} (at byte offset ${offset})` : `${code}: ${message}`,
      cause === undefined ? undefined : { cause },
    );
    this.name = 'ReplayError';
    this.code = code;
    this.offset = offset;
  }
}

/** Whether `e` is a {@link ReplayError}, optionally of one code. */
export function isReplayError(e: unknown, code?: ReplayErrorCode): e is ReplayError {
  return e instanceof ReplayError && (code === undefined || e.code === code);
}
