/**
 * `fixedstep check <module>`: a determinism check for anyone's game. Loads the module the way
 * `--games` does, runs each game (or `--game`'s) under the checks of ./checks.ts, then the same
 * seeded input script in the browsers that are installed (./browsers.ts), and prints one verdict
 * a check with the first divergent tick and, with a state schema, the field.
 * @module
 */
import { fileURLToPath } from 'node:url';
import type { AnyGameDefinition } from 'fixedstep';
import { GamesModuleError, loadGames, printable } from '@fixedstep/server';
import { UsageError, formatOptions, parseOptions, type OptionSpec } from '../args.js';
import {
  guardCheck,
  roundTripCheck,
  syncTestCheck,
  twinsCheck,
  type CheckResult,
  type TickProgress,
} from './checks.js';
import { BROWSER_IDS, runBrowsers, type BrowserId } from './browsers.js';
import { checkPlayers, type CheckPlan } from './script.js';

/** Exit codes of `fixedstep check`, for scripts and CI. */
export const CHECK_EXIT = Object.freeze({
  /** Every check passed. */
  ok: 0,
  /** The checker could not do its work (a browser that is installed would not run, bundling failed). */
  failure: 1,
  usage: 2,
  /** The module cannot be used: not found, throws on import, no games, never finishes loading. */
  badModule: 3,
  /** A check found the game not deterministic. */
  notDeterministic: 4,
  /** The game threw while it was checked (create, step, save or load). */
  gameThrew: 5,
});

export const DEFAULT_CHECK_TICKS = 600;
export const DEFAULT_CHECK_SEED = 1;
/** The most ticks a check runs (each is stepped about six times over, in Node alone). */
export const MAX_CHECK_TICKS = 1_000_000;

const ENGINE_IDS = ['node', ...BROWSER_IDS] as const;
type EngineId = (typeof ENGINE_IDS)[number];

const CHECK_OPTIONS: OptionSpec[] = [
  {
    name: 'game',
    kind: 'string',
    valueName: 'id',
    help: 'Check only this game of the module (default: every game in it)',
  },
  {
    name: 'ticks',
    kind: 'integer',
    min: 1,
    max: MAX_CHECK_TICKS,
    valueName: 'n',
    help: `Ticks to step (default: ${DEFAULT_CHECK_TICKS})`,
  },
  {
    name: 'seed',
    kind: 'integer',
    min: 0,
    max: 0xffffffff,
    valueName: 'u32',
    help: `The game's seed and the random input script's (default: ${DEFAULT_CHECK_SEED})`,
  },
  {
    name: 'engines',
    kind: 'string',
    valueName: 'list',
    help: 'Where the input script runs and is compared with Node, a comma-separated\nlist of node, chromium, firefox, webkit (default: all; a browser that is\nnot installed is skipped, one named here is required)',
  },
  {
    name: 'json',
    kind: 'flag',
    help: 'Print the report as JSON (each game, each check: status, tick, field,\ncall, summary, details) instead of text',
  },
  { name: 'quiet', short: 'q', kind: 'flag', help: 'No progress bar' },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];

export const CHECK_HELP = `fixedstep check — is your game deterministic?

Loads your games module (an ES module whose default, or "games", export is a game definition
made with defineGame, or an array of them) and runs each game with a seeded random input script:

  guard       every step under the determinism guard: Date.now, performance.now, Math.random,
              crypto and engine-dependent math (Math.sin, cos, atan2, exp, pow, hypot …) are named
  twins       two runs from the same setup with the same inputs agree at every tick
  sync-test   every tick: save, step, load, step again, compare (GGPO's sync test)
  round-trip  save, load into a fresh copy, step both: equal every tick; save(load(save())) equal
  <browser>   the same script in Chromium, Firefox ESR and WebKitGTK where installed: hash by hash
              equal to Node's

A failure names the first tick whose state differs and, when the game has a stateSchema
(defineStateSchema), the field — the column and row of the first differing byte.

Usage:
  fixedstep check <module> [--game <id>] [--ticks <n>] [--seed <u32>] [--engines <list>] [--json]

Options:
${formatOptions(CHECK_OPTIONS)}

Exit codes: 0 every check passed, 1 the checker could not run (a browser failed to start),
2 usage error, 3 the module cannot be used (not found, throws, no games), 4 not deterministic,
5 the game threw while being checked.
`;

