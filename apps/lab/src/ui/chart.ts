import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { h } from './dom.js';
import { deferWrite, dropWrite, writesHeld, type PendingWrite } from './write-phase.js';

/** One line of a {@link Chart}. */
export interface ChartSeries {
  label: string;
  color: string;
  /** Line width in CSS pixels. Default 1.75. */
  width?: number;
  dash?: number[];
  /** Draw as steps (a value holds until the next one). */
  stepped?: boolean;
  /** Fill under the line with a faint version of its colour. */
  fill?: boolean;
  /** Draw a dot at each point (with this radius in CSS px). */
  points?: number;
  /** Break the line where values are missing (null), instead of joining across. Default true. */
  gaps?: boolean;
}

export interface ChartAxis {
  /** Tick labels. */
  format?: (v: number) => string;
  /** Axis title, drawn small. */
  label?: string;
  /** A fixed range, or a function of the data's min and max. */
  range?: [number, number] | ((min: number, max: number) => [number, number]);
  /** 'linear' (default), 'log' (base 10) or 'asinh' (log-like, but 0 is fine). */
  scale?: 'linear' | 'log' | 'asinh';
  /** Reserved space for the tick labels, px. */
  size?: number;
  /** Where the ticks go, or a function of the scale's range (default: uPlot chooses). */
  splits?: number[] | ((min: number, max: number) => number[]);
}

export interface ChartOptions {
  /** Height in CSS px. */
  height: number;
  x: ChartAxis;
  y: ChartAxis;
  series: ChartSeries[];
  /** What the chart shows, for screen readers. */
  label: string;
  /** Show an HTML legend (colour chip + label) under the chart. Default true. */
  legend?: boolean;
}

/**
 * The axes of the chapters' own uPlot charts (a scatter, an energy plot on a log scale): a little
 * brighter than {@link Chart}'s, with bold titles.
 */
export const BRIGHT_AXIS: uPlot.Axis = {
  stroke: '#a3b3cc',
  font: '11px system-ui, sans-serif',
  labelFont: '600 11px system-ui, sans-serif',
  grid: { stroke: 'rgba(141, 160, 189, 0.12)', width: 1 },
  ticks: { show: false },
};

const AXIS: uPlot.Axis = {
  stroke: '#8da0bd',
  font: '11px system-ui, sans-serif',
  labelFont: '11px system-ui, sans-serif',
  grid: { stroke: 'rgba(141, 160, 189, 0.13)', width: 1 },
  ticks: { show: false },
  gap: 4,
};

/**
 * A thin wrapper over uPlot for the lab's dark theme: lines or steps on linear, log or asinh
 * scales, an HTML legend, and a width that follows its host. `set` replaces all the data.
 */
export class Chart implements PendingWrite {
  readonly el: HTMLElement;
  private readonly host: HTMLElement;
  private plot: uPlot | undefined;
  private readonly observer: ResizeObserver;
  private data: uPlot.AlignedData;
  private lastKey = '';

  constructor(private readonly options: ChartOptions) {
    this.host = h('div', { class: 'chart-plot' });
    this.el = h(
      'figure',
      { class: 'chart-figure', role: 'img', 'aria-label': options.label },
      this.host,
      options.legend === false
        ? null
        : h(
            'figcaption',
            { class: 'chart-legend', 'aria-hidden': 'true' },
            options.series.map((s) =>
              h(
                'span',
                { class: 'legend-item', style: `--chip: ${s.color}` },
                h('span', {
                  class: s.dash ? 'legend-chip dashed' : 'legend-chip',
                  'aria-hidden': 'true',
                }),
                s.label,
              ),
            ),
          ),
    );
    this.data = [[], ...options.series.map(() => [])];
    // The width comes from the observer (no layout read in a frame); the plot is made once known.
    this.observer = new ResizeObserver((entries) => {
      const entry = entries[entries.length - 1];
      if (entry) this.width = Math.floor(entry.contentRect.width);
      this.fit();
    });
    this.observer.observe(this.host);
  }

  private width = 0;

  /**
   * Replace the data: `[xs, ys1, ys2, …]`; nulls are gaps. Redraws only if `key` changed; inside
   * an animation frame the shell holds, with the next due frame (write-phase.ts).
   */
  set(data: (number | null)[][], key?: string): void {
    if (key !== undefined) {
      if (key === this.lastKey) return;
      this.lastKey = key;
    }
    this.data = data as uPlot.AlignedData;
    if (writesHeld()) deferWrite(this, 'chart');
    else this.flushWrite();
  }

