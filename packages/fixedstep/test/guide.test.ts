/**
 * Every code block of the guide (docs/guide/*.md) is run or checked here, so nothing in it can
 * drift from the code:
 * - a ```ts block preceded by `<!-- from: FILE#REGION -->` is the text between `// #region REGION`
 *   and `// #endregion REGION` of FILE, exactly (the engine recipes' glue);
 * - a ```ts block preceded by `<!-- from: FILE -->` is an excerpt of FILE: its parts between
 *   `// …` lines appear in FILE in that order, verbatim (coin-dash's code). Those files are built
 *   and played by e2e/examples.e2e.test.ts;
 * - every other ```ts block is a program: it is type-checked (strict, noUncheckedIndexedAccess)
 *   and run here, with `examples/coin-dash/src/game.ts` beside it as `./game.js`, and what it
 *   prints with console.log must be, line by line, the `// → …` comments it carries;
 * - a ```sh block preceded by `<!-- sh: DIR -->` may run only `npm run` scripts that DIR's
 *   package.json has; no other kind of block is allowed;
 * - every relative link of the guide points at a file that exists, and the index lists every page.
 */
import {
  copyFileSync,
  existsSync,
  mkdirSync,
  readdirSync,
  readFileSync,
  writeFileSync,
} from 'node:fs';
import { join, relative, resolve } from 'node:path';
import ts from 'typescript';
import { afterEach, describe, expect, it, vi } from 'vitest';

const root = join(import.meta.dirname, '..', '..', '..');
const guideDir = join(root, 'docs', 'guide');
const pages = readdirSync(guideDir)
  .filter((f) => f.endsWith('.md'))
  .sort();

interface Block {
  page: string;
  /** 1-based line of the opening fence. */
  line: number;
  lang: string;
  code: string;
  /** The `<!-- … -->` comment right before the fence (blank lines allowed), without the markers. */
  marker: string | undefined;
}

function blocksOf(page: string): Block[] {
  const lines = readFileSync(join(guideDir, page), 'utf8').split('\n');
  const out: Block[] = [];
  for (let i = 0; i < lines.length; i++) {
    const open = /^```(\S*)\s*$/.exec(lines[i]!);
    if (!open) continue;
    let end = i + 1;
    while (end < lines.length && lines[end] !== '```') end++;
    if (end === lines.length) throw new Error(`${page}:${i + 1}: a code block is never closed`);
    let k = i - 1;
    while (k >= 0 && lines[k]!.trim() === '') k--;
    const m = k >= 0 ? /^<!--\s*(.*?)\s*-->$/.exec(lines[k]!) : null;
    out.push({
      page,
      line: i + 1,
      lang: open[1]!,
      code: lines.slice(i + 1, end).join('\n') + '\n',
      marker: m?.[1],
    });
    i = end;
  }
  return out;
}

const blocks = pages.flatMap(blocksOf);
const programs = blocks.filter((b) => b.lang === 'ts' && !b.marker?.startsWith('from:'));
const excerpts = blocks.filter((b) => b.lang === 'ts' && b.marker?.startsWith('from:') === true);
const shells = blocks.filter((b) => b.lang === 'sh');
const name = (b: Block) => `${b.page}:${b.line}`;

/** The lines a block promises to print: its `// → …` comments, in order. */
function promised(code: string): string[] {
  return [...code.matchAll(/\/\/ → (.*)$/gm)].map((m) => m[1]!.trimEnd());
}

describe('the guide', () => {
  it('has pages, an index that links every page, and only ts and sh blocks', () => {
    expect(pages).toContain('README.md');
    expect(pages).toContain('getting-started.md');
    const index = readFileSync(join(guideDir, 'README.md'), 'utf8');
    for (const p of pages.filter((p) => p !== 'README.md')) expect(index).toContain(`](${p})`);
    expect(blocks.filter((b) => b.lang !== 'ts' && b.lang !== 'sh').map(name)).toEqual([]);
    expect(programs.length).toBeGreaterThan(5);
  });

  it('links only to files that exist', () => {
    const broken: string[] = [];
    for (const page of pages) {
      const text = readFileSync(join(guideDir, page), 'utf8');
      for (const m of text.matchAll(/\]\(([^)\s]+)\)/g)) {
        const target = m[1]!;
        if (/^[a-z]+:/.test(target) || target.startsWith('#')) continue;
        const file = resolve(guideDir, target.split('#')[0]!);
        if (!existsSync(file)) broken.push(`${page}: ${target}`);
      }
    }
    expect(broken).toEqual([]);
  });
});

