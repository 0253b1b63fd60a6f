/**
 * How the docs' tests read a block's marker (doc-blocks.ts): what each kind of block is taken for,
 * and that a block said to be run elsewhere names a test that exists and reads its page.
 */
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { describe, expect, it } from 'vitest';
import {
  anchorsOf,
  brokenLinks,
  elsewhereProblems,
  kindOf,
  promised,
  root,
  type Block,
} from './doc-blocks.js';

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

describe('links', () => {
  it('are GitHub’s anchors: lower case, punctuation dropped, a repeated heading numbered', () => {
    const dir = join(root, 'artifacts', 'doc-blocks');
    mkdirSync(dir, { recursive: true });
    writeFileSync(
      join(dir, 'page.md'),
      '# A page\n\n## The room core: what every server room inherits\n\n## `saveInto` — 2×\n\n' +
        '## Limits\n\n```sh\n# not a heading\n```\n\n### Limits\n\n' +
        '[a](#limits-1) [b](#limits-2) [c](../../docs/network.md#quick-match) [d](nowhere.md) ' +
        '[e](../../docs/network.md#nowhere) [f](https://example.org/#x)\n',
    );
    expect([...anchorsOf(join(dir, 'page.md'))]).toEqual([
      'a-page',
      'the-room-core-what-every-server-room-inherits',
      'saveinto--2',
      'limits',
      'limits-1',
    ]);
    expect(brokenLinks('artifacts/doc-blocks/page.md')).toEqual([
      'artifacts/doc-blocks/page.md: #limits-2 (no such heading)',
      'artifacts/doc-blocks/page.md: nowhere.md',
      'artifacts/doc-blocks/page.md: ../../docs/network.md#nowhere (no such heading)',
    ]);
  });
});
