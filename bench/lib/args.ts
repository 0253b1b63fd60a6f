/** Command-line arguments of `npm run bench -- …`. Pure: no I/O, no process access. */

export interface BenchOptions {
  /** Suite names to run, in the order given; empty means all. */
  readonly suites: readonly string[];
  /** Print the suites and exit. */
  readonly list: boolean;
  /** A short smoke run: fewer rounds and shorter samples (numbers are rough). */
  readonly quick: boolean;
  /** Where to write the results as JSON, if anywhere. */
  readonly json: string | undefined;
  /** Print the usage and exit. */
  readonly help: boolean;
}

export type ParseResult =
  | { readonly ok: true; readonly options: BenchOptions }
  | { readonly ok: false; readonly error: string };

export const USAGE = `usage: npm run bench -- [suite …] [--quick] [--json FILE] [--list] [--help]

  suite …      run only these suites (default: all of them)
  --quick      a short smoke run: few rounds, short samples; numbers are rough
  --json FILE  also write the results to FILE as JSON
  --list       list the suites and exit
  --help, -h   show this help`;

/** Parses the arguments after `bench/run.ts`. */
export function parseArgs(argv: readonly string[]): ParseResult {
  const suites: string[] = [];
  let list = false;
  let quick = false;
  let help = false;
  let json: string | undefined;

  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i]!;
    if (arg === '--list') list = true;
    else if (arg === '--quick') quick = true;
    else if (arg === '--help' || arg === '-h') help = true;
    else if (arg === '--json' || arg.startsWith('--json=')) {
      const value = arg === '--json' ? argv[++i] : arg.slice('--json='.length);
      if (value === undefined || value === '' || value.startsWith('-')) {
        return { ok: false, error: '--json needs a file name, e.g. --json bench-results.json' };
      }
      if (json !== undefined) return { ok: false, error: '--json given twice' };
      json = value;
    } else if (arg.startsWith('-')) {
      return { ok: false, error: `unknown option ${arg}` };
    } else if (!suites.includes(arg)) {
      suites.push(arg);
    }
  }
  return { ok: true, options: { suites, list, quick, json, help } };
}

/**
 * The suites to run: all of `available` when none were requested, else the requested ones in the
 * order given. Every requested name must exist.
 */
export function selectSuites(
  available: readonly string[],
  requested: readonly string[],
): { ok: true; names: string[] } | { ok: false; error: string } {
  if (requested.length === 0) return { ok: true, names: [...available] };
  const unknown = requested.filter((name) => !available.includes(name));
  if (unknown.length > 0) {
    const s = unknown.length > 1 ? 's' : '';
    return {
      ok: false,
      error: `unknown suite${s} ${unknown.join(', ')}; available: ${available.join(', ')}`,
    };
  }
  return { ok: true, names: [...requested] };
}
