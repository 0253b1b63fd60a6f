import { INTEGRATOR_METHODS } from 'fixedstep';
import {
  runIntegratorExperiment,
  type IntegratorExperiment,
  type IntegratorExperimentOptions,
  type IntegratorResult,
} from '@fixedstep/games';

// The experiment itself lives in @fixedstep/games (scenes/physics.ts), built on the same
// OscillatorRace the lab's physics chapter runs live; this module formats it for the CLI.
export { runIntegratorExperiment };
export type { IntegratorExperiment, IntegratorExperimentOptions, IntegratorResult };

function fmt(x: number, digits = 4): string {
  if (!Number.isFinite(x)) return Number.isNaN(x) ? 'NaN' : x > 0 ? 'inf' : '-inf';
  const a = Math.abs(x);
  if (a !== 0 && (a >= 1e6 || a < 1e-3)) return x.toExponential(2);
  return x.toFixed(digits);
}

/** The result as an aligned text table. */
export function formatIntegratorTable(exp: IntegratorExperiment): string {
  const { omega, dt, duration } = exp.options;
  const h = omega * dt;
  const head = `x'' = -ω²x with ω = ${fmt(omega, 3)} rad/s, dt = ${dt} s (ω·dt = ${fmt(h, 3)}), ${fmt(duration, 2)} s = ${exp.steps} steps`;
  const rows = exp.results.map((r) => [
    r.label,
    String(r.order),
    r.stabilityLimit === Infinity
      ? 'none'
      : r.stabilityLimit === 0
        ? 'always'
        : `ω·dt > ${fmt(r.stabilityLimit, 3)}`,
    h > r.stabilityLimit || r.stabilityLimit === 0 ? 'unstable' : 'stable',
    fmt(r.energyRatio),
    fmt(r.maxEnergyError),
    `${r.phaseError >= 0 ? '+' : ''}${fmt(r.phaseError)}`,
  ]);
  const header = [
    'method',
    'order',
    'grows when',
    'here',
    'E(T)/E(0)',
    'max |ΔE/E0|',
    'phase err (rad)',
  ];
  const widths = header.map((hd, i) => Math.max(hd.length, ...rows.map((r) => r[i]!.length)));
  const line = (cells: string[]) =>
    cells.map((c, i) => (i === 0 ? c.padEnd(widths[i]!) : c.padStart(widths[i]!))).join('  ');
  return (
    [head, '', line(header), widths.map((w) => '-'.repeat(w)).join('  '), ...rows.map(line)].join(
      '\n',
    ) + '\n'
  );
}

/** The sampled series as CSV: t, then x and energy ratio per method. */
export function integratorCsv(exp: IntegratorExperiment): string {
  const cols = exp.results.flatMap((r) => [`${r.method}_x`, `${r.method}_energy_ratio`]);
  const lines = [['t', ...cols].join(',')];
  const first = exp.results[0];
  if (!first) return `${lines.join('\n')}\n`;
  for (let i = 0; i < first.t.length; i++) {
    const cells = [String(first.t[i])];
    for (const r of exp.results) cells.push(String(r.x[i]), String(r.energy[i]));
    lines.push(cells.join(','));
  }
  return lines.join('\n') + '\n';
}

export { INTEGRATOR_METHODS };
