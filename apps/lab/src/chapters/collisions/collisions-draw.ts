/**
 * Chapter 3's drawing: a panel's firing range — the wall, the bodies in flight, bounced or through
 * (with the streak of their last step), and the step ruler in a strip above the range.
 */
import { RANGE_HALF_HEIGHT, RANGE_HALF_WIDTH, ShotStatus, type WallRange } from '@fixedstep/games';
import type { SceneCanvas } from '../../ui/canvas.js';
import { RADIUS, STEP_S, type RangePanel } from './collisions-lab.js';
import { BODY } from './collisions-text.js';

/** The strip at the top of a panel's canvas that holds the step ruler, CSS px. */
const RULER_STRIP = 38;
const RULE_COLOR = '#fbbf24';
const BOUNCE_COLOR = '#34d399';
/** The arena as drawn: a little margin around the range. */
const VIEW_W = 2 * RANGE_HALF_WIDTH + 1;
const VIEW_H = 2 * RANGE_HALF_HEIGHT + 1;
const scratch = { x: 0, y: 0 };

/**
 * The range of `run` (its CCD twin when `ccd`), bodies drawn between their last two states when
 * `interpolate`, the step ruler in the panel's `color`.
 */
export function drawRange(
  sc: SceneCanvas,
  run: RangePanel,
  color: string,
  ccd: boolean,
  interpolate: boolean,
): void {
  const range = run.range(ccd);
  const r = run.readouts();
  if (!sc.fit()) return;
  const { ctx, w, h: hh, dpr } = sc;
  // The ruler has a strip of its own at the top; the range is drawn below it.
  const strip = Math.round(RULER_STRIP * dpr);
  const s = Math.min(w / VIEW_W, (hh - strip) / VIEW_H);
  const ox = w / 2;
  const oy = strip + (hh - strip) / 2;
  const px = (x: number) => ox + x * s;
  const py = (y: number) => oy - y * s;
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = '#0d1529';
  ctx.fillRect(0, 0, w, strip);
  ctx.fillStyle = '#0a1122';
  ctx.fillRect(0, strip, w, hh - strip);
  ctx.fillStyle = 'rgba(141, 160, 189, 0.18)';
  ctx.fillRect(0, strip - Math.max(1, dpr), w, Math.max(1, dpr));

  // Grid, 2 m.
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.08)';
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let x = -RANGE_HALF_WIDTH; x <= RANGE_HALF_WIDTH; x += 2) {
    ctx.moveTo(Math.round(px(x)) + 0.5, strip);
    ctx.lineTo(Math.round(px(x)) + 0.5, hh);
  }
  for (let y = -4; y <= 4; y += 2) {
    ctx.moveTo(0, Math.round(py(y)) + 0.5);
    ctx.lineTo(w, Math.round(py(y)) + 0.5);
  }
  ctx.stroke();

  // The wall.
  const wallW = range.config.wall / 2;
  ctx.fillStyle = '#334155';
  ctx.fillRect(px(-wallW), strip, 2 * wallW * s, hh - strip);
  ctx.fillStyle = 'rgba(148, 163, 184, 0.5)';
  ctx.fillRect(px(-wallW), strip, Math.max(1, dpr), hh - strip);
  ctx.fillRect(px(wallW) - Math.max(1, dpr), strip, Math.max(1, dpr), hh - strip);
  ctx.strokeStyle = 'rgba(148, 163, 184, 0.35)';
  ctx.setLineDash([2 * dpr, 4 * dpr]);
  ctx.beginPath();
  ctx.moveTo(px(0), strip);
  ctx.lineTo(px(0), hh);
  ctx.stroke();
  ctx.setLineDash([]);

  const speed = range.config.speed;
  const stepLen = speed * (run.rig.kind === 'fixed' ? STEP_S : r.lastDtMs / 1000);
  drawRuler(sc, color, stepLen, range.config.wall, s, px(-wallW), strip);

  // Muzzle.
  ctx.fillStyle = 'rgba(141, 160, 189, 0.5)';
  ctx.fillRect(0, py(RANGE_HALF_HEIGHT - 0.2), 4 * dpr, (2 * RANGE_HALF_HEIGHT - 0.4) * s);

  drawBodies(ctx, range, interpolate ? run.rig.alpha : 1, s, px, py, dpr);
}

/**
 * One step of travel as a bar ending at the wall's face, against two marks: amber at the wall's
 * thickness (a longer step can jump the wall unseen: the talk's rule) and a green bar of half
 * the wall plus the radius (a longer step can land a body past the middle: pushed out the far
 * side). Drawn in the strip above the range, with its numbers on the line above the bar.
 */
