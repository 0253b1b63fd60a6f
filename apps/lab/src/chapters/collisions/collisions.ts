/**
 * Chapter 3 — Collisions. Bodies fired at a wall under a variable Δt and under a fixed step,
 * with discrete detection and with CCD, on a simulated display (or the page's real clock). The
 * numbers come from {@link CollisionsLab}; the words from collisions-text.ts; the ranges are drawn
 * by collisions-draw.ts and the speed × thickness chart by collisions-chart.ts.
 */
import {
  ClockRanges,
  CollisionsLab,
  DISPLAY_RATES,
  EXPERIMENTS,
  HITCH_MS,
  JITTER,
  MAX_REAL_FRAME_MS,
  PANELS,
  SPEED,
  WALL,
  type DisplayRate,
  type Experiment,
  type RangePanel,
  type RangePanelSpec,
  type RangeReadouts,
  type SettingResult,
  type SliderSpec,
} from './collisions-lab.js';
import { WallChart } from './collisions-chart.js';
import { drawRange } from './collisions-draw.js';
import {
  CHART_INTRO,
  LEDE,
  RANGE_INTRO,
  RESULT_COLUMNS,
  ROWS,
  RULE_ROWS,
  chartLegend,
  displayText,
  howItWorks,
  ideas,
  legend,
  percent,
  type Field,
} from './collisions-text.js';
import {
  ChapterShell,
  mountChapter,
  realTimeLine,
  type ChapterHead,
} from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { tryCards } from '../../ui/cards.js';
import {
  button,
  group,
  segmented,
  setPressed,
  slider,
  toggle,
  type Segmented,
  type Slider,
} from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { panel } from '../../ui/panel.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import './collisions.css';

const COLORS: Readonly<Record<string, string>> = {
  variable: '#f87171',
  fixed: '#38bdf8',
};

export const mount = mountChapter((root, head) => new CollisionsChapter(root, head));

/** The settings box and the controls the chapter sets later. */
interface Controls {
  readonly box: HTMLElement;
  readonly speed: Slider;
  readonly wall: Slider;
  readonly jitter: Slider;
  readonly rates: Segmented<DisplayRate>;
  readonly hitch: HTMLButtonElement;
  readonly ccd: HTMLButtonElement;
}

interface PanelView {
  readonly spec: RangePanelSpec;
  readonly color: string;
  readonly scene: SceneCanvas;
  readonly values: Map<Field, Readout>;
  readonly rows: Map<Field, HTMLElement>;
  readonly overlay: HTMLElement;
  readonly tally: HTMLElement;
}

