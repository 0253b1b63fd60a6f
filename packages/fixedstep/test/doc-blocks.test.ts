/**
 * How the docs' tests read a block's marker (doc-blocks.ts): what each kind of block is taken for,
 * and that a block said to be run elsewhere names a test that exists and reads its page.
 */
import { describe, expect, it } from 'vitest';
import { elsewhereProblems, kindOf, promised, type Block } from './doc-blocks.js';

const block = (lang: string, marker?: string, doc = 'docs/rapier.md'): Block => ({
  doc,
  line: 1,
  lang,
  code: '\n',
  marker,
});

describe('kindOf', () => {
  it.each([
    ['ts', undefined, 'program'],
    ['ts', 'typecheck: a browser page', 'typecheck'],
    ['ts', 'typecheck:', 'unchecked'],
    ['ts', 'from: examples/coin-dash/src/game.ts', 'excerpt'],
    ['ts', 'from: packages/fixedstep/src/x.ts#glue', 'region'],
    ['ts', 'rapier-example: this block is run by packages/rapier/test/docs.test.ts', 'elsewhere'],
    ['', 'text: run by packages/fixedstep/test/replay-spec-example.test.ts', 'elsewhere'],
    ['', 'text', 'text'],
    ['', undefined, 'unchecked'],
    ['json', undefined, 'unchecked'],
    ['sh', 'sh: .', 'sh'],
    ['sh', undefined, 'sh'],
    ['ts', 'server-example: node-http', 'unchecked'],
  ])('a %s block marked %s is %s', (lang, marker, kind) => {
    expect(kindOf(block(lang, marker))).toBe(kind);
  });
});

describe('elsewhereProblems', () => {
  it('takes a test that reads the page, and refuses one that is missing or reads another', () => {
    const ran = (test: string) => elsewhereProblems(block('ts', `run by ${test}`));
    expect(ran('packages/rapier/test/docs.test.ts')).toEqual([]);
    expect(ran('packages/rapier/test/nowhere.test.ts')).toEqual([
      'no test packages/rapier/test/nowhere.test.ts',
    ]);
    expect(ran('packages/fixedstep/test/readme.test.ts')).toEqual([
      'packages/fixedstep/test/readme.test.ts never names rapier.md',
    ]);
  });
});

describe('promised', () => {
  it('is every `// → ` comment, in order, without trailing blanks', () => {
    expect(promised('a(); // → 1 2  \n// not this\n// →   x\nb(); // 3\n')).toEqual(['1 2', '  x']);
  });
});
