/**
 * The frame every chapter lives in. A chapter names its time line (what the simulated display or
 * the page's real animation frames drive), how to draw and how to start again; the shell owns the
 * rest: the animation-frame driver, the clock (simulated display or real frames), the
 * interpolation and real-clock toggles, Pause / Skip / Restart with the clock readout and its mode
 * line, control boxes that redraw at once, canvases that keep their size, resize observers, window
 * listeners, and the teardown of all of it when the reader leaves.
 *
 * A chapter module exports a {@link MountChapter}; see apps/lab/README.md for the recipe.
 */
import { SceneCanvas } from '../ui/canvas.js';
import { TEXT_PERIOD_MS, deferWrite, flushWrites, holdWrites } from '../ui/write-phase.js';
import { TimeControls, group, setPressed, toggle } from '../ui/controls.js';
import { h } from '../ui/dom.js';
import { LabDriver, type LabDriverOptions } from './driver.js';

/** Who a chapter is: its route, its number and its title (from the registry). */
export interface ChapterHead {
  /** The route: `#/loop`. */
  readonly id: string;
  readonly number: number;
  readonly title: string;
}

/** What a chapter module exports: it builds itself into `root` and returns how to tear down. */
export type MountChapter = (root: HTMLElement, head: ChapterHead) => () => void;

/** What the shell drives: a chapter's model on its own time line (virtual ms from the start). */
export interface TimeLine {
  readonly timeMs: number;
  /** Simulated display: move virtual time forward by `ms` (if it runs on one). */
  advanceBy?(ms: number): void;
  /** Real clock: one display frame at `tMs` from the start of the real-clock run (if it runs on one). */
  realFrame?(tMs: number): void;
}

/** Something the shell destroys with the chapter (a chart, a canvas, a panel). */
export interface Disposable {
  destroy(): void;
}

/**
 * What the shell calls on the chapter it frames: its drawing on every animation frame, and the
 * bringing up to date of its own controls (if it has any) after every change the shell sees.
 */
export interface ShellChapter {
  /** Draw the current state and write the readouts. Called on every animation frame. */
  render(): void;
  /** Bring the chapter's controls up to date; called after any control of a {@link ChapterShell.controls} box. */
  refreshControls?(): void;
}

export interface ChapterShellOptions {
  /** The lede under the title. */
  lede: string;
  /**
   * The time line now, or undefined when nothing runs yet. Read at every use, so a chapter may
   * swap models (a new run for the real clock, another replay).
   */
  timeline(): TimeLine | undefined;
  /**
   * Restart: back to time zero. With it the shell shows Pause / Skip / Restart and the clock
   * readout (`readout-clock`); without it (a chapter with its own transport) it shows none.
   */
  restart?(): void;
  /** What the mode line says on the simulated display (`simulated display · 60 Hz`). */
  mode?(): string;
  /** What the mode line ends with while paused. Default ` · paused`. */
  pausedText?(): string;
  /** Offer "Real clock": `onChange` rebuilds what runs on it (the driver has switched already). */
  realClock?: { title: string; onChange(on: boolean): void };
  /** Offer "Interpolation" (on at the start): {@link ChapterShell.interpolate} follows it. */
  interpolation?: { title: string };
  /** How far "Skip" moves the simulated display, ms. Default 5000. */
  skipMs?: number;
  /** Start paused (the games chapter waits for Play). */
  startPaused?: boolean;
  driver?: LabDriverOptions;
}

export class ChapterShell {
  /** The chapter's `<article>`: its head is in, the chapter appends its sections. */
  readonly article: HTMLElement;
  readonly driver: LabDriver;
  /** Pause / Skip / Restart and the clock readout, when the chapter can restart. */
  readonly time: TimeControls | undefined;
  readonly clockBtn: HTMLButtonElement | undefined;
  readonly interpBtn: HTMLButtonElement | undefined;
  /** Draw fixed-step things between their last two states. */
  interpolate = true;
  private readonly owned: Disposable[] = [];
  private readonly cleanups: (() => void)[] = [];
  private readonly resizers = new Map<Element, () => void>();
  private readonly observer: ResizeObserver;
  /** The chapter's canvases: while none is on screen, its time stands (see {@link frame}). */
  private readonly canvases: SceneCanvas[] = [];
  /** When readouts and charts were last written (performance.now(), ms; UI only). */
  private lastWriteMs = -Infinity;

