/**
 * Chapter 8 — Final fixes. Two benches on one virtual clock: a hitch on a slow machine with no
 * clamp on the accumulator (the spiral of death, shown safely), with the clamp, and with
 * FixedLoop; and a clock that jumps backwards. The numbers come from {@link FinalLab}; the words
 * from final-fixes-text.ts; the charts from final-fixes-draw.ts.
 */
import { nanSection } from './final-fixes-nan.js';
import {
  BACKWARDS_LOOPS,
  FinalLab,
  MACHINES,
  POLICIES,
  SPIRAL_LOOPS,
  defaultFinalSettings,
  spiralOutlook,
  type BackwardsReadouts,
  type BenchLoop,
  type BenchRun,
  type SpiralReadouts,
} from './final-fixes-lab.js';
import {
  BACKWARDS_ROWS,
  LEDE,
  SPIRAL_ROWS,
  backwardsIntro,
  codePair,
  how,
  spiralIntro,
  type Row,
} from './final-fixes-text.js';
import {
  backwardsChart,
  drawCharts,
  spiralChart,
  isGoingBack,
  lastProgress,
} from './final-fixes-draw.js';
import type { BackwardsLoop, SpiralLoop } from '@fixedstep/games';
import type { OverloadPolicy } from 'fixedstep';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import { drawBall } from '../../ui/ball-view.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import type { Chart } from '../../ui/chart.js';
import { button, group, segmented } from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { panel } from '../../ui/panel.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import './final-fixes.css';

const TRAIL_MS = 600;
const BACK_SIZES = [500, 1500, 5000] as const;

export const mount = mountChapter((root, head) => new FinalFixesChapter(root, head));

interface PanelView {
  readonly spec: BenchLoop<string>;
  readonly scene: SceneCanvas;
  readonly values: Map<string, Readout>;
  /** What is happening to the page ("Busy", "Hitch"): a pill under the canvas, never on the ball. */
  readonly overlay: HTMLElement;
  readonly stall: HTMLElement | undefined;
}

/** One of the chapter's two benches: its intro and controls, a panel per loop, its chart. */
function bench(
  id: string,
  title: string,
  intro: HTMLElement,
  controls: HTMLElement,
  o: { panels: HTMLElement[]; chartTitle: string; chart: HTMLElement },
): HTMLElement {
  return introSection(
    'bench',
    id,
    title,
    intro,
    controls,
    h('div', { class: `panels panels-${o.panels.length}` }, o.panels),
    h('div', { class: 'chart-card' }, h('h3', {}, o.chartTitle), o.chart),
  );
}

