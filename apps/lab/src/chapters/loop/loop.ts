/**
 * Chapter 1 — The loop. The talk's four loops and the production FixedLoop run side by side on
 * one ball scene and one simulated display (or the page's real clock). The numbers come from
 * {@link LoopLab}; the words from loop-text.ts; this module builds the page and wires it.
 */
import {
  ClockLab,
  DISPLAY_RATES,
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
import {
  BENCH_INTRO,
  CHART_LABEL,
  COLORS,
  EVOLUTION,
  LEDE,
  ROWS,
  TRY,
  howItWorks,
  legend,
  type Field,
} from './loop-text.js';
import { drawPanel, stepsWindow } from './loop-draw.js';
import {
  ChapterShell,
  mountChapter,
  realTimeLine,
  type ChapterHead,
} from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { ideaCards, tryCards } from '../../ui/cards.js';
import { button, group, jitterSlider, segmented, toggle, setPressed } from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { panel } from '../../ui/panel.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { StepsChart } from '../../ui/steps-chart.js';
import { slipSection } from './loop-slip.js';
import './loop.css';

const HITCH_MS = 2000;
const HIDDEN_MS = 10_000;
/**
 * Where a "Things to try" card starts its run: past the checkpoint update (4.5 s), so its hash
 * is already in, and with the ball in flight when a hitch or a hidden tab begins.
 */
const EXPERIMENT_LEAD_MS = 5000;

/** The loops' key numbers in the compact table above the panels (on a phone). */
const COMPARE: readonly { field: Field; id: string; label: string }[] = [
  { field: 'ratio', id: 'ratio', label: 'Sim / real' },
  { field: 'maxSteps', id: 'max-steps', label: 'Max steps' },
  { field: 'droppedMs', id: 'dropped', label: 'Dropped' },
  { field: 'checkpointHash', id: 'hash150', label: ROWS.at(-1)!.label },
];

interface PanelView {
  readonly spec: PanelSpec;
  readonly color: string;
  readonly scene: SceneCanvas;
  readonly chartHost: HTMLElement;
  chart: StepsChart | undefined;
  readonly readouts: Map<Field, Readout>;
  readonly compare: Map<Field, Readout>;
  readonly stall: HTMLElement;
  readonly overlay: HTMLElement;
}

export const mount = mountChapter((root, head) => new LoopChapter(root, head));

class LoopChapter {
  readonly shell: ChapterShell;
  private readonly lab = new LoopLab();
  private clock: ClockLab | undefined;
  private readonly panels: PanelView[] = [];
  private readonly trailScratch: number[] = [];
  private readonly rates;
  private readonly jitter;
  private readonly hitchBtn: HTMLButtonElement;
  private readonly hiddenBtn: HTMLButtonElement;
  private readonly slowBtn: HTMLButtonElement;
  private readonly eventsOut: HTMLElement;
  private readonly panelGrid: HTMLElement;
  /** The real clock's run as the shell's time line. */
  private readonly realLine = realTimeLine(() => this.clock);

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => (this.clock ? this.realLine : this.lab),
      restart: () => {
        if (this.clock) this.clock = new ClockLab();
        else this.lab.restart();
      },
      mode: () => this.shell.display(`simulated display · ${this.lab.settings.hz} Hz`),
      realClock: {
        title: 'Feed the loops this page’s own requestAnimationFrame times',
        onChange: (on) => {
          this.clock = on ? new ClockLab() : undefined;
        },
      },
      interpolation: { title: 'Draw the fixed loops between their last two states, at alpha' },
      driver: { maxFrameMs: MAX_REAL_FRAME_MS },
    });
    const shell = this.shell;
    this.rates = segmented<DisplayRate>({
      name: 'display-hz',
      label: 'Display refresh rate',
      testPrefix: 'control-hz',
      values: DISPLAY_RATES,
      selected: this.lab.settings.hz,
      text: (hz) => `${hz} Hz`,
      onChange: (hz) => {
        this.lab.update({ hz });
      },
    });
    this.jitter = jitterSlider({
      id: 'jitter',
      percent: 0,
      text: (v) => `${v} %`,
      onChange: (jitter) => {
        this.lab.update({ jitter });
      },
    });
    this.hitchBtn = button('2 s hitch', 'control-hitch', () => {
      this.lab.addEvent('hitch', HITCH_MS);
    });
    this.hiddenBtn = button('Hidden tab, 10 s', 'control-hidden', () => {
      this.lab.addEvent('hidden', HIDDEN_MS);
    });
    this.slowBtn = toggle('Slow machine', 'control-slow', false, (on) => {
      this.lab.update({ slow: on });
    });
    this.slowBtn.title = `Every update costs ${SLOW_UPDATE_COST_MS} ms of real time, more than the ${STEP_MS} ms it simulates`;
    const throwBtn = button('Throw', 'control-throw', () => {
      if (this.clock) this.clock.addThrow();
      else this.lab.addThrow();
    });
    throwBtn.title = 'Throw the ball in every panel at the same moment';
    this.eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Display events so far' });
    const controls = shell.controls(
      'Simulated display',
      group('Display', this.rates.el),
      this.jitter.el,
      group('Trouble', this.hitchBtn, this.hiddenBtn, this.slowBtn),
      shell.drawGroup(),
      shell.timeGroup(throwBtn),
      shell.status(this.eventsOut),
    );
    this.panelGrid = h(
      'div',
      { class: 'panels' },
      PANELS.map((spec) => this.buildPanel(spec)),
    );
    shell.append(
      ideaCards({ id: 'evolution-title', title: 'How the loop evolved', cards: EVOLUTION }),
      introSection(
        'bench',
        'bench-title',
        'Five loops, one ball, one display',
        BENCH_INTRO,
        controls,
        this.compareTable(),
        this.panelGrid,
        legend(),
      ),
      slipSection(),
      this.experiments(),
      howItWorks(),
    );
    shell.listen(document, 'visibilitychange', () => {
      if (document.hidden) this.clock?.markHidden();
    });
    shell.start();
  }

  // ---------------------------------------------------------------- building

  private buildPanel(spec: PanelSpec): HTMLElement {
    const color = COLORS[spec.id] ?? '#38bdf8';
    const scene = this.shell.canvas({
      label: `The ball as the ${spec.title} loop draws it`,
      testId: `canvas-${spec.id}`,
    });
    const readouts = new Map<Field, Readout>();
    const rows = ROWS.map((row) => {
      const isHash = row.field === 'hash' || row.field === 'checkpointHash';
      const r = new Readout('dd', `${spec.id}-${row.id}`, { hash: isHash });
      readouts.set(row.field, r);
      return [h('dt', { title: row.title }, row.label), r.el];
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
      'aria-label': CHART_LABEL(spec.title),
    });
    const view: PanelView = {
      spec,
      color,
      scene,
      chartHost,
      chart: undefined,
      readouts,
      compare: new Map(),
      stall,
      overlay,
    };
    this.panels.push(view);
    this.shell.observe(chartHost, () => {
      const w = Math.floor(chartHost.getBoundingClientRect().width);
      if (!view.chart && w > 0) view.chart = this.shell.own(new StepsChart(chartHost, color, w));
      else view.chart?.resize(w);
    });
    return panel(
      { ...spec, accent: color },
      h('div', { class: 'scene-wrap' }, scene.canvas, overlay, stall),
      h('dl', { class: 'readouts' }, rows),
      h('p', { class: 'chart-title' }, 'Steps per frame'),
      chartHost,
    );
  }

  /** The five loops' key numbers in one table: shown above the panels on a phone. */
  private compareTable(): HTMLElement {
    const body = PANELS.map((spec, i) => {
      const view = this.panels[i];
      const cells = COMPARE.map((c) => {
        const r = new Readout('td', `compare-${spec.id}-${c.id}`, {
          hash: c.field === 'checkpointHash',
        });
        view?.compare.set(c.field, r);
        return r.el;
      });
      return h(
        'tr',
        { style: `--accent: ${COLORS[spec.id] ?? '#38bdf8'}` },
        h('th', { scope: 'row' }, spec.title),
        cells,
      );
    });
    return h(
      'table',
      { class: 'data-table loop-compare', 'data-testid': 'loop-compare' },
      h('caption', {}, 'The five loops now'),
      h(
        'thead',
        {},
        h(
          'tr',
          {},
          h('th', { scope: 'col' }, 'Loop'),
          COMPARE.map((c) => h('th', { scope: 'col' }, c.label)),
        ),
      ),
      h('tbody', {}, body),
    );
  }

  private experiments(): HTMLElement {
    const card = (key: keyof typeof TRY, setUp: () => void) => ({
      ...TRY[key],
      run: () => {
        if (this.clock) this.shell.setReal(false);
        setUp();
        this.shell.setPaused(false);
        this.panelGrid.scrollIntoView({ block: 'nearest' });
      },
    });
    return tryCards('experiments-title', [
      card('faster', () => {
        this.setUp({ hz: 144 });
      }),
      card('hitch', () => {
        this.setUp({});
        this.lab.addEvent('hitch', HITCH_MS);
      }),
      card('hidden', () => {
        this.setUp({});
        this.lab.addEvent('hidden', HIDDEN_MS);
      }),
      card('slow', () => {
        this.setUp({ slow: true });
      }),
      card('stutter', () => {
        this.setUp({ hz: 144 });
        this.shell.setInterpolation(false);
      }),
    ]);
  }

  /**
   * A card's fresh run, whatever was clicked before: the default display (60 Hz, no jitter, no
   * slow machine, no events or throws) changed by `change`, interpolation on, replayed from zero
   * to {@link EXPERIMENT_LEAD_MS}.
   */
  private setUp(change: Partial<LoopLabSettings>): void {
    this.lab.restart();
    this.lab.update({ ...defaultSettings(), ...change });
    this.lab.advanceTo(EXPERIMENT_LEAD_MS);
    this.rates.select(this.lab.settings.hz);
    this.shell.setInterpolation(true);
  }

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const sim = this.clock === undefined;
    this.rates.setDisabled(!sim);
    this.jitter.input.disabled = !sim;
    this.hitchBtn.disabled = !sim;
    this.hiddenBtn.disabled = !sim;
    this.slowBtn.disabled = !sim;
    const s = this.lab.settings;
    setPressed(this.slowBtn, s.slow);
    this.jitter.set(Math.round(s.jitter * 100));
    const events = sim
      ? s.events.map((e) =>
          h(
            'li',
            { class: `event event-${e.kind}` },
            `${e.kind} at ${(e.atMs / 1000).toFixed(1)} s`,
          ),
        )
      : [];
    if (sim && s.throws.length > 0) {
      events.push(
        h(
          'li',
          { class: 'event event-throw' },
          `${s.throws.length} throw${s.throws.length === 1 ? '' : 's'}`,
        ),
      );
    }
    this.eventsOut.replaceChildren(...events);
  }

  // ---------------------------------------------------------------- drawing

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const runs = this.clock ? this.clock.runs : this.lab.runs;
    const t = this.clock ? this.clock.timeMs : this.lab.timeMs;
    const event = this.clock ? undefined : this.lab.activeEvent()?.kind;
    runs.forEach((run, i) => {
      const p = this.panels[i];
      if (p) this.renderPanel(p, run, t, event);
    });
  }

  private renderPanel(p: PanelView, run: PanelRun, t: number, event?: 'hitch' | 'hidden'): void {
    const r = run.readouts();
    this.writeReadouts(p, r);
    const overlay = event === 'hitch' ? 'Hitch: no frames' : event === 'hidden' ? 'Tab hidden' : '';
    setHidden(p.overlay, overlay === '');
    setText(p.overlay, overlay);
    drawPanel(p.scene, run, p.color, this.shell.interpolate, this.trailScratch);
    if (p.chart) {
      const w = stepsWindow(run, t);
      p.chart.set(w.xs, w.ys, w.from, w.to);
    }
  }

  private writeReadouts(p: PanelView, r: PanelReadouts): void {
    const texts: Record<Field, [string, number | string | boolean | undefined]> = {
      updates: [fmt.count(r.updates), r.updates],
      simS: [fmt.seconds(r.simS), r.simS],
      realS: [fmt.seconds(r.realS), r.realS],
      ratio: [fmt.ratio(r.ratio), r.ratio],
      steps: [fmt.count(r.steps), r.steps],
      maxSteps: [fmt.count(r.maxSteps), r.maxSteps],
      droppedMs: [fmt.millis(r.droppedMs), r.droppedMs],
      hash: [r.hash, r.hash],
      checkpointHash: [r.checkpointHash ?? 'not yet', r.checkpointHash],
      stalled: [String(r.stalled), r.stalled],
    };
    const off = Number.isFinite(r.ratio) && Math.abs(r.ratio - 1) > 0.05;
    for (const [field, ro] of p.readouts) ro.set(...texts[field]);
    for (const [field, ro] of p.compare) {
      // A phone's table shows the hash's first eight digits (the chip tells equal ones apart).
      if (field === 'checkpointHash')
        ro.set(r.checkpointHash?.slice(0, 8) ?? '—', r.checkpointHash);
      else ro.set(...texts[field]);
    }
    p.readouts.get('ratio')?.warn(off);
    p.compare.get('ratio')?.warn(off);
    setHidden(p.stall, !r.stalled);
    setAttr(p.stall, 'data-value', String(r.stalled));
    setText(
      p.stall,
      r.stalled ? `Stalled: ${fmt.count(r.owed)} updates owed, never run` : 'Stalled',
    );
  }
}
