/** Draws the chapter 1 ball scene (a ball in a 12 × 7 m box) on a {@link SceneCanvas}. */
import { SceneCanvas, View, sceneView } from './canvas.js';

export const BOX_W = 12;
export const BOX_H = 7;

/**
 * The box, a fading trail (x, y, age triples; age 0 newest … 1 oldest) and the ball at (x, y).
 * Returns the view used, or undefined if the canvas has no size yet.
 */
export function drawBall(
  sc: SceneCanvas,
  ball: { x: number; y: number; radius: number },
  color: string,
  trail: readonly number[] = [],
): View | undefined {
  const view = sceneView(sc, { x0: 0, y0: 0, x1: BOX_W, y1: BOX_H });
  if (!view) return undefined;
  const { ctx, dpr } = sc;
  view.grid(ctx, 1);
  ctx.strokeStyle = 'rgba(141, 160, 189, 0.45)';
  ctx.lineWidth = Math.max(1, dpr);
  ctx.strokeRect(
    view.px(0) + 0.5,
    view.py(BOX_H) + 0.5,
    BOX_W * view.scale - 1,
    BOX_H * view.scale - 1,
  );
  const radius = ball.radius * view.scale;
  const dot = Math.max(1.5, radius * 0.32);
  ctx.fillStyle = color;
  for (let k = 0; k + 2 < trail.length; k += 3) {
    ctx.globalAlpha = 0.75 * (1 - Math.min(1, Math.max(0, trail[k + 2]!)));
    ctx.beginPath();
    ctx.arc(view.px(trail[k]!), view.py(trail[k + 1]!), dot, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.globalAlpha = 1;
  ctx.beginPath();
  ctx.arc(view.px(ball.x), view.py(ball.y), radius, 0, 2 * Math.PI);
  ctx.fill();
  ctx.lineWidth = Math.max(1, dpr);
  ctx.strokeStyle = 'rgba(255, 255, 255, 0.85)';
  ctx.stroke();
  return view;
}
