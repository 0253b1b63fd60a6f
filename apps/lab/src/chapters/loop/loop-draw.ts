/** Chapter 1's drawing: a panel's ball with its trail, and its steps-per-frame window. */
import { drawBall } from '../../ui/ball-view.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { HISTORY_MS, type PanelRun } from './loop-lab.js';

/** The ball of `run` (drawn between its last two states when `interpolate`) and its trail. */
export function drawPanel(
  sc: SceneCanvas,
  run: PanelRun,
  color: string,
  interpolate: boolean,
  scratch: number[],
): void {
  const trail = run.trailPoints(run.rig.realMs, interpolate, scratch);
  const ball = run.ballAt(interpolate);
  drawBall(sc, { ...ball, radius: run.rig.scene.config.radius }, color, trail);
}

/**
 * The steps each display frame asked for over the last {@link HISTORY_MS} before `tMs`: x in
 * seconds, the window `[from, to]` in seconds. The last frame before the window is kept (at the
 * window's start), so a sparse run still draws its step.
 */
export function stepsWindow(
  run: PanelRun,
  tMs: number,
): { xs: number[]; ys: number[]; from: number; to: number } {
  const xs: number[] = [];
  const ys: number[] = [];
  const from = tMs - HISTORY_MS;
  const history = run.history;
  for (let k = 0; k < history.size; k++) {
    const ft = history.get(k, 0);
    const next = k + 1 < history.size ? history.get(k + 1, 0) : Infinity;
    if (next < from) continue;
    xs.push(Math.max(ft, from) / 1000);
    ys.push(history.get(k, 1));
  }
  return { xs, ys, from: from / 1000, to: tMs / 1000 };
}
