import {
  HarmonicOscillator,
  INTEGRATOR_INFO,
  INTEGRATOR_METHODS,
  createIntegrator,
  datan2,
  dcos,
  dsin,
  type IntegratorMethod,
} from 'fixedstep';

export interface IntegratorExperimentOptions {
  /** Angular frequency ω, rad/s. */
  omega: number;
  /** Step, s. */
  dt: number;
  /** Simulated time, s. */
  duration: number;
  /** Start position (m) and velocity (m/s). */
  x0: number;
  v0: number;
  methods: readonly IntegratorMethod[];
  /** Keep every `sampleEvery`-th step in the series (for CSV and plots). Default: ~500 samples. */
  sampleEvery?: number;
}

export interface IntegratorResult {
  method: IntegratorMethod;
  label: string;
  order: number;
  stabilityLimit: number;
  /** E(T) / E(0). */
  energyRatio: number;
  /** max over the run of |E(t)/E(0) − 1|. */
  maxEnergyError: number;
  /** Phase of the numerical (x, v/ω) minus the exact phase at the end, wrapped to (−π, π], rad. */
  phaseError: number;
  /** Sampled series: time (s), x (m), energy ratio. */
  t: number[];
  x: number[];
  energy: number[];
}

export interface IntegratorExperiment {
  options: IntegratorExperimentOptions;
  steps: number;
  results: IntegratorResult[];
}

const TWO_PI = 2 * Math.PI;

function wrap(a: number): number {
  let r = a - TWO_PI * Math.floor((a + Math.PI) / TWO_PI);
  if (r <= -Math.PI) r += TWO_PI;
  return r;
}

/** Runs each method on `x'' = −ω²x` and measures energy drift and phase error against the exact solution. */
export function runIntegratorExperiment(
  options: IntegratorExperimentOptions,
): IntegratorExperiment {
  const { omega, dt, duration, x0, v0 } = options;
  const steps = Math.max(1, Math.round(duration / dt));
  const every = options.sampleEvery ?? Math.max(1, Math.ceil(steps / 500));
  const model = new HarmonicOscillator(omega);
  const e0 = model.energy(x0, v0);
  if (!(e0 > 0))
    throw new RangeError(
      'the oscillator needs some energy: x0 and v0 cannot both be 0 (or ω = 0 with v0 = 0)',
    );
  const results = options.methods.map((method): IntegratorResult => {
    const info = INTEGRATOR_INFO[method];
    const integrator = createIntegrator(method, model);
    const state = model.state(x0, v0);
    integrator.start(state, dt);
    const t = [0];
    const xs = [x0];
    const energy = [1];
    let maxErr = 0;
    for (let n = 1; n <= steps; n++) {
      integrator.step(state, dt);
      const ratio = model.energy(state.x[0]!, state.v[0]!) / e0;
      const err = Math.abs(ratio - 1);
      if (err > maxErr || Number.isNaN(err)) maxErr = Number.isNaN(err) ? Infinity : err;
      if (n % every === 0 || n === steps) {
        t.push(n * dt);
        xs.push(state.x[0]!);
        energy.push(ratio);
      }
    }
    const T = steps * dt;
    // Exact: x = x0 cos ωT + (v0/ω) sin ωT, v = −x0 ω sin ωT + v0 cos ωT.
    const c = dcos(omega * T);
    const s = dsin(omega * T);
    const xe = x0 * c + (omega > 0 ? (v0 / omega) * s : v0 * T);
    const ve = -x0 * omega * s + v0 * c;
    const phase = (x: number, v: number) => datan2(omega > 0 ? -v / omega : -v, x);
    return {
      method,
      label: info.label,
      order: info.order,
      stabilityLimit: info.stabilityLimit,
      energyRatio: energy[energy.length - 1]!,
      maxEnergyError: maxErr,
      phaseError: wrap(phase(state.x[0]!, state.v[0]!) - phase(xe, ve)),
      t,
      x: xs,
      energy,
    };
  });
  return { options, steps, results };
}

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
