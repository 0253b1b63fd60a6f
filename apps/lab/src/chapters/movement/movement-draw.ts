/**
 * Chapter 2's drawing: each loop's runs of the jump traced over each other, one line per display
 * (widest for 30 Hz, thinnest for 240 Hz), the apex and landing marks of the jump in the table, and
 * the runners on top as nested discs.
 */
import { sceneView, type SceneCanvas } from '../../ui/canvas.js';
import { rateColor } from '../../ui/readout.js';
import type { Track } from './movement-lab.js';

/** The world the canvases show, metres: the run-up, the jump, the landing strip under the floor. */
const VIEW = { x0: 0, x1: 8.4, y0: -0.56, y1: 2.05 };
/** Line widths (CSS px) per display, widest first, so coinciding lines show as nested stripes. */
export const WIDTHS: Readonly<Record<string, number>> = {
  30: 8,
  60: 5.5,
  144: 3.4,
  240: 1.6,
  real: 1,
};

/** The tracks of one loop at `atMs`, with the marks of jump `jumpIndex` (−1: none yet). */
export function drawJumps(
  sc: SceneCanvas,
  tracks: readonly Track[],
  jumpIndex: number,
  atMs: number,
  interpolate: boolean,
): void {
  const view = sceneView(sc, VIEW);
  if (!view) return;
  const { ctx, dpr } = sc;
  const px = (x: number) => view.px(x);
  const py = (y: number) => view.py(y);
  view.grid(ctx, 0.5);
  // Ground and the landing strip under it.
  view.ground(ctx, dpr, 'rgba(141, 160, 189, 0.06)');
  ctx.fillStyle = 'rgba(163, 179, 204, 0.75)';
  ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
  ctx.textBaseline = 'middle';
  ctx.fillText('landings', px(VIEW.x0) + 6 * dpr, py(-0.25));
  // Scale bar: 1 m.
  const sx = px(VIEW.x1) - 10 * dpr - view.scale;
  const sy = py(VIEW.y1) + 12 * dpr;
  ctx.strokeStyle = 'rgba(163, 179, 204, 0.7)';
  ctx.beginPath();
  ctx.moveTo(sx, sy);
  ctx.lineTo(sx + view.scale, sy);
  ctx.moveTo(sx, sy - 3 * dpr);
  ctx.lineTo(sx, sy + 3 * dpr);
  ctx.moveTo(sx + view.scale, sy - 3 * dpr);
  ctx.lineTo(sx + view.scale, sy + 3 * dpr);
  ctx.stroke();
  ctx.textAlign = 'center';
  ctx.fillText('1 m', sx + view.scale / 2, sy + 10 * dpr);
  ctx.textAlign = 'start';

  ctx.lineJoin = 'round';
  ctx.lineCap = 'round';
  const rowH = 0.095;
  const runners = tracks.map((t) => t.runnerAt(atMs, interpolate));
  tracks.forEach((t, i) => {
    const color = rateColor(t.source);
    const width = (WIDTHS[String(t.source)] ?? 1) * dpr;
    const runner = runners[i]!;
    // The path of this round, up to where the runner is drawn.
    const p = t.path;
    ctx.strokeStyle = color;
    ctx.globalAlpha = 0.92;
    ctx.lineWidth = width;
    ctx.beginPath();
    if (runner.points > 0) {
      ctx.moveTo(px(p[1]!), py(p[2]!));
      for (let k = 1; k < runner.points; k++) ctx.lineTo(px(p[3 * k + 1]!), py(p[3 * k + 2]!));
      ctx.lineTo(px(runner.x), py(runner.y));
    }
    ctx.stroke();
    ctx.globalAlpha = 1;
    // Apex and landing of the jump shown in the table.
    const j = jumpIndex >= 0 ? t.jump(jumpIndex) : undefined;
    if (j) {
      ctx.lineWidth = width;
      ctx.beginPath();
      ctx.moveTo(px(j.apexX) - 7 * dpr, py(j.apex));
      ctx.lineTo(px(j.apexX) + 7 * dpr, py(j.apex));
      ctx.stroke();
      const y = -0.05 - i * rowH;
      ctx.lineWidth = Math.max(2, 3 * dpr);
      ctx.lineCap = 'butt';
      ctx.beginPath();
      ctx.moveTo(px(j.landingX), py(y));
      ctx.lineTo(px(j.landingX), py(y - rowH * 0.8));
      ctx.stroke();
      ctx.lineCap = 'round';
    }
  });
  drawRunnerDiscs(
    sc,
    tracks.map((t, i) => ({
      color: rateColor(t.source),
      x: px(runners[i]!.x),
      y: py(runners[i]!.y),
      radius: (WIDTHS[String(t.source)] ?? 1) + 3.5,
    })),
  );
}

/**
 * The runners on top, as nested discs (where they coincide they look like a target): each at
 * (x, y) on the canvas, `radius` CSS px, in `color`.
 */
export function drawRunnerDiscs(
  sc: SceneCanvas,
  runners: readonly { color: string; x: number; y: number; radius: number }[],
): void {
  const { ctx, dpr } = sc;
  for (const r of runners) {
    ctx.fillStyle = r.color;
    ctx.strokeStyle = '#0a1122';
    ctx.lineWidth = Math.max(1, dpr);
    ctx.beginPath();
    ctx.arc(r.x, r.y, r.radius * dpr, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
  }
}
