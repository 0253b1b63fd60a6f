import { stat } from 'node:fs/promises';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { defineGame, type AnyGameDefinition } from 'fixedstep';

/**
 * Loading games as plug-ins: a games module is an ES module whose default export, or whose
 * `games` export, is a game definition ({@link defineGame}) or an array of them. The server, the
 * verification workers and `fixedstep replay verify` load the same module, so the main thread and
 * every worker run the same code.
 */

/** A games module that cannot be used: the message names the module and what is wrong. */
export class GamesModuleError extends Error {
  override readonly name = 'GamesModuleError';
}

/** The module URL of the built-in games (Runner, Capture the flag, Survival). */
export function builtinGamesUrl(): string {
  const here = import.meta.url;
  return new URL(`./builtin${here.endsWith('.ts') ? '.ts' : '.js'}`, here).href;
}

/**
 * Turns what the user typed (`./my-game.js`, `/abs/game.mjs`, a `file:` URL or a package name
 * such as `@me/games`) into a URL to import. A path is resolved against `cwd` and must exist.
 */
export async function resolveGamesModule(spec: string, cwd = process.cwd()): Promise<string> {
  if (spec === '') throw new GamesModuleError('--games needs a module (a file or a package name)');
  if (spec.startsWith('file:')) return spec;
  const looksLikePath =
    spec.startsWith('.') ||
    path.isAbsolute(spec) ||
    /\.[cm]?[jt]s$/.test(spec) ||
    spec.includes('\\');
  if (!looksLikePath) {
    try {
      return import.meta.resolve(spec, pathToFileURL(path.join(cwd, 'noop.js')).href);
    } catch (error) {
      throw new GamesModuleError(
        `games module "${spec}": cannot find the package (${String(error)})`,
      );
    }
  }
  const file = path.resolve(cwd, spec);
  let info;
  try {
    info = await stat(file);
  } catch {
    throw new GamesModuleError(`games module "${spec}": no such file (${file})`);
  }
  if (!info.isFile()) throw new GamesModuleError(`games module "${spec}": not a file (${file})`);
  return pathToFileURL(file).href;
}

function describe(value: unknown): string {
  if (value === null) return 'null';
  if (Array.isArray(value)) return `an array of ${value.length}`;
  if (typeof value === 'object')
    return `an object with keys ${Object.keys(value).slice(0, 5).join(', ') || '(none)'}`;
  return typeof value;
}

/**
 * The game definitions of an imported module's namespace: its `default` export, else its `games`
 * export; one definition or an array. Each is checked with {@link defineGame}; ids must be unique.
 * Throws a {@link GamesModuleError} naming `label` and what is wrong.
 */
export function gamesFromModule(
  namespace: Record<string, unknown>,
  label: string,
): AnyGameDefinition[] {
  const picked = namespace.default ?? namespace.games;
  if (picked === undefined) {
    throw new GamesModuleError(
      `games module ${label}: no default export and no "games" export (export a game definition or an array of them)`,
    );
  }
  const list: unknown[] = Array.isArray(picked) ? (picked as unknown[]) : [picked];
  if (list.length === 0)
    throw new GamesModuleError(`games module ${label}: the list of games is empty`);
  const games: AnyGameDefinition[] = [];
  for (const [i, item] of list.entries()) {
    const where = Array.isArray(picked) ? ` (item ${i})` : '';
    if (typeof item !== 'object' || item === null) {
      throw new GamesModuleError(
        `games module ${label}${where}: expected a game definition (defineGame), got ${describe(item)}`,
      );
    }
    try {
      defineGame(item as AnyGameDefinition); // checks every field; the original object is kept
      games.push(item as AnyGameDefinition);
    } catch (error) {
      throw new GamesModuleError(
        `games module ${label}${where}: not a valid game definition: ${error instanceof Error ? error.message : String(error)}`,
      );
    }
  }
  const seen = new Set<string>();
  for (const g of games) {
    if (seen.has(g.id))
      throw new GamesModuleError(`games module ${label}: two games have the id "${g.id}"`);
    seen.add(g.id);
  }
  return games;
}

