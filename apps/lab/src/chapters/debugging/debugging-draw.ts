/** Chapter 7's drawing: the level with each loop's four runs, and the recording's timeline. */
import { JumperButtons, type ScriptedInput } from '@fixedstep/games';
import { clearScene, sceneView, type SceneCanvas } from '../../ui/canvas.js';
import { drawRunnerDiscs } from '../movement/movement-draw.js';
import { rateColor } from '../../ui/readout.js';
import type { DebugLab, DebugTrack } from './debugging-lab.js';

/** The level as drawn, metres. */
const LEVEL = { x0: 0, x1: 14, y0: -0.15, y1: 2.95 };
/** Line widths (CSS px) per display, widest first. */
const WIDTHS: Readonly<Record<string, number>> = { 30: 7, 60: 5, 144: 3.2, 240: 1.6, real: 1 };
/** How far back a runner's trail reaches, ms. */
const TRAIL_MS = 700;

/** The four runs of one loop drawn over each other at `atMs`: coins, trails and runners. */
export function drawLevel(
  sc: SceneCanvas,
  tracks: readonly DebugTrack[],
  atMs: number,
  interpolate: boolean,
): void {
  const view = sceneView(sc, LEVEL);
  if (!view) return;
  const { ctx, dpr } = sc;
  view.grid(ctx, 1);
  const px = (x: number) => view.px(x);
  const py = (y: number) => view.py(y);
  view.ground(ctx, dpr, 'rgba(141, 160, 189, 0.08)');

  // Coins: a ring per display, nested like the lines.
  for (const t of tracks) {
    const s = t.scene;
    ctx.strokeStyle = rateColor(t.source);
    ctx.lineWidth = Math.max(1, (WIDTHS[String(t.source)] ?? 1) * 0.6 * dpr);
    for (let k = 0; k < s.coinCount; k++) {
      ctx.beginPath();
      ctx.arc(px(s.coinX(k)), py(s.coinY(k)), s.config.coinRadius * view.scale, 0, 2 * Math.PI);
      ctx.stroke();
    }
  }
  // Trails and runners.
  ctx.lineJoin = 'round';
  ctx.lineCap = 'round';
  const half = tracks[0]?.scene.config.height ?? 0.9;
  const pos = tracks.map((t) => t.positionAt(atMs, interpolate));
  tracks.forEach((t, i) => {
    const p = t.path;
    const color = rateColor(t.source);
    ctx.strokeStyle = color;
    ctx.lineWidth = (WIDTHS[String(t.source)] ?? 1) * dpr;
    ctx.globalAlpha = 0.8;
    ctx.beginPath();
    let started = false;
    for (let k = 0; k + 2 < p.length; k += 3) {
      const tt = p[k]!;
      if (tt < atMs - TRAIL_MS) continue;
      if (tt > atMs) break;
      const X = px(p[k + 1]!);
      const Y = py(p[k + 2]! + half / 2);
      if (started) ctx.lineTo(X, Y);
      else ctx.moveTo(X, Y);
      started = true;
    }
    if (started) ctx.lineTo(px(pos[i]!.x), py(pos[i]!.y + half / 2));
    ctx.stroke();
  });
  ctx.globalAlpha = 1;
  drawRunnerDiscs(
    sc,
    tracks.map((t, i) => ({
      color: rateColor(t.source),
      x: px(pos[i]!.x),
      y: py(pos[i]!.y + half / 2),
      radius: (WIDTHS[String(t.source)] ?? 1) + 4,
    })),
  );
}

/** The recording as bars per button over time, with the play head. */
export function drawTimeline(sc: SceneCanvas, lab: DebugLab): void {
  if (!sc.fit()) return;
  const { ctx, dpr } = sc;
  clearScene(sc, '#0a1122');
  const events: readonly ScriptedInput[] = lab.recordingEvents();
  const span = Math.max(10_000, lab.recordingMs + 500, lab.timeMs + 500);
  const padL = 52 * dpr;
  const w = sc.w - padL - 8 * dpr;
  const rows: [number, string][] = [
    [JumperButtons.left, '◀ left'],
    [JumperButtons.right, '▶ right'],
    [JumperButtons.jump, 'jump'],
  ];
  const rowH = sc.h / rows.length;
  const x = (t: number) => padL + (t / span) * w;
  ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
  ctx.textBaseline = 'middle';
  rows.forEach(([b, label], i) => {
    const y = i * rowH;
    ctx.fillStyle = 'rgba(163, 179, 204, 0.8)';
    ctx.fillText(label, 6 * dpr, y + rowH / 2);
    ctx.fillStyle = 'rgba(141, 160, 189, 0.08)';
    ctx.fillRect(padL, y + rowH * 0.2, w, rowH * 0.6);
    ctx.fillStyle = b === JumperButtons.jump ? '#fbbf24' : '#7dd3fc';
    let downAt: number | undefined;
    for (const e of events) {
      if (e.button !== b) continue;
      if (e.down) downAt = e.timeMs;
      else if (downAt !== undefined) {
        ctx.fillRect(
          x(downAt),
          y + rowH * 0.2,
          Math.max(2 * dpr, x(e.timeMs) - x(downAt)),
          rowH * 0.6,
        );
        downAt = undefined;
      }
    }
    if (downAt !== undefined) {
      ctx.fillRect(
        x(downAt),
        y + rowH * 0.2,
        Math.max(2 * dpr, x(lab.timeMs) - x(downAt)),
        rowH * 0.6,
      );
    }
  });
  // The play head.
  const hx = Math.min(x(lab.timeMs), padL + w);
  ctx.strokeStyle = lab.mode === 'recording' ? '#f87171' : '#e6edf7';
  ctx.lineWidth = Math.max(1.5, 1.5 * dpr);
  ctx.beginPath();
  ctx.moveTo(hx, 0);
  ctx.lineTo(hx, sc.h);
  ctx.stroke();
}
