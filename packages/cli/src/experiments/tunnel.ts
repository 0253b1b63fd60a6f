import { measureTunnelling, type TunnelResult } from '@fixedstep/games';
import { minWallSize } from 'fixedstep';
import { formatOptions, parseOptions, type OptionSpec } from '../args.js';

export interface TunnelExperimentOptions {
  speeds: number[];
  walls: number[];
  dts: number[];
  radius: number;
  trials: number;
  seed: number;
}

const OPTIONS: OptionSpec[] = [
  {
    name: 'speeds',
    kind: 'numbers',
    min: 0.001,
    max: 1e5,
    valueName: 'm/s,…',
    help: 'Body speeds (default: 5,10,20,50,100,1000)',
  },
  {
    name: 'walls',
    kind: 'numbers',
    min: 0.001,
    max: 1e3,
    valueName: 'm,…',
    help: 'Wall thicknesses (default: 0.05,0.1,0.3,1)',
  },
  {
    name: 'dts',
    kind: 'numbers',
    min: 1e-5,
    max: 1,
    valueName: 's,…',
    help: "Fixed steps (default: 0.03, the talk's TIME_STEP)",
  },
  {
    name: 'radius',
    kind: 'number',
    min: 0.001,
    max: 10,
    valueName: 'm',
    help: 'Body radius (default: 0.05)',
  },
  {
    name: 'trials',
    kind: 'integer',
    min: 1,
    max: 100_000,
    valueName: 'n',
    help: 'Bodies fired per cell, each at a random phase (default: 1000)',
  },
  {
    name: 'seed',
    kind: 'integer',
    min: 0,
    max: 4294967295,
    valueName: 'n',
    help: 'Seed of the phases (default: 1)',
  },
  { name: 'csv', kind: 'string', valueName: 'file', help: 'Write the table as CSV' },
  { name: 'help', short: 'h', kind: 'flag', help: 'Show this help' },
];

export const TUNNEL_HELP = `fixedstep experiment tunnel — how often fast bodies pass through walls

Fires circles at a wall from random phases and counts how many end up on the far side, for every
speed × wall thickness × step, with discrete collision detection and with continuous collision
detection (CCD). The talk's rule, minWallSize = maxObjectSpeed × TIMESTEP, only guarantees that a
hit is detected; with a push-out response a correct bounce needs v·dt ≤ w/2 + r, and the share
that tunnels is max(0, 1 − (w + 2r) / (2·v·dt)) — the "theory" column.

Usage:
  fixedstep experiment tunnel [options]

Options:
${formatOptions(OPTIONS)}
`;

type Parsed =
  | { kind: 'help'; text: string }
  | { kind: 'experiment-tunnel'; options: TunnelExperimentOptions; csv?: string };

export function parseTunnel(rest: readonly string[]): Parsed {
  const { values: v } = parseOptions('experiment tunnel', rest, OPTIONS);
  if (v.help) return { kind: 'help', text: TUNNEL_HELP };
  const list = (x: unknown, d: number[]) => (Array.isArray(x) ? (x as number[]) : d);
  const options: TunnelExperimentOptions = {
    speeds: list(v.speeds, [5, 10, 20, 50, 100, 1000]),
    walls: list(v.walls, [0.05, 0.1, 0.3, 1]),
    dts: list(v.dts, [0.03]),
    radius: typeof v.radius === 'number' ? v.radius : 0.05,
    trials: typeof v.trials === 'number' ? v.trials : 1000,
    seed: typeof v.seed === 'number' ? v.seed : 1,
  };
  return {
    kind: 'experiment-tunnel',
    options,
    ...(typeof v.csv === 'string' ? { csv: v.csv } : {}),
  };
}

export interface TunnelRow {
  discrete: TunnelResult;
  ccd: TunnelResult;
}

/** Runs every cell, discrete and CCD, reporting progress after each. */
export function runTunnelExperiment(
  o: TunnelExperimentOptions,
  progress?: (done: number, total: number) => void,
): TunnelRow[] {
  const rows: TunnelRow[] = [];
  const total = o.dts.length * o.walls.length * o.speeds.length;
  for (const dt of o.dts) {
    for (const wall of o.walls) {
      for (const speed of o.speeds) {
        const base = { speed, wall, radius: o.radius, dt };
        rows.push({
          discrete: measureTunnelling({ ...base, ccd: 'off' }, o.trials, o.seed),
          ccd: measureTunnelling({ ...base, ccd: 'auto' }, o.trials, o.seed),
        });
        progress?.(rows.length, total);
      }
    }
  }
  return rows;
}

const pct = (x: number) => `${(100 * x).toFixed(1)} %`;

export function formatTunnelTable(rows: readonly TunnelRow[]): string {
  const header = [
    'dt (s)',
    'wall (m)',
    'speed (m/s)',
    'v·dt (m)',
    "talk's rule",
    'theory',
    'discrete',
    'CCD',
  ];
  const cells = rows.map(({ discrete: d, ccd }) => [
    String(d.dt),
    String(d.wall),
    String(d.speed),
    (d.speed * d.dt).toPrecision(3),
    d.wall >= minWallSize(d.speed, d.dt) ? 'kept' : 'broken',
    pct(d.theory),
    pct(d.share),
    pct(ccd.share),
  ]);
  const widths = header.map((h, i) => Math.max(h.length, ...cells.map((c) => c[i]!.length)));
  const line = (c: string[]) => c.map((x, i) => x.padStart(widths[i]!)).join('  ');
  const trials = rows[0]?.discrete.trials ?? 0;
  const radius = rows[0]?.discrete.radius ?? 0;
  return [
    `Share of bodies (radius ${radius} m, ${trials} per cell) that end up on the far side of the wall`,
    '',
    line(header),
    widths.map((w) => '-'.repeat(w)).join('  '),
    ...cells.map(line),
    '',
  ].join('\n');
}

export function tunnelCsv(rows: readonly TunnelRow[]): string {
  const lines = ['dt,wall,speed,radius,trials,rule_kept,theory,discrete_share,ccd_share'];
  for (const { discrete: d, ccd } of rows) {
    lines.push(
      [
        d.dt,
        d.wall,
        d.speed,
        d.radius,
        d.trials,
        d.wall >= minWallSize(d.speed, d.dt),
        d.theory,
        d.share,
        ccd.share,
      ].join(','),
    );
  }
  return lines.join('\n') + '\n';
}
