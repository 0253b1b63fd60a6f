import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { deferWrite, dropWrite, writesHeld, type PendingWrite } from './write-phase.js';

/**
 * Whole-number ticks from 0 to `max`: every integer up to 4, else steps of 1, 2 or 5 × 10ⁿ so
 * there are at most four intervals.
 */
export function integerTicks(max: number): number[] {
  if (!(max > 0)) return [0];
  let step = 1;
  for (const k of [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000]) {
    step = k;
    if (max / k <= 4) break;
  }
  const out: number[] = [];
  for (let v = 0; v <= max + 1e-9; v += step) out.push(v);
  return out;
}

/**
 * A small stepped chart of updates per display frame over a sliding window of virtual time.
 * The x range is set by the caller, so every panel shows the same window.
 */
export class StepsChart implements PendingWrite {
  private readonly plot: uPlot;
  private xs: number[] = [];
  private ys: number[] = [];
  private window: [number, number] = [-3, 0];
  private lastKey = '';

  constructor(host: HTMLElement, color: string, width: number) {
    const axis: uPlot.Axis = {
      stroke: '#8da0bd',
      font: '10px system-ui, sans-serif',
      grid: { stroke: 'rgba(141, 160, 189, 0.12)', width: 1 },
      ticks: { show: false },
      size: 22,
      gap: 3,
    };
    this.plot = new uPlot(
      {
        width: Math.max(120, width),
        height: 84,
        legend: { show: false },
        cursor: { show: false },
        select: { show: false, left: 0, top: 0, width: 0, height: 0 },
        scales: {
          x: { time: false, auto: false, range: () => this.window },
          y: { auto: true, range: (_u, _min, max) => [0, Math.max(2, Math.ceil(max * 1.1))] },
        },
        axes: [
          { ...axis, values: (_u, splits) => splits.map((v) => `${v.toFixed(0)} s`) },
          {
            ...axis,
            size: 30,
            // Whole steps only, from 0 up to the top of the scale, so every chart has a y scale.
            splits: (_u, _axis, _min, max) => integerTicks(max),
            values: (_u, splits) => splits.map((v) => v.toFixed(0)),
          },
        ],
        series: [
          {},
          {
            stroke: color,
            width: 1.5,
            fill: `${color}33`,
            paths: uPlot.paths.stepped!({ align: 1 }),
            points: { show: false },
          },
        ],
      },
      [[], []],
      host,
    );
  }

  /**
   * Replace the data (x in seconds) and the window; redraws only if something changed, inside an
   * animation frame the shell holds with the next due frame (write-phase.ts).
   */
  set(xs: number[], ys: number[], from: number, to: number): void {
    const key = `${xs.length}:${xs[xs.length - 1] ?? 0}:${from}`;
    if (key === this.lastKey) return;
    this.lastKey = key;
    this.xs = xs;
    this.ys = ys;
    this.window = [from, to];
    if (writesHeld()) deferWrite(this, 'chart');
    else this.flushWrite();
  }

  /** Draw the newest data. */
  flushWrite(): void {
    dropWrite(this);
    // Drawn at once (uPlot's immediate mode), while the page's style is still clean.
    this.plot.batch(() => {
      this.plot.setData([this.xs, this.ys]);
    });
  }

  resize(width: number): void {
    if (width > 0 && Math.abs(width - this.plot.width) > 1) {
      this.plot.setSize({ width, height: 84 });
    }
  }

  destroy(): void {
    dropWrite(this);
    this.plot.destroy();
  }
}
