/**
 * Chapter 1 — The loop. The talk's four loops and the production FixedLoop run side by side on
 * one ball scene and one simulated display (or the page's real clock). The numbers come from
 * {@link LoopLab}; this module only builds the page and draws.
 */
import {
  CHECKPOINT_TICK,
  ClockLab,
  DISPLAY_RATES,
  HISTORY_MS,
  LoopLab,
  MAX_REAL_FRAME_MS,
  PANELS,
  SLOW_UPDATE_COST_MS,
  STEP_MS,
  defaultSettings,
  type DisplayRate,
  type LoopLabSettings,
  type PanelReadouts,
  type PanelRun,
  type PanelSpec,
} from './loop-lab.js';
import { button, toggle } from '../ui/controls.js';
import { h, setAttr, setText } from '../ui/dom.js';
import { ideaCards, type IdeaCard } from '../ui/cards.js';
import { LabDriver } from '../ui/driver.js';
import * as fmt from '../ui/format.js';
import { StepsChart } from '../ui/steps-chart.js';

const COLORS: Readonly<Record<string, string>> = {
  'frame-locked': '#f5a524',
  variable: '#f87171',
  'fixed-naive': '#a78bfa',
  'fixed-final': '#34d399',
  fixed: '#38bdf8',
};

const BOX_W = 12;
const BOX_H = 7;
const HITCH_MS = 2000;
const HIDDEN_MS = 10_000;
const SKIP_MS = 5000;
/**
 * Where a "Things to try" card starts its run: past update {@link CHECKPOINT_TICK} (4.5 s), so
 * "Hash @150" is already in, and with the ball in flight when a hitch or a hidden tab begins.
 */
const EXPERIMENT_LEAD_MS = 5000;

type Field = keyof Omit<PanelReadouts, 'owed'>;

/** The readout rows of a panel: test id suffix, label, what it means. */
const ROWS: readonly { field: Field; id: string; label: string; title: string }[] = [
  { field: 'simS', id: 'sim', label: 'Sim time', title: 'Time as the loop has simulated it' },
  { field: 'realS', id: 'real', label: 'Real time', title: 'Time of the last display frame' },
  {
    field: 'ratio',
    id: 'ratio',
    label: 'Sim / real',
    title: 'Simulated time over real time: 1 is right',
  },
  {
    field: 'steps',
    id: 'steps',
    label: 'Steps / frame',
    title: 'Updates the last display frame asked for',
  },
  {
    field: 'maxSteps',
    id: 'max-steps',
    label: 'Max steps',
    title: 'The most updates one display frame asked for',
  },
  {
    field: 'droppedMs',
    id: 'dropped',
    label: 'Dropped',
    title: 'Real time the loop chose not to simulate (n/a: the loop has no accumulator)',
  },
  {
    field: 'hash',
    id: 'hash',
    label: 'Hash now',
    title:
      'FNV-1a 64 of the ball’s state now. On a frame that lands exactly on a step boundary the slides’ loops (acc > STEP) are one update behind FixedLoop (acc ≥ step) until the next frame',
  },
  {
    field: 'checkpointHash',
    id: 'hash150',
    label: `Hash @${CHECKPOINT_TICK}`,
    title: `FNV-1a 64 of the ball’s state right after update ${CHECKPOINT_TICK}: equal ticks, equal hashes?`,
  },
];

interface PanelView {
  readonly spec: PanelSpec;
  readonly color: string;
  readonly canvas: HTMLCanvasElement;
  readonly ctx: CanvasRenderingContext2D;
  readonly chartHost: HTMLElement;
  chart: StepsChart | undefined;
  /** The text of each readout. */
  readonly values: Map<Field, HTMLElement>;
  /** The cell of each readout, carrying its test id and exact `data-value`. */
  readonly valueCells: Map<Field, HTMLElement>;
  readonly swatches: Map<Field, HTMLElement>;
  readonly stall: HTMLElement;
  readonly overlay: HTMLElement;
  /** Canvas size in device pixels. */
  w: number;
  h: number;
  dpr: number;
}

export function mount(root: HTMLElement): () => void {
  const chapter = new LoopChapter(root);
  return () => {
    chapter.destroy();
  };
}

