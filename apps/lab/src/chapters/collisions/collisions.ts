/**
 * Chapter 3 — Collisions. Bodies fired at a wall under a variable Δt and under a fixed step,
 * with discrete detection and with CCD, on a simulated display (or the page's real clock). The
 * numbers come from {@link CollisionsLab}; this module only builds the page and draws.
 */
import { RANGE_HALF_HEIGHT, RANGE_HALF_WIDTH, ShotStatus, type WallRange } from '@fixedstep/games';
import {
  ClockRanges,
  CollisionsLab,
  DISPLAY_RATES,
  EXPERIMENTS,
  FIRE_EVERY_S,
  HITCH_MS,
  JITTER,
  LANES,
  MAX_REAL_FRAME_MS,
  PANELS,
  RADIUS,
  SPEED,
  STEP_MS,
  STEP_S,
  WALL,
  type DisplayRate,
  type Experiment,
  type RangePanel,
  type RangePanelSpec,
  type RangeReadouts,
  type SettingResult,
  type SliderSpec,
} from './collisions-lab.js';
import { CHART_COLORS, WallChart } from './collisions-chart.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import { ideaCards, type IdeaCard } from '../../ui/cards.js';
import { LabDriver } from '../../shell/driver.js';
import {
  TimeControls,
  button,
  setPressed,
  slider,
  toggle,
  type Slider,
} from '../../ui/controls.js';
import * as fmt from '../../ui/format.js';
import './collisions.css';

const COLORS: Readonly<Record<string, string>> = {
  variable: '#f87171',
  fixed: '#38bdf8',
};
const BODY = { flying: '#e2e8f0', bounced: '#34d399', through: '#e879f9' } as const;

const SKIP_MS = 5000;
/** The strip at the top of a panel's canvas that holds the step ruler, CSS px. */
const RULER_STRIP = 38;
const RULE_COLOR = '#fbbf24';
const BOUNCE_COLOR = '#34d399';
/** The arena as drawn: a little margin around the range. */
const VIEW_W = 2 * RANGE_HALF_WIDTH + 1;
const VIEW_H = 2 * RANGE_HALF_HEIGHT + 1;

type Field = 'fired' | 'tunnelled' | 'ccd-tunnelled' | 'share' | 'dt' | 'max-dt' | 'steps' | 'sim';

/** The readout rows of a panel: test id suffix, label, what it means; `time` rows go right. */
const ROWS: readonly { field: Field; label: string; title: string; time?: true }[] = [
  { field: 'fired', label: 'Fired', title: 'Bodies fired at the wall so far' },
  {
    field: 'tunnelled',
    label: 'Through, discrete',
    title: 'Bodies that ended on the far side with discrete detection only (of those resolved)',
  },
  {
    field: 'ccd-tunnelled',
    label: 'Through, CCD',
    title: 'The same shots with continuous collision detection',
  },
  {
    field: 'share',
    label: 'Share through',
    title: 'Through / resolved, discrete detection',
  },
  { field: 'dt', label: 'Last step', title: 'The Δt of the last update', time: true },
  { field: 'max-dt', label: 'Longest step', title: 'The longest update so far', time: true },
  {
    field: 'steps',
    label: 'Steps / frame',
    title: 'Updates the last display frame ran',
    time: true,
  },
  { field: 'sim', label: 'Sim time', title: 'Time as the loop has simulated it', time: true },
];

/** The per-setting table's columns; `short` labels a value when a narrow screen stacks a row. */
const RESULT_COLUMNS: readonly { label: string; short: string; cls: string; title: string }[] = [
  { label: 'Speed', short: 'Speed', cls: 'col-speed', title: 'Speed of the bodies' },
  { label: 'Wall', short: 'Wall', cls: 'col-wall', title: 'Wall thickness' },
  { label: 'Ran', short: 'Ran', cls: 'col-ran', title: 'Virtual time the setting ran for' },
  {
    label: 'Variable Δt',
    short: 'Variable Δt',
    cls: 'col-num',
    title: 'Through / resolved, variable Δt, discrete detection',
  },
  {
    label: 'Fixed step',
    short: 'Fixed step',
    cls: 'col-num',
    title: 'Through / resolved, fixed step, discrete detection',
  },
  {
    label: 'Theory, fixed',
    short: 'Theory, fixed',
    cls: 'col-num',
    title: 'The share through that geometry predicts for the fixed step',
  },
  {
    label: 'CCD',
    short: 'CCD, both',
    cls: 'col-num',
    title: 'Through / resolved, the CCD twins of both loops',
  },
];

