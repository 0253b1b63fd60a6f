import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { BRIGHT_AXIS } from '../../ui/chart.js';
import type { EnergyHistory } from './physics-lab.js';

/** The plot never goes beyond these energy ratios (an exploded lane stops at 1e9). */
const FLOOR = 1e-9;
const CEIL = 1e10;

/** Powers of ten as labels: 1e-3 → "10⁻³", 1 → "1", 1000 → "10³". */
export function decade(v: number | null): string {
  // uPlot hands a log axis null for the splits its filter hides.
  if (v === null || !(v > 0)) return '';
  const e = Math.round(Math.log10(v));
  if (Math.abs(Math.log10(v) - e) > 1e-9) return '';
  if (e === 0) return '1';
  if (e === 1) return '10';
  const sup = String(e)
    .replace('-', '⁻')
    .replace(/[0-9]/g, (d) => '⁰¹²³⁴⁵⁶⁷⁸⁹'[Number(d)]!);
  return `10${sup}`;
}

/**
 * E/E₀ of every method over simulated time, log scale: explicit Euler is a straight line up
 * (×(1 + (ω·dt)²) per step), backward Euler a straight line down, the symplectic methods wobble
 * around 1, RK4 sinks very slowly.
 */
export class EnergyChart {
  private readonly plot: uPlot;
  private lastKey = '';
  private yRange: [number, number] = [0.1, 10];
  private xMax = 10;
  private readonly height: () => number;

  constructor(
    host: HTMLElement,
    width: number,
    labels: readonly string[],
    colors: readonly string[],
    height: () => number,
  ) {
    this.height = height;
    this.plot = new uPlot(
      {
        width: Math.max(200, width),
        height: height(),
        legend: { show: false },
        cursor: { show: false },
        select: { show: false, left: 0, top: 0, width: 0, height: 0 },
        scales: {
          x: { time: false, auto: false, range: () => [0, this.xMax] },
          // uPlot's Distr is an ambient const enum, unreachable under isolatedModules: 3 is its
          // Logarithmic.
          // eslint-disable-next-line @typescript-eslint/no-unsafe-enum-assignment
          y: { distr: 3, log: 10, auto: false, range: () => this.yRange },
        },
        axes: [
          {
            ...BRIGHT_AXIS,
            label: 'Simulated time, s',
            size: 34,
            labelSize: 16,
            values: (_u, splits) =>
              splits.map((v) => (Number.isInteger(v) ? v.toFixed(0) : v.toFixed(1))),
          },
          {
            ...BRIGHT_AXIS,
            label: 'Energy E / E₀',
            size: 52,
            labelSize: 16,
            // Decades only (every second or third when there are many).
            splits: (_u, _i, min, max) => {
              const lo = Math.round(Math.log10(min));
              const hi = Math.round(Math.log10(max));
              const by = Math.max(1, Math.ceil((hi - lo) / 8));
              const out: number[] = [];
              for (let e = lo; e <= hi; e += by) out.push(10 ** e);
              return out;
            },
            values: (_u, splits) => splits.map((v) => decade(v as number | null)),
          },
        ],
        series: [
          {},
          ...labels.map((label, i): uPlot.Series => ({
            label,
            stroke: colors[i] ?? '#38bdf8',
            width: 1.75,
            points: { show: false },
          })),
        ],
      },
      [[], ...labels.map(() => [])],
      host,
    );
  }

  /** Redraw from the history if it changed; the x axis spans at least 10 s. */
  set(history: EnergyHistory, nowS: number): void {
    const n = history.t.length;
    const key = `${n}:${history.t[n - 1] ?? 0}:${history.series.length}`;
    if (key === this.lastKey) return;
    this.lastKey = key;
    let lo = 0.5;
    let hi = 2;
    const series = history.series.map((s) =>
      s.map((v) => {
        const c = Number.isFinite(v) ? Math.min(CEIL, Math.max(FLOOR, v)) : CEIL;
        if (c < lo) lo = c;
        if (c > hi) hi = c;
        return c;
      }),
    );
    this.yRange = [10 ** Math.floor(Math.log10(lo)), 10 ** Math.ceil(Math.log10(hi))];
    this.xMax = Math.max(10, Math.ceil(nowS));
    this.plot.batch(() => {
      this.plot.setData([history.t.slice(), ...series], false);
      this.plot.setScale('x', { min: 0, max: this.xMax });
      this.plot.setScale('y', { min: this.yRange[0], max: this.yRange[1] });
    });
  }

  resize(width: number): void {
    const height = this.height();
    if (width > 0 && (Math.abs(width - this.plot.width) > 1 || height !== this.plot.height)) {
      this.plot.setSize({ width, height });
    }
  }

  destroy(): void {
    this.plot.destroy();
  }
}