class LoopChapter {
  private readonly lab = new LoopLab();
  private clock: ClockLab | undefined;
  private interpolate = true;
  private readonly driver: LabDriver;
  private readonly panels: PanelView[] = [];
  private readonly trailScratch: number[] = [];
  private readonly observer: ResizeObserver;
  private readonly cleanups: (() => void)[] = [];

  // Controls.
  private readonly rateInputs = new Map<DisplayRate, HTMLInputElement>();
  private readonly jitterInput: HTMLInputElement;
  private readonly jitterOut: HTMLOutputElement;
  private readonly hitchBtn: HTMLButtonElement;
  private readonly hiddenBtn: HTMLButtonElement;
  private readonly slowBtn: HTMLButtonElement;
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly pauseBtn: HTMLButtonElement;
  private readonly skipBtn: HTMLButtonElement;
  private readonly restartBtn: HTMLButtonElement;
  private readonly throwBtn: HTMLButtonElement;
  private readonly clockOut: HTMLElement;
  private readonly modeOut: HTMLElement;
  private readonly eventsOut: HTMLElement;
  private readonly panelGrid: HTMLElement;

  constructor(private readonly root: HTMLElement) {
    this.driver = new LabDriver(
      {
        advance: (ms) => {
          this.lab.advanceBy(ms);
        },
        realFrame: (t) => {
          this.clock?.frameAt(t);
        },
        render: () => {
          this.render();
        },
      },
      { maxFrameMs: MAX_REAL_FRAME_MS },
    );
    // ------------------------------------------------------------ controls
    const rates = h(
      'div',
      { class: 'segmented', role: 'radiogroup', 'aria-label': 'Display refresh rate' },
      DISPLAY_RATES.map((hz) => {
        const input = h('input', {
          type: 'radio',
          name: 'display-hz',
          value: hz,
          id: `hz-${hz}`,
          checked: hz === this.lab.settings.hz,
        });
        input.addEventListener('change', () => {
          if (input.checked) this.lab.update({ hz });
          this.refreshControls();
        });
        this.rateInputs.set(hz, input);
        return h(
          'label',
          { for: `hz-${hz}`, 'data-testid': `control-hz-${hz}` },
          input,
          h('span', {}, `${hz} Hz`),
        );
      }),
    );
    this.jitterInput = h('input', {
      type: 'range',
      min: 0,
      max: 30,
      step: 1,
      value: 0,
      id: 'jitter',
      'data-testid': 'control-jitter',
      'aria-describedby': 'jitter-out',
    });
    this.jitterOut = h('output', { id: 'jitter-out', for: 'jitter' }, '0 %');
    // The label follows the slider; the replay waits until it is let go.
    this.jitterInput.addEventListener('input', () => {
      setText(this.jitterOut, `${this.jitterInput.value} %`);
    });
    this.jitterInput.addEventListener('change', () => {
      this.lab.update({ jitter: Number(this.jitterInput.value) / 100 });
      this.refreshControls();
    });

    this.hitchBtn = button('2 s hitch', 'control-hitch', () => {
      this.lab.addEvent('hitch', HITCH_MS);
    });
    this.hiddenBtn = button('Hidden tab, 10 s', 'control-hidden', () => {
      this.lab.addEvent('hidden', HIDDEN_MS);
    });
    this.slowBtn = toggle(`Slow machine`, 'control-slow', false, (on) => {
      this.lab.update({ slow: on });
    });
    this.slowBtn.title = `Every update costs ${SLOW_UPDATE_COST_MS} ms of real time, more than the ${STEP_MS} ms it simulates`;
    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw the fixed loops between their last two states, at alpha';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setRealClock(on);
    });
    this.clockBtn.title = 'Feed the loops this page’s own requestAnimationFrame times';
    this.pauseBtn = button('Pause', 'control-pause', () => {
      this.setPaused(!this.paused);
    });
    this.pauseBtn.setAttribute('aria-pressed', 'false');
    this.skipBtn = button('Skip +5 s', 'control-skip', () => {
      this.lab.advanceBy(SKIP_MS);
    });
    this.skipBtn.title = 'Advance the simulated display by 5 s at once';
    this.restartBtn = button('Restart', 'control-restart', () => {
      this.restart();
    });
    this.throwBtn = button('Throw', 'control-throw', () => {
      if (this.clock) this.clock.addThrow();
      else this.lab.addThrow();
    });
    this.throwBtn.title = 'Throw the ball in every panel at the same moment';

    this.clockOut = h('span', { class: 'clock', 'data-testid': 'readout-clock' }, '0.000 s');
    this.modeOut = h('span', { class: 'mode' });
    this.eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Display events so far' });

    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'Simulated display' },
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label', id: 'rate-label' }, 'Display'),
        rates,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('label', { class: 'control-label', for: 'jitter' }, 'Jitter'),
        this.jitterInput,
        this.jitterOut,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Trouble'),
        this.hitchBtn,
        this.hiddenBtn,
        this.slowBtn,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Draw'),
        this.interpBtn,
        this.clockBtn,
      ),
      h(
        'div',
        { class: 'control-group time-group' },
        h('span', { class: 'control-label' }, 'Time'),
        this.pauseBtn,
        this.skipBtn,
        this.restartBtn,
        this.throwBtn,
      ),
      h(
        'div',
        { class: 'status', 'aria-live': 'off' },
        h('span', { class: 'status-item' }, 't = ', this.clockOut),
        this.modeOut,
        this.eventsOut,
      ),
    );

    // Show the result of any control at once, not on the next animation frame.
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ panels
    this.panelGrid = h('div', { class: 'panels' });
    for (const spec of PANELS) this.panelGrid.append(this.buildPanel(spec));

    // ------------------------------------------------------------ page
    root.append(
      h(
        'article',
        { class: 'chapter loop-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 1'),
          h('h1', {}, 'The loop'),
          h(
            'p',
            { class: 'lede' },
            'A game is a loop: read input, update the world, draw it. How that loop turns the clock on the wall into updates decides whether your game runs the same on every machine — or faster on a gaming monitor, differently after a hiccup, and never the same twice.',
          ),
        ),
        this.evolution(),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'bench-title' },
          h('h2', { id: 'bench-title' }, 'Five loops, one ball, one display'),
          h(
            'p',
            { class: 'section-intro' },
            'Each panel runs the same scene — a ball thrown in a 12 × 7 m box, with the same scripted throws at the same real moments — under a different loop. All five watch the same simulated display. Change the display and see which loops notice.',
          ),
          controls,
          this.panelGrid,
          legend(),
        ),
        this.experiments(),
        howItWorks(),
      ),
    );

    // ------------------------------------------------------------ wiring
    this.observer = new ResizeObserver(() => {
      this.resize();
    });
    for (const p of this.panels) this.observer.observe(p.canvas);

    const onVisibility = () => {
      if (document.hidden) this.clock?.markHidden();
    };
    document.addEventListener('visibilitychange', onVisibility);
    this.cleanups.push(() => {
      document.removeEventListener('visibilitychange', onVisibility);
    });

    this.resize();
    this.refreshControls();
    this.driver.start();
  }

  private get paused(): boolean {
    return this.driver.isPaused;
  }

  destroy(): void {
    this.driver.destroy();
    this.observer.disconnect();
    for (const c of this.cleanups) c();
    for (const p of this.panels) p.chart?.destroy();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- building

  private evolution(): HTMLElement {
    const steps: IdeaCard[] = [
      {
        title: 'Frame-locked',
        color: COLORS['frame-locked']!,
        text: 'Update once per drawn frame and assume every frame lasts 1/60 s. Nothing measures time, so time is the machine: on a 144 Hz screen the game runs 2.4 times too fast, on a slow one in slow motion.',
        snippet: 'velocity += acceleration\nposition += velocity',
      },
      {
        title: 'Variable Δt',
        color: COLORS.variable!,
        text: 'Measure how long the frame took and move by that much. The speed is right on average, but every machine now takes different steps: physics depends on the frame rate, and a 2 s hiccup becomes one 2 s step — straight through a wall.',
        snippet: 'dt = now - last\nupdate(dt)',
      },
      {
        title: 'Fixed step',
        color: COLORS['fixed-naive']!,
        text: 'Put real time in an accumulator and pay it out in equal steps of 30 ms. Every display runs the very same steps, so the same inputs give the same game. As on the slides, nothing bounds the debt yet.',
        snippet: 'acc += dt\nwhile (acc > STEP) {\n  update(STEP); acc -= STEP\n}',
      },
      {
        title: 'Final fixes',
        color: COLORS['fixed-final']!,
        text: 'Time never runs backwards (Δt ≥ 0), and the accumulator is capped at 1 s, so a long pause can no longer demand hundreds of steps in one frame.',
        snippet: 'dt = max(0, now - last)\nacc = clamp(acc + dt, 0, 1.0)',
      },
      {
        title: 'FixedLoop',
        color: COLORS.fixed!,
        text: 'What a real game adds: time as an integer tick count (no drifting float sums), a cap on steps per frame with an explicit overload policy, every dropped millisecond counted, hidden tabs paused — and α for the renderer to draw between the last two states.',
        snippet: 'n = loop.frame(now)\nfor (…n) world.step()\nrender(loop.alpha)',
      },
    ];
    return ideaCards({ id: 'evolution-title', title: 'How the loop evolved', cards: steps });
  }

  private buildPanel(spec: PanelSpec): HTMLElement {
    const color = COLORS[spec.id] ?? '#38bdf8';
    const canvas = h('canvas', {
      class: 'scene',
      role: 'img',
      'aria-label': `The ball as the ${spec.title} loop draws it`,
      'data-testid': `canvas-${spec.id}`,
    });
    const ctx = canvas.getContext('2d');
    if (!ctx) throw new Error('The lab needs a 2D canvas');
    const values = new Map<Field, HTMLElement>();
    const valueCells = new Map<Field, HTMLElement>();
    const swatches = new Map<Field, HTMLElement>();
    const rows = ROWS.map((row) => {
      const isHash = row.field === 'hash' || row.field === 'checkpointHash';
      const text = h('span', {});
      const sw = h('span', { class: 'swatch', 'aria-hidden': 'true' });
      const value = h(
        'dd',
        {
          'data-testid': `readout-${spec.id}-${row.id}`,
          'data-value': '',
          class: isHash && 'hash',
        },
        isHash && sw,
        text,
      );
      values.set(row.field, text);
      valueCells.set(row.field, value);
      if (isHash) swatches.set(row.field, sw);
      return [h('dt', { title: row.title }, row.label), value];
    }).flat();
    const stall = h(
      'p',
      {
        class: 'stall',
        role: 'status',
        'data-testid': `readout-${spec.id}-stalled`,
        'data-value': 'false',
        hidden: true,
      },
      'Stalled',
    );
    const overlay = h('p', { class: 'overlay', hidden: true, 'aria-hidden': 'true' });
    const chartHost = h('div', {
      class: 'chart',
      role: 'img',
      'aria-label': `Steps per frame over the last ${HISTORY_MS / 1000} s, ${spec.title}`,
    });
    this.panels.push({
      spec,
      color,
      canvas,
      ctx,
      chartHost,
      chart: undefined,
      values,
      valueCells,
      swatches,
      stall,
      overlay,
      w: 0,
      h: 0,
      dpr: 1,
    });
    return h(
      'section',
      {
        class: 'panel',
        style: `--accent: ${color}`,
        'data-panel': spec.id,
        'aria-labelledby': `panel-${spec.id}`,
      },
      h(
        'header',
        { class: 'panel-head' },
        h('h3', { id: `panel-${spec.id}` }, spec.title),
        h('p', {}, spec.tagline),
      ),
      h('div', { class: 'scene-wrap' }, canvas, overlay, stall),
      h('dl', { class: 'readouts' }, rows),
      h('p', { class: 'chart-title' }, 'Steps per frame'),
      chartHost,
    );
  }

  private experiments(): HTMLElement {
    const items: { title: string; text: string; action: string; run: () => void }[] = [
      {
        title: 'A faster screen',
        text: 'Switch the display to 144 Hz. The frame-locked ball now runs 2.4 times too fast (look at its sim / real). The variable-Δt ball keeps the right speed but follows a different path. The three fixed loops do not notice: same ticks, same Hash @150.',
        action: 'Show 144 Hz',
        run: () => {
          this.setUp({ hz: 144 });
        },
      },
      {
        title: 'A hitch',
        text: 'No frame for 2 s, then life goes on. Variable Δt takes one 2 s update. The slides’ accumulator runs every owed step in one frame (look at max steps), the final fixes clamp the debt at 1 s, and FixedLoop runs at most 8 steps and counts what it dropped.',
        action: 'Drop a 2 s hitch',
        run: () => {
          this.setUp({});
          this.lab.addEvent('hitch', HITCH_MS);
        },
      },
      {
        title: 'A tab in the background',
        text: 'The page is hidden for 10 s (press Skip twice to get through it). On return the naive loop fast-forwards 10 s at once; FixedLoop pauses instead and counts the hidden time as dropped.',
        action: 'Hide the tab',
        run: () => {
          this.setUp({});
          this.lab.addEvent('hidden', HIDDEN_MS);
        },
      },
      {
        title: 'A slow machine',
        text: `Each update now costs ${SLOW_UPDATE_COST_MS} ms but simulates only ${STEP_MS} ms. The slides’ loop spirals: each frame owes more steps than the last, until the page stalls. The clamp bounds the debt; FixedLoop caps the steps per frame and stays responsive, in slow motion.`,
        action: 'Slow this machine down',
        run: () => {
          this.setUp({ slow: true });
        },
      },
      {
        title: 'Stutter',
        text: `At 144 Hz a ${STEP_MS} ms step lasts 4–5 frames. Turn interpolation off and the fixed balls stand still for several frames, then jump: their trails turn into clumps of dots. With interpolation they are drawn between the last two states, at α = accumulator / step.`,
        action: 'Show stutter',
        run: () => {
          this.setUp({ hz: 144 });
          this.setInterpolation(false);
        },
      },
    ];
    return h(
      'section',
      { class: 'experiments', 'aria-labelledby': 'experiments-title' },
      h('h2', { id: 'experiments-title' }, 'Things to try'),
      h(
        'ol',
        { class: 'experiment-list' },
        items.map((item) => {
          const btn = h('button', { type: 'button', class: 'btn btn-small' }, item.action);
          btn.addEventListener('click', () => {
            if (this.clock) this.setRealClock(false);
            item.run();
            this.setPaused(false);
            this.refreshControls();
            this.render();
            this.panelGrid.scrollIntoView({ block: 'nearest' });
          });
          return h('li', {}, h('h3', {}, item.title), h('p', {}, item.text), btn);
        }),
      ),
    );
  }

  // ---------------------------------------------------------------- state changes

  /**
   * A card's fresh run, whatever was clicked before: the default display (60 Hz, no jitter, no
   * slow machine, no events or throws) changed by `change`, interpolation on, replayed from zero
   * to {@link EXPERIMENT_LEAD_MS}.
   */
  private setUp(change: Partial<LoopLabSettings>): void {
    this.lab.restart();
    this.lab.update({ ...defaultSettings(), ...change });
    this.lab.advanceTo(EXPERIMENT_LEAD_MS);
    const s = this.lab.settings;
    const input = this.rateInputs.get(s.hz);
    if (input) input.checked = true;
    this.jitterInput.value = String(Math.round(s.jitter * 100));
    this.setInterpolation(true);
  }

  private setInterpolation(on: boolean): void {
    this.interpolate = on;
    this.interpBtn.setAttribute('aria-pressed', String(on));
  }

  private setPaused(paused: boolean): void {
    if (paused === this.paused) return;
    this.driver.setPaused(paused);
    this.refreshControls();
  }

  private setRealClock(on: boolean): void {
    this.clock = on ? new ClockLab() : undefined;
    this.driver.setReal(on);
    this.clockBtn.setAttribute('aria-pressed', String(on));
    this.refreshControls();
  }

  private restart(): void {
    if (this.clock) this.setRealClock(true);
    else this.lab.restart();
    this.refreshControls();
  }

  private refreshControls(): void {
    const sim = this.clock === undefined;
    for (const input of this.rateInputs.values()) input.disabled = !sim;
    this.jitterInput.disabled = !sim;
    this.hitchBtn.disabled = !sim;
    this.hiddenBtn.disabled = !sim;
    this.slowBtn.disabled = !sim;
    this.skipBtn.disabled = !sim;
    const s = this.lab.settings;
    this.slowBtn.setAttribute('aria-pressed', String(s.slow));
    setText(this.jitterOut, `${Math.round(s.jitter * 100)} %`);
    setText(this.pauseBtn, this.paused ? 'Play' : 'Pause');
    this.pauseBtn.setAttribute('aria-pressed', String(this.paused));
    this.eventsOut.replaceChildren(
      ...(sim
        ? [
            ...s.events.map((e) =>
              h(
                'li',
                { class: `event event-${e.kind}` },
                `${e.kind === 'hitch' ? 'hitch' : 'hidden'} at ${(e.atMs / 1000).toFixed(1)} s`,
              ),
            ),
            ...(s.throws.length > 0
              ? [h('li', { class: 'event event-throw' }, `${s.throws.length} throw(s)`)]
              : []),
          ]
        : []),
    );
  }

  private resize(): void {
    for (const p of this.panels) {
      const rect = p.canvas.getBoundingClientRect();
      const dpr = Math.min(window.devicePixelRatio || 1, 3);
      const w = Math.max(1, Math.round(rect.width * dpr));
      const hh = Math.max(1, Math.round(rect.height * dpr));
      if (w !== p.w || hh !== p.h) {
        p.canvas.width = w;
        p.canvas.height = hh;
        p.w = w;
        p.h = hh;
        p.dpr = dpr;
      }
      const cw = Math.floor(p.chartHost.getBoundingClientRect().width);
      if (!p.chart && cw > 0) p.chart = new StepsChart(p.chartHost, p.color, cw);
      else p.chart?.resize(cw);
    }
  }

  // ---------------------------------------------------------------- drawing

  private render(): void {
    if (this.clock) this.draw(this.clock.runs, this.clock.timeMs);
    else this.draw(this.lab.runs, this.lab.timeMs);
  }

  private draw(runs: PanelRun[], t: number): void {
    setText(this.clockOut, fmt.seconds(t / 1000));
    setAttr(this.clockOut, 'data-value', fmt.exact(t));
    const hz = this.driver.measuredHz;
    setText(
      this.modeOut,
      this.clock
        ? `real clock · your display ≈ ${hz} Hz${this.paused ? ' · paused' : ''}`
        : `simulated display · ${this.lab.settings.hz} Hz${this.paused ? ' · paused' : ''}`,
    );
    const active = this.clock ? undefined : this.lab.activeEvent();
    runs.forEach((run, i) => {
      const p = this.panels[i];
      if (p) this.drawPanel(p, run, t, active?.kind);
    });
  }

  private drawPanel(p: PanelView, run: PanelRun, t: number, event?: 'hitch' | 'hidden'): void {
    const r = run.readouts();
    this.writeReadouts(p, r);

    // Overlay: why nothing moves.
    const overlay = event === 'hitch' ? 'Hitch: no frames' : event === 'hidden' ? 'Tab hidden' : '';
    p.overlay.hidden = overlay === '';
    setText(p.overlay, overlay);

    // Scene.
    const { ctx, w, h: hh } = p;
    if (w <= 1 || hh <= 1) return;
    const s = Math.min(w / BOX_W, hh / BOX_H);
    const ox = (w - BOX_W * s) / 2;
    const oy = (hh - BOX_H * s) / 2;
    const px = (x: number) => ox + x * s;
    const py = (y: number) => oy + (BOX_H - y) * s;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#0a1122';
    ctx.fillRect(0, 0, w, hh);
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.10)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let x = 1; x < BOX_W; x++) {
      ctx.moveTo(Math.round(px(x)) + 0.5, py(BOX_H));
      ctx.lineTo(Math.round(px(x)) + 0.5, py(0));
    }
    for (let y = 1; y < BOX_H; y++) {
      ctx.moveTo(px(0), Math.round(py(y)) + 0.5);
      ctx.lineTo(px(BOX_W), Math.round(py(y)) + 0.5);
    }
    ctx.stroke();
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.45)';
    ctx.lineWidth = Math.max(1, p.dpr);
    ctx.strokeRect(px(0) + 0.5, py(BOX_H) + 0.5, BOX_W * s - 1, BOX_H * s - 1);

    const radius = run.rig.scene.config.radius * s;
    const pts = run.trailPoints(run.rig.realMs, this.interpolate, this.trailScratch);
    ctx.fillStyle = p.color;
    const dot = Math.max(1.5, radius * 0.32);
    for (let k = 0; k < pts.length; k += 3) {
      ctx.globalAlpha = 0.75 * (1 - pts[k + 2]!);
      ctx.beginPath();
      ctx.arc(px(pts[k]!), py(pts[k + 1]!), dot, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.globalAlpha = 1;
    const ball = run.ballAt(this.interpolate);
    ctx.beginPath();
    ctx.arc(px(ball.x), py(ball.y), radius, 0, 2 * Math.PI);
    ctx.fill();
    ctx.lineWidth = Math.max(1, p.dpr);
    ctx.strokeStyle = 'rgba(255, 255, 255, 0.85)';
    ctx.stroke();

    // Steps per frame over the window.
    if (p.chart) {
      const xs: number[] = [];
      const ys: number[] = [];
      const from = t - HISTORY_MS;
      for (let k = 0; k < run.history.size; k++) {
        const ft = run.history.get(k, 0);
        // Keep the last frame before the window too, so a sparse run still draws its step.
        const next = k + 1 < run.history.size ? run.history.get(k + 1, 0) : Infinity;
        if (next < from) continue;
        xs.push(Math.max(ft, from) / 1000);
        ys.push(run.history.get(k, 1));
      }
      p.chart.set(xs, ys, from / 1000, t / 1000);
    }
  }

  private writeReadouts(p: PanelView, r: PanelReadouts): void {
    const put = (field: Field, text: string, value: number | string | boolean | undefined) => {
      const el = p.values.get(field);
      const cell = p.valueCells.get(field);
      if (!el || !cell) return;
      setText(el, text);
      setAttr(cell, 'data-value', fmt.exact(value));
    };
    put('simS', fmt.seconds(r.simS), r.simS);
    put('realS', fmt.seconds(r.realS), r.realS);
    put('ratio', fmt.ratio(r.ratio), r.ratio);
    put('steps', fmt.count(r.steps), r.steps);
    put('maxSteps', fmt.count(r.maxSteps), r.maxSteps);
    put('droppedMs', fmt.millis(r.droppedMs), r.droppedMs);
    put('hash', r.hash, r.hash);
    put('checkpointHash', r.checkpointHash ?? 'not yet', r.checkpointHash);
    for (const [field, sw] of p.swatches) {
      const hex = field === 'hash' ? r.hash : r.checkpointHash;
      setAttr(sw, 'style', hex ? `--swatch: hsl(${fmt.hashHue(hex)} 80% 60%)` : '');
    }
    const ratioEl = p.valueCells.get('ratio');
    if (ratioEl) {
      const off = Number.isFinite(r.ratio) && Math.abs(r.ratio - 1) > 0.05;
      ratioEl.classList.toggle('warn', off);
    }
    p.stall.hidden = !r.stalled;
    setAttr(p.stall, 'data-value', String(r.stalled));
    setText(
      p.stall,
      r.stalled ? `Stalled: ${fmt.count(r.owed)} updates owed, never run` : 'Stalled',
    );
  }
}

