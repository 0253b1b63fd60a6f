import { describe, expect, it } from 'vitest';
import { parseArgs, selectSuites } from '../lib/args.js';
import {
  formatBytes,
  formatDuration,
  formatRange,
  formatRatio,
  formatTable,
} from '../lib/format.js';
import { renderAllocation, renderComparison } from '../lib/report.js';
import type { AllocationSection, ComparisonSection } from '../lib/report.js';
import {
  bytesPerOp,
  median,
  opsForSample,
  ratios,
  roundOrder,
  spread,
  summarize,
} from '../lib/stats.js';
import { isSuite } from '../lib/suite.js';

describe('parseArgs', () => {
  it('defaults to every suite, full run, no JSON', () => {
    expect(parseArgs([])).toEqual({
      ok: true,
      options: { suites: [], list: false, quick: false, json: undefined, help: false },
    });
  });

  it('reads suites, flags and --json in either form', () => {
    expect(parseArgs(['loop', '--quick', '--json', 'out/r.json', 'physics', 'loop'])).toEqual({
      ok: true,
      options: {
        suites: ['loop', 'physics'],
        list: false,
        quick: true,
        json: 'out/r.json',
        help: false,
      },
    });
    const eq = parseArgs(['--json=r.json', '--list', '-h']);
    expect(eq.ok && eq.options).toMatchObject({ json: 'r.json', list: true, help: true });
  });

  it('rejects unknown options and a --json without a file', () => {
    expect(parseArgs(['--fast'])).toEqual({ ok: false, error: 'unknown option --fast' });
    expect(parseArgs(['--json'])).toMatchObject({ ok: false, error: /--json needs a file/ });
    expect(parseArgs(['--json', '--quick'])).toMatchObject({ ok: false });
    expect(parseArgs(['--json='])).toMatchObject({ ok: false });
    expect(parseArgs(['--json', 'a', '--json', 'b'])).toEqual({
      ok: false,
      error: '--json given twice',
    });
  });
});

describe('selectSuites', () => {
  const available = ['loop', 'physics', 'replay'];

  it('selects all, or the requested ones in the order given', () => {
    expect(selectSuites(available, [])).toEqual({ ok: true, names: available });
    expect(selectSuites(available, ['replay', 'loop'])).toEqual({
      ok: true,
      names: ['replay', 'loop'],
    });
  });

  it('names every unknown suite and lists the available ones', () => {
    expect(selectSuites(available, ['loop', 'lop', 'net'])).toEqual({
      ok: false,
      error: 'unknown suites lop, net; available: loop, physics, replay',
    });
  });
});

describe('statistics', () => {
  it('median of odd and even counts, whatever the order', () => {
    expect(median([5, 1, 3])).toBe(3);
    expect(median([10, 2, 4, 8])).toBe(6);
    expect(median([7])).toBe(7);
    expect(() => median([])).toThrow(RangeError);
    // Numeric, not string, order: 10 < 9 as strings.
    expect(median([9, 10, 100])).toBe(10);
  });

  it('spread and per-round ratios', () => {
    expect(spread([3, 1, 2])).toEqual({ median: 2, min: 1, max: 3 });
    expect(ratios([20, 30, 45], [10, 10, 15])).toEqual([2, 3, 3]);
    expect(() => ratios([1, 2], [1])).toThrow(RangeError);
  });

  it('summarize takes ratios round by round, not as a ratio of medians', () => {
    // Round 2 is slow for everyone (machine noise): the per-round ratio stays 2.
    const samples = [
      [10, 10, 40, 10, 10],
      [20, 20, 80, 20, 20],
      [15, 30, 60, 15, 45],
    ];
    const [base, twice, mixed] = summarize(['base', 'twice', 'mixed'], samples, 0);
    expect(base).toEqual({
      name: 'base',
      ns: { median: 10, min: 10, max: 40 },
      ratio: undefined,
    });
    expect(twice!.ratio).toEqual({ median: 2, min: 2, max: 2 });
    expect(twice!.ns.median).toBe(20);
    expect(mixed!.ratio).toEqual({ median: 1.5, min: 1.5, max: 4.5 });
    // Against another baseline.
    expect(summarize(['a', 'b'], [[10], [20]], 1)[0]!.ratio!.median).toBe(0.5);
    expect(() => summarize(['a'], [[1]], 1)).toThrow(RangeError);
  });

  it('alternates the order of the candidates from round to round', () => {
    expect(roundOrder(3, 0)).toEqual([0, 1, 2]);
    expect(roundOrder(3, 1)).toEqual([2, 1, 0]);
    expect(roundOrder(3, 2)).toEqual([0, 1, 2]);
    expect(roundOrder(1, 1)).toEqual([0]);
  });

  it('sizes a sample from the cost per op', () => {
    expect(opsForSample(15e6, 30)).toBe(500_000);
    expect(opsForSample(15e6, 2.5e7)).toBe(1);
    expect(opsForSample(15e6, 0)).toBe(1_000_000);
    expect(opsForSample(15e6, NaN)).toBe(1_000_000);
  });

  it('bytes per op subtract the readings’ own overhead and never go negative', () => {
    // Heap readings around 10 000-op chunks: 640 B of overhead; one chunk grew by 160 000 B more.
    const b = bytesPerOp([640, 648, 160_640, 600], [640, 640, 632], 10_000);
    expect(b.median).toBeCloseTo(0.0004, 10);
    expect(b.min).toBe(0);
    expect(b.max).toBe(16);
    expect(bytesPerOp([320_000], [], 10_000)).toEqual({ median: 32, min: 32, max: 32 });
  });
});