export interface CheckCommand {
  kind: 'check';
  module: string;
  game?: string;
  ticks: number;
  seed: number;
  /** Browsers asked for by name (required), or undefined: every one that is installed. */
  browsers?: BrowserId[];
  quiet: boolean;
  json: boolean;
}

export function parseCheck(rest: readonly string[]): CheckCommand | { kind: 'help'; text: string } {
  const { values, positionals } = parseOptions('check', rest, CHECK_OPTIONS, 1);
  if (values.help) return { kind: 'help', text: CHECK_HELP };
  const module = positionals[0];
  if (module === undefined)
    throw new UsageError('check needs a games module (a file or a package)');
  let browsers: BrowserId[] | undefined;
  if (typeof values.engines === 'string') {
    const list = values.engines.split(',').map((s) => s.trim());
    const unknown = list.find((e) => !(ENGINE_IDS as readonly string[]).includes(e));
    if (unknown !== undefined || list.length === 0) {
      throw new UsageError(
        `--engines: unknown engine "${unknown ?? ''}"; choose from ${ENGINE_IDS.join(', ')}`,
      );
    }
    browsers = (list as EngineId[]).filter((e): e is BrowserId => e !== 'node');
  }
  return {
    kind: 'check',
    module,
    ...(typeof values.game === 'string' ? { game: values.game } : {}),
    ticks: typeof values.ticks === 'number' ? values.ticks : DEFAULT_CHECK_TICKS,
    seed: typeof values.seed === 'number' ? values.seed : DEFAULT_CHECK_SEED,
    ...(browsers !== undefined ? { browsers } : {}),
    quiet: values.quiet === true,
    json: values.json === true,
  };
}

interface Io {
  out(text: string): void;
  err(text: string): void;
  progress?(done: number, total: number): void;
}

const LABEL: Record<CheckResult['status'], string> = {
  pass: 'PASS',
  fail: 'FAIL',
  error: 'ERROR',
  skipped: 'SKIP',
};

/** The report of one game's checks, as printed. */
export function formatGameReport(
  game: AnyGameDefinition,
  plan: CheckPlan,
  results: readonly CheckResult[],
): string {
  const inputs = `${game.input.buttons.length} button${game.input.buttons.length === 1 ? '' : 's'}, ${game.input.axes.length} ax${game.input.axes.length === 1 ? 'is' : 'es'}`;
  const lines = [
    `${printable(game.id)} v${game.version}: ${plan.ticks} ticks, seed ${plan.seed}, ${plan.players} player${plan.players === 1 ? '' : 's'} (${inputs}), ${game.stateSchema ? 'state schema: fields named' : 'no state schema: bytes named'}`,
  ];
  const width = Math.max(...results.map((r) => r.check.length)) + 2;
  for (const r of results) {
    lines.push(`  ${LABEL[r.status].padEnd(5)} ${r.check.padEnd(width)}${r.summary}`);
    for (const d of r.details) lines.push(`  ${' '.repeat(6 + width)}${d}`);
  }
  const failed = results.filter((r) => r.status === 'fail');
  const errors = results.filter((r) => r.status === 'error');
  const first = failed.filter((r) => r.tick !== undefined).sort((a, b) => a.tick! - b.tick!)[0];
  if (failed.length > 0) {
    const where = first
      ? first.call !== undefined
        ? ` — first: ${first.call} at tick ${first.tick}`
        : ` — first divergent tick ${first.tick}${first.field ? `, field ${first.field}` : ''}`
      : '';
    lines.push(
      `  NOT DETERMINISTIC: ${failed.length} of ${results.length} checks failed (${failed.map((r) => r.check).join(', ')})${where}`,
    );
  } else if (errors.length > 0) {
    lines.push(`  THE GAME THREW in ${errors.map((r) => r.check).join(', ')}`);
  } else {
    const ran = results.filter((r) => r.status === 'pass').length;
    lines.push(
      `  deterministic: ${ran} checks passed${results.length > ran ? ` (${results.length - ran} skipped)` : ''}`,
    );
  }
  return `${lines.join('\n')}\n`;
}

