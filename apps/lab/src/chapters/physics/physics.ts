/**
 * Chapter 4 — Physics. The talk's spring at a fixed step under six integrators side by side, with
 * a live energy plot and the stability limits, a hitch under a variable Δt, and a rope of springs
 * to poke under a chosen integrator; on a simulated display (or the page's real clock). The
 * numbers come from {@link PhysicsLab}; the words from physics-text.ts; the drawing from
 * physics-draw.ts; the rope from physics-rope.ts.
 */
import { INTEGRATOR_INFO, INTEGRATOR_METHODS, type IntegratorMethod } from 'fixedstep';
import {
  ClockPhysics,
  EXPLODE_AT,
  MAX_REAL_FRAME_MS,
  PhysicsLab,
  STEP,
  STIFFNESS,
  omegaOf,
  stabilityOf,
  type PhysicsRun,
  type PhysicsSettings,
  type Stability,
} from './physics-lab.js';
import { EnergyChart } from './physics-chart.js';
import { drawLane } from './physics-draw.js';
import { HitchSection } from './physics-hitch.js';
import { formulasSection } from './physics-formulas.js';
import { RopeSection } from './physics-rope.js';
import {
  COLORS,
  LEDE,
  SHORT,
  SPRING_INTRO,
  TRY,
  UPDATE,
  energyLegend,
  energyText,
  errorText,
  howItWorks,
  methodsIntro,
  verdictText,
} from './physics-text.js';
import {
  ChapterShell,
  mountChapter,
  realTimeLine,
  type ChapterHead,
} from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { tryCards } from '../../ui/cards.js';
import { ladderSlider, slider } from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import './physics.css';

/** Where the ω·dt ruler ends. */
const RULER_MAX = 4;

type LaneField = 'energy-ratio' | 'max-error' | 'phase';

interface LaneView {
  readonly method: IntegratorMethod;
  readonly scene: SceneCanvas;
  readonly values: Map<LaneField, Readout>;
  readonly chip: Readout;
  /** "Exploded at …": a line under the canvas, never over the spring. */
  readonly note: HTMLElement;
}

interface RulerRow {
  readonly method: IntegratorMethod;
  readonly row: HTMLElement;
  readonly verdict: HTMLElement;
}

export const mount = mountChapter((root, head) => new PhysicsChapter(root, head));