  /**
   * Frames `chapter` in an `<article>` appended to `root`, classed `<route>-chapter` (for the
   * chapter's own styles), headed by the chapter's number, title and `options.lede`.
   */
  constructor(
    private readonly root: HTMLElement,
    head: ChapterHead,
    private readonly chapter: ShellChapter,
    private readonly options: ChapterShellOptions,
  ) {
    const o = options;
    this.driver = new LabDriver(
      {
        advance: (ms) => {
          o.timeline()?.advanceBy?.(ms);
        },
        realFrame: (t) => {
          o.timeline()?.realFrame?.(t);
        },
        render: () => {
          this.frame(false);
        },
      },
      o.driver,
    );
    if (o.startPaused) this.driver.setPaused(true);
    const skipMs = o.skipMs ?? 5000;
    this.time = o.restart
      ? new TimeControls({
          skipMs,
          onPause: () => {
            this.setPaused(!this.paused);
          },
          onSkip: () => {
            o.timeline()?.advanceBy?.(skipMs);
          },
          onRestart: () => {
            o.restart?.();
            if (this.real) this.driver.restartReal();
          },
        })
      : undefined;
    this.interpBtn = o.interpolation
      ? toggle('Interpolation', 'control-interp', true, (on) => {
          this.interpolate = on;
        })
      : undefined;
    if (this.interpBtn && o.interpolation) this.interpBtn.title = o.interpolation.title;
    this.clockBtn = o.realClock
      ? toggle('Real clock', 'control-real-clock', false, (on) => {
          this.setReal(on);
        })
      : undefined;
    if (this.clockBtn && o.realClock) this.clockBtn.title = o.realClock.title;
    this.observer = new ResizeObserver((entries) => {
      for (const e of entries) this.resizers.get(e.target)?.();
    });
    this.article = h(
      'article',
      { class: `chapter ${head.id}-chapter` },
      h(
        'header',
        { class: 'chapter-head' },
        h('p', { class: 'eyebrow' }, `Chapter ${head.number}`),
        h('h1', {}, head.title),
        h('p', { class: 'lede' }, o.lede),
      ),
    );
    root.append(this.article);
  }

  get paused(): boolean {
    return this.driver.isPaused;
  }

  get real(): boolean {
    return this.driver.isReal;
  }

  /** The page's display rate as measured from its animation frames, Hz (0 until known). */
  get measuredHz(): number {
    return this.driver.measuredHz;
  }

  setPaused(paused: boolean): void {
    this.driver.setPaused(paused);
    this.refresh();
  }

  /** Switch between the simulated display and the page's real frames (a new real-clock run). */
  setReal(on: boolean): void {
    this.driver.setReal(on);
    if (this.clockBtn) setPressed(this.clockBtn, on);
    this.options.realClock?.onChange(on);
    this.refresh();
  }

  setInterpolation(on: boolean): void {
    this.interpolate = on;
    if (this.interpBtn) setPressed(this.interpBtn, on);
  }

  /** `sim` on the simulated display; on the real clock, the page's measured rate. */
  display(sim: string): string {
    return this.real ? `real clock · your display ≈ ${this.measuredHz} Hz` : sim;
  }

  /** Append the chapter's sections to its article. */
  append(...sections: (Node | null | undefined | false)[]): void {
    for (const s of sections) if (s) this.article.append(s);
  }

  /**
   * A box of controls (`.controls`, a labelled group): any click or change in it brings the
   * controls up to date and redraws at once, not on the next animation frame.
   */
  controls(label: string, ...children: (Node | null | undefined | false)[]): HTMLElement {
    const box = h('div', { class: 'controls', role: 'group', 'aria-label': label }, children);
    this.settleOn(box);
    return box;
  }

  /** Redraw at once after any click or change inside `el`. */
  settleOn(el: HTMLElement): void {
    el.addEventListener('click', this.settle);
    el.addEventListener('change', this.settle);
  }

  /** The "Draw" group: `extra`, then the interpolation and real-clock toggles. */
  drawGroup(...extra: HTMLElement[]): HTMLElement {
    return group('Draw', ...extra, this.interpBtn ?? null, this.clockBtn ?? null);
  }

  /** The "Time" group: Pause, Skip, Restart, then `extra`. */
  timeGroup(...extra: HTMLElement[]): HTMLElement {
    return group('Time', ...(this.time?.buttons ?? []), ...extra);
  }

