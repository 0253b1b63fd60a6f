/**
 * A canvas that keeps its backing store at its CSS size × device pixel ratio, and a view that
 * maps world metres (y up) into it.
 */
import { h } from './dom.js';

/** What a {@link SceneCanvas} is made with. */
export interface SceneCanvasAttrs {
  class?: string;
  label: string;
  testId: string;
  /**
   * Called after the backing store was resized (which clears it), for a canvas whose owner does
   * not redraw on every animation frame. Such a canvas is drawn off screen too (it draws seldom).
   */
  onResize?: () => void;
}

/**
 * How far outside the window a canvas still counts as on screen, so a demo scrolled towards is
 * drawn before it shows.
 */
const ON_SCREEN_MARGIN = '200px';

export class SceneCanvas {
  readonly canvas: HTMLCanvasElement;
  readonly ctx: CanvasRenderingContext2D;
  /** Backing-store size in device pixels. */
  w = 0;
  h = 0;
  dpr = 1;
  /**
   * On screen (within {@link ON_SCREEN_MARGIN} of the window), as the IntersectionObserver last
   * said; true until it first speaks.
   */
  onScreen = true;
  /** CSS size as the ResizeObserver last said (undefined until it first speaks). */
  private cssW: number | undefined;
  private cssH = 0;
  private readonly observer: ResizeObserver;
  private readonly visibility: IntersectionObserver;
  private readonly onResize: (() => void) | undefined;

  constructor(attrs: SceneCanvasAttrs) {
    this.canvas = h('canvas', {
      class: attrs.class ?? 'scene',
      role: 'img',
      'aria-label': attrs.label,
      'data-testid': attrs.testId,
    });
    const ctx = this.canvas.getContext('2d');
    if (!ctx) throw new Error('The lab needs a 2D canvas');
    this.ctx = ctx;
    const onResize = attrs.onResize;
    this.onResize = onResize;
    // Sizes are measured when the browser says they changed, never in a frame: drawing reads none.
    this.observer = new ResizeObserver((entries) => {
      const entry = entries[entries.length - 1];
      if (!entry) return;
      this.cssW = entry.contentRect.width;
      this.cssH = entry.contentRect.height;
      const w = this.w;
      const hh = this.h;
      if (this.fit() && onResize && (this.w !== w || this.h !== hh)) onResize();
    });
    this.observer.observe(this.canvas);
    this.visibility = new IntersectionObserver(
      (entries) => {
        const entry = entries[entries.length - 1];
        if (entry) this.onScreen = entry.isIntersecting;
      },
      { rootMargin: ON_SCREEN_MARGIN },
    );
    this.visibility.observe(this.canvas);
  }

  /**
   * Match the backing store to the CSS size; true if the canvas can be drawn on: it has a size and,
   * if its owner draws it every frame, it is on screen (a demo off screen is not drawn). Reads no
   * layout (but once, before the observer first speaks).
   */
  fit(): boolean {
    if (this.cssW === undefined) {
      const rect = this.canvas.getBoundingClientRect();
      this.cssW = rect.width;
      this.cssH = rect.height;
    }
    if (!this.onScreen && !this.onResize) return false;
    const dpr = Math.min(window.devicePixelRatio || 1, 3);
    const w = Math.max(1, Math.round(this.cssW * dpr));
    const hh = Math.max(1, Math.round(this.cssH * dpr));
    if (w !== this.w || hh !== this.h) {
      this.canvas.width = w;
      this.canvas.height = hh;
      this.w = w;
      this.h = hh;
      this.dpr = dpr;
    }
    return w > 1 && hh > 1;
  }

  destroy(): void {
    this.observer.disconnect();
    this.visibility.disconnect();
  }
}

/** A world rectangle (metres, y up) fitted into a canvas, centred, keeping proportions. */
export class View {
  readonly scale: number;
  private readonly ox: number;
  private readonly oy: number;

  constructor(
    readonly w: number,
    readonly h: number,
    readonly x0: number,
    readonly y0: number,
    readonly x1: number,
    readonly y1: number,
  ) {
    this.scale = Math.min(w / (x1 - x0), h / (y1 - y0));
    this.ox = (w - (x1 - x0) * this.scale) / 2;
    this.oy = (h - (y1 - y0) * this.scale) / 2;
  }

  px(x: number): number {
    return this.ox + (x - this.x0) * this.scale;
  }

  py(y: number): number {
    return this.oy + (this.y1 - y) * this.scale;
  }

  /** Faint lines every `step` metres inside the view. */
  grid(ctx: CanvasRenderingContext2D, step = 1, stroke = 'rgba(141, 160, 189, 0.10)'): void {
    ctx.strokeStyle = stroke;
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = Math.ceil(this.x0 / step) * step; x <= this.x1; x += step) {
      const X = Math.round(this.px(x)) + 0.5;
      ctx.moveTo(X, this.py(this.y1));
      ctx.lineTo(X, this.py(this.y0));
    }
    for (let y = Math.ceil(this.y0 / step) * step; y <= this.y1; y += step) {
      const Y = Math.round(this.py(y)) + 0.5;
      ctx.moveTo(this.px(this.x0), Y);
      ctx.lineTo(this.px(this.x1), Y);
    }
    ctx.stroke();
  }

  /**
   * The floor (y = 0) across the view: what lies under it shaded in `fill`, then the floor line,
   * at least one device pixel wide (`dpr`) and on a pixel's centre so it stays crisp.
   */
  ground(ctx: CanvasRenderingContext2D, dpr: number, fill: string): void {
    const x0 = this.px(this.x0);
    const x1 = this.px(this.x1);
    const y = this.py(0);
    ctx.fillStyle = fill;
    ctx.fillRect(x0, y, x1 - x0, this.py(this.y0) - y);
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.55)';
    ctx.lineWidth = Math.max(1, dpr);
    ctx.beginPath();
    ctx.moveTo(x0, Math.round(y) + 0.5);
    ctx.lineTo(x1, Math.round(y) + 0.5);
    ctx.stroke();
  }
}

/**
 * Fits `sc` to its box, clears it to the scene background and gives the view of the world's
 * rectangle `box` (metres) on it: undefined while the canvas has no size (nothing to draw on).
 */
export function sceneView(
  sc: SceneCanvas,
  box: { readonly x0: number; readonly y0: number; readonly x1: number; readonly y1: number },
): View | undefined {
  if (!sc.fit()) return undefined;
  clearScene(sc);
  return new View(sc.w, sc.h, box.x0, box.y0, box.x1, box.y1);
}

/** Clear a canvas to the lab's scene background. */
export function clearScene(sc: SceneCanvas, fill = '#0a1122'): void {
  const { ctx } = sc;
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.globalAlpha = 1;
  ctx.fillStyle = fill;
  ctx.fillRect(0, 0, sc.w, sc.h);
}