function drawRuler(
  sc: SceneCanvas,
  color: string,
  stepLen: number,
  wall: number,
  s: number,
  face: number,
  strip: number,
): void {
  const { ctx, w, dpr } = sc;
  const barY = strip - 15 * dpr;
  const limitY = strip - 7 * dpr;
  const safe = wall / 2 + RADIUS;
  const edge = 2 * dpr;
  // The talk's rule: a tick at the wall's thickness, across both bars.
  const xa = face - wall * s;
  if (xa >= edge) {
    ctx.fillStyle = RULE_COLOR;
    ctx.fillRect(xa - dpr, barY - 5 * dpr, 2 * dpr, limitY - barY + 8 * dpr);
    ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    ctx.textAlign = 'right';
    ctx.fillText('w', xa - 4 * dpr, (barY + limitY) / 2);
  }
  // The bounce limit, a second bar below: every body bounces while the step is no longer.
  const xs = Math.max(edge, face - safe * s);
  ctx.fillStyle = BOUNCE_COLOR;
  ctx.fillRect(xs, limitY - 1.5 * dpr, face - xs, 3 * dpr);
  ctx.fillRect(xs - dpr, limitY - 4 * dpr, 2 * dpr, 8 * dpr);
  // The step.
  const x0 = Math.max(edge, face - stepLen * s);
  ctx.strokeStyle = color;
  ctx.lineWidth = 2 * dpr;
  ctx.beginPath();
  ctx.moveTo(x0, barY);
  ctx.lineTo(face, barY);
  ctx.moveTo(x0, barY - 4 * dpr);
  ctx.lineTo(x0, barY + 4 * dpr);
  ctx.moveTo(face, barY - 4 * dpr);
  ctx.lineTo(face, limitY + 4 * dpr);
  ctx.stroke();

  ctx.font = `${Math.round(11 * dpr)}px system-ui, sans-serif`;
  ctx.textBaseline = 'middle';
  ctx.textAlign = 'left';
  const textY = 9 * dpr;
  const step = `one step ${stepLen.toFixed(2)} m`;
  const gap = 12 * dpr;
  const room = w - 12 * dpr - ctx.measureText(step).width - gap;
  const bounce =
    [
      `every body bounces while ≤ ${safe.toFixed(2)} m (w/2 + r)`,
      `all bounce while ≤ ${safe.toFixed(2)} m`,
      `bounce ≤ ${safe.toFixed(2)} m`,
    ].find((t) => ctx.measureText(t).width <= room) ?? '';
  ctx.fillStyle = color;
  ctx.fillText(step, 6 * dpr, textY);
  ctx.fillStyle = '#6ee7b7';
  if (bounce) ctx.fillText(bounce, 6 * dpr + ctx.measureText(step).width + gap, textY);
}

function drawBodies(
  ctx: CanvasRenderingContext2D,
  range: WallRange,
  alpha: number,
  s: number,
  px: (x: number) => number,
  py: (y: number) => number,
  dpr: number,
): void {
  const world = range.world;
  const radius = Math.max(RADIUS * s, 3.2 * dpr);
  const t = range.time;
  for (let id = 0; id < world.slotCount; id++) {
    const status = range.status[id]!;
    if (status === 0) continue;
    const pos = range.renderPosition(id, alpha, scratch);
    const color =
      status === ShotStatus.through
        ? BODY.through
        : status === ShotStatus.bounced
          ? BODY.bounced
          : BODY.flying;
    const fade =
      status === ShotStatus.bounced ? Math.max(0.15, 1 - (t - range.changedAt[id]!) / 0.35) : 1;
    // The jump of the last step: where the body was, where it is drawn now.
    ctx.strokeStyle = color;
    ctx.globalAlpha = 0.3 * fade;
    ctx.lineWidth = Math.max(1, radius * 0.8);
    ctx.beginPath();
    ctx.moveTo(px(range.prevX[id]!), py(range.prevY[id]!));
    ctx.lineTo(px(pos.x), py(pos.y));
    ctx.stroke();
    ctx.globalAlpha = fade;
    ctx.fillStyle = color;
    ctx.beginPath();
    ctx.arc(px(pos.x), py(pos.y), radius, 0, 2 * Math.PI);
    ctx.fill();
    if (status === ShotStatus.through) {
      ctx.lineWidth = 1.5 * dpr;
      ctx.strokeStyle = '#ffffff';
      ctx.stroke();
    }
  }
  ctx.globalAlpha = 1;
}