  /** The status row: the clock, the mode line, then `extra`. */
  status(...extra: (Node | null)[]): HTMLElement {
    return h('div', { class: 'status', 'aria-live': 'off' }, ...(this.time?.status ?? []), extra);
  }

  /** A canvas that keeps its backing store at its size; destroyed with the chapter. */
  canvas(attrs: ConstructorParameters<typeof SceneCanvas>[0]): SceneCanvas {
    const sc = this.own(new SceneCanvas(attrs));
    this.canvases.push(sc);
    return sc;
  }

  /** Destroy `thing` with the chapter. */
  own<T extends Disposable>(thing: T): T {
    this.owned.push(thing);
    return thing;
  }

  /** Listen to `type` on `target` until the chapter goes. */
  listen<K extends keyof WindowEventMap>(
    target: Window,
    type: K,
    fn: (e: WindowEventMap[K]) => void,
  ): void;
  listen<K extends keyof DocumentEventMap>(
    target: Document,
    type: K,
    fn: (e: DocumentEventMap[K]) => void,
  ): void;
  listen(target: EventTarget, type: string, fn: (e: Event) => void): void {
    target.addEventListener(type, fn);
    this.cleanups.push(() => {
      target.removeEventListener(type, fn);
    });
  }

  /** Call `fn` whenever `el` changes size (and once when it is first laid out). */
  observe(el: Element, fn: () => void): void {
    this.resizers.set(el, fn);
    this.observer.observe(el);
  }

  /** Bring the controls up to date (Pause/Play, Skip only on the simulated display, the chapter's). */
  refresh(): void {
    this.time?.refresh(this.paused, !this.real);
    this.chapter.refreshControls?.();
  }

  /** Bring the controls up to date and draw now, not on the next animation frame. */
  redraw(): void {
    this.settle();
  }

  /** Start the animation frames (after the chapter has built its page). */
  start(): void {
    this.refresh();
    this.frame(true);
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    this.observer.disconnect();
    for (const c of this.cleanups) c();
    for (const o of this.owned) o.destroy();
    this.root.replaceChildren();
  }

  private readonly settle = (): void => {
    this.refresh();
    this.frame(true);
  };

  /**
   * One frame's drawing, in one write phase (write-phase.ts): nothing here reads the page's layout
   * (sizes come from observers); the chapter draws its canvases on a clean page while its readout
   * and chart writes are held, and they go out together at the end — every
   * {@link TEXT_PERIOD_MS}, or at once (`now`) after a control changed something. Then, for the
   * next frame: if the chapter has canvases and none is on screen, its time stands.
   */
  private frame(now: boolean): void {
    const o = this.options;
    const t = performance.now();
    holdWrites(true);
    try {
      this.chapter.render();
    } finally {
      holdWrites(false);
    }
    if (now || t - this.lastWriteMs >= TEXT_PERIOD_MS) {
      const time = this.time;
      if (time) {
        const paused = this.paused ? (o.pausedText?.() ?? ' · paused') : '';
        const timeMs = o.timeline()?.timeMs ?? 0;
        const mode = `${o.mode?.() ?? this.display('')}${paused}`;
        deferWrite(
          {
            flushWrite: () => {
              time.show(timeMs, mode);
            },
          },
          'text',
        );
      }
      flushWrites();
      this.lastWriteMs = t;
    }
    this.driver.setOffScreen(this.canvases.length > 0 && !this.canvases.some((c) => c.onScreen));
  }
}

/**
 * The time line of a model that runs on the page's real frames only, read through `model` (a
 * chapter's real-clock run, replaced at every restart): its `timeMs`, and `frameAt` for each frame.
 */
export function realTimeLine(
  model: () => { readonly timeMs: number; frameAt(tMs: number): void } | undefined,
): TimeLine {
  return {
    get timeMs() {
      return model()?.timeMs ?? 0;
    },
    realFrame(tMs) {
      model()?.frameAt(tMs);
    },
  };
}

/** Mounts a chapter class whose constructor takes `(root, head)` and keeps its shell in `shell`. */
export function mountChapter(
  make: (root: HTMLElement, head: ChapterHead) => { readonly shell: ChapterShell },
): MountChapter {
  return (root, head) => {
    const chapter = make(root, head);
    return () => {
      chapter.shell.destroy();
    };
  };
}
