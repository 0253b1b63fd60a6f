/**
 * Chapter 4's drawing: a lane (the spring as a mass on a coil, and its phase portrait against the
 * exact orbit, zoomed out as far as the trace has gone) and the rope with its pokes.
 */
import type { Rope } from '@fixedstep/games';
import { clearScene, type SceneCanvas } from '../../ui/canvas.js';
import { COLORS, zoomText } from './physics-text.js';
import { X0, type PhysicsRun } from './physics-lab.js';

/** The oscillator panel: the column of the spring shows ±this many metres. */
const SPRING_VIEW = 1.6;
/** The rope view, metres: centre and half extents. */
export const ROPE_VIEW = { cx: 0, cy: -1.1, hw: 4.2, hh: 2.4 };

/** Lane `k` of `run` (drawn at `alpha` between its last two steps) in `color`. */
export function drawLane(
  sc: SceneCanvas,
  run: PhysicsRun,
  k: number,
  color: string,
  alpha: number,
): void {
  const lane = run.race.lanes[k];
  if (!lane) return;
  const race = run.race;
  // --- the canvas: a spring column on the left, the phase portrait on the right.
  if (!sc.fit()) return;
  const { ctx, w, h: hh, dpr } = sc;
  clearScene(sc);
  const x = lane.prevX + (lane.state.x[0]! - lane.prevX) * alpha;
  const v = lane.prevV + (lane.state.v[0]! - lane.prevV) * alpha;
  const omega = race.omega;

  // Zoom out as far as the trace has gone, so an exploding spring stays in view: the dashed
  // exact orbit then shrinks in the middle of the spiral.
  const trails = run.trails;
  const n = trails.size;
  const vs = omega > 0 ? 1 / omega : 1;
  let reach = Math.hypot(x, v * vs);
  for (let j = 0; j < n; j++) {
    const r = Math.hypot(trails.x(k, j), trails.v(k, j) * vs);
    if (r > reach) reach = r;
  }
  const zoom = Number.isFinite(reach) ? Math.max(1, reach / X0) : 1e12;

  // Spring column.
  const colW = Math.round(w * 0.3);
  const cx = colW / 2;
  const top = 8 * dpr;
  const mid = hh / 2;
  const scale = (hh / 2 - 14 * dpr) / (SPRING_VIEW * zoom);
  ctx.fillStyle = 'rgba(141, 160, 189, 0.35)';
  ctx.fillRect(cx - colW * 0.3, top - 3 * dpr, colW * 0.6, 3 * dpr);
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.25)';
  ctx.setLineDash([3 * dpr, 3 * dpr]);
  ctx.beginPath();
  ctx.moveTo(cx - colW * 0.35, mid);
  ctx.lineTo(cx + colW * 0.35, mid);
  ctx.stroke();
  ctx.setLineDash([]);
  const boxH = Math.max(10 * dpr, hh * 0.09);
  const yMass = mid + clamp(x, -SPRING_VIEW * zoom, SPRING_VIEW * zoom) * scale;
  // Zig-zag from the ceiling to the mass.
  const coils = 9;
  const springTop = top;
  const springBottom = Math.max(springTop + 2 * dpr, yMass - boxH / 2);
  ctx.strokeStyle = color;
  ctx.lineWidth = 1.5 * dpr;
  ctx.beginPath();
  ctx.moveTo(cx, springTop);
  const amp = colW * 0.16;
  for (let i = 1; i <= 2 * coils; i++) {
    const yy = springTop + ((springBottom - springTop) * i) / (2 * coils + 1);
    ctx.lineTo(cx + (i % 2 === 0 ? -amp : amp), yy);
  }
  ctx.lineTo(cx, springBottom);
  ctx.stroke();
  ctx.fillStyle = color;
  ctx.fillRect(cx - colW * 0.22, springBottom, colW * 0.44, boxH);

  // Phase portrait.
  const px0 = colW;
  const pw = w - colW;
  const pcx = px0 + pw / 2;
  const pcy = hh / 2;
  const R = (Math.min(pw, hh) * 0.4) / zoom;
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.18)';
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(px0 + 6 * dpr, pcy);
  ctx.lineTo(w - 6 * dpr, pcy);
  ctx.moveTo(pcx, 6 * dpr);
  ctx.lineTo(pcx, hh - 6 * dpr);
  ctx.stroke();
  ctx.strokeStyle = 'rgba(226, 232, 240, 0.55)';
  ctx.setLineDash([4 * dpr, 4 * dpr]);
  ctx.beginPath();
  ctx.arc(pcx, pcy, R * X0, 0, 2 * Math.PI);
  ctx.stroke();
  ctx.setLineDash([]);
  ctx.save();
  ctx.beginPath();
  ctx.rect(px0, 0, pw, hh);
  ctx.clip();
  ctx.strokeStyle = color;
  ctx.lineWidth = 1.5 * dpr;
  ctx.beginPath();
  for (let j = 0; j < n; j++) {
    const tx = pcx + clamp(trails.x(k, j) * R, -w, w);
    const ty = pcy - clamp(trails.v(k, j) * vs * R, -hh, hh);
    if (j === 0) ctx.moveTo(tx, ty);
    else ctx.lineTo(tx, ty);
  }
  ctx.globalAlpha = 0.8;
  ctx.stroke();
  ctx.globalAlpha = 1;
  const dx = pcx + clamp(x * R, -w, w);
  const dy = pcy - clamp(v * vs * R, -hh, hh);
  ctx.fillStyle = '#ffffff';
  ctx.beginPath();
  ctx.arc(dx, dy, 3.5 * dpr, 0, 2 * Math.PI);
  ctx.fill();
  ctx.restore();
  ctx.fillStyle = 'rgba(163, 179, 204, 0.8)';
  ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
  ctx.textAlign = 'right';
  ctx.textBaseline = 'bottom';
  ctx.fillText('x', w - 5 * dpr, pcy - 2 * dpr);
  ctx.textAlign = 'left';
  ctx.textBaseline = 'top';
  ctx.fillText('v/ω', pcx + 4 * dpr, 4 * dpr);
  if (zoom > 1.25) {
    ctx.fillStyle = '#fcd34d';
    ctx.textBaseline = 'bottom';
    ctx.fillText(`zoomed out ×${zoomText(zoom)}`, 5 * dpr, hh - 4 * dpr);
  }
}

