/**
 * The command line of every `fixedstep` command, driven by specs: `node:util`'s `parseArgs` splits
 * it (`--name value`, `--name=value`, `-n value`, flags); this checks numbers with ranges and lists
 * of numbers and writes the help. Errors are plain sentences naming the option and the value.
 */
import { parseArgs as parseArgv } from 'node:util';

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
 * Parses `argv` against `specs`, tokenized by `node:util`'s `parseArgs`; this adds the checks and
 * the messages: unknown options, values of the wrong kind or range, too many positionals. `command`
 * names the command in messages. A value that starts with `-` counts as missing (it is the next
 * option), except a negative number for a numeric option.
 */
export function parseOptions(
  command: string,
  argv: readonly string[],
  specs: readonly OptionSpec[],
  maxPositionals = 0,
): ParsedOptions {
  const options: Record<string, { type: 'string' | 'boolean'; short?: string }> = {};
  for (const s of specs) {
    options[s.name] = {
      type: s.kind === 'flag' ? 'boolean' : 'string',
      ...(s.short !== undefined ? { short: s.short } : {}),
    };
  }
  const { tokens } = parseArgv({
    args: [...argv],
    options,
    strict: false,
    allowPositionals: true,
    tokens: true,
  });
  const values: Record<string, OptionValue | undefined> = {};
  const positionals: string[] = [];
  for (const t of tokens) {
    if (t.kind === 'option-terminator') continue;
    if (t.kind === 'positional') {
      if (positionals.length >= maxPositionals) {
        throw new UsageError(`unexpected argument for ${command}: ${t.value}`);
      }
      positionals.push(t.value);
      continue;
    }
    const spec = specs.find((s) => s.name === t.name);
    const label = t.rawName;
    if (!spec) throw new UsageError(`unknown option for ${command}: ${label}`);
    if (spec.kind === 'flag') {
      if (t.value !== undefined) throw new UsageError(`${label} takes no value`);
      values[spec.name] = true;
      continue;
    }
    const raw = t.value;
    const numeric = spec.kind !== 'string';
    const isNextOption =
      raw !== undefined &&
      !t.inlineValue &&
      raw.startsWith('-') &&
      !(numeric && /^-[\d.]/.test(raw));
    if (raw === undefined || raw === '' || isNextOption) {
      throw new UsageError(`${label} needs a value`);
    }
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
