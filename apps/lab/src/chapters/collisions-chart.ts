import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { RADIUS, SPEED, STEP_S, WALL, type SettingResult } from './collisions-lab.js';

/** What the chart shows besides its two fixed lines. */
export interface WallChartState {
  speed: number;
  wall: number;
  /** The variable-Δt panel's longest step so far, s (0: none yet). */
  variableMaxDt: number;
  /** Results of earlier settings and of the current one. */
  results: readonly SettingResult[];
}

export const CHART_COLORS = {
  rule: '#fbbf24',
  bounce: '#34d399',
  variable: '#f87171',
  current: '#fde047',
  none: '#34d399',
  some: '#e879f9',
} as const;

const AXIS: uPlot.Axis = {
  stroke: '#a3b3cc',
  font: '11px system-ui, sans-serif',
  labelFont: '600 11px system-ui, sans-serif',
  grid: { stroke: 'rgba(141, 160, 189, 0.12)', width: 1 },
  ticks: { show: false },
};

/**
 * Speed on x, wall thickness on y, for the fixed step: the talk's rule `w = v·dt` (thinner walls
 * can be jumped over unseen), the correct-bounce bound `w = 2·(v·dt − r)` (thinner walls may
 * push a body out through the far face), the variable-Δt panel's worst step as a dashed line,
 * the current setting and the measured share of earlier settings as points. Clicking the chart
 * picks a setting.
 */
export class WallChart {
  private readonly plot: uPlot;
  private state: WallChartState = { speed: 0, wall: 0, variableMaxDt: 0, results: [] };
  private lastKey = '';
  private readonly height: () => number;

  constructor(
    host: HTMLElement,
    width: number,
    onPick: (speed: number, wall: number) => void,
    height: () => number,
  ) {
    this.height = height;
    const xs = [0, RADIUS / STEP_S, SPEED.max];
    this.plot = new uPlot(
      {
        width: Math.max(200, width),
        height: height(),
        legend: { show: false },
        cursor: {
          show: true,
          x: true,
          y: true,
          points: { show: false },
          drag: { x: false, y: false },
        },
        select: { show: false, left: 0, top: 0, width: 0, height: 0 },
        scales: {
          x: { time: false, auto: false, range: [0, SPEED.max] },
          y: { auto: false, range: [0, WALL.max] },
        },
        axes: [
          {
            ...AXIS,
            label: 'Speed, m/s',
            size: 34,
            labelSize: 16,
            values: (_u, splits) => splits.map((v) => v.toFixed(0)),
          },
          {
            ...AXIS,
            label: 'Wall thickness, m',
            size: 34,
            labelSize: 18,
            values: (_u, splits) => splits.map((v) => v.toFixed(0)),
          },
        ],
        series: [
          {},
          {
            label: 'minWallSize = v·dt',
            stroke: CHART_COLORS.rule,
            width: 2,
            fill: 'rgba(248, 113, 113, 0.13)',
            points: { show: false },
          },
          {
            label: 'v·dt = w/2 + r',
            stroke: CHART_COLORS.bounce,
            width: 2,
            points: { show: false },
          },
          {
            label: 'v·Δt at the longest variable step',
            stroke: CHART_COLORS.variable,
            width: 1.5,
            dash: [6, 5],
            points: { show: false },
          },
        ],
        bands: [{ series: [2, 1], fill: 'rgba(251, 191, 36, 0.12)' }],
        hooks: {
          draw: [
            (u) => {
              this.drawMarks(u);
            },
          ],
        },
      },
      [xs, xs.map((v) => v * STEP_S), xs.map(() => 0), xs.map(() => null)],
      host,
    );
    this.plot.over.addEventListener('click', (event) => {
      const rect = this.plot.over.getBoundingClientRect();
      const speed = this.plot.posToVal(event.clientX - rect.left, 'x');
      const wall = this.plot.posToVal(event.clientY - rect.top, 'y');
      if (Number.isFinite(speed) && Number.isFinite(wall)) onPick(speed, wall);
    });
    this.plot.over.style.cursor = 'crosshair';
  }

  /** New marks and variable line; redraws only if something changed. */
  set(state: WallChartState): void {
    const last = state.results[state.results.length - 1];
    const key = `${state.speed}:${state.wall}:${state.variableMaxDt}:${state.results.length}:${last?.fixed.resolved ?? 0}:${last?.fixed.through ?? 0}`;
    if (key === this.lastKey) return;
    this.lastKey = key;
    this.state = state;
    const xs = [0, RADIUS / STEP_S, SPEED.max];
    const dtv = state.variableMaxDt;
    this.plot.setData([
      xs,
      xs.map((v) => v * STEP_S),
      xs.map((v) => Math.max(0, 2 * (v * STEP_S - RADIUS))),
      xs.map((v) => (dtv > 0 ? v * dtv : null)),
    ]);
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

  /** The settings tried (measured fixed-step share) and the current one, on the plot's canvas. */
  private drawMarks(u: uPlot): void {
    const ctx = u.ctx;
    const dpr = devicePixelRatio || 1;
    const { left, top, width, height } = u.bbox;
    ctx.save();
    ctx.beginPath();
    ctx.rect(left, top, width, height);
    ctx.clip();
    const X = (v: number) => u.valToPos(v, 'x', true);
    const Y = (v: number) => u.valToPos(v, 'y', true);
    for (const r of this.state.results) {
      const n = r.fixed.resolved;
      if (n === 0) continue;
      const share = r.fixed.through / n;
      ctx.beginPath();
      ctx.arc(X(r.speed), Y(r.wall), (3.5 + 5 * share) * dpr, 0, 2 * Math.PI);
      ctx.fillStyle = share > 0 ? CHART_COLORS.some : CHART_COLORS.none;
      ctx.globalAlpha = 0.85;
      ctx.fill();
      ctx.globalAlpha = 1;
      ctx.lineWidth = dpr;
      ctx.strokeStyle = '#0b1020';
      ctx.stroke();
    }
    // Name the three regions: two against the right edge, one against the left.
    ctx.font = `600 ${Math.round((width < 500 * dpr ? 10 : 11) * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    const vr = SPEED.max * 0.93;
    const rule = vr * STEP_S;
    const right = left + width - 8 * dpr;
    ctx.textAlign = 'right';
    ctx.fillStyle = 'rgba(252, 165, 165, 0.9)';
    ctx.fillText('can jump over unseen', right, Y(rule * 0.4));
    ctx.fillStyle = 'rgba(252, 211, 77, 0.9)';
    ctx.fillText('seen, some pushed through', right, Y(0.25 * rule + 0.75 * 2 * (rule - RADIUS)));
    ctx.textAlign = 'left';
    ctx.fillStyle = 'rgba(110, 231, 183, 0.9)';
    ctx.fillText('always bounces', left + 8 * dpr, Y(WALL.max * 0.6));
    const cx = X(this.state.speed);
    const cy = Y(this.state.wall);
    ctx.strokeStyle = CHART_COLORS.current;
    ctx.lineWidth = 1.5 * dpr;
    ctx.setLineDash([3 * dpr, 3 * dpr]);
    ctx.beginPath();
    ctx.moveTo(cx, top + height);
    ctx.lineTo(cx, cy);
    ctx.lineTo(left, cy);
    ctx.globalAlpha = 0.5;
    ctx.stroke();
    ctx.globalAlpha = 1;
    ctx.setLineDash([]);
    ctx.beginPath();
    ctx.arc(cx, cy, 7 * dpr, 0, 2 * Math.PI);
    ctx.lineWidth = 2.5 * dpr;
    ctx.stroke();
    ctx.restore();
  }
}