/** What is wrong with a quoted block: nothing when it is the file's own text. */
function quoteProblems(b: Block): string[] {
  const [file, region] = b.marker!.slice('from:'.length).trim().split('#');
  const text = readFileSync(join(root, file!), 'utf8');
  if (region !== undefined) {
    const m = new RegExp(
      `^\\s*// #region ${region}\\n([\\s\\S]*?)^\\s*// #endregion ${region}$`,
      'm',
    ).exec(text);
    if (!m) return [`${file} has no region ${region}`];
    return m[1] === b.code ? [] : [`differs from the region ${region} of ${file}:\n${m[1]}`];
  }
  const missing: string[] = [];
  let at = 0;
  for (const part of b.code.split(/^\s*\/\/ …\n/m)) {
    const chunk = part.replace(/^\n+|\n+$/g, '');
    if (chunk === '') continue;
    const found = text.indexOf(chunk, at);
    if (found < 0) missing.push(`not in ${file} (after offset ${at}):\n${chunk}`);
    else at = found + chunk.length;
  }
  return missing;
}

/** Commands of a sh block that are neither `npm install`/`npm ci` nor a script DIR has. */
function shellProblems(b: Block): string[] {
  if (!/^sh: \S+$/.test(b.marker ?? '')) return ['a sh block needs <!-- sh: DIR -->'];
  const dir = b.marker!.slice('sh:'.length).trim();
  const pkg = JSON.parse(readFileSync(join(root, dir, 'package.json'), 'utf8')) as {
    scripts?: Record<string, string>;
  };
  const scripts = Object.keys(pkg.scripts ?? {});
  const problems: string[] = [];
  for (const line of b.code.split('\n')) {
    const command = line.replace(/#.*$/, '').trim();
    if (command === '' || /^npm (install|ci)\b/.test(command)) continue;
    const script = /^npm run (\S+)/.exec(command);
    if (!script || !scripts.includes(script[1]!)) problems.push(`${dir}: ${command}`);
  }
  return problems;
}

describe('guide blocks taken from files', () => {
  it.each(excerpts.map((b) => [name(b), b] as const))('%s is the file’s own text', (_, b) => {
    expect(quoteProblems(b)).toEqual([]);
  });
});

describe('guide shell blocks', () => {
  it.each(shells.map((b) => [name(b), b] as const))('%s runs only scripts that exist', (_, b) => {
    expect(shellProblems(b)).toEqual([]);
  });
});

/** Where the programs are written: with coin-dash's game beside them as ./game.js. */
const outDir = join(root, 'artifacts', 'guide');
const files = new Map<Block, string>();
mkdirSync(outDir, { recursive: true });
copyFileSync(join(root, 'examples/coin-dash/src/game.ts'), join(outDir, 'game.ts'));
for (const b of programs) {
  const file = join(outDir, `${b.page.replace(/\.md$/, '')}-${b.line}.ts`);
  writeFileSync(file, b.code);
  files.set(b, file);
}

describe('guide programs', () => {
  it('type-check strictly against the library', () => {
    const program = ts.createProgram([...files.values()], {
      target: ts.ScriptTarget.ES2022,
      module: ts.ModuleKind.ESNext,
      moduleResolution: ts.ModuleResolutionKind.Bundler,
      customConditions: ['source'],
      lib: ['lib.es2022.d.ts', 'lib.dom.d.ts'],
      types: ['node'],
      typeRoots: [join(root, 'node_modules/@types')],
      strict: true,
      noUncheckedIndexedAccess: true,
      noImplicitOverride: true,
      noEmit: true,
      skipLibCheck: true,
      allowImportingTsExtensions: false,
    });
    const ours = new Set([...files.values(), join(outDir, 'game.ts')].map((f) => resolve(f)));
    const problems = ts
      .getPreEmitDiagnostics(program)
      .filter((d) => d.file !== undefined && ours.has(resolve(d.file.fileName)))
      .map((d) => {
        const { line } = d.file!.getLineAndCharacterOfPosition(d.start ?? 0);
        const text = ts.flattenDiagnosticMessageText(d.messageText, '\n');
        return `${relative(root, d.file!.fileName)}:${line + 1}: ${text}`;
      });
    expect(problems).toEqual([]);
  }, 120_000);

  afterEach(() => {
    vi.restoreAllMocks();
  });

  it.each(programs.map((b) => [name(b), b] as const))(
    '%s runs and prints what its // → comments say',
    async (_, b) => {
      const printed: string[] = [];
      vi.spyOn(console, 'log').mockImplementation((...args: unknown[]) => {
        printed.push(args.map(String).join(' '));
      });
      const warn = vi.spyOn(console, 'warn').mockImplementation(() => undefined);
      await import(/* @vite-ignore */ files.get(b)!);
      expect(printed).toEqual(promised(b.code));
      // A block that means to show a warning catches it itself (onWarning): none may escape.
      expect(warn).not.toHaveBeenCalled();
    },
  );
});