  /** Draw the newest data. */
  flushWrite(): void {
    dropWrite(this);
    const plot = this.plot;
    // Drawn at once (uPlot's immediate mode), while the page's style is still clean.
    if (plot) {
      plot.batch(() => {
        plot.setData(this.data);
      });
    } else this.fit();
  }

  destroy(): void {
    dropWrite(this);
    this.observer.disconnect();
    this.plot?.destroy();
    this.plot = undefined;
  }

  private fit(): void {
    const width = this.width;
    if (width <= 0) return;
    if (!this.plot) {
      this.plot = new uPlot(this.config(width), this.data, this.host);
    } else if (Math.abs(width - this.plot.width) > 1) {
      this.plot.setSize({ width, height: this.options.height });
    }
  }

  private config(width: number): uPlot.Options {
    const o = this.options;
    const scale = (a: ChartAxis, isX: boolean): uPlot.Scale => {
      const s: uPlot.Scale = { time: isX ? false : undefined, auto: a.range === undefined };
      // uPlot's Distr is an ambient const enum, which isolatedModules cannot reference.
      if (a.scale === 'log') {
        // eslint-disable-next-line @typescript-eslint/no-unsafe-enum-assignment
        s.distr = 3;
        s.log = 10;
      } else if (a.scale === 'asinh') {
        // eslint-disable-next-line @typescript-eslint/no-unsafe-enum-assignment
        s.distr = 4;
        s.asinh = 1;
      }
      const r = a.range;
      if (typeof r === 'function') {
        s.auto = true;
        s.range = (_u, min, max) => r(min, max);
      } else if (r) {
        s.range = () => r;
      }
      return s;
    };
    const axis = (a: ChartAxis): uPlot.Axis => {
      const ax: uPlot.Axis = { ...AXIS, size: a.size ?? 34 };
      const splits = a.splits;
      if (splits) {
        ax.splits = (u, axisIdx) => {
          if (typeof splits !== 'function') return splits;
          const scale = u.scales[axisIdx === 0 ? 'x' : 'y'];
          return splits(scale?.min ?? 0, scale?.max ?? 1);
        };
        ax.filter = (_u, sp) => sp; // uPlot thins log-scale labels to powers of ten otherwise
      }
      const f = a.format;
      if (f) ax.values = (_u, splits) => splits.map((v) => f(v));
      if (a.label) {
        ax.label = a.label;
        ax.labelSize = 16;
        ax.labelGap = 0;
      }
      return ax;
    };
    return {
      width,
      height: o.height,
      legend: { show: false },
      cursor: { show: false },
      select: { show: false, left: 0, top: 0, width: 0, height: 0 },
      scales: { x: scale(o.x, true), y: scale(o.y, false) },
      axes: [axis(o.x), axis(o.y)],
      series: [
        {},
        ...o.series.map((s): uPlot.Series => ({
          label: s.label,
          stroke: s.color,
          width: s.width ?? 1.75,
          dash: s.dash,
          fill: s.fill ? `${s.color}2e` : undefined,
          spanGaps: s.gaps === false,
          paths: s.stepped ? uPlot.paths.stepped!({ align: 1 }) : undefined,
          points: s.points
            ? { show: true, size: s.points * 2, fill: s.color, stroke: s.color }
            : { show: false },
        })),
      ],
    };
  }
}

/**
 * Joins series sampled at different x values into uPlot's aligned form: one sorted x array, and
 * per series its value at its own x values and null elsewhere (draw them with `gaps: false`).
 */
export function alignSeries(
  series: readonly { xs: readonly number[]; ys: readonly number[] }[],
): (number | null)[][] {
  const all = new Set<number>();
  for (const s of series) for (const x of s.xs) all.add(x);
  const xs = [...all].sort((a, b) => a - b);
  const index = new Map<number, number>();
  xs.forEach((x, i) => index.set(x, i));
  const out: (number | null)[][] = [xs];
  for (const s of series) {
    const ys = new Array<number | null>(xs.length).fill(null);
    s.xs.forEach((x, i) => {
      ys[index.get(x)!] = s.ys[i] ?? null;
    });
    out.push(ys);
  }
  return out;
}