/** A poke to draw: on which bead, which way, and when (virtual ms). */
export interface DrawnPoke {
  bead: number;
  dvx: number;
  dvy: number;
  atMs: number;
}

/** The rope at `alpha`, the selected bead, the last poke fading, a drag in progress. */
export function drawRope(
  sc: SceneCanvas,
  rope: Rope,
  alpha: number,
  tMs: number,
  selected: number,
  lastPoke: DrawnPoke | undefined,
  drag: { bead: number; x0: number; y0: number; x: number; y: number } | undefined,
): void {
  const pos = { x: 0, y: 0 };
  if (!sc.fit()) return;
  const { ctx, w, h: hh, dpr } = sc;
  const scale = Math.min(w / (2 * ROPE_VIEW.hw), hh / (2 * ROPE_VIEW.hh));
  const X = (x: number) => w / 2 + (x - ROPE_VIEW.cx) * scale;
  const Y = (y: number) => hh / 2 - (y - ROPE_VIEW.cy) * scale;
  clearScene(sc);
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.08)';
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let gx = -4; gx <= 4; gx++) {
    ctx.moveTo(Math.round(X(gx)) + 0.5, 0);
    ctx.lineTo(Math.round(X(gx)) + 0.5, hh);
  }
  for (let gy = -4; gy <= 2; gy++) {
    ctx.moveTo(0, Math.round(Y(gy)) + 0.5);
    ctx.lineTo(w, Math.round(Y(gy)) + 0.5);
  }
  ctx.stroke();

  const color = COLORS[rope.config.integrator];
  const n = rope.count;
  const pts: number[] = [];
  for (let i = 0; i < n; i++) {
    const p = rope.renderPosition(i, rope.exploded ? 1 : alpha, pos);
    pts.push(X(clamp(p.x, -1e4, 1e4)), Y(clamp(p.y, -1e4, 1e4)));
  }
  ctx.strokeStyle = color;
  ctx.lineWidth = 2 * dpr;
  ctx.lineJoin = 'round';
  ctx.beginPath();
  for (let i = 0; i < n; i++) {
    if (i === 0) ctx.moveTo(pts[0]!, pts[1]!);
    else ctx.lineTo(pts[2 * i]!, pts[2 * i + 1]!);
  }
  ctx.stroke();
  const beadR = Math.max(3.5 * dpr, 0.07 * scale);
  for (let i = 0; i < n; i++) {
    const bx = pts[2 * i]!;
    const by = pts[2 * i + 1]!;
    const pinned = i === 0 || i === n - 1;
    ctx.beginPath();
    if (pinned) {
      ctx.fillStyle = '#94a3b8';
      ctx.fillRect(bx - 5 * dpr, by - 5 * dpr, 10 * dpr, 10 * dpr);
      continue;
    }
    ctx.arc(bx, by, i === selected ? beadR * 1.5 : beadR, 0, 2 * Math.PI);
    ctx.fillStyle = i === selected ? '#fde047' : color;
    ctx.fill();
  }

  // The last poke, fading over half a second.
  const lp = lastPoke;
  if (lp && tMs - lp.atMs < 600) {
    const fade = 1 - (tMs - lp.atMs) / 600;
    const bx = pts[2 * lp.bead];
    const by = pts[2 * lp.bead + 1];
    if (bx !== undefined && by !== undefined) {
      const len = Math.hypot(lp.dvx, lp.dvy) || 1;
      const L = Math.min(60 * dpr, len * 8 * dpr);
      arrow(ctx, bx, by, bx + (lp.dvx / len) * L, by - (lp.dvy / len) * L, dpr, fade);
    }
  }
  // A drag in progress.
  const d = drag;
  if (d) {
    const bx = pts[2 * d.bead];
    const by = pts[2 * d.bead + 1];
    if (bx !== undefined && by !== undefined) {
      arrow(ctx, bx, by, bx + (d.x - d.x0) * scale, by - (d.y - d.y0) * scale, dpr, 0.9);
    }
  }
}

