/**
 * A small, strict command-line option parser driven by specs, shared by every `fixedstep`
 * command: `--name value`, `--name=value`, `-n value`, flags, numbers with ranges and lists of
 * numbers. Errors are plain sentences naming the option and the value.
 */

export type OptionKind = 'string' | 'number' | 'integer' | 'flag' | 'numbers';

export interface OptionSpec {
  /** Long name without dashes, e.g. `port`. */
  name: string;
  short?: string;
  kind: OptionKind;
  /** For numbers: inclusive bounds. */
  min?: number;
  max?: number;
  /** Shown in help as `--name <valueName>`. */
  valueName?: string;
  help: string;
}

export type OptionValue = string | number | boolean | number[];

export interface ParsedOptions {
  values: Record<string, OptionValue | undefined>;
  positionals: string[];
}

/** A mistake on the command line: the message is for the user. */
export class UsageError extends Error {
  override readonly name = 'UsageError';
}

function describeRange(spec: OptionSpec, what: string): string {
  const lo = spec.min ?? -Infinity;
  const hi = spec.max ?? Infinity;
  if (lo > -Infinity && hi < Infinity) return `${what} from ${lo} to ${hi}`;
  if (lo > -Infinity) return `${what} ≥ ${lo}`;
  if (hi < Infinity) return `${what} ≤ ${hi}`;
  return what;
}

/** Converts one option value; throws a UsageError naming `label` (as typed) on a bad value. */
export function convertValue(spec: OptionSpec, label: string, raw: string): OptionValue {
  if (spec.kind === 'string') {
    if (raw === '') throw new UsageError(`${label} needs a value`);
    return raw;
  }
  const one = (text: string): number => {
    const isInt = spec.kind === 'integer';
    const ok = isInt ? /^-?\d+$/.test(text) : /^-?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?$/i.test(text);
    const n = Number(text);
    if (!ok || !Number.isFinite(n) || n < (spec.min ?? -Infinity) || n > (spec.max ?? Infinity)) {
      const what = describeRange(spec, isInt ? 'an integer' : 'a number');
      throw new UsageError(`${label} must be ${what}, got "${text}"`);
    }
    return n;
  };
  if (spec.kind === 'numbers') {
    const parts = raw.split(',');
    if (raw === '' || parts.some((p) => p === '')) {
      throw new UsageError(`${label} must be a comma-separated list of numbers, got "${raw}"`);
    }
    return parts.map(one);
  }
  return one(raw);
}

/**
 * Parses `argv` against `specs`. `command` names the command in messages. Values that start with
 * `-` count as missing, except negative numbers for numeric options.
 */
export function parseOptions(
  command: string,
  argv: readonly string[],
  specs: readonly OptionSpec[],
  maxPositionals = 0,
): ParsedOptions {
  const values: Record<string, OptionValue | undefined> = {};
  const positionals: string[] = [];
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i]!;
    if (!arg.startsWith('-') || arg === '-') {
      if (positionals.length >= maxPositionals) {
        throw new UsageError(`unexpected argument for ${command}: ${arg}`);
      }
      positionals.push(arg);
      continue;
    }
    const eq = arg.indexOf('=');
    const label = arg.startsWith('--') && eq > 0 ? arg.slice(0, eq) : arg;
    const spec = specs.find(
      (s) => label === `--${s.name}` || (s.short !== undefined && label === `-${s.short}`),
    );
    if (!spec) throw new UsageError(`unknown option for ${command}: ${arg}`);
    if (spec.kind === 'flag') {
      if (eq > 0) throw new UsageError(`${label} takes no value`);
      values[spec.name] = true;
      continue;
    }
    let raw: string | undefined;
    if (arg.startsWith('--') && eq > 0) raw = arg.slice(eq + 1);
    else {
      const next = argv[i + 1];
      // A negative number is a value for a numeric option (the range check then judges it).
      const numeric = spec.kind !== 'string';
      if (next !== undefined && (!next.startsWith('-') || (numeric && /^-[\d.]/.test(next)))) {
        raw = next;
        i++;
      }
    }
    if (raw === undefined || raw === '') throw new UsageError(`${label} needs a value`);
    values[spec.name] = convertValue(spec, label, raw);
  }
  return { values, positionals };
}

/** The options part of a help text, aligned. */
export function formatOptions(specs: readonly OptionSpec[]): string {
  const left = specs.map((s) => {
    const names = `${s.short ? `-${s.short}, ` : '    '}--${s.name}`;
    return s.kind === 'flag' ? names : `${names} <${s.valueName ?? s.kind}>`;
  });
  const width = Math.max(...left.map((l) => l.length)) + 2;
  return specs
    .map((s, i) => {
      const lines = s.help.split('\n');
      return `  ${left[i]!.padEnd(width)}${lines.join(`\n  ${' '.repeat(width)}`)}`;
    })
    .join('\n');
}
