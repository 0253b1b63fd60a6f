/**
 * Chapter 10's drawing: a world of boxes and balls at their (interpolated) poses — positions and
 * angles — over its static ground and walls. Pure functions of what the model hands over.
 */
import { View, clearScene, type SceneCanvas } from '../../ui/canvas.js';
import type { BodyShape, Bounds, StaticBox } from './rigid-bodies-lab.js';

/** Colours: upright boxes, boxes turned past the threshold, each player's ball. */
const BOX = '#f5a524';
const BOX_TURNED = '#fb7185';
const BALLS = ['#38bdf8', '#a78bfa'];
const GROUND = '#334155';

/** What to draw: the bodies' shapes, their poses (x, y, angle per body), the scenery. */
export interface WorldPicture {
  readonly bounds: Bounds;
  readonly statics: readonly StaticBox[];
  readonly shapes: readonly BodyShape[];
  /** Body i's x, y and angle (radians, counter-clockwise) at `3i … 3i + 2`. */
  readonly poses: ArrayLike<number>;
  /** Boxes turned past this angle (radians) are drawn in the "turned" colour. */
  readonly turnedRad: number;
  /** A line at the top left (tick, a badge), or undefined. */
  readonly label?: string;
}

/** The wrapped size of an angle, 0 … π. */
function turnOf(a: number): number {
  let x = a % (2 * Math.PI);
  if (x > Math.PI) x -= 2 * Math.PI;
  else if (x < -Math.PI) x += 2 * Math.PI;
  return Math.abs(x);
}

/** Draw `pic` into `sc` (fitted, centred, y up). */
export function drawWorld(sc: SceneCanvas, pic: WorldPicture): void {
  if (!sc.fit()) return;
  clearScene(sc);
  const { ctx, w, h, dpr } = sc;
  const [x0, y0, x1, y1] = pic.bounds;
  const v = new View(w, h, x0, y0, x1, y1);
  v.grid(ctx, 1);
  const s = v.scale;
  ctx.fillStyle = GROUND;
  for (const b of pic.statics) {
    ctx.fillRect(
      v.px(b.x - b.halfWidth),
      v.py(b.y + b.halfHeight),
      2 * b.halfWidth * s,
      2 * b.halfHeight * s,
    );
  }
  ctx.lineWidth = Math.max(1, dpr);
  for (let i = 0; i < pic.shapes.length; i++) {
    const shape = pic.shapes[i]!;
    const x = pic.poses[3 * i] ?? 0;
    const y = pic.poses[3 * i + 1] ?? 0;
    const a = pic.poses[3 * i + 2] ?? 0;
    // Canvas y grows downwards: a counter-clockwise angle in the world is a negative rotation here.
    ctx.setTransform(1, 0, 0, 1, v.px(x), v.py(y));
    ctx.rotate(-a);
    if (shape.kind === 'box') {
      const hw = shape.halfWidth * s;
      const hh = shape.halfHeight * s;
      ctx.fillStyle = turnOf(a) > pic.turnedRad ? BOX_TURNED : BOX;
      ctx.globalAlpha = 0.85;
      ctx.fillRect(-hw, -hh, 2 * hw, 2 * hh);
      ctx.globalAlpha = 1;
      ctx.strokeStyle = 'rgba(10, 17, 34, 0.9)';
      ctx.strokeRect(-hw, -hh, 2 * hw, 2 * hh);
    } else {
      const r = shape.halfWidth * s;
      ctx.fillStyle = BALLS[shape.owner] ?? BALLS[0]!;
      ctx.beginPath();
      ctx.arc(0, 0, r, 0, 2 * Math.PI);
      ctx.fill();
      // A spoke, so the ball's spin shows.
      ctx.strokeStyle = 'rgba(10, 17, 34, 0.85)';
      ctx.beginPath();
      ctx.moveTo(0, 0);
      ctx.lineTo(r, 0);
      ctx.stroke();
    }
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  if (pic.label !== undefined) {
    ctx.font = `${Math.round(11 * dpr)}px ui-monospace, SFMono-Regular, Menlo, monospace`;
    ctx.fillStyle = 'rgba(230, 237, 247, 0.75)';
    ctx.textBaseline = 'top';
    ctx.fillText(pic.label, 8 * dpr, 6 * dpr);
  }
}

/** The CSS aspect ratio (width / height) of a world's bounds. */
export function aspectOf(bounds: Bounds): number {
  return (bounds[2] - bounds[0]) / (bounds[3] - bounds[1]);
}
