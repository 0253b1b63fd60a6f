import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';
import { BRIGHT_AXIS } from '../../ui/chart.js';
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

/**
 * The scales reach a little past the sliders' ends, so a setting at 150 m/s or an 8 m wall is a
 * whole dot, not half of one clipped at the plot's edge.
 */
const X_MAX = SPEED.max * 1.05;
const Y_MAX = WALL.max * 1.05;

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
    const xs = [0, RADIUS / STEP_S, X_MAX];
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
          // No drag: a press and release is always a click that picks a setting. (uPlot would
          // otherwise take a click whose rect went stale as a drag and swallow it.)
          drag: { x: false, y: false, setScale: false, click: () => undefined },
        },
        select: { show: false, left: 0, top: 0, width: 0, height: 0 },
        scales: {
          x: { time: false, auto: false, range: [0, X_MAX] },
          y: { auto: false, range: [0, Y_MAX] },
        },
        axes: [
          {
            ...BRIGHT_AXIS,
            label: 'Speed, m/s',
            size: 34,
            labelSize: 16,
            // Ticks inside the sliders' range only (the scale runs 5 % past it).
            splits: () => [0, 25, 50, 75, 100, 125, 150].filter((v) => v <= SPEED.max),
            values: (_u, splits) => splits.map((v) => v.toFixed(0)),
          },
          {
            ...BRIGHT_AXIS,
            label: 'Wall thickness, m',
            splits: () => [0, 2, 4, 6, 8].filter((v) => v <= WALL.max),
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
    // The page above the chart can change height; measure the plot afresh on every press.
    const sync = () => {
      this.plot.syncRect();
    };
    this.plot.over.addEventListener('pointerenter', sync);
    this.plot.over.addEventListener('pointerdown', sync);
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
    const xs = [0, RADIUS / STEP_S, X_MAX];
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

  /** The page moved or changed size around the chart: let uPlot measure it again. */
  syncRect(): void {
    this.plot.syncRect(true);
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
    ctx.setLineDash([]);
    const X = (v: number) => u.valToPos(v, 'x', true);
    const Y = (v: number) => u.valToPos(v, 'y', true);

    // Name the three regions where each fits, clear of the lines that bound it.
    const rule: Line = (v) => v * STEP_S;
    const bounce: Line = (v) => 2 * (v * STEP_S - RADIUS);
    const dtv = this.state.variableMaxDt;
    const dashed: Line[] = dtv > 0 ? [(v) => v * dtv] : [];
    const size = width < 500 * dpr ? 10 : 11;
    ctx.font = `600 ${Math.round(size * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    ctx.textAlign = 'left';
    const area: Area = { u, ctx, dpr, lineH: Math.round((size + 3) * dpr) };
    const label = (texts: string[][], color: string, fit: Fit) => {
      // Clear of every line if it can be; else across the dashed line (the halo keeps it
      // readable), but never across the lines that bound its region.
      const fits = [fit, { ...fit, avoid: [] }];
      for (const [lines, f] of fits.flatMap((f) => texts.map((t) => [t, f] as const))) {
        const at = placeLabel(area, lines, f);
        if (!at) continue;
        ctx.lineJoin = 'round';
        ctx.lineWidth = 3 * dpr;
        ctx.strokeStyle = 'rgba(17, 24, 39, 0.8)';
        ctx.fillStyle = color;
        lines.forEach((line, i) => {
          const y = at.y + (i + 0.5) * area.lineH;
          ctx.strokeText(line, at.x, y);
          ctx.fillText(line, at.x, y);
        });
        return;
      }
      // Nowhere to fit: the chart's legend names the region.
    };
    label([['can jump over unseen'], ['can jump', 'over unseen']], 'rgba(252, 165, 165, 0.95)', {
      above: [rule],
      below: [],
      avoid: dashed,
      from: 'right',
    });
    label(
      [['seen, some pushed through'], ['seen, some', 'pushed through']],
      'rgba(252, 211, 77, 0.95)',
      {
        above: [bounce],
        below: [rule],
        avoid: dashed,
        from: 'right',
      },
    );
    label([['always bounces'], ['always', 'bounces']], 'rgba(110, 231, 183, 0.95)', {
      above: [],
      below: [bounce],
      avoid: dashed,
      from: 'left',
    });

    // Settings tried: a dot each, with a ring so it stands out on the lines.
    for (const r of this.state.results) {
      const n = r.fixed.resolved;
      if (n === 0) continue;
      const share = r.fixed.through / n;
      const x = X(r.speed);
      const y = Y(r.wall);
      const radius = (5.5 + 5 * share) * dpr;
      ctx.beginPath();
      ctx.arc(x, y, radius, 0, 2 * Math.PI);
      ctx.fillStyle = share > 0 ? CHART_COLORS.some : CHART_COLORS.none;
      ctx.fill();
      ctx.lineWidth = 2 * dpr;
      ctx.strokeStyle = '#0b1020';
      ctx.stroke();
      ctx.beginPath();
      ctx.arc(x, y, radius + 1.75 * dpr, 0, 2 * Math.PI);
      ctx.lineWidth = 1.5 * dpr;
      ctx.strokeStyle = 'rgba(255, 255, 255, 0.9)';
      ctx.stroke();
    }

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
    ctx.arc(cx, cy, 9 * dpr, 0, 2 * Math.PI);
    ctx.lineWidth = 2.5 * dpr;
    ctx.stroke();
    ctx.restore();
  }
}

/** A line of the chart: wall thickness (m) as a function of speed (m/s), increasing. */
type Line = (speed: number) => number;

/** Where a region's label may go: lines that must pass above it, below it, and not through it. */
interface Fit {
  above: Line[];
  below: Line[];
  avoid: Line[];
  /** Which side of the chart to try first. */
  from: 'left' | 'right';
}

interface Area {
  u: uPlot;
  ctx: CanvasRenderingContext2D;
  dpr: number;
  /** Height of one line of text, canvas px. */
  lineH: number;
}

/**
 * The top-left corner (canvas px) of a box for `lines` inside the plot that no line of `fit`
 * crosses, with the `above` lines above it and the `below` lines below it; the first position
 * from `fit.from` that has room, centred in the room it has there. Undefined if none.
 */
function placeLabel(area: Area, lines: string[], fit: Fit): { x: number; y: number } | undefined {
  const { u, ctx, dpr, lineH } = area;
  const { left, top, width, height } = u.bbox;
  const pad = 5 * dpr;
  const boxW = Math.max(...lines.map((l) => ctx.measureText(l).width));
  const boxH = lines.length * lineH;
  if (boxW + 2 * pad > width || boxH + 2 * pad > height) return undefined;
  // Canvas px ↔ values: both scales are linear and fixed.
  const speedAt = (x: number) => ((x - left) / width) * X_MAX;
  const yOf = (wall: number) => top + height - (wall / Y_MAX) * height;
  const stepX = 4 * dpr;
  const stepY = 2 * dpr;
  const xs: number[] = [];
  for (let x = left + pad; x + boxW <= left + width - pad; x += stepX) xs.push(x);
  if (fit.from === 'right') xs.reverse();
  for (const x0 of xs) {
    const v0 = speedAt(x0 - pad);
    const v1 = speedAt(x0 + boxW + pad);
    // A line over [v0, v1] runs from pixel y `lo` (at v1, highest) to `hi` (at v0, lowest).
    const span = (f: Line) => ({ lo: yOf(f(v1)), hi: yOf(f(v0)) });
    const above = fit.above.map(span);
    const below = fit.below.map(span);
    const avoid = fit.avoid.map(span);
    let best: { start: number; n: number } | undefined;
    let run: { start: number; n: number } | undefined;
    for (let y0 = top + pad; y0 + boxH <= top + height - pad; y0 += stepY) {
      const y1 = y0 + boxH;
      const ok =
        above.every((l) => l.hi < y0 - pad) &&
        below.every((l) => l.lo > y1 + pad) &&
        avoid.every((l) => l.hi < y0 - pad || l.lo > y1 + pad);
      if (ok) {
        run = run ? { start: run.start, n: run.n + 1 } : { start: y0, n: 1 };
        if (!best || run.n > best.n) best = run;
      } else run = undefined;
    }
    if (best) return { x: x0, y: best.start + ((best.n - 1) * stepY) / 2 };
  }
  return undefined;
}