class FinalFixesChapter {
  readonly shell: ChapterShell;
  private lab = new FinalLab();
  private readonly spiralPanels: PanelView[] = [];
  private readonly backPanels: PanelView[] = [];
  private readonly stepsChart: Chart;
  private readonly simChart: Chart;
  private readonly eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Hitches so far' });
  private readonly clockReading = new Readout('span', 'backwards-clock', { className: 'clock' });
  private readonly clockNote = h('span', { class: 'status-item' });
  /** The sections' intros: what the current settings will show (rewritten as they change). */
  private readonly spiralText = h('span', { 'data-testid': 'spiral-intro' });
  private readonly backText = h('span', { 'data-testid': 'backwards-intro' });
  private readonly scratch: number[] = [];
  private textKey = '';

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      restart: () => {
        if (this.lab.realClock) this.lab = new FinalLab({ ...this.lab.settings }, true);
        else this.lab.restart();
      },
      mode: () => this.shell.display('simulated 60 Hz display'),
      realClock: {
        title: 'Feed both benches this page’s own animation frames',
        onChange: (on) => {
          this.lab = new FinalLab({ ...this.lab.settings }, on);
        },
      },
      interpolation: { title: 'Draw the fixed-step balls between their last two states' },
      driver: { maxRealGapMs: 250 },
    });
    const shell = this.shell;
    const timebar = shell.controls(
      'Time',
      shell.timeGroup(),
      shell.drawGroup(),
      h(
        'div',
        { class: 'status status-inline', 'aria-live': 'off' },
        ...(shell.time?.status ?? []),
      ),
    );
    timebar.classList.add('timebar');
    this.stepsChart = shell.own(spiralChart());
    this.simChart = shell.own(backwardsChart());
    shell.append(
      codePair(),
      timebar,
      bench('spiral-title', 'A hitch on a slow machine', this.spiralText, this.spiralControls(), {
        panels: SPIRAL_LOOPS.map((spec) =>
          this.buildPanel(spec, SPIRAL_ROWS, '', this.spiralPanels, true),
        ),
        chartTitle: 'Steps per frame',
        chart: this.stepsChart.el,
      }),
      bench('backwards-title', 'A clock that jumps backwards', this.backText, this.backControls(), {
        panels: BACKWARDS_LOOPS.map((spec) =>
          this.buildPanel(spec, BACKWARDS_ROWS, 'backwards-', this.backPanels, false),
        ),
        chartTitle: 'How far behind the display each loop’s time is',
        chart: this.simChart.el,
      }),
      nanSection(),
      how(),
    );
    shell.start();
  }

  // ---------------------------------------------------------------- building

  private spiralControls(): HTMLElement {
    const s = this.lab.settings;
    const machine = segmented({
      name: 'machine',
      label: 'What one update costs',
      testPrefix: 'control-machine',
      values: MACHINES.map((m) => m.costMs),
      selected: s.costMs,
      text: (ms) => `${MACHINES.find((m) => m.costMs === ms)?.label ?? ''} · ${ms} ms`,
      onChange: (ms) => {
        this.lab.update({ costMs: ms });
      },
    });
    for (const m of MACHINES) {
      const label = machine.inputs.get(m.costMs)?.parentElement;
      if (label) label.title = m.title;
    }
    const policy = segmented<OverloadPolicy>({
      name: 'overload',
      label: 'FixedLoop’s overload policy',
      testPrefix: 'control-policy',
      values: POLICIES,
      selected: s.overload,
      text: (p) => p,
      onChange: (p) => {
        this.lab.update({ overload: p });
      },
    });
    const hitch = button('1 s hitch', 'control-hitch', () => {
      this.lab.addHitch(1000);
    });
    hitch.title = 'No frame for 1 s, starting now (a garbage-collection pause, a slow disk)';
    const breakpoint = button('10 s breakpoint', 'control-breakpoint', () => {
      this.lab.addHitch(10_000);
    });
    breakpoint.title = 'No frame for 10 s, starting now: the page sat on a debugger breakpoint';
    return this.shell.controls(
      'The slow machine',
      group('Machine', machine.el),
      group('FixedLoop', policy.el),
      group('Trouble', hitch, breakpoint),
      h(
        'div',
        { class: 'status' },
        h('span', { class: 'status-item' }, 'Each update simulates 30 ms.'),
        this.eventsOut,
      ),
    );
  }

  private backControls(): HTMLElement {
    const backSize = segmented({
      name: 'back-size',
      label: 'How far the clock jumps back',
      testPrefix: 'control-back',
      values: BACK_SIZES,
      selected: this.lab.settings.backMs,
      text: (ms) => `${ms / 1000} s`,
      onChange: (ms) => {
        this.lab.update({ backMs: ms });
      },
    });
    const jumpBack = button('Set the clock back now', 'control-jump-back', () => {
      this.lab.jumpBack();
    });
    jumpBack.title = 'The wall clock the loops read jumps back, as after a time-server correction';
    return this.shell.controls(
      'The wall clock',
      group('Jump', backSize.el, jumpBack),
      h(
        'div',
        { class: 'status' },
        h('span', { class: 'status-item' }, 'the wall clock reads ', this.clockReading.el),
        this.clockNote,
      ),
    );
  }

  private buildPanel(
    spec: BenchLoop<string>,
    rows: readonly Row[],
    prefix: string,
    into: PanelView[],
    stall: boolean,
  ): HTMLElement {
    const scene = this.shell.canvas({
      label: `The ball under ${spec.title}`,
      testId: `canvas-${prefix}${spec.id}`,
    });
    const values = new Map<string, Readout>();
    const dl = h(
      'dl',
      { class: 'readouts' },
      rows
        .map(([id, label, title]) => {
          const r = new Readout('dd', `${prefix}${spec.id}-${id}`);
          values.set(id, r);
          return [h('dt', { title }, label), r.el];
        })
        .flat(),
    );
    const overlay = h('span', {
      class: 'scene-pill',
      hidden: true,
      'data-testid': `pill-${prefix}${spec.id}`,
    });
    const stallEl = stall
      ? h(
          'span',
          {
            class: 'scene-stall',
            role: 'status',
            'data-testid': `readout-${prefix}${spec.id}-stalled`,
            'data-value': 'false',
            hidden: true,
          },
          'Stalled',
        )
      : undefined;
    into.push({ spec, scene, values, overlay, stall: stallEl });
    return panel(
      { id: `${prefix}${spec.id}`, title: spec.title, tagline: spec.tagline, accent: spec.color },
      h('div', { class: 'scene-wrap' }, scene.canvas),
      h('p', { class: 'scene-notes' }, overlay, stallEl ?? null),
      dl,
    );
  }

  // ---------------------------------------------------------------- state

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const s = this.lab.settings;
    // (The segmented controls are not re-selected here: this runs during their own clicks.)
    this.eventsOut.replaceChildren(
      ...s.hitches.map((e) =>
        h(
          'li',
          { class: 'event event-hitch' },
          `${e.durationMs / 1000} s hitch at ${(e.atMs / 1000).toFixed(1)} s`,
        ),
      ),
    );
    // The intros' numbers: the machine's spiral after the first hitch, the clock's jumps.
    const hitch = s.hitches[0] ?? defaultFinalSettings().hitches[0]!;
    const key = `${s.costMs}|${hitch.atMs}|${hitch.durationMs}|${s.backMs}|${s.backJumps.join(',')}`;
    if (key === this.textKey) return;
    this.textKey = key;
    setText(this.spiralText, spiralIntro(spiralOutlook(s.costMs, hitch)));
    setText(this.backText, backwardsIntro(s));
  }

  // ---------------------------------------------------------------- drawing

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const lab = this.lab;
    const hitch = lab.activeHitch();
    lab.spiral.forEach((run, i) => {
      const p = this.spiralPanels[i];
      if (p) this.renderSpiral(p, run, lab.spiralReadouts(run), hitch !== undefined);
    });
    lab.backwards.forEach((run, i) => {
      const p = this.backPanels[i];
      if (p) this.renderBackwards(p, run, lab.backwardsReadouts(run));
    });
    const reading = lab.clockReading;
    this.clockReading.set(fmt.seconds(reading / 1000), reading);
    const behind = lab.timeMs - reading;
    setText(
      this.clockNote,
      behind > 0
        ? `${fmt.seconds(behind / 1000)} behind the display’s time`
        : 'in step with the display',
    );
    this.clockNote.classList.toggle('warn-text', behind > 0);
    drawCharts(lab, this.stepsChart, this.simChart);
  }

  private renderSpiral(
    p: PanelView,
    run: BenchRun<SpiralLoop>,
    r: SpiralReadouts,
    hitch: boolean,
  ): void {
    const v = p.values;
    v.get('steps')?.set(fmt.count(r.steps), r.steps);
    v.get('max-steps')?.set(fmt.count(r.maxSteps), r.maxSteps);
    v.get('longest-frame')?.set(fmt.millis(r.longestFrameMs), r.longestFrameMs);
    v.get('fps')?.set(r.fps.toFixed(1), r.fps);
    v.get('ratio')?.set(fmt.ratio(r.ratio), r.ratio);
    v.get('owed')?.set(fmt.count(r.owed), r.owed);
    v.get('max-steps')?.warn(r.maxSteps > 33);
    v.get('fps')?.warn(r.fps < 1);
    this.pill(
      p,
      hitch
        ? 'Hitch: no frames'
        : r.busyMs > 250
          ? `Busy: next frame in ${fmt.seconds(r.busyMs / 1000)}`
          : '',
    );
    if (p.stall) {
      setHidden(p.stall, !r.stalled);
      setAttr(p.stall, 'data-value', String(r.stalled));
      setText(
        p.stall,
        r.stalled ? `Would have stalled: ${fmt.count(r.owed)} steps owed, never run` : 'Stalled',
      );
    }
    this.drawRun(p, run);
  }

  private renderBackwards(p: PanelView, run: BenchRun<BackwardsLoop>, r: BackwardsReadouts): void {
    const v = p.values;
    v.get('sim')?.set(fmt.seconds(r.simS), r.simS);
    v.get('lag')?.set(fmt.millis(r.lagMs), r.lagMs);
    v.get('reversed')?.set(r.reversed ? 'yes' : 'no', r.reversed);
    v.get('frozen')?.set(fmt.millis(r.frozenMs), r.frozenMs);
    v.get('backward-frames')?.set(
      r.backwardFrames === undefined ? 'n/a' : fmt.count(r.backwardFrames),
      r.backwardFrames,
    );
    v.get('reversed')?.warn(r.reversed);
    v.get('frozen')?.warn(r.frozenMs > 200);
    v.get('lag')?.warn(r.lagMs > 200);
    const now = this.lab.timeMs;
    this.pill(
      p,
      r.reversed && run.frames.length >= 8 && isGoingBack(run)
        ? 'Time runs backwards'
        : run.frozenUntil(now) > 200 && now - lastProgress(run) > 200
          ? 'Frozen: paying back the clock'
          : '',
    );
    this.drawRun(p, run);
  }

  private pill(p: PanelView, text: string): void {
    setHidden(p.overlay, text === '');
    setText(p.overlay, text);
  }

  private drawRun(p: PanelView, run: BenchRun<string>): void {
    const interpolate = this.shell.interpolate;
    const ball = run.ballAt(interpolate);
    const pts = run.trailPoints(run.rig.realMs, TRAIL_MS, interpolate, this.scratch);
    drawBall(p.scene, { ...ball, radius: run.scene.config.radius }, run.spec.color, pts);
  }
}