class PhysicsChapter {
  readonly shell: ChapterShell;
  private readonly lab = new PhysicsLab();
  private clock: ClockPhysics | undefined;
  private readonly realLine = realTimeLine(() => this.clock);
  private readonly lanes: LaneView[] = [];
  private chart: EnergyChart | undefined;
  private readonly step;
  private readonly stiffness;
  private readonly status = {
    omega: new Readout('span', 'omega', { className: 'clock' }),
    omegaDt: new Readout('span', 'omega-dt', { className: 'clock' }),
    ticks: new Readout('span', 'ticks', { className: 'clock' }),
  };
  private readonly ruler: RulerRow[] = [];
  private readonly rulerMarker = h('div', { class: 'ruler-marker', 'aria-hidden': 'true' });
  private readonly rulerMarkerLabel = h('span', { class: 'ruler-marker-label' });
  private readonly laneGrid: HTMLElement;
  private readonly hitch: HitchSection;
  private readonly rope: RopeSection;

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => (this.clock ? this.realLine : this.lab),
      restart: () => {
        this.hitch.restart();
        if (this.clock) this.clock = new ClockPhysics(this.lab.settings);
        else this.lab.restart();
        this.rope.forgetPoke();
      },
      mode: () => this.shell.display('simulated display · 60 Hz'),
      realClock: {
        title: 'Drive the fixed-step loop with this page’s own requestAnimationFrame times',
        onChange: (on) => {
          this.clock = on ? new ClockPhysics(this.lab.settings) : undefined;
        },
      },
      interpolation: { title: 'Draw between the last two steps, at alpha' },
      driver: { maxFrameMs: MAX_REAL_FRAME_MS },
    });
    const shell = this.shell;
    const s = this.lab.settings;
    this.step = slider({
      id: 'phys-step',
      label: 'Step',
      testId: 'control-step',
      min: STEP.min,
      max: STEP.max,
      step: STEP.step,
      value: s.stepMs,
      text: (v) => `${v} ms`,
      onChange: (v) => {
        this.change({ stepMs: v });
      },
    });
    this.stiffness = ladderSlider({
      id: 'phys-k',
      label: 'Spring k',
      testId: 'control-stiffness',
      values: STIFFNESS,
      value: s.stiffness,
      unit: 'N/m',
      onChange: (k) => {
        this.change({ stiffness: k });
      },
    });
    this.hitch = new HitchSection(
      () => {
        shell.redraw();
      },
      (attrs) => shell.canvas(attrs),
    );
    this.rope = new RopeSection(shell, {
      settings: () => this.lab.settings,
      run: () => this.run(),
      timeMs: () => (this.clock ? this.clock.timeMs : this.lab.timeMs),
      change: (change) => {
        this.change(change);
      },
      poke: (p) => {
        if (this.clock) this.clock.poke(p);
        else this.lab.poke(p);
        if (shell.paused) shell.setPaused(false);
      },
    });
    this.laneGrid = h(
      'div',
      { class: 'panels lane-panels' },
      INTEGRATOR_METHODS.map((m) => this.buildLane(m)),
    );
    const chartHost = h('div', {
      class: 'energy-chart',
      role: 'img',
      'aria-label': 'Energy over time of each method, on a log scale',
      'data-testid': 'chart-energy',
    });
    shell.observe(chartHost, () => {
      this.fitChart(chartHost);
    });
    shell.append(
      formulasSection(),
      methodsIntro(),
      introSection(
        'bench',
        'spring-title',
        'One spring, six integrators',
        SPRING_INTRO,
        shell.controls(
          'The spring',
          this.step.el,
          this.stiffness.el,
          shell.drawGroup(),
          shell.timeGroup(),
          shell.status(
            h('span', { class: 'status-item' }, 'ω = ', this.status.omega.el),
            h('span', { class: 'status-item' }, 'ω·dt = ', this.status.omegaDt.el),
            h('span', { class: 'status-item' }, 'steps: ', this.status.ticks.el),
          ),
        ),
        this.buildRuler(),
        this.laneGrid,
        h('h3', { class: 'chart-heading' }, 'Energy, E / E₀ (log scale)'),
        h('div', { class: 'energy-chart-wrap' }, chartHost, energyLegend()),
      ),
      this.hitch.el,
      this.rope.el,
      this.experiments(),
      howItWorks(),
    );
    shell.start();
  }

  // ---------------------------------------------------------------- building

  private fitChart(host: HTMLElement): void {
    const cw = Math.floor(host.getBoundingClientRect().width);
    if (!this.chart && cw > 0) {
      this.chart = this.shell.own(
        new EnergyChart(
          host,
          cw,
          INTEGRATOR_METHODS.map((m) => INTEGRATOR_INFO[m].label),
          INTEGRATOR_METHODS.map((m) => COLORS[m]),
          () => (window.innerWidth < 600 ? 220 : 280),
        ),
      );
    } else this.chart?.resize(cw);
  }

  private buildRuler(): HTMLElement {
    this.rulerMarker.append(this.rulerMarkerLabel);
    const rows = INTEGRATOR_METHODS.map((method) => {
      const limit = INTEGRATOR_INFO[method].stabilityLimit;
      const stableTo = limit === Infinity ? 100 : (Math.min(limit, RULER_MAX) / RULER_MAX) * 100;
      const verdict = h('span', { class: 'ruler-verdict' });
      const row = h(
        'div',
        { class: 'ruler-row', style: `--accent: ${COLORS[method]}` },
        h('span', { class: 'ruler-name' }, SHORT[method]),
        h(
          'span',
          { class: 'ruler-track', style: `--stable: ${stableTo}%` },
          limit > 0 && limit < Infinity
            ? h(
                'span',
                { class: 'ruler-limit', style: `left: ${stableTo}%` },
                limit === 2 ? '2' : '2√2',
              )
            : null,
        ),
        verdict,
      );
      this.ruler.push({ method, row, verdict });
      return row;
    });
    return h(
      'div',
      {
        class: 'ruler',
        role: 'img',
        'aria-label':
          'ω·dt against each method’s stability limit: explicit Euler grows at any ω·dt, semi-implicit Euler and the Verlets up to 2, RK4 up to 2√2, backward Euler never',
      },
      h(
        'div',
        { class: 'ruler-head' },
        h('span', { class: 'ruler-name' }, 'ω·dt'),
        h(
          'span',
          { class: 'ruler-scale' },
          [0, 1, 2, 3, 4].map((v) =>
            h('span', { style: `left: ${(v / RULER_MAX) * 100}%` }, String(v)),
          ),
        ),
        h('span', { class: 'ruler-verdict' }),
      ),
      rows,
      h('div', { class: 'ruler-overlay' }, this.rulerMarker),
    );
  }

  private buildLane(method: IntegratorMethod): HTMLElement {
    const info = INTEGRATOR_INFO[method];
    const scene = this.shell.canvas({
      class: 'scene lane-scene',
      label: `The spring under ${info.label}: the mass and its phase portrait`,
      testId: `canvas-${method}`,
    });
    const rows: { field: LaneField; label: string; title: string }[] = [
      {
        field: 'energy-ratio',
        label: 'E / E₀',
        title: 'Energy now over energy at the start: 1 is exact',
      },
      {
        field: 'max-error',
        label: 'max |ΔE| / E₀',
        title: 'The largest relative energy error so far',
      },
      {
        field: 'phase',
        label: 'Phase error',
        title: 'Ahead (+) or behind (−) the exact motion, radians',
      },
    ];
    const values = new Map<LaneField, Readout>();
    const list = rows.flatMap((row) => {
      const r = new Readout('dd', `${method}-${row.field}`);
      values.set(row.field, r);
      return [h('dt', { title: row.title }, row.label), r.el];
    });
    const chip = new Readout('span', `${method}-state`, { className: 'state-chip' });
    const note = h('span', { class: 'scene-pill', hidden: true });
    this.lanes.push({ method, scene, values, chip, note });
    const limit =
      info.stabilityLimit === 0
        ? 'grows at any step'
        : info.stabilityLimit === Infinity
          ? 'never grows; damps'
          : `stable while ω·dt < ${info.stabilityLimit === 2 ? '2' : '2√2'}`;
    return h(
      'section',
      {
        class: 'panel lane-panel',
        style: `--accent: ${COLORS[method]}`,
        'data-panel': method,
        'aria-labelledby': `lane-${method}`,
      },
      h(
        'header',
        { class: 'panel-head lane-head' },
        h(
          'h3',
          { id: `lane-${method}` },
          h('span', { class: 'name-long' }, info.label),
          h('span', { class: 'name-short', 'aria-hidden': 'true' }, SHORT[method]),
          chip.el,
        ),
        h('p', {}, h('code', {}, UPDATE[method]), h('br', {}), `order ${info.order} · ${limit}`),
      ),
      h('div', { class: 'scene-wrap' }, scene.canvas),
      h('p', { class: 'scene-notes' }, note),
      h('dl', { class: 'readouts' }, list),
    );
  }

  private experiments(): HTMLElement {
    // Each sets everything its text assumes and starts again, whatever was clicked before.
    const card = (
      key: keyof typeof TRY,
      settings: Partial<PhysicsSettings>,
      playMs: number | undefined,
      show: () => HTMLElement,
    ) => ({
      ...TRY[key],
      run: () => {
        if (this.clock) this.shell.setReal(false);
        this.lab.update({
          stepMs: 30,
          stiffness: 20,
          ropeStiffness: 40,
          ropeMethod: 'semi-implicit-euler',
          ...settings,
        });
        this.rope.show(this.lab.settings, true);
        this.lab.restart();
        this.rope.forgetPoke();
        if (playMs !== undefined) {
          this.lab.advanceBy(playMs);
          this.shell.setPaused(true);
        } else {
          this.shell.setPaused(false);
        }
        show().scrollIntoView({ block: 'start', behavior: 'smooth' });
      },
    });
    return tryCards('phys-experiments-title', [
      card('exploding', {}, 10_000, () => this.laneGrid),
      card('past2', { stiffness: 5000 }, undefined, () => this.laneGrid),
      card('smaller', { stepMs: 15 }, 10_000, () => this.laneGrid),
      card(
        'stiffrope',
        { ropeStiffness: 1000, ropeMethod: 'backward-euler' },
        undefined,
        () => this.rope.canvas.canvas,
      ),
    ]);
  }

  // ---------------------------------------------------------------- state changes

  private change(change: Partial<PhysicsSettings>): void {
    this.lab.update(change);
    if (this.clock) this.shell.setReal(true);
    this.shell.refresh();
  }

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const s = this.lab.settings;
    this.step.set(s.stepMs);
    this.stiffness.set(s.stiffness);
    // The method radios are not set here: this runs inside their own click, and would undo it.
    this.rope.show(s, false);
  }

  // ---------------------------------------------------------------- the frame

  private run(): PhysicsRun {
    return this.clock ? this.clock.run : this.lab.run;
  }

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const run = this.run();
    const t = this.clock ? this.clock.timeMs : this.lab.timeMs;
    this.hitch.render(t);
    const omega = omegaOf(this.lab.settings.stiffness);
    const omegaDt = run.omegaDt;
    this.status.omega.set(`${omega.toFixed(2)} rad/s`, omega);
    this.status.omegaDt.set(omegaDt.toFixed(3), omegaDt);
    this.status.ticks.set(fmt.count(run.race.tick), run.race.tick);
    this.renderRuler(omegaDt);
    const alpha = this.shell.interpolate ? run.alpha : 1;
    this.lanes.forEach((lane, k) => {
      this.renderLane(lane, run, k, alpha, omegaDt);
    });
    this.chart?.set(run.energy, run.race.time);
    this.rope.render(alpha);
  }

  private renderRuler(omegaDt: number): void {
    const left = (Math.min(omegaDt, RULER_MAX) / RULER_MAX) * 100;
    setAttr(this.rulerMarker, 'style', `left: ${left.toFixed(3)}%`);
    this.rulerMarker.classList.toggle('beyond', omegaDt > RULER_MAX);
    setText(this.rulerMarkerLabel, `${omegaDt > RULER_MAX ? '→ ' : ''}${omegaDt.toFixed(2)}`);
    for (const r of this.ruler) {
      const st = stabilityOf(r.method, omegaDt);
      setText(r.verdict, verdictText(st));
      setAttr(r.row, 'data-state', st);
    }
  }

  private renderLane(
    l: LaneView,
    run: PhysicsRun,
    k: number,
    alpha: number,
    omegaDt: number,
  ): void {
    const lane = run.race.lanes[k];
    if (!lane) return;
    const race = run.race;
    const ratio = race.energyRatio(lane);
    const v = l.values;
    v.get('energy-ratio')?.set(energyText(ratio), ratio);
    v.get('energy-ratio')?.warn(!(Math.abs(ratio - 1) < 0.1));
    v.get('max-error')?.set(errorText(lane.maxEnergyError), lane.maxEnergyError);
    const phase = race.phaseError(lane);
    const phaseText = Math.abs(phase).toFixed(3);
    v.get('phase')?.set(
      `${phaseText === '0.000' ? '±' : phase >= 0 ? '+' : '−'}${phaseText} rad`,
      phase,
    );
    // A method inside its stability limit may still drain the motion (RK4 near 2√2): that is
    // "damped", not "stable" — stable is not the same as right.
    const limitState = stabilityOf(l.method, omegaDt);
    const st: Stability | 'exploded' = lane.exploded
      ? 'exploded'
      : limitState === 'stable' && ratio < 1e-3
        ? 'damped'
        : limitState;
    l.chip.set(st, st);
    setAttr(l.chip.el, 'data-state', st);
    setHidden(l.note, !lane.exploded);
    setText(
      l.note,
      lane.exploded
        ? `Exploded at ${(lane.explodedAt * race.dt).toFixed(2)} s: energy ×${fmt.sci(EXPLODE_AT, 0)}`
        : '',
    );
    drawLane(l.scene, run, k, COLORS[l.method], alpha);
  }
}