/** Runs `fixedstep check`; resolves with the exit code. */
export async function runCheckCommand(
  cmd: CheckCommand,
  io: Io,
  env: Readonly<Record<string, string | undefined>> = process.env,
): Promise<number> {
  let games: readonly AnyGameDefinition[];
  let moduleUrl: string;
  try {
    const loaded = await loadGames([cmd.module], { env });
    games = loaded.games;
    moduleUrl = loaded.modules[0]!;
  } catch (error) {
    const message = error instanceof Error ? error.message : String(error);
    io.err(
      `fixedstep check: ${error instanceof GamesModuleError ? '' : 'cannot load: '}${message}\n`,
    );
    return CHECK_EXIT.badModule;
  }
  if (cmd.game !== undefined) {
    const one = games.find((g) => g.id === cmd.game);
    if (!one) {
      io.err(
        `fixedstep check: games module "${cmd.module}" has no game "${printable(cmd.game)}"; it has ${games.map((g) => printable(g.id)).join(', ')}\n`,
      );
      return CHECK_EXIT.badModule;
    }
    games = [one];
  }
  const text = (t: string) => {
    if (!cmd.json) io.out(t);
  };
  const report: { id: string; version: number; plan: CheckPlan; results: CheckResult[] }[] = [];
  text(
    `fixedstep check ${cmd.module}: ${games.length} game${games.length === 1 ? '' : 's'} (${games.map((g) => printable(g.id)).join(', ')})\n\n`,
  );
  const checks = [guardCheck, twinsCheck, syncTestCheck, roundTripCheck];
  const perGame = cmd.ticks * checks.length;
  const total = perGame * games.length;
  let base = 0;
  let last = -1;
  const progress = (done: number) => {
    if (cmd.quiet || !io.progress) return;
    // At most ~200 updates for a whole run.
    const step = Math.max(1, Math.floor(total / 200));
    if (done === total || Math.floor(done / step) !== last) {
      last = Math.floor(done / step);
      io.progress(done, total);
    }
  };
  let worst: number = CHECK_EXIT.ok;
  const raise = (code: number) => {
    const rank = (c: number) =>
      c === CHECK_EXIT.notDeterministic
        ? 3
        : c === CHECK_EXIT.gameThrew
          ? 2
          : c === CHECK_EXIT.failure
            ? 1
            : 0;
    if (rank(code) > rank(worst)) worst = code;
  };
  for (const game of games) {
    const plan: CheckPlan = {
      gameId: game.id,
      ticks: cmd.ticks,
      seed: cmd.seed,
      players: checkPlayers(game),
    };
    const results: CheckResult[] = [];
    for (const check of checks) {
      const offset = base;
      const tickProgress: TickProgress = (t) => {
        progress(offset + t);
      };
      results.push(check(game, plan, tickProgress));
      base += cmd.ticks;
      progress(base);
    }
    const browserResults = await runBrowsers({
      game,
      moduleFile: moduleUrl.startsWith('file:') ? fileURLToPath(moduleUrl) : moduleUrl,
      plan,
      ...(cmd.browsers !== undefined ? { only: cmd.browsers } : {}),
      env,
      onStart: (browser) => {
        if (!cmd.quiet) io.err(`fixedstep check: ${game.id}: running the script in ${browser}…\n`);
      },
    });
    results.push(...browserResults.results);
    if (browserResults.infrastructureError) raise(CHECK_EXIT.failure);
    for (const r of results) {
      if (r.status === 'fail') raise(CHECK_EXIT.notDeterministic);
      if (r.status === 'error') raise(CHECK_EXIT.gameThrew);
    }
    text(formatGameReport(game, plan, results));
    text('\n');
    report.push({ id: game.id, version: game.version, plan, results });
  }
  if (cmd.json) {
    io.out(`${JSON.stringify({ module: cmd.module, exitCode: worst, games: report }, null, 2)}\n`);
    return worst;
  }
  io.out(
    worst === CHECK_EXIT.ok
      ? 'ok: every check passed\n'
      : worst === CHECK_EXIT.notDeterministic
        ? `not deterministic (exit ${worst})\n`
        : worst === CHECK_EXIT.gameThrew
          ? `the game threw while being checked (exit ${worst})\n`
          : `the check could not run everywhere (exit ${worst})\n`,
  );
  return worst;
}