function arrow(
  ctx: CanvasRenderingContext2D,
  x0: number,
  y0: number,
  x1: number,
  y1: number,
  dpr: number,
  alpha: number,
): void {
  const len = Math.hypot(x1 - x0, y1 - y0);
  if (len < 2) return;
  const ux = (x1 - x0) / len;
  const uy = (y1 - y0) / len;
  ctx.globalAlpha = alpha;
  ctx.strokeStyle = '#fde047';
  ctx.fillStyle = '#fde047';
  ctx.lineWidth = 2 * dpr;
  ctx.beginPath();
  ctx.moveTo(x0, y0);
  ctx.lineTo(x1, y1);
  ctx.stroke();
  const hs = 7 * dpr;
  ctx.beginPath();
  ctx.moveTo(x1 + ux * 2, y1 + uy * 2);
  ctx.lineTo(x1 - ux * hs - uy * hs * 0.6, y1 - uy * hs + ux * hs * 0.6);
  ctx.lineTo(x1 - ux * hs + uy * hs * 0.6, y1 - uy * hs - ux * hs * 0.6);
  ctx.closePath();
  ctx.fill();
  ctx.globalAlpha = 1;
}

function clamp(v: number, lo: number, hi: number): number {
  return Number.isFinite(v) ? Math.min(hi, Math.max(lo, v)) : v > 0 ? hi : lo;
}