describe('formatting', () => {
  it('pads columns: first left, others right, a rule under the header', () => {
    const table = formatTable(
      ['candidate', 'per frame', 'ratio'],
      [
        ['hand-written', '8.89 ns', '1.00×'],
        ['FixedLoop.advance', '29.7 ns', '3.34×'],
      ],
    );
    expect(table.split('\n')).toEqual([
      '  candidate          per frame  ratio',
      '  -----------------  ---------  -----',
      '  hand-written         8.89 ns  1.00×',
      '  FixedLoop.advance    29.7 ns  3.34×',
    ]);
  });

  it('honours alignment and indent, trims trailing space, checks row widths', () => {
    expect(formatTable(['a', 'bb'], [['xyz', 'q']], ['left', 'left'], '')).toBe(
      'a    bb\n---  --\nxyz  q',
    );
    expect(() => formatTable(['a', 'b'], [['only one']])).toThrow(RangeError);
  });

  it('durations in the unit that reads best, three significant digits', () => {
    expect(formatDuration(8.888)).toBe('8.89 ns');
    expect(formatDuration(29.71)).toBe('29.7 ns');
    expect(formatDuration(314.2)).toBe('314 ns');
    expect(formatDuration(12_345)).toBe('12.3 µs');
    expect(formatDuration(1_500_000)).toBe('1.50 ms');
    expect(formatDuration(2e9)).toBe('2.00 s');
    expect(formatDuration(NaN)).toBe('NaN');
  });

  it('ratios, ranges and bytes', () => {
    expect(formatRatio(3.3449)).toBe('3.34×');
    expect(formatRange(1.8512, 2.3)).toBe('1.85–2.30');
    expect(formatBytes(0.0024)).toBe('0.002');
    expect(formatBytes(16)).toBe('16.0');
    expect(formatBytes(216.7)).toBe('217');
  });
});

describe('reports', () => {
  it('a comparison: ns per op, ratio and its spread per candidate', () => {
    const section: ComparisonSection = {
      kind: 'comparison',
      title: 'Time per display frame',
      unit: 'frame',
      baseline: 'hand-written',
      rounds: 30,
      sampleMs: 15,
      candidates: [
        {
          name: 'hand-written',
          opsPerSample: 1_700_000,
          ns: { median: 8.89, min: 8.7, max: 9.4 },
          samplesNs: [8.89],
        },
        {
          name: 'FixedLoop.advance',
          opsPerSample: 500_000,
          ns: { median: 29.7, min: 29, max: 31 },
          ratio: { median: 3.344, min: 3.31, max: 3.352 },
          samplesNs: [29.7],
        },
      ],
    };
    expect(renderComparison(section).split('\n')).toEqual([
      'Time per display frame',
      '  candidate          per frame  ratio  ratio min–max',
      '  -----------------  ---------  -----  -------------',
      '  hand-written         8.89 ns  1.00×     (baseline)',
      '  FixedLoop.advance    29.7 ns  3.34×      3.31–3.35',
      '  median of 30 interleaved rounds (~15 ms per sample); ratio = per-round time / hand-written',
    ]);
  });

  it('an allocation check: bytes per op and a verdict above the noise floor', () => {
    const section: AllocationSection = {
      kind: 'allocation',
      title: 'Heap per frame',
      unit: 'frame',
      chunks: 100,
      opsPerChunk: 10_000,
      candidates: [
        { name: 'FixedLoop', bytes: { median: 0.002, min: 0.002, max: 1.2 } },
        { name: 'control', bytes: { median: 32, min: 32, max: 32 } },
      ],
    };
    expect(renderAllocation(section).split('\n')).toEqual([
      'Heap per frame',
      '  candidate  B/frame  max chunk  allocates',
      '  ---------  -------  ---------  ---------',
      '  FixedLoop    0.002      1.200         no',
      '  control       32.0       32.0        yes',
      "  100 chunks × 10000 frames, each after a minor gc; median chunk; 'no' = under 0.006 B/frame",
    ]);
    expect(renderAllocation({ ...section, skipped: 'no gc', candidates: [] })).toBe(
      'Heap per frame\n  skipped: no gc',
    );
  });
});

describe('isSuite', () => {
  it('accepts { name, description, run } and nothing less', () => {
    const run = () => undefined;
    expect(isSuite({ name: 'loop', description: 'd', run })).toBe(true);
    expect(isSuite({ name: '', description: 'd', run })).toBe(false);
    expect(isSuite({ name: 'loop', run })).toBe(false);
    expect(isSuite({ name: 'loop', description: 'd', run: 1 })).toBe(false);
    expect(isSuite(null)).toBe(false);
    expect(isSuite(undefined)).toBe(false);
  });
});
