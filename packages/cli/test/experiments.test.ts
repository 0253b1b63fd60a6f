import { mkdtemp, readFile, rm } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { describe, expect, it } from 'vitest';
import { TALK_INTEGRATOR_EXPERIMENT } from '@fixedstep/games';
import { EXIT_OK, EXIT_USAGE, parseArgs, run } from '@fixedstep/cli';
import {
  formatIntegratorTable,
  integratorCsv,
  runIntegratorExperiment,
} from '../src/experiments/integrators.js';
import { UsageError, parseOptions, type OptionSpec } from '../src/args.js';

const ALL = [
  'explicit-euler',
  'semi-implicit-euler',
  'backward-euler',
  'position-verlet',
  'velocity-verlet',
  'rk4',
] as const;

function io() {
  const out = { stdout: '', stderr: '' };
  return {
    out,
    cli: {
      out: (t: string) => {
        out.stdout += t;
      },
      err: (t: string) => {
        out.stderr += t;
      },
    },
  };
}

describe('experiment integrators', () => {
  const exp = runIntegratorExperiment({ ...TALK_INTEGRATOR_EXPERIMENT, methods: ALL });
  const by = (m: string) => exp.results.find((r) => r.method === m)!;
  const h2 = 20 * 0.03 * 0.03;

  it("reproduces the talk's exploding spring: explicit Euler gains (1 + (ω·dt)²) per step", () => {
    expect(exp.steps).toBe(333);
    expect(by('explicit-euler').energyRatio / (1 + h2) ** 333).toBeCloseTo(1, 9);
    expect(by('explicit-euler').energyRatio).toBeGreaterThan(10);
  });

  it('backward Euler loses 1/(1 + (ω·dt)²) per step; velocity Verlet and RK4 stay within 1 %', () => {
    expect(by('backward-euler').energyRatio * (1 + h2) ** 333).toBeCloseTo(1, 9);
    expect(by('velocity-verlet').maxEnergyError).toBeLessThan(0.01);
    expect(by('rk4').maxEnergyError).toBeLessThan(0.01);
    expect(Math.abs(by('rk4').phaseError)).toBeLessThan(1e-3);
    expect(Math.abs(by('semi-implicit-euler').phaseError)).toBeGreaterThan(
      Math.abs(by('rk4').phaseError),
    );
  });

  it('formats a table and a CSV of the samples', () => {
    const table = formatIntegratorTable(exp);
    expect(table).toContain('ω·dt = 0.134');
    expect(table.split('\n').filter((l) => /Euler|Verlet|Runge/.test(l))).toHaveLength(6);
    const csv = integratorCsv(exp).trim().split('\n');
    expect(csv[0]).toBe(['t', ...ALL.flatMap((m) => [`${m}_x`, `${m}_energy_ratio`])].join(','));
    expect(csv).toHaveLength(exp.results[0]!.t.length + 1);
    expect(csv.at(-1)!.split(',')).toHaveLength(13);
  });

  it('runs from the command line and writes CSV and SVG', async () => {
    const dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-exp-'));
    try {
      const csv = path.join(dir, 'e.csv');
      const svg = path.join(dir, 'e.svg');
      const { out, cli } = io();
      const code = await run(
        ['experiment', 'integrators', '--dt', '0.03', '--csv', csv, '--svg', svg],
        {},
        cli,
      );
      expect(code).toBe(EXIT_OK);
      expect(out.stdout).toContain('Explicit Euler');
      expect((await readFile(csv, 'utf8')).startsWith('t,explicit-euler_x')).toBe(true);
      const picture = await readFile(svg, 'utf8');
      expect(picture.match(/<polyline/g)).toHaveLength(6);
      expect(picture).toContain('</svg>');
    } finally {
      await rm(dir, { recursive: true, force: true });
    }
  });

  it.each([
    [['experiment'], 'experiment needs a name: integrators or tunnel'],
    [
      ['experiment', 'integrators', '--dt', '0'],
      '--dt must be a number from 0.000001 to 10, got "0"',
    ],
    [
      ['experiment', 'integrators', '--dt', 'fast'],
      '--dt must be a number from 0.000001 to 10, got "fast"',
    ],
    [
      ['experiment', 'integrators', '--methods', 'euler'],
      '--methods: unknown method "euler"; choose from',
    ],
    [['experiment', 'integrators', '--x0', '0'], '--x0 and --v0 cannot both be 0'],
    [['experiment', 'integrators', '--dt', '1e-6', '--duration', '1000'], 'at most 10 000 000'],
  ])('rejects %j with a clear message', (argv, message) => {
    const c = parseArgs(argv);
    expect(c.kind).toBe('usage-error');
    expect(c.kind === 'usage-error' ? c.message : '').toContain(message);
  });

  it('exits 2 on a usage error', async () => {
    const { out, cli } = io();
    expect(await run(['experiment', 'integrators', '--omega', '-1'], {}, cli)).toBe(EXIT_USAGE);
    expect(out.stderr).toContain('--omega must be a number from 0 to 1000000, got "-1"');
  });
});