class CollisionsChapter {
  readonly shell: ChapterShell;
  private readonly lab = new CollisionsLab();
  private clock: ClockRanges | undefined;
  private readonly realLine = realTimeLine(() => this.clock);
  private ccd = false;
  private readonly panels: PanelView[] = [];
  private chart: WallChart | undefined;
  private readonly ctl: Controls;
  private readonly eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Hitches so far' });
  private readonly panelGrid: HTMLElement;
  private readonly chartHost: HTMLElement;
  private readonly rule = new Map<string, Readout>();
  private readonly stepDistance = h('span', { 'data-testid': 'readout-step-distance' });
  private readonly totals = new Map<string, Readout>();
  private readonly resultsBody = h('tbody', {});
  private resultsKey = '';

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => (this.clock ? this.realLine : this.lab),
      restart: () => {
        if (this.clock) this.clock = new ClockRanges(this.lab.settings);
        else this.lab.restart();
      },
      mode: () => {
        const s = this.lab.settings;
        return this.shell.display(
          `simulated display · ${s.hz} Hz ±${Math.round(s.jitter * 100)} %`,
        );
      },
      realClock: {
        title: 'Feed both loops this page’s own requestAnimationFrame times',
        onChange: (on) => {
          this.clock = on ? new ClockRanges(this.lab.settings) : undefined;
        },
      },
      interpolation: { title: 'Draw the fixed step between its last two states, at alpha' },
      driver: { maxFrameMs: MAX_REAL_FRAME_MS },
    });
    const shell = this.shell;
    this.ctl = this.buildControls();
    this.panelGrid = h(
      'div',
      { class: 'panels range-panels' },
      PANELS.map((spec) => this.buildPanel(spec)),
    );
    this.chartHost = h('div', {
      class: 'wall-chart',
      role: 'img',
      'aria-label':
        'Wall thickness against speed for the fixed step: the talk’s rule, the correct-bounce bound, the current setting and the settings tried',
      'data-testid': 'chart-walls',
    });
    shell.append(
      ideas(),
      introSection(
        'bench',
        'range-title',
        'The firing range',
        RANGE_INTRO,
        this.ctl.box,
        this.panelGrid,
        this.totalsList(),
        legend(),
      ),
      introSection(
        'wall-chart-section',
        'chart-title',
        'Speed × thickness',
        CHART_INTRO,
        h('div', { class: 'wall-chart-wrap' }, this.chartHost, this.ruleReadouts()),
        chartLegend(),
        this.resultsTable(),
      ),
      tryCards(
        'col-experiments-title',
        EXPERIMENTS.map((item, i) => ({
          ...item,
          testId: `experiment-${i + 1}`,
          run: () => {
            this.runExperiment(item);
            this.panelGrid.scrollIntoView({ block: 'nearest' });
          },
        })),
      ),
      howItWorks(),
    );
    shell.observe(this.chartHost, () => {
      this.fitChart();
    });
    // Anything above the chart that changes height moves it: uPlot must measure it again.
    shell.observe(this.ctl.box, () => this.chart?.syncRect());
    shell.observe(this.panelGrid, () => this.chart?.syncRect());
    shell.start();
  }

  // ---------------------------------------------------------------- building

  /** The range's settings: speed, wall, display, jitter and a hitch, what to draw, the clock, time. */
  private buildControls(): Controls {
    const s = this.lab.settings;
    const rangeSlider = (
      id: string,
      label: string,
      spec: SliderSpec,
      value: number,
      text: (v: number) => string,
      onChange: (v: number) => void,
    ) =>
      slider({
        id: `col-${id}`,
        label,
        testId: `control-${id}`,
        min: spec.min,
        max: spec.max,
        step: spec.step,
        value,
        text,
        onChange,
      });
    const speed = rangeSlider(
      'speed',
      'Speed',
      SPEED,
      s.speed,
      (v) => `${v.toFixed(0)} m/s`,
      (v) => {
        this.changeSetting({ speed: v });
      },
    );
    const wall = rangeSlider(
      'wall',
      'Wall',
      WALL,
      s.wall,
      (v) => `${v.toFixed(1)} m`,
      (v) => {
        this.changeSetting({ wall: v });
      },
    );
    const jitter = rangeSlider(
      'jitter',
      'Jitter',
      JITTER,
      s.jitter * 100,
      (v) => `±${v.toFixed(0)} %`,
      (v) => {
        this.lab.update({ jitter: v / 100 });
      },
    );
    const rates = segmented<DisplayRate>({
      name: 'collisions-hz',
      label: 'Simulated display refresh rate',
      testPrefix: 'control-hz',
      values: DISPLAY_RATES,
      selected: s.hz,
      text: (hz) => `${hz} Hz`,
      onChange: (hz) => {
        this.lab.update({ hz });
      },
    });
    const hitchBtn = button(`${HITCH_MS} ms hitch`, 'control-hitch', () => {
      this.lab.addHitch();
    });
    hitchBtn.title = `No display frame for ${HITCH_MS} ms: the variable loop's next step is at least that long`;
    jitter.el.append(hitchBtn);
    const ccdBtn = toggle('CCD twins', 'control-ccd', false, (on) => {
      this.ccd = on;
    });
    ccdBtn.title =
      'Draw the twin ranges that use continuous collision detection instead of the discrete ones (both always run)';
    const box = this.shell.controls(
      'The range and its display',
      speed.el,
      wall.el,
      group('Display', rates.el),
      jitter.el,
      group('Draw', ccdBtn, this.shell.interpBtn ?? null),
      group('Clock', this.shell.clockBtn ?? null),
      this.shell.timeGroup(),
      this.shell.status(this.eventsOut),
    );
    return { box, speed, wall, jitter, rates, hitch: hitchBtn, ccd: ccdBtn };
  }

  private buildPanel(spec: RangePanelSpec): HTMLElement {
    const color = COLORS[spec.id] ?? '#38bdf8';
    const scene = this.shell.canvas({
      class: 'scene range-scene',
      label: `The firing range under ${spec.title}`,
      testId: `canvas-${spec.id}`,
    });
    const values = new Map<Field, Readout>();
    const rows = new Map<Field, HTMLElement>();
    const list = (time: boolean) =>
      ROWS.filter((row) => (row.time ?? false) === time).flatMap((row) => {
        const r = new Readout('dd', `${spec.id}-${row.field}`);
        const dt = h('dt', { title: row.title }, row.label);
        values.set(row.field, r);
        rows.set(row.field, dt);
        return [dt, r.el];
      });
    const view: PanelView = {
      spec,
      color,
      scene,
      values,
      rows,
      overlay: h('p', { class: 'overlay', hidden: true }),
      tally: h('p', { class: 'range-tally', 'aria-hidden': 'true' }),
    };
    this.panels.push(view);
    return panel(
      { ...spec, accent: color },
      h('div', { class: 'scene-wrap' }, scene.canvas, view.overlay, view.tally),
      h(
        'div',
        { class: 'range-readouts' },
        h('dl', { class: 'readouts', 'aria-label': 'Shots' }, list(false)),
        h('dl', { class: 'readouts', 'aria-label': 'Steps' }, list(true)),
      ),
    );
  }

  private totalsList(): HTMLElement {
    const total = (id: string, label: string) => {
      const r = new Readout('dd', id);
      this.totals.set(id, r);
      return h('div', { class: 'range-total' }, h('dt', {}, label), r.el);
    };
    return h(
      'dl',
      { class: 'range-totals', 'aria-label': 'Totals at this setting' },
      total('variable-tunnelled', 'Variable Δt, discrete'),
      total('fixed-tunnelled', 'Fixed step, discrete'),
      total('ccd-tunnelled', 'Either loop, CCD'),
    );
  }

  private ruleReadouts(): HTMLElement {
    return h(
      'dl',
      { class: 'readouts rule-readouts', 'aria-label': 'The rule at this setting' },
      RULE_ROWS.flatMap((row) => {
        const r = new Readout('dd', row.id);
        this.rule.set(row.id, r);
        // One step and minWallSize are the same number: one row, both readouts.
        if (row.id === 'min-wall') r.el.append(this.stepDistance);
        return [h('dt', { title: row.title }, row.label), r.el];
      }),
    );
  }

  private resultsTable(): HTMLElement {
    return h(
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
            RESULT_COLUMNS.map((c) =>
              h('th', { scope: 'col', class: c.cls, title: c.title }, c.label),
            ),
          ),
        ),
        this.resultsBody,
      ),
    );
  }

  private fitChart(): void {
    const cw = Math.floor(this.chartHost.getBoundingClientRect().width);
    if (!this.chart && cw > 0) {
      this.chart = this.shell.own(
        new WallChart(
          this.chartHost,
          cw,
          (speed, wall) => {
            this.changeSetting({ speed, wall });
            this.shell.redraw();
          },
          () => (window.innerWidth < 600 ? 240 : 320),
        ),
      );
      this.shell.redraw();
    } else if (this.chart) {
      this.chart.resize(cw);
      this.chart.syncRect();
    }
  }

  /** Set everything the experiment's text assumes and start again from zero, playing. */
  private runExperiment(item: Experiment): void {
    if (this.clock) this.shell.setReal(false);
    const s = item.settings;
    this.lab.startOver(s);
    this.ctl.speed.set(s.speed);
    this.ctl.wall.set(s.wall);
    this.ctl.jitter.set(Math.round(s.jitter * 100));
    this.ctl.rates.select(s.hz);
    this.ccd = item.ccd;
    setPressed(this.ctl.ccd, item.ccd);
    this.shell.setPaused(false);
  }

  // ---------------------------------------------------------------- state changes

  private changeSetting(change: { speed?: number; wall?: number }): void {
    const speed = snap(change.speed ?? this.lab.settings.speed, SPEED);
    const wall = snap(change.wall ?? this.lab.settings.wall, WALL);
    this.ctl.speed.set(speed);
    this.ctl.wall.set(wall);
    if (this.clock) {
      // A new setting starts a new real-clock run.
      this.lab.remember(this.clock.result());
      this.lab.update({ speed, wall });
      this.clock = new ClockRanges({ speed, wall });
      this.shell.driver.restartReal();
    } else {
      this.lab.update({ speed, wall });
    }
  }

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const sim = this.clock === undefined;
    this.ctl.rates.setDisabled(!sim);
    this.ctl.jitter.input.disabled = !sim;
    this.ctl.hitch.disabled = !sim;
    const s = this.lab.settings;
    this.ctl.jitter.set(Math.round(s.jitter * 100));
    // Radios are not set here: this runs inside their own click, and would undo it.
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

  // ---------------------------------------------------------------- the frame

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const source = this.clock ?? this.lab;
    const hitch = this.clock ? false : this.lab.activeEvent() !== undefined;
    const runs = source.runs;
    runs.forEach((run, i) => {
      const p = this.panels[i];
      if (p) this.renderPanel(p, run, hitch);
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
    const put = (id: string, text: string, value: number) => this.rule.get(id)?.set(text, value);
    put('min-wall', `${rule.minWall.toFixed(2)} m`, rule.minWall);
    setAttr(this.stepDistance, 'data-value', fmt.exact(rule.stepDistance));
    put('bounce-wall', `${rule.bounceWall.toFixed(2)} m`, rule.bounceWall);
    put('max-safe-speed', `${rule.maxSafeSpeed.toFixed(1)} m/s`, rule.maxSafeSpeed);
    put('theory-share', percent(rule.theoryShare), rule.theoryShare);
    put(
      'measured-share',
      fixed && fixed.resolved > 0 ? percent(fixed.share) : '—',
      fixed?.share ?? NaN,
    );
    this.rule.get('min-wall')?.warn(!rule.ruleHolds);
    this.rule.get('theory-share')?.warn(rule.theoryShare > 0);
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
    const r = this.totals.get(id);
    if (!r) return;
    r.set(`${fmt.count(through)} of ${fmt.count(resolved)} through`, through);
    r.el.classList.toggle('bad', through > 0);
  }

  private renderResults(results: SettingResult[]): void {
    const key = results
      .map((r) =>
        [
          r.speed,
          r.wall,
          displayText(r.display),
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
    // Cells in RESULT_COLUMNS' order; each names itself for a phone, where the header is hidden.
    const cell = (i: number, text: string, state = '') => {
      const c = RESULT_COLUMNS[i]!;
      return h('td', { class: `${c.cls} ${state}`.trim(), 'data-label': c.short }, text);
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
            cell(2, displayText(r.display)),
            cell(3, `${r.seconds.toFixed(0)} s`),
            frac(4, r.variable.through, r.variable.resolved),
            frac(5, r.fixed.through, r.fixed.resolved),
            cell(6, percent(r.theoryShare)),
            frac(
              7,
              r.variable.ccdThrough + r.fixed.ccdThrough,
              r.variable.ccdResolved + r.fixed.ccdResolved,
            ),
          ),
        ),
    );
  }

  private renderPanel(p: PanelView, run: RangePanel, hitch: boolean): void {
    const r = run.readouts();
    this.writeReadouts(p, r);
    setHidden(p.overlay, !hitch);
    setText(p.overlay, hitch ? 'Hitch: no frames' : '');
    const through = run.range(this.ccd).through;
    setText(p.tally, through > 0 ? `${through} through` : '');
    setHidden(p.tally, through === 0);
    drawRange(p.scene, run, p.color, this.ccd, this.shell.interpolate);
  }

  private writeReadouts(p: PanelView, r: RangeReadouts): void {
    const put = (field: Field, text: string, value: number) =>
      p.values.get(field)?.set(text, value);
    put('fired', fmt.count(r.fired), r.fired);
    put('tunnelled', `${fmt.count(r.through)} of ${fmt.count(r.resolved)}`, r.through);
    put('ccd-tunnelled', `${fmt.count(r.ccdThrough)} of ${fmt.count(r.ccdResolved)}`, r.ccdThrough);
    put('share', r.resolved > 0 ? percent(r.share) : '—', r.share);
    put('dt', fmt.millis(r.lastDtMs), r.lastDtMs);
    put('max-dt', fmt.millis(r.maxDtMs), r.maxDtMs);
    put('steps', fmt.count(r.steps), r.steps);
    put('sim', fmt.seconds(r.simS), r.simS);
    p.values.get('tunnelled')?.el.classList.toggle('bad', r.through > 0);
    p.values.get('ccd-tunnelled')?.el.classList.toggle('bad', r.ccdThrough > 0);
  }
}

function sameSetting(a: SettingResult, b: SettingResult): boolean {
  return a.speed === b.speed && a.wall === b.wall;
}

function snap(v: number, spec: SliderSpec): number {
  const k = Math.round((v - spec.min) / spec.step);
  const snapped = spec.min + k * spec.step;
  const clamped = Math.min(spec.max, Math.max(spec.min, snapped));
  return Number(clamped.toFixed(6));
}
