import { closeSync, constants, fstatSync, openSync, readSync } from 'node:fs';
import {
  DEFAULT_REPLAY_LIMITS,
  ReplayError,
  hex64,
  readReplay,
  replayFactory,
  verifyReplay,
  type Replay,
} from 'fixedstep';
import { UsageError, formatOptions, parseOptions, type OptionSpec } from './args.js';
import { loadGames, printable } from '@fixedstep/server';

/** Exit codes of `fixedstep replay …`, for scripts. */
export const EXIT_BAD_REPLAY = 3;
export const EXIT_REPLAY_MISMATCH = 4;

const INFO_OPTIONS: OptionSpec[] = [
  { name: 'json', kind: 'flag', help: 'Print the information as JSON' },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];
const VERIFY_OPTIONS: OptionSpec[] = [
  { name: 'quiet', short: 'q', kind: 'flag', help: 'No progress bar' },
  {
    name: 'games',
    kind: 'string',
    valueName: 'module',
    help: 'Your games: an ES module whose default (or "games") export is a game\ndefinition or an array of them (default: the built-in games)',
  },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];

export const REPLAY_INFO_HELP = `fixedstep replay info — what a replay file holds

Usage:
  fixedstep replay info <file> [--json]

Options:
${formatOptions(INFO_OPTIONS)}

Exit codes: 0 ok, 1 cannot read the file, 2 usage error, 3 not a valid replay file.
`;

export const REPLAY_VERIFY_HELP = `fixedstep replay verify — re-simulate a replay and check every stored hash

Rebuilds the game from the replay's header (game, version, seed, config), feeds it the recorded
inputs tick by tick, and compares the state hash at every checkpoint, every keyframe and the end.
On a difference it names the first tick whose state differs (exactly, when the replay stores
per-tick hashes; otherwise within one checkpoint interval).

Usage:
  fixedstep replay verify <file> [--quiet] [--games <module>]

Options:
${formatOptions(VERIFY_OPTIONS)}

Exit codes: 0 reproduced, 1 cannot read the file (or the games module), 2 usage error, 3 not a
valid replay file (or a game this build does not have), 4 the replay does not reproduce.
`;

export type ReplayCommand =
  | { kind: 'help'; text: string }
  | { kind: 'replay-info'; file: string; json: boolean }
  | { kind: 'replay-verify'; file: string; quiet: boolean; games?: string };

export function parseReplayInfo(rest: readonly string[]): ReplayCommand {
  const { values, positionals } = parseOptions('replay info', rest, INFO_OPTIONS, 1);
  if (values.help) return { kind: 'help', text: REPLAY_INFO_HELP };
  const file = positionals[0];
  if (file === undefined) throw new UsageError('replay info needs a file');
  return { kind: 'replay-info', file, json: values.json === true };
}

export function parseReplayVerify(rest: readonly string[]): ReplayCommand {
  const { values, positionals } = parseOptions('replay verify', rest, VERIFY_OPTIONS, 1);
  if (values.help) return { kind: 'help', text: REPLAY_VERIFY_HELP };
  const file = positionals[0];
  if (file === undefined) throw new UsageError('replay verify needs a file');
  const games = typeof values.games === 'string' ? values.games : undefined;
  return {
    kind: 'replay-verify',
    file,
    quiet: values.quiet === true,
    ...(games !== undefined ? { games } : {}),
  };
}

interface Io {
  out(text: string): void;
  err(text: string): void;
  progress?(done: number, total: number): void;
}

/** The largest file the replay commands read (the replay format's own default limit). */
export const MAX_REPLAY_FILE_BYTES = DEFAULT_REPLAY_LIMITS.maxFileBytes;

/**
 * Reads a file for the replay commands: only a regular file (a FIFO, a device such as /dev/zero,
 * a directory or a socket is refused with a message — never waited on, never read without bound),
 * at most {@link MAX_REPLAY_FILE_BYTES}, checked before reading; a file that grows while it is read
 * is cut at the limit and then refused by the parser.
 */
export function readReplayFile(file: string, io: Pick<Io, 'err'>): Uint8Array | undefined {
  let fd: number;
  try {
    // O_NONBLOCK: opening a FIFO must not wait for a writer.
    fd = openSync(file, constants.O_RDONLY | constants.O_NONBLOCK);
  } catch (error) {
    io.err(
      `fixedstep: cannot read ${file}: ${error instanceof Error ? error.message : String(error)}\n`,
    );
    return undefined;
  }
  try {
    const info = fstatSync(fd);
    if (!info.isFile()) {
      const kind = info.isDirectory()
        ? 'a directory'
        : info.isFIFO()
          ? 'a FIFO (named pipe)'
          : info.isCharacterDevice() || info.isBlockDevice()
            ? 'a device'
            : info.isSocket()
              ? 'a socket'
              : 'not a regular file';
      io.err(`fixedstep: cannot read ${file}: it is ${kind}, not a replay file\n`);
      return undefined;
    }
    if (info.size > MAX_REPLAY_FILE_BYTES) {
      io.err(
        `fixedstep: ${file} is ${info.size} bytes; replays are at most ${MAX_REPLAY_FILE_BYTES} bytes\n`,
      );
      return undefined;
    }
    const buffer = Buffer.alloc(Math.min(info.size + 1, MAX_REPLAY_FILE_BYTES + 1));
    let length = 0;
    while (length < buffer.length) {
      const n = readSync(fd, buffer, length, buffer.length - length, null);
      if (n === 0) break;
      length += n;
    }
    return new Uint8Array(buffer.buffer, buffer.byteOffset, length);
  } catch (error) {
    io.err(
      `fixedstep: cannot read ${file}: ${error instanceof Error ? error.message : String(error)}\n`,
    );
    return undefined;
  } finally {
    closeSync(fd);
  }
}

