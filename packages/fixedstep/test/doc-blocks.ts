/**
 * The code blocks of a Markdown page, and what checks each: shared by the guide's test
 * (guide.test.ts) and the other pages' (docs.test.ts). What a block is, is said by the
 * `<!-- … -->` comment right before its fence (blank lines allowed):
 * - `from: FILE#REGION`: the text between `// #region REGION` and `// #endregion REGION` of FILE,
 *   exactly;
 * - `from: FILE`: an excerpt of FILE: its parts between `// …` lines appear in FILE in that order,
 *   verbatim;
 * - `sh: DIR`: shell commands, checked against DIR's package.json scripts, the CLI's own parser and
 *   the repository's files (doc-shell.ts);
 * - `typecheck: WHY`: a ```ts program that is type-checked but not run, WHY saying what running it
 *   needs (a browser, a games module on disk, …);
 * - a comment naming a `….test.ts` file that runs or checks the block (`… run by
 *   packages/x/test/y.test.ts`, `… checked by …`): that test exists and reads this page; a ```ts
 *   block is type-checked here too;
 * - `text` (or `text: …`): a diagram, a table or an example of output, checked by no one;
 * - no comment on a ```ts block: a program, type-checked and run, whose `// → …` comments are
 *   what it prints with console.log, line by line.
 * Any other block is an error: a block nobody checks says so with `<!-- text -->`.
 */
