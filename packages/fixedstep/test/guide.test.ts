/**
 * Every code block of the guide (docs/guide/*.md) is run or checked here, so nothing in it can
 * drift from the code (the markers and their checks: doc-blocks.ts):
 * - a ```ts block preceded by `<!-- from: FILE#REGION -->` is the text of that region of FILE,
 *   exactly (the engine recipes' glue);
 * - a ```ts block preceded by `<!-- from: FILE -->` is an excerpt of FILE (coin-dash's code). Those
 *   files are built and played by e2e/examples.e2e.test.ts;
 * - every other ```ts block is a program: it is type-checked (strict, noUncheckedIndexedAccess)
 *   and run here, with `examples/coin-dash/src/game.ts` beside it as `./game.js`, and what it
 *   prints with console.log must be, line by line, the `// → …` comments it carries;
 * - a ```sh block preceded by `<!-- sh: DIR -->` runs only what DIR has (doc-shell.ts); no other
 *   kind of block is allowed;
 * - every relative link of the guide points at a file that exists, and the index lists every page.
 */
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  blockName,
  blocksOf,
  brokenLinks,
  kindOf,
  programFile,
  writePrograms,
  promised,
  quoteProblems,
  root,
  runProgram,
  typeProblems,
} from './doc-blocks.js';
import { shellProblems } from './doc-shell.js';

const pages = readdirSync(join(root, 'docs', 'guide'))
  .filter((f) => f.endsWith('.md'))
  .sort()
  .map((f) => `docs/guide/${f}`);

const blocks = pages.flatMap(blocksOf);
const programs = blocks.filter((b) => kindOf(b) === 'program');
const quotes = blocks.filter((b) => kindOf(b) === 'region' || kindOf(b) === 'excerpt');
const shells = blocks.filter((b) => kindOf(b) === 'sh');

describe('the guide', () => {
  it('has pages, an index that links every page, and only programs, quotes and sh blocks', () => {
    expect(pages).toContain('docs/guide/README.md');
    expect(pages).toContain('docs/guide/getting-started.md');
    const index = readFileSync(join(root, 'docs/guide/README.md'), 'utf8');
    for (const p of pages.filter((p) => !p.endsWith('README.md'))) {
      expect(index).toContain(`](${p.slice('docs/guide/'.length)})`);
    }
    expect(
      blocks
        .filter((b) => !['program', 'region', 'excerpt', 'sh'].includes(kindOf(b)))
        .map(blockName),
    ).toEqual([]);
    expect(blocks.filter((b) => b.lang !== 'ts' && b.lang !== 'sh').map(blockName)).toEqual([]);
    expect(programs.length).toBeGreaterThan(5);
  });

  it('links only to files that exist', () => {
    expect(pages.flatMap(brokenLinks)).toEqual([]);
  });
});

describe('guide blocks taken from files', () => {
  it.each(quotes.map((b) => [blockName(b), b] as const))('%s is the file’s own text', (_, b) => {
    expect(quoteProblems(b)).toEqual([]);
  });
});

describe('guide shell blocks', () => {
  it.each(shells.map((b) => [blockName(b), b] as const))('%s runs only what exists', (_, b) => {
    expect(shellProblems(b)).toEqual([]);
  });
});

/** Where the programs are written. */
const outDir = join(root, 'artifacts', 'guide');
const files = writePrograms(root, outDir, programs);

describe('guide programs', () => {
  it('type-check strictly against the library', () => {
    expect(typeProblems(files)).toEqual([]);
  }, 120_000);

  it.each(programs.map((b) => [blockName(b), b] as const))(
    '%s runs and prints what its // → comments say',
    async (_, b) => {
      const { printed, warnings } = await runProgram(programFile(outDir, b));
      expect(printed).toEqual(promised(b.code));
      // A block that means to show a warning catches it itself (onWarning): none may escape.
      expect(warnings).toBe(0);
    },
  );
});