describe('parseOptions', () => {
  const specs: OptionSpec[] = [
    { name: 'speed', kind: 'numbers', min: 0, help: '' },
    { name: 'offset', kind: 'number', min: -10, max: 10, help: '' },
    { name: 'n', kind: 'integer', min: 1, help: '' },
    { name: 'ccd', kind: 'flag', help: '' },
  ];
  it('reads lists, negatives where allowed, flags and positionals', () => {
    const r = parseOptions(
      'x',
      ['--speed', '1,2.5,1e3', '--offset', '-2.5', '--ccd', 'file'],
      specs,
      1,
    );
    expect(r.values).toEqual({ speed: [1, 2.5, 1000], offset: -2.5, ccd: true });
    expect(r.positionals).toEqual(['file']);
  });
  it('names the option and value in every error', () => {
    expect(() => parseOptions('x', ['--speed', '1,,2'], specs)).toThrow(
      new UsageError('--speed must be a comma-separated list of numbers, got "1,,2"'),
    );
    expect(() => parseOptions('x', ['--n', '0'], specs)).toThrow(
      '--n must be an integer ≥ 1, got "0"',
    );
    expect(() => parseOptions('x', ['--ccd=yes'], specs)).toThrow('--ccd takes no value');
    expect(() => parseOptions('x', ['a'], specs)).toThrow('unexpected argument for x: a');
    expect(() => parseOptions('x', ['--offset', '11'], specs)).toThrow(
      '--offset must be a number from -10 to 10, got "11"',
    );
  });
});

describe('experiment tunnel', () => {
  it('measures discrete tunnelling as geometry predicts, and none with CCD', async () => {
    const { out, cli } = io();
    const code = await run(
      ['experiment', 'tunnel', '--speeds', '10,50', '--walls', '0.3', '--trials', '600'],
      {},
      cli,
    );
    expect(code).toBe(EXIT_OK);
    // v·dt = 0.3 keeps the talk's rule yet 33 % tunnel; at 50 m/s 87 % do. CCD: none.
    const rows = out.stdout.split('\n').filter((l) => /^\s+0\.03\s/.test(l));
    expect(rows).toHaveLength(2);
    const cells = rows.map((r) => r.trim().split(/\s{2,}/));
    expect(cells[0]![4]).toBe('kept');
    for (const c of cells) {
      const theory = parseFloat(c[5]!);
      const discrete = parseFloat(c[6]!);
      expect(Math.abs(discrete - theory)).toBeLessThan(6); // percentage points, 600 samples
      expect(c[7]).toBe('0.0 %');
    }
  });

  it('rejects bad lists', () => {
    const c = parseArgs(['experiment', 'tunnel', '--speeds', '10,fast']);
    expect(c).toMatchObject({
      kind: 'usage-error',
      message: '--speeds must be a number from 0.001 to 100000, got "fast"',
    });
  });
});
