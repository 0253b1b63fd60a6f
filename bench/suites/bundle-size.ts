/**
 * What the library costs a game's bundle: minified (and gzipped) sizes of what a game imports,
 * bundled by esbuild from the package entry with tree shaking — the way Vite, Rollup or esbuild
 * bundle it for a user. Targets (issue 11): the loop alone ≤ 7 KB minified; the loop, the input
 * pipeline and the interpolation buffer ≤ 12 KB.
 */
import { gzipSync } from 'node:zlib';
import { build } from 'esbuild';
import { defineSuite } from '../lib/suite.js';

interface Entry {
  readonly name: string;
  /** The named imports from 'fixedstep'. */
  readonly imports: readonly string[];
  /** Target, minified bytes (undefined: no target). */
  readonly limit?: number;
}

const ENTRIES: readonly Entry[] = [
  { name: 'loop only', imports: ['FixedLoop'], limit: 7 * 1024 },
  {
    name: 'loop + input + interpolation',
    imports: ['FixedLoop', 'FrameStepper', 'InputSampler', 'attachKeyboard', 'InterpolationBuffer'],
    limit: 12 * 1024,
  },
  {
    name: '+ a schema of your own (defineInput, axes)',
    imports: [
      'FixedLoop',
      'FrameStepper',
      'InputSampler',
      'attachKeyboard',
      'InterpolationBuffer',
      'defineInput',
    ],
  },
  {
    name: '+ touch buttons, stick, gamepad, rAF driver',
    imports: [
      'FixedLoop',
      'FrameStepper',
      'InputSampler',
      'defineInput',
      'attachKeyboard',
      'attachButtons',
      'attachStick',
      'gamepadPoller',
      'InterpolationBuffer',
      'FrameDriver',
      'animationFrameScheduler',
    ],
  },
  {
    name: '+ replays (recorder, reader, verifier)',
    imports: ['FixedLoop', 'ReplayRecorder', 'readReplay', 'verifyReplay'],
  },
  {
    name: '+ rollback over WebSocket',
    imports: ['FixedLoop', 'RollbackSession', 'webSocketTransport'],
  },
  { name: 'everything', imports: ['*'] },
];

async function bundle(entry: Entry): Promise<{ min: number; gzip: number }> {
  const source =
    entry.imports[0] === '*'
      ? `export * from 'fixedstep';`
      : `export { ${entry.imports.join(', ')} } from 'fixedstep';`;
  const out = await build({
    stdin: { contents: source, resolveDir: process.cwd(), loader: 'ts' },
    bundle: true,
    minify: true,
    format: 'esm',
    platform: 'browser',
    target: 'es2022',
    conditions: ['source'],
    write: false,
    logLevel: 'silent',
  });
  const bytes = out.outputFiles[0]!.contents;
  return { min: bytes.length, gzip: gzipSync(bytes).length };
}

const kb = (n: number) => `${(n / 1024).toFixed(1)} KB`;

export default defineSuite({
  name: 'bundle-size',
  description:
    'minified + gzipped size of what a game imports from fixedstep (esbuild, tree-shaken)',
  async run(ctx) {
    const rows: string[][] = [];
    const over: string[] = [];
    for (const entry of ENTRIES) {
      const { min, gzip } = await bundle(entry);
      const within =
        entry.limit === undefined
          ? ''
          : min <= entry.limit
            ? `≤ ${kb(entry.limit)} ✓`
            : `> ${kb(entry.limit)} ✗`;
      if (entry.limit !== undefined && min > entry.limit) over.push(entry.name);
      rows.push([entry.name, kb(min), kb(gzip), within]);
    }
    ctx.table(
      'Bundle size (esbuild --minify, ES2022, tree-shaken)',
      ['imports', 'minified', 'gzip', 'target'],
      rows,
    );
    if (over.length > 0) ctx.note(`over target: ${over.join(', ')}`);
  },
});
