/**
 * Every code block of the pages outside the guide — docs/*.md, the root README and every
 * package's and example's README — is run or checked here, as the guide's are (guide.test.ts; the
 * markers and their checks: doc-blocks.ts and doc-shell.ts):
 * - a ```ts block with no marker is a program: type-checked and run, printing its `// → …` lines;
 * - `<!-- typecheck: WHY -->`: type-checked only, WHY saying what running it needs;
 * - a marker naming the test that runs it (`… run by packages/x/test/y.test.ts`): that test exists
 *   and reads the page, and a ```ts block is type-checked here too;
 * - `<!-- from: FILE -->` / `<!-- from: FILE#REGION -->`: the file's own text;
 * - `<!-- sh: DIR -->`: commands of DIR's scripts, the CLI's parser and the repository's files;
 * - `<!-- text -->`: a diagram, a table or an example of output;
 * and nothing else. Every relative link points at a file that exists.
 */
import { existsSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  blockName,
  blocksOf,
  brokenLinks,
  elsewhereProblems,
  kindOf,
  programFile,
  writePrograms,
  promised,
  quoteProblems,
  root,
  runProgram,
  typeProblems,
  type Block,
} from './doc-blocks.js';
import { shellProblems } from './doc-shell.js';

const readmes = (dir: string) =>
  readdirSync(join(root, dir))
    .filter((d) => existsSync(join(root, dir, d, 'README.md')))
    .map((d) => `${dir}/${d}/README.md`);

const pages = [
  ...readdirSync(join(root, 'docs'))
    .filter((f) => f.endsWith('.md'))
    .map((f) => `docs/${f}`),
  ...readmes('examples'),
  ...readmes('packages'),
  'README.md',
].sort();

const blocks = pages.flatMap(blocksOf);
const of = (...kinds: string[]) => blocks.filter((b) => kinds.includes(kindOf(b)));
const cases = (list: Block[]) => list.map((b) => [blockName(b), b] as const);
const programs = of('program');
const typed = [...of('program', 'typecheck'), ...of('elsewhere').filter((b) => b.lang === 'ts')];

describe('the docs', () => {
  it('are the pages of docs/ and every README', () => {
    expect(pages).toContain('docs/physics-world.md');
    expect(pages).toContain('examples/coin-dash/README.md');
    expect(pages).toContain('packages/server/README.md');
    expect(pages.length).toBeGreaterThanOrEqual(20);
  });

  it('have no block that is neither run nor checked nor marked as text', () => {
    expect(of('unchecked').map((b) => `${blockName(b)} (${b.lang || 'no language'})`)).toEqual([]);
  });

  it.each(pages)('%s links only to files that exist', (page) => {
    expect(brokenLinks(page)).toEqual([]);
  });
});

describe('doc blocks taken from files', () => {
  it.each(cases(of('region', 'excerpt')))('%s is the file’s own text', (_, b) => {
    expect(quoteProblems(b)).toEqual([]);
  });
});

describe('doc blocks run by other tests', () => {
  it.each(cases(of('elsewhere')))('%s is read by the test that runs it', (_, b) => {
    expect(elsewhereProblems(b)).toEqual([]);
  });
});

describe('doc shell blocks', () => {
  it.each(cases(of('sh')))('%s runs only what exists', (_, b) => {
    expect(shellProblems(b)).toEqual([]);
  });
});

/** Where the programs are written. */
const outDir = join(root, 'artifacts', 'docs');
const files = writePrograms(root, outDir, typed);

describe('doc programs', () => {
  it('type-check strictly against the packages', () => {
    expect(typeProblems(files)).toEqual([]);
  }, 120_000);

  it.each(cases(programs))('%s runs and prints what its // → comments say', async (_, b) => {
    const { printed, warnings } = await runProgram(programFile(outDir, b));
    expect(printed).toEqual(promised(b.code));
    expect(warnings).toBe(0);
  });
});