/** How long a games module may take to load before {@link importGames} gives up (ms). */
export const GAMES_IMPORT_TIMEOUT_MS = 30_000;

/**
 * Imports a games module by URL and returns its checked definitions (see {@link gamesFromModule}).
 * A module that has not finished loading after `timeoutMs` — a top-level `await` that never
 * settles, a database it waits for — is refused with a message saying so, instead of Node's bare
 * exit code 13 ("unsettled top-level await") or a start-up that never ends.
 */
export async function importGames(
  url: string,
  label = url,
  timeoutMs = GAMES_IMPORT_TIMEOUT_MS,
): Promise<AnyGameDefinition[]> {
  let namespace: Record<string, unknown>;
  let timer: ReturnType<typeof setTimeout> | undefined;
  try {
    namespace = await Promise.race([
      import(url) as Promise<Record<string, unknown>>,
      new Promise<never>((_, reject) => {
        timer = setTimeout(() => {
          reject(
            new GamesModuleError(
              `games module ${label}: still loading after ${timeoutMs / 1000} s — does its top level await something that never settles? (the limit: FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS)`,
            ),
          );
        }, timeoutMs);
      }),
    ]);
  } catch (error) {
    if (error instanceof GamesModuleError) throw error;
    throw new GamesModuleError(
      `games module ${label}: cannot be imported: ${error instanceof Error ? error.message : String(error)}`,
    );
  } finally {
    clearTimeout(timer);
  }
  return gamesFromModule(namespace, label);
}

/**
 * Where a server or a command gets its games: the module URLs (imported here and by each
 * verification worker) and the definitions themselves.
 */
export interface LoadedGames {
  /** Module URLs, in order; a later module's game replaces an earlier one's of the same id. */
  readonly modules: readonly string[];
  readonly games: readonly AnyGameDefinition[];
}

/**
 * Loads the games of `specs` (what `--games` was given, possibly several times), or the built-in
 * games when there is none. With `withBuiltins`, the built-in games come first and a module's game
 * of the same id replaces the built-in one.
 */
export async function loadGames(
  specs: readonly string[] = [],
  options: {
    cwd?: string;
    withBuiltins?: boolean;
    /** How long each module may take to load (default FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS, else 30 s). */
    timeoutMs?: number;
    env?: Readonly<Record<string, string | undefined>>;
  } = {},
): Promise<LoadedGames> {
  const timeoutMs = options.timeoutMs ?? importTimeoutFromEnv(options.env ?? process.env);
  const modules: string[] = [];
  if (specs.length === 0 || options.withBuiltins === true) modules.push(builtinGamesUrl());
  for (const spec of specs) modules.push(await resolveGamesModule(spec, options.cwd));
  const byId = new Map<string, AnyGameDefinition>();
  for (const [i, url] of modules.entries()) {
    const label =
      i === 0 && url === builtinGamesUrl()
        ? 'the built-in games'
        : `"${specs[i - (modules.length - specs.length)] ?? url}"`;
    for (const g of await importGames(url, label, timeoutMs)) byId.set(g.id, g);
  }
  return { modules, games: [...byId.values()] };
}

/** FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS, a whole number of ms ≥ 1, or the default; else an error. */
function importTimeoutFromEnv(env: Readonly<Record<string, string | undefined>>): number {
  const text = env.FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS;
  if (text === undefined || text === '') return GAMES_IMPORT_TIMEOUT_MS;
  const ms = Number(text);
  if (!Number.isInteger(ms) || ms < 1) {
    throw new GamesModuleError(
      `FIXEDSTEP_GAMES_IMPORT_TIMEOUT_MS must be a whole number of milliseconds ≥ 1, got "${text}"`,
    );
  }
  return ms;
}