function badReplay(io: Io, file: string, error: unknown): number {
  if (error instanceof ReplayError) {
    io.err(`fixedstep: ${file}: not a valid replay (${error.code}): ${printable(error.message)}\n`);
    return EXIT_BAD_REPLAY;
  }
  if (error instanceof RangeError) {
    io.err(`fixedstep: ${file}: cannot replay: ${printable(error.message)}\n`);
    return EXIT_BAD_REPLAY;
  }
  throw error;
}

/** The facts of a parsed replay, for people (and, with --json, for scripts). */
export function replayFacts(replay: Replay, fileBytes: number): Record<string, unknown> {
  const h = replay.header;
  const seconds = (replay.tickCount * h.stepNumerator) / h.stepDenominator;
  // Names come from the file: printed without control characters (no terminal escape sequences).
  return {
    game: printable(h.gameId),
    gameVersion: printable(h.gameVersion),
    step: `${h.stepNumerator}/${h.stepDenominator} s`,
    tickRate: h.stepDenominator / h.stepNumerator,
    ticks: replay.tickCount,
    duration: `${seconds.toFixed(2)} s`,
    players: h.players.map(printable),
    seeds: h.seeds,
    configBytes: h.config.length,
    checkpointEvery: replay.checkpointEvery,
    keyframeEvery: replay.keyframeEvery,
    keyframes: replay.keyframes.length,
    perTickHashes: replay.tickHashes !== null,
    finalHash: hex64(replay.finalHash),
    fileBytes,
    bytesPerMinute: seconds > 0 ? Math.round((fileBytes / seconds) * 60) : null,
    sections: replay.sections.map((s) => ({ name: s.name, offset: s.offset, length: s.length })),
  };
}

export function replayInfo(cmd: { file: string; json: boolean }, io: Io): number {
  const bytes = readReplayFile(cmd.file, io);
  if (!bytes) return 1;
  let replay: Replay;
  try {
    replay = readReplay(bytes);
  } catch (error) {
    return badReplay(io, cmd.file, error);
  }
  const facts = replayFacts(replay, bytes.length);
  if (cmd.json) {
    io.out(`${JSON.stringify(facts, null, 2)}\n`);
    return 0;
  }
  const lines = Object.entries(facts)
    .filter(([k]) => k !== 'sections')
    .map(([k, v]) => `  ${k.padEnd(16)}${Array.isArray(v) ? v.join(', ') : String(v)}`);
  const sections = replay.sections.map(
    (s) => `    ${s.name.padEnd(14)} at ${String(s.offset).padStart(8)}  ${s.length} bytes`,
  );
  io.out([cmd.file, ...lines, '  sections', ...sections, ''].join('\n'));
  return 0;
}

export async function replayVerify(
  cmd: { file: string; quiet: boolean; games?: string },
  io: Io,
): Promise<number> {
  let games;
  try {
    games = await loadGames(cmd.games === undefined ? [] : [cmd.games]);
  } catch (error) {
    io.err(`fixedstep: ${error instanceof Error ? error.message : String(error)}\n`);
    return 1;
  }
  const bytes = readReplayFile(cmd.file, io);
  if (!bytes) return 1;
  let result;
  const started = process.hrtime.bigint();
  try {
    result = verifyReplay(bytes, replayFactory(games.games), {
      onProgress: cmd.quiet ? undefined : (tick, total) => io.progress?.(tick, total),
    });
  } catch (error) {
    return badReplay(io, cmd.file, error);
  }
  const seconds = Number(process.hrtime.bigint() - started) / 1e9;
  const h = result.replay.header;
  if (result.ok) {
    const rate = seconds > 0 ? Math.round(result.simulated / seconds) : 0;
    io.out(
      `ok: ${printable(h.gameId)} v${printable(h.gameVersion)}, ${result.ticks} ticks reproduced, final hash ${hex64(result.replay.finalHash)} (${rate.toLocaleString('en-US')} ticks/s)\n`,
    );
    return 0;
  }
  const where = result.exact
    ? `the state first differs after tick ${result.firstMismatchTick}`
    : `the state first differs after a tick in (${result.lastGoodTick}, ${result.firstMismatchTick}]`;
  io.out(
    `MISMATCH: ${printable(h.gameId)} v${printable(h.gameVersion)}: ${where}; ${result.kind ?? 'hash'} expected ${hex(result.expected)}, got ${hex(result.actual)}\n`,
  );
  return EXIT_REPLAY_MISMATCH;
}

function hex(v: bigint | null): string {
  return v === null ? '-' : hex64(v);
}