import { copyFileSync, existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { basename, dirname, join, relative, resolve } from 'node:path';
import ts from 'typescript';
import { vi } from 'vitest';

export const root = join(import.meta.dirname, '..', '..', '..');

export interface Block {
  /** The page, relative to the repository's root. */
  doc: string;
  /** 1-based line of the opening fence. */
  line: number;
  lang: string;
  code: string;
  /** The `<!-- … -->` comment right before the fence, without the markers. */
  marker: string | undefined;
}

export type BlockKind =
  'program' | 'typecheck' | 'elsewhere' | 'region' | 'excerpt' | 'sh' | 'text' | 'unchecked';

export function blocksOf(doc: string): Block[] {
  const lines = readFileSync(join(root, doc), 'utf8').split('\n');
  const out: Block[] = [];
  for (let i = 0; i < lines.length; i++) {
    const open = /^```(\S*)\s*$/.exec(lines[i]!);
    if (!open) continue;
    let end = i + 1;
    while (end < lines.length && lines[end] !== '```') end++;
    if (end === lines.length) throw new Error(`${doc}:${i + 1}: a code block is never closed`);
    let k = i - 1;
    while (k >= 0 && lines[k]!.trim() === '') k--;
    const m = k >= 0 ? /^<!--\s*(.*?)\s*-->$/.exec(lines[k]!) : null;
    out.push({
      doc,
      line: i + 1,
      lang: open[1]!,
      code: lines.slice(i + 1, end).join('\n') + '\n',
      marker: m?.[1],
    });
    i = end;
  }
  return out;
}

export const blockName = (b: Block): string => `${b.doc}:${b.line}`;

/** The tests a marker says run or check the block (`… run by packages/x/test/y.test.ts …`). */
export function runners(b: Block): string[] {
  if (b.marker === undefined || !/\b(run|checked)\b/.test(b.marker)) return [];
  return [...b.marker.matchAll(/[\w./-]+\.test\.ts/g)].map((m) => m[0]);
}

export function kindOf(b: Block): BlockKind {
  const marker = b.marker ?? '';
  if (/^from: \S+#\S+$/.test(marker)) return 'region';
  if (/^from: \S+$/.test(marker)) return 'excerpt';
  if (runners(b).length > 0) return 'elsewhere';
  if (/^text(:|$)/.test(marker)) return 'text';
  if (b.lang === 'sh') return 'sh';
  if (b.lang === 'ts' && /^typecheck: \S/.test(marker)) return 'typecheck';
  if (b.lang === 'ts' && b.marker === undefined) return 'program';
  return 'unchecked';
}

/** The lines a block promises to print: its `// → …` comments, in order. */
export function promised(code: string): string[] {
  return [...code.matchAll(/\/\/ → (.*)$/gm)].map((m) => m[1]!.trimEnd());
}

/** What is wrong with a quoted block (`from:`): nothing when it is the file's own text. */
export function quoteProblems(b: Block): string[] {
  const [file, region] = b.marker!.slice('from:'.length).trim().split('#');
  if (!existsSync(join(root, file!))) return [`no file ${file}`];
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

/** What is wrong with a block run elsewhere: a named test that is missing or never reads the page. */
export function elsewhereProblems(b: Block): string[] {
  return runners(b).flatMap((test) => {
    if (!existsSync(join(root, test))) return [`no test ${test}`];
    const text = readFileSync(join(root, test), 'utf8');
    return text.includes(basename(b.doc)) ? [] : [`${test} never names ${basename(b.doc)}`];
  });
}

/** GitHub's anchors of a page's headings: lower case, punctuation dropped, spaces as hyphens. */
export function anchorsOf(file: string): Set<string> {
  const anchors = new Set<string>();
  const seen = new Map<string, number>();
  let fenced = false;
  for (const line of readFileSync(file, 'utf8').split('\n')) {
    if (line.startsWith('```')) fenced = !fenced;
    const heading = fenced ? null : /^#{1,6}\s+(.*?)\s*#*$/.exec(line);
    if (!heading) continue;
    const slug = heading[1]!
      .toLowerCase()
      .replace(/[^\p{L}\p{N}\s_-]/gu, '')
      .replace(/\s/g, '-');
    const n = seen.get(slug) ?? 0;
    seen.set(slug, n + 1);
    anchors.add(n === 0 ? slug : `${slug}-${n}`);
  }
  return anchors;
}

/** Relative links of `doc` whose file, or whose heading in a Markdown file, does not exist. */
export function brokenLinks(doc: string): string[] {
  const text = readFileSync(join(root, doc), 'utf8');
  const broken: string[] = [];
  for (const m of text.matchAll(/\]\(([^)\s]+)\)/g)) {
    const target = m[1]!;
    if (/^[a-z]+:/.test(target)) continue;
    const [path, anchor] = target.split('#');
    const file = path === '' ? join(root, doc) : resolve(root, dirname(doc), path!);
    if (!existsSync(file)) broken.push(`${doc}: ${target}`);
    else if (anchor !== undefined && file.endsWith('.md') && !anchorsOf(file).has(anchor)) {
      broken.push(`${doc}: ${target} (no such heading)`);
    }
  }
  return broken;
}

/** The file a ```ts block is written to in `outDir`, to be type-checked and imported. */
export function programFile(outDir: string, b: Block): string {
  return join(outDir, `${b.doc.replace(/\.md$/, '').replace(/[/\\]/g, '_')}-${b.line}.ts`);
}

/**
 * Writes `blocks` to `outDir` as programs (with coin-dash's game beside them as `./game.js`, which
 * the docs import) and returns their files, in order.
 */
export function writePrograms(root: string, outDir: string, blocks: readonly Block[]): string[] {
  mkdirSync(outDir, { recursive: true });
  copyFileSync(join(root, 'examples/coin-dash/src/game.ts'), join(outDir, 'game.ts'));
  return blocks.map((b) => {
    const file = programFile(outDir, b);
    writeFileSync(file, b.code);
    return file;
  });
}

/**
 * Type errors in `files`, all checked in one program: strict, noUncheckedIndexedAccess, the
 * packages resolved to their sources, the DOM's and Node's types both known.
 */
export function typeProblems(files: readonly string[]): string[] {
  const program = ts.createProgram([...files], {
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
  });
  // Only the diagnostics of the files in their directories (game.ts beside them included):
  // checking the packages' own sources is tsc's job, and would triple the time.
  const dirs = new Set(files.map((f) => dirname(resolve(f))));
  return program
    .getSourceFiles()
    .filter((sf) => dirs.has(dirname(resolve(sf.fileName))))
    .flatMap((sf) => [
      ...program.getSyntacticDiagnostics(sf),
      ...program.getSemanticDiagnostics(sf),
    ])
    .map((d) => {
      const { line } = d.file!.getLineAndCharacterOfPosition(d.start ?? 0);
      const text = ts.flattenDiagnosticMessageText(d.messageText, '\n');
      return `${relative(root, d.file!.fileName)}:${line + 1}: ${text}`;
    });
}

/**
 * Imports a program written by {@link programFile} and returns what it printed with console.log
 * (arguments joined by spaces) and how often it called console.warn.
 */
export async function runProgram(file: string): Promise<{ printed: string[]; warnings: number }> {
  const printed: string[] = [];
  const log = vi.spyOn(console, 'log').mockImplementation((...args: unknown[]) => {
    printed.push(args.map(String).join(' '));
  });
  const warn = vi.spyOn(console, 'warn').mockImplementation(() => undefined);
  try {
    await import(/* @vite-ignore */ file);
    return { printed, warnings: warn.mock.calls.length };
  } finally {
    log.mockRestore();
    warn.mockRestore();
  }
}