function legend(): HTMLElement {
  return h(
    'details',
    { class: 'legend' },
    h('summary', {}, 'How to read a panel'),
    h(
      'dl',
      {},
      ROWS.map((row) => [h('dt', {}, row.label), h('dd', {}, row.title)]).flat(),
      h('dt', {}, 'Trail'),
      h(
        'dd',
        {},
        'One dot per display frame over the last 0.6 s: even spacing is smooth motion, clumps are stutter.',
      ),
      h('dt', {}, 'Colour chips'),
      h('dd', {}, 'Derived from the hash: equal colours, equal states.'),
    ),
  );
}

function howItWorks(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'how-title' },
    h('h2', { id: 'how-title' }, 'How this page works'),
    h(
      'p',
      {},
      'The display here is simulated: frame times are computed, not measured, so every run is exactly repeatable. On each real animation frame the page moves a virtual clock forward by the real time that passed and runs, for every panel, the display frames due by then. “Skip +5 s” moves the virtual clock at once.',
    ),
    h(
      'p',
      {},
      'Changing the display (its rate, jitter, a hitch, a hidden tab, a slow machine, a throw) rebuilds all five runs and replays them from zero to the current moment. The loops are deterministic, so the replay lands on exactly the state a live run would have reached.',
    ),
    h(
      'p',
      {},
      '“Real clock” feeds the loops this page’s own requestAnimationFrame times instead. Switch to another tab for a few seconds and come back to see a real hidden tab.',
    ),
  );
}