interface PanelView {
  readonly spec: RangePanelSpec;
  readonly color: string;
  readonly canvas: HTMLCanvasElement;
  readonly ctx: CanvasRenderingContext2D;
  readonly values: Map<Field, HTMLElement>;
  readonly cells: Map<Field, HTMLElement>;
  readonly rows: Map<Field, HTMLElement>;
  readonly overlay: HTMLElement;
  readonly tally: HTMLElement;
  w: number;
  h: number;
  dpr: number;
}

export function mount(root: HTMLElement): () => void {
  const chapter = new CollisionsChapter(root);
  return () => {
    chapter.destroy();
  };
}

class CollisionsChapter {
  private readonly lab = new CollisionsLab();
  private clock: ClockRanges | undefined;
  private readonly driver: LabDriver;
  private interpolate = true;
  private ccd = false;
  private readonly panels: PanelView[] = [];
  private readonly observer: ResizeObserver;
  private readonly cleanups: (() => void)[] = [];
  private chart: WallChart | undefined;
  private readonly pos = { x: 0, y: 0 };

  private readonly speed: Slider;
  private readonly wall: Slider;
  private readonly jitter: Slider;
  private readonly rateInputs = new Map<DisplayRate, HTMLInputElement>();
  private readonly hitchBtn: HTMLButtonElement;
  private readonly ccdBtn: HTMLButtonElement;
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly time: TimeControls;
  private readonly eventsOut: HTMLElement;
  private readonly panelGrid: HTMLElement;
  private readonly chartHost: HTMLElement;
  private readonly ruleValues = new Map<string, HTMLElement>();
  private readonly totals = new Map<string, HTMLElement>();
  private readonly resultsBody: HTMLTableSectionElement;
  private resultsKey = '';

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
    const s = this.lab.settings;
    // ------------------------------------------------------------ controls
    this.speed = rangeSlider(
      'speed',
      'Speed',
      SPEED,
      s.speed,
      (v) => `${v.toFixed(0)} m/s`,
      (v) => {
        this.changeSetting({ speed: v });
      },
    );
    this.wall = rangeSlider(
      'wall',
      'Wall',
      WALL,
      s.wall,
      (v) => `${v.toFixed(1)} m`,
      (v) => {
        this.changeSetting({ wall: v });
      },
    );
    this.jitter = rangeSlider(
      'jitter',
      'Jitter',
      JITTER,
      s.jitter * 100,
      (v) => `±${v.toFixed(0)} %`,
      (v) => {
        this.lab.update({ jitter: v / 100 });
      },
    );
    const rates = h(
      'div',
      { class: 'segmented', role: 'radiogroup', 'aria-label': 'Simulated display refresh rate' },
      DISPLAY_RATES.map((hz) => {
        const input = h('input', {
          type: 'radio',
          name: 'collisions-hz',
          value: hz,
          id: `col-hz-${hz}`,
          checked: hz === s.hz,
        });
        input.addEventListener('change', () => {
          if (input.checked) this.lab.update({ hz });
        });
        this.rateInputs.set(hz, input);
        return h(
          'label',
          { for: `col-hz-${hz}`, 'data-testid': `control-hz-${hz}` },
          input,
          h('span', {}, `${hz} Hz`),
        );
      }),
    );
    this.hitchBtn = button(`${HITCH_MS} ms hitch`, 'control-hitch', () => {
      this.lab.addHitch();
    });
    this.hitchBtn.title = `No display frame for ${HITCH_MS} ms: the variable loop's next step is at least that long`;
    this.ccdBtn = toggle('CCD twins', 'control-ccd', false, (on) => {
      this.ccd = on;
    });
    this.ccdBtn.title =
      'Draw the twin ranges that use continuous collision detection instead of the discrete ones (both always run)';
    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw the fixed step between its last two states, at alpha';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setRealClock(on);
    });
    this.clockBtn.title = 'Feed both loops this page’s own requestAnimationFrame times';
    this.time = new TimeControls({
      onPause: () => {
        this.setPaused(!this.driver.isPaused);
      },
      onSkip: () => {
        this.lab.advanceBy(SKIP_MS);
      },
      onRestart: () => {
        this.restart();
      },
      skipMs: SKIP_MS,
    });

    this.eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Hitches so far' });

    this.jitter.el.append(this.hitchBtn);
    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'The range and its display' },
      this.speed.el,
      this.wall.el,
      h('div', { class: 'control-group' }, h('span', { class: 'control-label' }, 'Display'), rates),
      this.jitter.el,
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Draw'),
        this.ccdBtn,
        this.interpBtn,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Clock'),
        this.clockBtn,
      ),
      h(
        'div',
        { class: 'control-group time-group' },
        h('span', { class: 'control-label' }, 'Time'),
        ...this.time.buttons,
      ),
      h(
        'div',
        { class: 'status', 'aria-live': 'off' },
        this.time.status[0],
        this.time.status[1],
        this.eventsOut,
      ),
    );
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ panels
    this.panelGrid = h('div', { class: 'panels range-panels' });
    for (const spec of PANELS) this.panelGrid.append(this.buildPanel(spec));

    const totals = h(
      'dl',
      { class: 'range-totals', 'aria-label': 'Totals at this setting' },
      this.total('variable-tunnelled', 'Variable Δt, discrete', 'through'),
      this.total('fixed-tunnelled', 'Fixed step, discrete', 'through'),
      this.total('ccd-tunnelled', 'Either loop, CCD', 'through'),
    );

    this.resultsBody = h('tbody', {});
    const results = h(
      'div',
      { class: 'results-wrap' },
      h(
        'table',
        { class: 'results', 'data-testid': 'results-table' },
        h('caption', {}, 'Through the wall, per setting tried (through / resolved)'),
        h(
          'thead',
          {},
          h(
            'tr',
            {},
            ...RESULT_COLUMNS.map((c) =>
              h('th', { scope: 'col', class: c.cls, title: c.title }, c.label),
            ),
          ),
        ),
        this.resultsBody,
      ),
    );

    // ------------------------------------------------------------ chart
    this.chartHost = h('div', {
      class: 'wall-chart',
      role: 'img',
      'aria-label':
        'Wall thickness against speed for the fixed step: the talk’s rule, the correct-bounce bound, the current setting and the settings tried',
      'data-testid': 'chart-walls',
    });

    root.append(
      h(
        'article',
        { class: 'chapter collisions-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 3'),
          h('h1', {}, 'Collisions'),
          h(
            'p',
            { class: 'lede' },
            'A simulation does not watch bodies move: it teleports them one step at a time and then looks for overlaps. A body that jumps farther in one step than a wall is thick can land beyond it, and nothing ever saw them touch. Even a shorter jump can end past the middle of the wall, and the engine pushes an overlapping body out through the nearest face — here the far one. So every body bounces only while one step is at most half the wall plus the body’s radius. With a variable Δt the step is as long as the last frame — a hiccup of the display is a giant leap through the wall.',
          ),
        ),
        ideas(),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'range-title' },
          h('h2', { id: 'range-title' }, 'The firing range'),
          h(
            'p',
            { class: 'section-intro' },
            `A body of radius ${RADIUS * 100} cm leaves the muzzle every ${FIRE_EVERY_S} s, in one of ${LANES} lanes, straight at a wall. Both panels fire the same shots; the left takes one step per display frame, the right takes steps of ${STEP_MS} ms. Each also runs a twin with continuous detection (CCD) — press CCD twins to draw those instead. Bodies that end up on the far side turn magenta. The bar above each range is one step; once it is longer than the green bar below it (half the wall plus the radius), some bodies are pushed through.`,
          ),
          controls,
          this.panelGrid,
          totals,
          legend(),
        ),
        h(
          'section',
          { class: 'wall-chart-section', 'aria-labelledby': 'chart-title' },
          h('h2', { id: 'chart-title' }, 'Speed × thickness'),
          h(
            'p',
            { class: 'section-intro' },
            `Which walls are safe at which speed, for a fixed step of ${STEP_MS} ms and a body of radius ${RADIUS} m. Below the amber line the wall is thinner than one step and a body can jump over it unseen. The talk’s rule puts the wall on that line — but a discrete engine pushes an overlapping body out through the nearer face, so a body that lands past the middle of the wall leaves on the far side. Only above the green line (v·dt ≤ w/2 + r) does every body bounce. Click the chart to try a setting; each one tried stays as a dot, magenta if some went through.`,
          ),
          h('div', { class: 'wall-chart-wrap' }, this.chartHost, this.ruleReadouts()),
          chartLegend(),
          results,
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
    this.observer.observe(this.chartHost);
    // Anything above the chart that changes height moves it: uPlot must measure it again.
    this.observer.observe(controls);
    this.observer.observe(this.panelGrid);

    this.resize();
    this.refreshControls();
    this.render();
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    this.observer.disconnect();
    for (const c of this.cleanups) c();
    this.chart?.destroy();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- building

  private buildPanel(spec: RangePanelSpec): HTMLElement {
    const color = COLORS[spec.id] ?? '#38bdf8';
    const canvas = h('canvas', {
      class: 'scene range-scene',
      role: 'img',
      'aria-label': `The firing range under ${spec.title}`,
      'data-testid': `canvas-${spec.id}`,
    });
    const ctx = canvas.getContext('2d');
    if (!ctx) throw new Error('The lab needs a 2D canvas');
    const values = new Map<Field, HTMLElement>();
    const cells = new Map<Field, HTMLElement>();
    const rows = new Map<Field, HTMLElement>();
    const list = (time: boolean) =>
      ROWS.filter((row) => (row.time ?? false) === time)
        .map((row) => {
          const text = h('span', {});
          const cell = h('dd', { 'data-testid': `readout-${spec.id}-${row.field}` }, text);
          const dt = h('dt', { title: row.title }, row.label);
          values.set(row.field, text);
          cells.set(row.field, cell);
          rows.set(row.field, dt);
          return [dt, cell];
        })
        .flat();
    const overlay = h('p', { class: 'overlay', hidden: true });
    const tally = h('p', { class: 'range-tally', 'aria-hidden': 'true' });
    this.panels.push({
      spec,
      color,
      canvas,
      ctx,
      values,
      cells,
      rows,
      overlay,
      tally,
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
      h('div', { class: 'scene-wrap' }, canvas, overlay, tally),
      h(
        'div',
        { class: 'range-readouts' },
        h('dl', { class: 'readouts', 'aria-label': 'Shots' }, list(false)),
        h('dl', { class: 'readouts', 'aria-label': 'Steps' }, list(true)),
      ),
    );
  }

  private total(id: string, label: string, unit: string): HTMLElement {
    const value = h('span', {});
    const dd = h('dd', { 'data-testid': `readout-${id}` }, value, ` ${unit}`);
    this.totals.set(id, value);
    this.totals.set(`${id}:cell`, dd);
    return h('div', { class: 'range-total' }, h('dt', {}, label), dd);
  }

  private ruleReadouts(): HTMLElement {
    const rows: { id: string; label: string; title: string }[] = [
      {
        id: 'min-wall',
        label: 'One step v·dt = minWallSize',
        title:
          'How far a body moves in one fixed step — the talk’s rule makes that the thinnest wall a body cannot jump over unseen',
      },
      {
        id: 'bounce-wall',
        label: 'All bounce if w ≥ 2(v·dt − r)',
        title: 'The thinnest wall from which every body bounces: v·dt ≤ w/2 + r',
      },
      {
        id: 'max-safe-speed',
        label: 'Max safe speed, (w/2 + r) / dt',
        title: 'The fastest body that always bounces off this wall',
      },
      {
        id: 'theory-share',
        label: 'Theory, share through',
        title: 'max(0, 1 − (w + 2r) / (2·v·dt)), fixed step, uniform phase',
      },
      {
        id: 'measured-share',
        label: 'Measured, fixed step',
        title: 'Through / resolved in the fixed-step panel, discrete detection',
      },
    ];
    return h(
      'dl',
      { class: 'readouts rule-readouts', 'aria-label': 'The rule at this setting' },
      rows
        .map((r) => {
          const value = h('span', {});
          // One step and minWallSize are the same number: one row, both readouts.
          const inner =
            r.id === 'min-wall'
              ? h('span', { 'data-testid': 'readout-step-distance' }, value)
              : value;
          const dd = h('dd', { 'data-testid': `readout-${r.id}` }, inner);
          this.ruleValues.set(r.id, value);
          this.ruleValues.set(`${r.id}:cell`, dd);
          if (inner !== value) this.ruleValues.set('step-distance:cell', inner);
          return [h('dt', { title: r.title }, r.label), dd];
        })
        .flat(),
    );
  }

  private experiments(): HTMLElement {
    return h(
      'section',
      { class: 'experiments', 'aria-labelledby': 'col-experiments-title' },
      h('h2', { id: 'col-experiments-title' }, 'Things to try'),
      h(
        'ol',
        { class: 'experiment-list' },
        EXPERIMENTS.map((item, i) => {
          const btn = h(
            'button',
            { type: 'button', class: 'btn btn-small', 'data-testid': `experiment-${i + 1}` },
            item.action,
          );
          btn.addEventListener('click', () => {
            this.runExperiment(item);
            this.panelGrid.scrollIntoView({ block: 'nearest' });
          });
          return h('li', {}, h('h3', {}, item.title), h('p', {}, item.text), btn);
        }),
      ),
    );
  }

  /** Set everything the experiment's text assumes and start again from zero, playing. */
  private runExperiment(item: Experiment): void {
    if (this.clock) this.setRealClock(false);
    const s = item.settings;
    this.lab.startOver(s);
    this.speed.set(s.speed);
    this.wall.set(s.wall);
    this.jitter.set(Math.round(s.jitter * 100));
    const radio = this.rateInputs.get(s.hz);
    if (radio) radio.checked = true;
    this.ccd = item.ccd;
    setPressed(this.ccdBtn, item.ccd);
    this.setPaused(false);
    this.refreshControls();
    this.render();
  }

  // ---------------------------------------------------------------- state changes

  private changeSetting(change: { speed?: number; wall?: number }): void {
    const speed = snap(change.speed ?? this.lab.settings.speed, SPEED);
    const wall = snap(change.wall ?? this.lab.settings.wall, WALL);
    this.speed.set(speed);
    this.wall.set(wall);
    if (this.clock) {
      // A new setting starts a new real-clock run.
      this.lab.remember(this.clock.result());
      this.lab.update({ speed, wall });
      this.clock = new ClockRanges({ speed, wall });
      this.driver.restartReal();
    } else {
      this.lab.update({ speed, wall });
    }
    this.refreshControls();
    this.render();
  }

  private setPaused(paused: boolean): void {
    this.driver.setPaused(paused);
    this.refreshControls();
  }

  private setRealClock(on: boolean): void {
    if (on) {
      this.clock = new ClockRanges({
        speed: this.lab.settings.speed,
        wall: this.lab.settings.wall,
      });
    } else {
      this.clock = undefined;
    }
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
    this.jitter.input.disabled = !sim;
    this.hitchBtn.disabled = !sim;
    const s = this.lab.settings;
    this.jitter.set(Math.round(s.jitter * 100));
    // Radios are not set here: this runs inside their own click, and would undo it.
    this.time.refresh(this.driver.isPaused, this.clock === undefined);
    this.eventsOut.replaceChildren(
      ...(sim
        ? s.events.map((e) =>
            h('li', { class: 'event event-hitch' }, `hitch at ${(e.atMs / 1000).toFixed(1)} s`),
          )
        : []),
    );
    for (const p of this.panels) {
      p.rows.get('tunnelled')?.classList.toggle('active', !this.ccd);
      p.rows.get('ccd-tunnelled')?.classList.toggle('active', this.ccd);
    }
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
    }
    const cw = Math.floor(this.chartHost.getBoundingClientRect().width);
    if (!this.chart && cw > 0) {
      this.chart = new WallChart(
        this.chartHost,
        cw,
        (speed, wall) => {
          this.changeSetting({ speed, wall });
        },
        () => (window.innerWidth < 600 ? 240 : 320),
      );
      this.render();
    } else if (this.chart) {
      this.chart.resize(cw);
      this.chart.syncRect();
    }
  }

  // ---------------------------------------------------------------- the frame

  private render(): void {
    const source = this.clock ?? this.lab;
    const t = source.timeMs;
    const hz = this.driver.measuredHz;
    const s = this.lab.settings;
    this.time.show(
      t,
      this.clock
        ? `real clock · your display ≈ ${hz} Hz${this.driver.isPaused ? ' · paused' : ''}`
        : `simulated display · ${s.hz} Hz ±${Math.round(s.jitter * 100)} %${this.driver.isPaused ? ' · paused' : ''}`,
    );
    const active = this.clock ? undefined : this.lab.activeEvent();
    const runs = source.runs;
    runs.forEach((run, i) => {
      const p = this.panels[i];
      if (p) this.drawPanel(p, run, active !== undefined);
    });
    const byId = (id: string) => runs.find((r) => r.spec.id === id)?.readouts();
    const variable = byId('variable');
    const fixed = byId('fixed');
    this.putTotal('variable-tunnelled', variable?.through ?? 0, variable?.resolved ?? 0);
    this.putTotal('fixed-tunnelled', fixed?.through ?? 0, fixed?.resolved ?? 0);
    this.putTotal(
      'ccd-tunnelled',
      (variable?.ccdThrough ?? 0) + (fixed?.ccdThrough ?? 0),
      (variable?.ccdResolved ?? 0) + (fixed?.ccdResolved ?? 0),
    );

    const rule = source.rule;
    const put = (id: string, text: string, value: number | string) => {
      const v = this.ruleValues.get(id);
      const cell = this.ruleValues.get(`${id}:cell`);
      if (!v || !cell) return;
      setText(v, text);
      setAttr(cell, 'data-value', fmt.exact(value));
    };
    put('min-wall', `${rule.minWall.toFixed(2)} m`, rule.minWall);
    const stepCell = this.ruleValues.get('step-distance:cell');
    if (stepCell) setAttr(stepCell, 'data-value', fmt.exact(rule.stepDistance));
    put('bounce-wall', `${rule.bounceWall.toFixed(2)} m`, rule.bounceWall);
    put('max-safe-speed', `${rule.maxSafeSpeed.toFixed(1)} m/s`, rule.maxSafeSpeed);
    put('theory-share', percent(rule.theoryShare), rule.theoryShare);
    put(
      'measured-share',
      fixed && fixed.resolved > 0 ? percent(fixed.share) : '—',
      fixed?.share ?? NaN,
    );
    const ruleCell = this.ruleValues.get('min-wall:cell');
    ruleCell?.classList.toggle('warn', !rule.ruleHolds);
    this.ruleValues.get('theory-share:cell')?.classList.toggle('warn', rule.theoryShare > 0);

    const current = source.result();
    const results = [...this.lab.history.filter((r) => !sameSetting(r, current)), current];
    this.renderResults(results);
    this.chart?.set({
      speed: current.speed,
      wall: current.wall,
      variableMaxDt: (variable?.maxDtMs ?? 0) / 1000,
      results,
    });
  }

  private putTotal(id: string, through: number, resolved: number): void {
    const v = this.totals.get(id);
    const cell = this.totals.get(`${id}:cell`);
    if (!v || !cell) return;
    setText(v, `${fmt.count(through)} of ${fmt.count(resolved)}`);
    setAttr(cell, 'data-value', fmt.exact(through));
    cell.classList.toggle('bad', through > 0);
  }

  private renderResults(results: SettingResult[]): void {
    const key = results
      .map((r) =>
        [
          r.speed,
          r.wall,
          r.variable.through,
          r.variable.resolved,
          r.fixed.through,
          r.fixed.resolved,
          r.variable.ccdThrough + r.fixed.ccdThrough,
          r.variable.ccdResolved + r.fixed.ccdResolved,
          Math.floor(r.seconds),
        ].join('|'),
      )
      .join(';');
    if (key === this.resultsKey) return;
    this.resultsKey = key;
    const cell = (i: number, text: string, cls = '') => {
      const c = RESULT_COLUMNS[i]!;
      return h('td', { class: `${c.cls} ${cls}`.trim(), 'data-label': c.short }, text);
    };
    const frac = (i: number, t: number, n: number) =>
      cell(i, `${t} / ${n}`, t > 0 ? 'bad' : n > 0 ? 'good' : '');
    this.resultsBody.replaceChildren(
      ...[...results]
        .reverse()
        .map((r, i) =>
          h(
            'tr',
            i === 0 ? { class: 'current', 'aria-current': 'true' } : {},
            cell(0, `${r.speed} m/s`),
            cell(1, `${r.wall.toFixed(1)} m`),
            cell(2, `${r.seconds.toFixed(0)} s`),
            frac(3, r.variable.through, r.variable.resolved),
            frac(4, r.fixed.through, r.fixed.resolved),
            cell(5, percent(r.theoryShare)),
            frac(
              6,
              r.variable.ccdThrough + r.fixed.ccdThrough,
              r.variable.ccdResolved + r.fixed.ccdResolved,
            ),
          ),
        ),
    );
  }

  private drawPanel(p: PanelView, run: RangePanel, hitch: boolean): void {
    const r = run.readouts();
    this.writeReadouts(p, r);
    p.overlay.hidden = !hitch;
    setText(p.overlay, hitch ? 'Hitch: no frames' : '');
    const range = run.range(this.ccd);
    const through = range.through;
    setText(p.tally, through > 0 ? `${through} through` : '');
    p.tally.hidden = through === 0;

    const { ctx, w, h: hh, dpr } = p;
    if (w <= 1 || hh <= 1) return;
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
    this.drawRuler(p, stepLen, range.config.wall, s, px(-wallW), strip);

    // Muzzle.
    ctx.fillStyle = 'rgba(141, 160, 189, 0.5)';
    ctx.fillRect(0, py(RANGE_HALF_HEIGHT - 0.2), 4 * dpr, (2 * RANGE_HALF_HEIGHT - 0.4) * s);

    this.drawBodies(ctx, range, run.rig.alpha, s, px, py, dpr);
  }

  /**
   * One step of travel as a bar ending at the wall's face, against two marks: amber at the wall's
   * thickness (a longer step can jump the wall unseen: the talk's rule) and a green bar of half
   * the wall plus the radius (a longer step can land a body past the middle: pushed out the far
   * side). Drawn in the strip above the range, with its numbers on the line above the bar.
   */
  private drawRuler(
    p: PanelView,
    stepLen: number,
    wall: number,
    s: number,
    face: number,
    strip: number,
  ): void {
    const { ctx, w, dpr } = p;
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
    ctx.strokeStyle = p.color;
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
    ctx.fillStyle = p.color;
    ctx.fillText(step, 6 * dpr, textY);
    ctx.fillStyle = '#6ee7b7';
    if (bounce) ctx.fillText(bounce, 6 * dpr + ctx.measureText(step).width + gap, textY);
  }

  private drawBodies(
    ctx: CanvasRenderingContext2D,
    range: WallRange,
    rigAlpha: number,
    s: number,
    px: (x: number) => number,
    py: (y: number) => number,
    dpr: number,
  ): void {
    const alpha = this.interpolate ? rigAlpha : 1;
    const world = range.world;
    const radius = Math.max(RADIUS * s, 3.2 * dpr);
    const t = range.time;
    for (let id = 0; id < world.slotCount; id++) {
      const status = range.status[id]!;
      if (status === 0) continue;
      const pos = range.renderPosition(id, alpha, this.pos);
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

  private writeReadouts(p: PanelView, r: RangeReadouts): void {
    const put = (field: Field, text: string, value: number) => {
      const el = p.values.get(field);
      const cell = p.cells.get(field);
      if (!el || !cell) return;
      setText(el, text);
      setAttr(cell, 'data-value', fmt.exact(value));
    };
    put('fired', fmt.count(r.fired), r.fired);
    put('tunnelled', `${fmt.count(r.through)} of ${fmt.count(r.resolved)}`, r.through);
    put('ccd-tunnelled', `${fmt.count(r.ccdThrough)} of ${fmt.count(r.ccdResolved)}`, r.ccdThrough);
    put('share', r.resolved > 0 ? percent(r.share) : '—', r.share);
    put('dt', fmt.millis(r.lastDtMs), r.lastDtMs);
    put('max-dt', fmt.millis(r.maxDtMs), r.maxDtMs);
    put('steps', fmt.count(r.steps), r.steps);
    put('sim', fmt.seconds(r.simS), r.simS);
    p.cells.get('tunnelled')?.classList.toggle('bad', r.through > 0);
    p.cells.get('ccd-tunnelled')?.classList.toggle('bad', r.ccdThrough > 0);
  }
}

function sameSetting(a: SettingResult, b: SettingResult): boolean {
  return a.speed === b.speed && a.wall === b.wall;
}

function percent(share: number): string {
  return Number.isFinite(share) ? `${(share * 100).toFixed(1)} %` : '—';
}

/** A value on a slider's grid, within its range. */
function snap(v: number, spec: SliderSpec): number {
  const k = Math.round((v - spec.min) / spec.step);
  const snapped = spec.min + k * spec.step;
  const clamped = Math.min(spec.max, Math.max(spec.min, snapped));
  return Number(clamped.toFixed(6));
}

/** A slider over a {@link SliderSpec}; `onChange` fires when it is let go (or on a key). */
function rangeSlider(
  id: string,
  label: string,
  spec: SliderSpec,
  initial: number,
  text: (v: number) => string,
  onChange: (v: number) => void,
): Slider {
  return slider({
    id: `col-${id}`,
    label,
    testId: `control-${id}`,
    min: spec.min,
    max: spec.max,
    step: spec.step,
    value: initial,
    text,
    onChange,
  });
}

function ideas(): HTMLElement {
  const cards: IdeaCard[] = [
    {
      title: 'Discrete detection',
      color: '#94a3b8',
      text: 'Move every body by v·dt, then look for overlaps and push overlapping bodies apart. Cheap, and what most engines do by default — but nothing happens between two steps.',
      snippet: 'x += v * dt\nif (overlaps(body, wall))\n  pushOut(body, wall)',
    },
    {
      title: 'The talk’s rule of thumb',
      color: CHART_COLORS.rule,
      text: 'A wall at least as thick as one step cannot be jumped over: some step always lands inside it. With a fixed step you know dt in advance, so you can size walls (or cap speeds) once.',
      snippet: 'minWallSize =\n  maxObjectSpeed * TIMESTEP',
    },
    {
      title: '…guarantees detection, not a bounce',
      color: CHART_COLORS.bounce,
      text: 'The push-out leaves through the nearer face. A body whose first overlap is past the middle of the wall is pushed out on the far side. Every body bounces only if one step is at most half the wall plus the radius.',
      snippet: 'v * dt <= w / 2 + r\nthrough = 1 - (w + 2r) / (2 v dt)',
    },
    {
      title: 'Continuous detection',
      color: CHART_COLORS.some,
      text: 'For bullets and very fast bodies: sweep the body along its path, find the time of impact, move it there and respond. It costs more, so engines use it only for bodies that need it.',
      snippet: 't = timeOfImpact(body, wall)\nx += v * dt * t\nbounce(); sweep the rest',
    },
  ];
  return ideaCards({
    id: 'ideas-title',
    title: 'Why bodies go through walls',
    cards,
    listClass: 'idea-cards',
  });
}

function legend(): HTMLElement {
  const dot = (color: string, ring = false) =>
    h('span', {
      class: `body-dot${ring ? ' ring' : ''}`,
      style: `--dot: ${color}`,
      'aria-hidden': 'true',
    });
  return h(
    'details',
    { class: 'legend' },
    h('summary', {}, 'How to read a panel'),
    h(
      'dl',
      {},
      h('dt', {}, dot(BODY.flying), ' In flight'),
      h('dd', {}, 'On its way to the wall. The faint streak is its jump in the last step.'),
      h('dt', {}, dot(BODY.bounced), ' Bounced'),
      h('dd', {}, 'Came back off the near face; it fades out.'),
      h('dt', {}, dot(BODY.through, true), ' Through'),
      h('dd', {}, 'Its centre is past the middle of the wall: it tunnelled.'),
      h('dt', {}, 'One step'),
      h(
        'dd',
        {},
        'The bar above the range is one step (the last one, for variable Δt), ending at the wall’s face. Past the amber mark it is longer than the wall is thick: the talk’s rule is broken and a body can jump the wall unseen. Past the end of the green bar below it, half the wall plus the radius (w/2 + r), a body can land beyond the wall’s middle and is pushed out the far side. While it is no longer than the green bar, every body bounces.',
      ),
      h('dt', {}, 'Through, discrete / CCD'),
      h(
        'dd',
        {},
        'Both twins fire the same shots. The highlighted row is the one drawn; “CCD twins” draws the continuous ones instead.',
      ),
    ),
  );
}

function chartLegend(): HTMLElement {
  const item = (swatch: HTMLElement, text: string) => h('li', {}, swatch, text);
  const line = (color: string, dashed = false) =>
    h('span', {
      class: `line-swatch${dashed ? ' dashed' : ''}`,
      style: `--swatch: ${color}`,
      'aria-hidden': 'true',
    });
  const area = (color: string) =>
    h('span', { class: 'area-swatch', style: `--swatch: ${color}`, 'aria-hidden': 'true' });
  const dot = (color: string) =>
    h('span', { class: 'body-dot', style: `--dot: ${color}`, 'aria-hidden': 'true' });
  return h(
    'ul',
    { class: 'chart-legend' },
    item(line(CHART_COLORS.rule), 'the talk’s rule, w = v·dt'),
    item(line(CHART_COLORS.bounce), 'every body bounces above: v·dt = w/2 + r'),
    item(line(CHART_COLORS.variable, true), 'the rule at the variable loop’s longest step'),
    item(area('rgba(248, 113, 113, 0.35)'), 'bodies can jump over the wall unseen'),
    item(area('rgba(251, 191, 36, 0.35)'), 'seen, but some are pushed out the far side'),
    item(dot(CHART_COLORS.current), 'this setting'),
    item(dot(CHART_COLORS.none), 'tried: none through (fixed step)'),
    item(dot(CHART_COLORS.some), 'tried: some through (bigger = more)'),
  );
}

function howItWorks(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'col-how-title' },
    h('h2', { id: 'col-how-title' }, 'How this page works'),
    h(
      'p',
      {},
      `Each panel runs two copies of one deterministic physics world (fixedstep’s PhysicsWorld): one with collision detection off between steps (ccd: 'off'), one with continuous detection ('auto'). Restitution is 1 and gravity is off, so a body that hits the wall comes straight back. Each shot starts up to one step of travel behind the muzzle (a seeded random phase), so the place where it first overlaps the wall is spread evenly over a step — that is what makes the theory’s share come out.`,
    ),
    h(
      'p',
      {},
      'The display is simulated, as in chapter 1: its frame times are computed, so every run repeats exactly. Changing a setting rebuilds both panels and replays them from zero to the current moment. “Real clock” feeds the loops this page’s own frame times instead; then the variable loop’s steps are your display’s frames.',
    ),
  );
}
