/**
 * Chapter 2 — Movement. The same run-and-jump on four displays (30, 60, 144 and 240 Hz, with
 * jitter), once under a variable Δt and once under a fixed step, each loop's four trajectories
 * traced over each other. The numbers come from {@link MovementLab}; the words from
 * movement-text.ts; the drawing from movement-draw.ts.
 */
import {
  DEFAULT_JITTER,
  LOOPS,
  MovementLab,
  RATES,
  sweep,
  type LoopInfo,
  type LoopReadouts,
  sourceLabel,
} from './movement-lab.js';
import { drawJumps } from './movement-draw.js';
import { LOOP_COLORS, rateChip, runsPanel, type RunsPanel } from './runs-panel.js';
import {
  BENCH_INTRO,
  LEDE,
  SWEEP_INTRO,
  SWEEP_TITLE,
  how,
  legend,
  verdictText,
  why,
} from './movement-text.js';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import { Chart } from '../../ui/chart.js';
import { button, group, jitterSlider } from '../../ui/controls.js';
import { h, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { headRow } from '../../ui/panel.js';
import { Readout } from '../../ui/readout.js';

export const mount = mountChapter((root, head) => new MovementChapter(root, head));

function metres(v: number | undefined): string {
  return v === undefined || !Number.isFinite(v) ? '—' : `${v.toFixed(3)} m`;
}

/** A spread in words: "0 — identical", "1.5 cm", "0.300 mm". */
export function spreadText(v: number): string {
  if (!Number.isFinite(v)) return '—';
  if (v === 0) return '0 — identical';
  const cm = v * 100;
  return cm < 0.1 ? `${(cm * 10).toFixed(3)} mm` : `${cm.toFixed(1)} cm`;
}

interface LoopView extends RunsPanel<{ apex: Readout; landing: Readout }> {
  readonly info: LoopInfo;
  readonly apexSpread: Readout;
  readonly landingSpread: Readout;
  readonly jump: Readout;
}

class MovementChapter {
  readonly shell: ChapterShell;
  private lab = new MovementLab();
  private readonly views: LoopView[] = [];
  private readonly jitter;
  private readonly apexChart: Chart;
  private readonly landingChart: Chart;
  private sweepJitter = NaN;

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      restart: () => {
        if (this.lab.realClock) this.lab = this.fresh(true);
        else this.lab.restart();
      },
      mode: () =>
        this.shell.display(
          `simulated displays · jitter ±${Math.round(this.lab.settings.jitter * 100)} %`,
        ),
      realClock: {
        title: 'Add a fifth run per loop, fed this page’s own animation frames',
        onChange: (on) => {
          this.lab = this.fresh(on);
        },
      },
      interpolation: {
        title: 'Draw the fixed-step runners between their last two states, at alpha',
      },
      driver: { maxRealGapMs: 200 },
    });
    const shell = this.shell;
    this.jitter = jitterSlider({
      id: 'movement-jitter',
      percent: Math.round(DEFAULT_JITTER * 100),
      onChange: (jitter) => {
        this.lab.update({ jitter });
      },
    });
    this.jitter.input.title = 'How much each frame’s length varies, as a share of the period';
    const jumpBtn = button('Jump', 'control-jump', () => {
      this.lab.addJump();
    });
    jumpBtn.title = 'Press jump now, on every display at the same moment';
    const charts = this.sweepCharts();
    this.apexChart = charts[0];
    this.landingChart = charts[1];
    shell.append(
      introSection(
        'bench',
        'movement-bench-title',
        'One jump, four displays',
        BENCH_INTRO,
        shell.controls(
          'Displays and time',
          group('Displays', h('span', { class: 'rate-chips' }, RATES.map(rateChip))),
          this.jitter.el,
          shell.drawGroup(),
          shell.timeGroup(jumpBtn),
          shell.status(),
        ),
        h(
          'div',
          { class: 'duo' },
          LOOPS.map((info) => this.buildPanel(info)),
        ),
        legend(),
      ),
      introSection(
        'sweep',
        'sweep-title',
        SWEEP_TITLE,
        SWEEP_INTRO,
        h('div', { class: 'chart-pair' }, this.apexChart.el, this.landingChart.el),
      ),
      why(),
      how(),
    );
    shell.start();
  }

  /** A new run of the current jitter: on the real clock (a fifth run per loop) or not. */
  private fresh(real: boolean): MovementLab {
    return new MovementLab({ jitter: this.lab.settings.jitter, jumps: [] }, real);
  }

  // ---------------------------------------------------------------- building

  private sweepCharts(): [Chart, Chart] {
    const axisY = (label: string) => ({
      label,
      format: (v: number) => v.toFixed(2),
      size: 40,
      range: (min: number, max: number): [number, number] => {
        const pad = Math.max(0.02, (max - min) * 0.25);
        return [min - pad, max + pad];
      },
    });
    const axisX = {
      scale: 'log' as const,
      label: 'display rate, Hz',
      format: (v: number) => String(Math.round(v)),
      range: [22, 400] as [number, number],
      splits: [24, 30, 60, 144, 240, 360],
    };
    const series = LOOPS.map((l) => ({
      label: l.title,
      color: LOOP_COLORS[l.id],
      points: 2.5,
      width: l.fixed ? 2.25 : 1.5,
    }));
    const chart = (what: string, label: string) =>
      this.shell.own(
        new Chart({
          height: 200,
          label: `${what} of the first jump against display rate, variable Δt and fixed step`,
          x: axisX,
          y: axisY(label),
          series,
        }),
      );
    return [chart('Apex height', 'apex, m'), chart('Landing distance', 'landing distance, m')];
  }

  private buildPanel(info: LoopInfo): HTMLElement {
    const jump = new Readout('span', `${info.id}-jump`);
    const apexSpread = new Readout('td', `${info.id}-apex-spread`, { className: 'spread' });
    const landingSpread = new Readout('td', `${info.id}-landing-spread`, { className: 'spread' });
    const built = runsPanel(this.shell, info, {
      sceneClass: 'scene jump-scene',
      sceneLabel: `The four runs of the jump under ${info.title}, traced over each other`,
      cells: (src) => ({
        apex: new Readout('td', `${info.id}-${src}-apex`),
        landing: new Readout('td', `${info.id}-${src}-landing`),
      }),
      tableClass: 'jump-table',
      caption: ['Jump ', jump.el, ', as each display’s simulation computed it'],
      head: headRow('Display', 'Apex', 'Landing distance'),
      foot: h(
        'tfoot',
        {},
        h(
          'tr',
          {},
          h('th', { scope: 'row', title: 'max − min over the displays' }, 'Spread'),
          apexSpread.el,
          landingSpread.el,
        ),
      ),
    });
    this.views.push({ ...built, info, apexSpread, landingSpread, jump });
    return built.element;
  }

  // ---------------------------------------------------------------- state

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const real = this.lab.realClock;
    this.jitter.input.disabled = real;
    this.jitter.set(Math.round(this.lab.settings.jitter * 100));
    for (const v of this.views) {
      const row = v.rows.get('real');
      if (row) row.row.hidden = !real;
      setHidden(v.legendReal, !real);
    }
    const jitter = this.lab.settings.jitter;
    if (jitter === this.sweepJitter) return;
    this.sweepJitter = jitter;
    const s = sweep(jitter);
    this.apexChart.set([s.hz, s.apex.variable, s.apex.fixed]);
    this.landingChart.set([s.hz, s.landing.variable, s.landing.fixed]);
  }

  // ---------------------------------------------------------------- drawing

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const lab = this.lab;
    const hz = this.shell.measuredHz;
    for (const v of this.views) {
      const r = lab.readouts(v.info.id);
      this.writeReadouts(v, r, hz);
      drawJumps(
        v.scene,
        lab.tracks(v.info.id),
        r.jumpIndex,
        lab.drawTimeMs(v.info),
        this.shell.interpolate,
      );
    }
  }

  private writeReadouts(v: LoopView, r: LoopReadouts, hz: number): void {
    for (const row of r.rows) {
      const view = v.rows.get(row.source);
      if (!view) continue;
      setText(view.label, sourceLabel(row.source, hz));
      view.apex.set(metres(row.jump?.apex), row.jump?.apex);
      view.landing.set(metres(row.jump?.distance), row.jump?.distance);
    }
    const ok = r.jumpIndex >= 0;
    v.jump.set(ok ? `#${r.jumpIndex + 1}` : '—', ok ? r.jumpIndex + 1 : undefined);
    v.apexSpread.set(spreadText(r.apexSpread), ok ? r.apexSpread : undefined);
    v.landingSpread.set(spreadText(r.landingSpread), ok ? r.landingSpread : undefined);
    const same = ok && r.apexSpread === 0 && r.landingSpread === 0;
    for (const s of [v.apexSpread, v.landingSpread]) {
      s.good(same);
      s.warn(ok && !same);
    }
    setText(v.verdict, verdictText(r, spreadText));
    v.verdict.classList.toggle('good', same);
    v.verdict.classList.toggle('bad', ok && !same);
  }
}
