/**
 * Chapter 2 — Movement. The same run-and-jump on four displays (30, 60, 144 and 240 Hz, with
 * jitter), once under a variable Δt and once under a fixed step, each loop's four trajectories
 * traced over each other. The numbers come from {@link MovementLab}; this module builds the page
 * and draws.
 */
import {
  DEFAULT_JITTER,
  LOOPS,
  MovementLab,
  RATES,
  STEP_MS,
  SWEEP_RATES,
  sweep,
  type LoopInfo,
  type LoopReadouts,
  type Source,
  type Track,
} from './movement-lab.js';
import type { MovementLoop } from '@fixedstep/games';
import { SceneCanvas, View, clearScene } from '../../ui/canvas.js';
import { Chart } from '../../ui/chart.js';
import { TimeControls, button, group, slider, toggle, setPressed } from '../../ui/controls.js';
import { code, h, setText } from '../../ui/dom.js';
import { LabDriver } from '../../shell/driver.js';
import { Readout, rateColor } from '../../ui/readout.js';

const SKIP_MS = 5000;
/** The world the canvases show, metres: the run-up, the jump, the landing strip under the floor. */
const VIEW = { x0: 0, x1: 8.4, y0: -0.56, y1: 2.05 };
/** Line widths (CSS px) per display, widest first, so coinciding lines show as nested stripes. */
const WIDTHS: Readonly<Record<string, number>> = { 30: 8, 60: 5.5, 144: 3.4, 240: 1.6, real: 1 };
const LOOP_COLORS: Readonly<Record<MovementLoop, string>> = {
  variable: '#f87171',
  fixed: '#38bdf8',
};

export function mount(root: HTMLElement): () => void {
  const chapter = new MovementChapter(root);
  return () => {
    chapter.destroy();
  };
}

function sourceLabel(s: Source, hz = 0): string {
  return s === 'real' ? (hz > 0 ? `yours ≈ ${hz} Hz` : 'yours') : `${s} Hz`;
}

function metres(v: number | undefined): string {
  return v === undefined || !Number.isFinite(v) ? '—' : `${v.toFixed(3)} m`;
}

function spreadText(v: number): string {
  if (!Number.isFinite(v)) return '—';
  if (v === 0) return '0 — identical';
  const cm = v * 100;
  return cm < 0.1 ? `${(cm * 10).toFixed(3)} mm` : `${cm.toFixed(1)} cm`;
}

interface RowView {
  readonly row: HTMLTableRowElement;
  readonly label: HTMLElement;
  readonly apex: Readout;
  readonly landing: Readout;
}

interface LoopView {
  readonly info: LoopInfo;
  readonly scene: SceneCanvas;
  readonly rows: Map<Source, RowView>;
  readonly apexSpread: Readout;
  readonly landingSpread: Readout;
  readonly jump: Readout;
  readonly verdict: HTMLElement;
  readonly legendReal: HTMLElement;
}

class MovementChapter {
  private lab = new MovementLab();
  private interpolate = true;
  private readonly driver: LabDriver;
  private readonly views: LoopView[] = [];
  private readonly time: TimeControls;
  private readonly jitter: ReturnType<typeof slider>;
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly jumpBtn: HTMLButtonElement;
  private readonly apexChart: Chart;
  private readonly landingChart: Chart;
  private readonly duo: HTMLElement;
  private sweepJitter = NaN;

  constructor(private readonly root: HTMLElement) {
    this.driver = new LabDriver(
      {
        advance: (ms) => {
          this.lab.advanceBy(ms);
        },
        realFrame: (t) => {
          this.lab.realFrame(t);
        },
        render: () => {
          this.render();
        },
      },
      { maxRealGapMs: 200 },
    );

    // ------------------------------------------------------------ controls
    this.jitter = slider({
      id: 'movement-jitter',
      label: 'Jitter',
      testId: 'control-jitter',
      min: 0,
      max: 30,
      step: 1,
      value: Math.round(DEFAULT_JITTER * 100),
      text: (v) => `±${v} %`,
      onChange: (v) => {
        this.lab.update({ jitter: v / 100 });
      },
    });
    this.jitter.input.title = 'How much each frame’s length varies, as a share of the period';
    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw the fixed-step runners between their last two states, at alpha';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setRealClock(on);
    });
    this.clockBtn.title = 'Add a fifth run per loop, fed this page’s own animation frames';
    this.time = new TimeControls({
      skipMs: SKIP_MS,
      onPause: () => {
        this.driver.setPaused(!this.driver.isPaused);
      },
      onSkip: () => {
        this.lab.advanceBy(SKIP_MS);
      },
      onRestart: () => {
        if (this.lab.realClock) this.setRealClock(true);
        else this.lab.restart();
      },
    });
    this.jumpBtn = button('Jump', 'control-jump', () => {
      this.lab.addJump();
    });
    this.jumpBtn.title = 'Press jump now, on every display at the same moment';

    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'Displays and time' },
      group(
        'Displays',
        h(
          'span',
          { class: 'rate-chips' },
          RATES.map((hz) => chip(hz)),
        ),
      ),
      this.jitter.el,
      group('Draw', this.interpBtn, this.clockBtn),
      group('Time', ...this.time.buttons, this.jumpBtn),
      h('div', { class: 'status', 'aria-live': 'off' }, ...this.time.status),
    );
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ panels
    this.duo = h('div', { class: 'duo' });
    for (const info of LOOPS) this.duo.append(this.buildPanel(info));

    // ------------------------------------------------------------ charts
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
    this.apexChart = new Chart({
      height: 200,
      label: 'Apex height of the first jump against display rate, variable Δt and fixed step',
      x: axisX,
      y: axisY('apex, m'),
      series,
    });
    this.landingChart = new Chart({
      height: 200,
      label: 'Landing distance of the first jump against display rate, variable Δt and fixed step',
      x: axisX,
      y: axisY('landing distance, m'),
      series,
    });

    root.append(
      h(
        'article',
        { class: 'chapter movement-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 2'),
          h('h1', {}, 'Movement'),
          h(
            'p',
            { class: 'lede' },
            'A jump is a few lines of Euler integration: add gravity to the velocity, add the velocity to the position. Hand those lines a different Δt and they trace a different arc. With a variable Δt, every display rate — and every hiccup of the frame clock — gets its own jump. With a fixed step, everyone gets the designer’s jump.',
          ),
        ),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'movement-bench-title' },
          h('h2', { id: 'movement-bench-title' }, 'One jump, four displays'),
          h(
            'p',
            { class: 'section-intro' },
            'A runner starts, jumps (holding the button for 0.18 s), lands and brakes; every 2.5 s it starts again. The same timestamped button presses reach four simulated displays — 30, 60, 144 and 240 Hz, each with its own frame jitter. Each loop traces its four runs over each other, widest line for 30 Hz, thinnest for 240 Hz: where they coincide you see one striped line.',
          ),
          controls,
          this.duo,
          legend(),
        ),
        h(
          'section',
          { class: 'sweep', 'aria-labelledby': 'sweep-title' },
          h('h2', { id: 'sweep-title' }, 'The same jump at nineteen display rates'),
          h(
            'p',
            { class: 'section-intro' },
            `The first jump of the script, run headless at every rate from ${SWEEP_RATES[0]} to ${SWEEP_RATES[SWEEP_RATES.length - 1]} Hz with the jitter above. Under a variable Δt the result depends on the display; under a fixed step it is one number.`,
          ),
          h('div', { class: 'chart-pair' }, this.apexChart.el, this.landingChart.el),
        ),
        why(),
        how(),
      ),
    );

    this.refreshSweep();
    this.refreshControls();
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    for (const v of this.views) v.scene.destroy();
    this.apexChart.destroy();
    this.landingChart.destroy();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- building

  private buildPanel(info: LoopInfo): HTMLElement {
    const scene = new SceneCanvas({
      class: 'scene jump-scene',
      label: `The four runs of the jump under ${info.title}, traced over each other`,
      testId: `canvas-${info.id}`,
    });
    const rows = new Map<Source, RowView>();
    const sources: Source[] = [...RATES, 'real'];
    const body = h(
      'tbody',
      {},
      sources.map((src) => {
        const label = h('span', {}, sourceLabel(src));
        const apex = new Readout('td', `${info.id}-${src}-apex`);
        const landing = new Readout('td', `${info.id}-${src}-landing`);
        const row = h(
          'tr',
          { hidden: src === 'real' },
          h(
            'th',
            { scope: 'row' },
            h(
              'span',
              { class: 'row-label' },
              h('span', { class: 'rate-dot', style: `--chip: ${rateColor(src)}` }),
              label,
            ),
          ),
          apex.el,
          landing.el,
        );
        rows.set(src, { row, label, apex, landing });
        return row;
      }),
    );
    const apexSpread = new Readout('td', `${info.id}-apex-spread`, { className: 'spread' });
    const landingSpread = new Readout('td', `${info.id}-landing-spread`, { className: 'spread' });
    const jump = new Readout('span', `${info.id}-jump`);
    const verdict = h('p', { class: 'verdict', 'data-testid': `verdict-${info.id}` });
    const legendReal = h(
      'span',
      { class: 'legend-item', style: `--chip: ${rateColor('real')}`, hidden: true },
      h('span', { class: 'legend-chip' }),
      'yours',
    );
    this.views.push({
      info,
      scene,
      rows,
      apexSpread,
      landingSpread,
      jump,
      verdict,
      legendReal,
    });
    const color = LOOP_COLORS[info.id];
    return h(
      'section',
      {
        class: 'panel track-panel',
        style: `--accent: ${color}`,
        'data-panel': info.id,
        'aria-labelledby': `panel-${info.id}`,
      },
      h(
        'header',
        { class: 'panel-head' },
        h('h3', { id: `panel-${info.id}` }, info.title),
        h('p', {}, info.tagline),
      ),
      h('div', { class: 'scene-wrap' }, scene.canvas),
      h(
        'div',
        { class: 'chart-legend scene-legend', 'aria-hidden': 'true' },
        RATES.map((hz) =>
          h(
            'span',
            { class: 'legend-item', style: `--chip: ${rateColor(hz)}` },
            h('span', { class: 'legend-chip' }),
            `${hz} Hz`,
          ),
        ),
        legendReal,
      ),
      h(
        'table',
        { class: 'jump-table' },
        h('caption', {}, 'Jump ', jump.el, ', as each display’s simulation computed it'),
        h(
          'thead',
          {},
          h(
            'tr',
            {},
            h('th', { scope: 'col' }, 'Display'),
            h('th', { scope: 'col' }, 'Apex'),
            h('th', { scope: 'col' }, 'Landing distance'),
          ),
        ),
        body,
        h(
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
      ),
      verdict,
    );
  }

  // ---------------------------------------------------------------- state

  private setRealClock(on: boolean): void {
    const settings = this.lab.settings;
    this.lab = new MovementLab({ jitter: settings.jitter, jumps: [] }, on);
    this.driver.setReal(on);
    setPressed(this.clockBtn, on);
    this.refreshControls();
  }

  private refreshControls(): void {
    const real = this.lab.realClock;
    this.time.refresh(this.driver.isPaused, !real);
    this.jitter.input.disabled = real;
    this.jitter.set(Math.round(this.lab.settings.jitter * 100));
    for (const v of this.views) {
      const row = v.rows.get('real');
      if (row) row.row.hidden = !real;
      v.legendReal.hidden = !real;
    }
    this.refreshSweep();
  }

  private refreshSweep(): void {
    const jitter = this.lab.settings.jitter;
    if (jitter === this.sweepJitter) return;
    this.sweepJitter = jitter;
    const s = sweep(jitter);
    this.apexChart.set([s.hz, s.apex.variable, s.apex.fixed]);
    this.landingChart.set([s.hz, s.landing.variable, s.landing.fixed]);
  }

  // ---------------------------------------------------------------- drawing

  private render(): void {
    const lab = this.lab;
    const real = lab.realClock;
    const hz = this.driver.measuredHz;
    this.time.show(
      lab.timeMs,
      real
        ? `real clock · your display ≈ ${hz} Hz${this.driver.isPaused ? ' · paused' : ''}`
        : `simulated displays · jitter ±${Math.round(lab.settings.jitter * 100)} %${this.driver.isPaused ? ' · paused' : ''}`,
    );
    for (const v of this.views) {
      const r = lab.readouts(v.info.id);
      this.writeReadouts(v, r, hz);
      this.drawScene(v, lab.tracks(v.info.id), r.jumpIndex, lab.drawTimeMs(v.info));
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
    const n = r.rows.length;
    const text = !ok
      ? 'Waiting for the first landing…'
      : same
        ? `${n} displays, one jump — identical to the last bit.`
        : `${n} displays, ${n} different jumps: the apex varies by ${spreadText(r.apexSpread)}, the landing by ${spreadText(r.landingSpread)}.`;
    setText(v.verdict, text);
    v.verdict.classList.toggle('good', same);
    v.verdict.classList.toggle('bad', ok && !same);
  }

  private drawScene(v: LoopView, tracks: Track[], jumpIndex: number, atMs: number): void {
    const sc = v.scene;
    if (!sc.fit()) return;
    const { ctx, dpr } = sc;
    clearScene(sc);
    const view = new View(sc.w, sc.h, VIEW.x0, VIEW.y0, VIEW.x1, VIEW.y1);
    const px = (x: number) => view.px(x);
    const py = (y: number) => view.py(y);
    view.grid(ctx, 0.5);
    // Ground and the landing strip under it.
    ctx.fillStyle = 'rgba(141, 160, 189, 0.06)';
    ctx.fillRect(px(VIEW.x0), py(0), px(VIEW.x1) - px(VIEW.x0), py(VIEW.y0) - py(0));
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.55)';
    ctx.lineWidth = Math.max(1, dpr);
    ctx.beginPath();
    ctx.moveTo(px(VIEW.x0), Math.round(py(0)) + 0.5);
    ctx.lineTo(px(VIEW.x1), Math.round(py(0)) + 0.5);
    ctx.stroke();
    ctx.fillStyle = 'rgba(163, 179, 204, 0.75)';
    ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    ctx.fillText('landings', px(VIEW.x0) + 6 * dpr, py(-0.25));
    // Scale bar: 1 m.
    const sx = px(VIEW.x1) - 10 * dpr - view.scale;
    const sy = py(VIEW.y1) + 12 * dpr;
    ctx.strokeStyle = 'rgba(163, 179, 204, 0.7)';
    ctx.beginPath();
    ctx.moveTo(sx, sy);
    ctx.lineTo(sx + view.scale, sy);
    ctx.moveTo(sx, sy - 3 * dpr);
    ctx.lineTo(sx, sy + 3 * dpr);
    ctx.moveTo(sx + view.scale, sy - 3 * dpr);
    ctx.lineTo(sx + view.scale, sy + 3 * dpr);
    ctx.stroke();
    ctx.textAlign = 'center';
    ctx.fillText('1 m', sx + view.scale / 2, sy + 10 * dpr);
    ctx.textAlign = 'start';

    ctx.lineJoin = 'round';
    ctx.lineCap = 'round';
    const rowH = 0.095;
    const runners = tracks.map((t) => t.runnerAt(atMs, this.interpolate));
    tracks.forEach((t, i) => {
      const color = rateColor(t.source);
      const width = (WIDTHS[String(t.source)] ?? 1) * dpr;
      const runner = runners[i]!;
      // The path of this round, up to where the runner is drawn.
      const p = t.path;
      ctx.strokeStyle = color;
      ctx.globalAlpha = 0.92;
      ctx.lineWidth = width;
      ctx.beginPath();
      if (runner.points > 0) {
        ctx.moveTo(px(p[1]!), py(p[2]!));
        for (let k = 1; k < runner.points; k++) ctx.lineTo(px(p[3 * k + 1]!), py(p[3 * k + 2]!));
        ctx.lineTo(px(runner.x), py(runner.y));
      }
      ctx.stroke();
      ctx.globalAlpha = 1;
      // Apex and landing of the jump shown in the table.
      const j = jumpIndex >= 0 ? t.jump(jumpIndex) : undefined;
      if (j) {
        ctx.lineWidth = width;
        ctx.beginPath();
        ctx.moveTo(px(j.apexX) - 7 * dpr, py(j.apex));
        ctx.lineTo(px(j.apexX) + 7 * dpr, py(j.apex));
        ctx.stroke();
        const y = -0.05 - i * rowH;
        ctx.lineWidth = Math.max(2, 3 * dpr);
        ctx.lineCap = 'butt';
        ctx.beginPath();
        ctx.moveTo(px(j.landingX), py(y));
        ctx.lineTo(px(j.landingX), py(y - rowH * 0.8));
        ctx.stroke();
        ctx.lineCap = 'round';
      }
    });
    // The runners on top, as nested discs: where they coincide they look like a target.
    tracks.forEach((t, i) => {
      const r = runners[i]!;
      const radius = ((WIDTHS[String(t.source)] ?? 1) + 3.5) * dpr;
      ctx.fillStyle = rateColor(t.source);
      ctx.strokeStyle = '#0a1122';
      ctx.lineWidth = Math.max(1, dpr);
      ctx.beginPath();
      ctx.arc(px(r.x), py(r.y), radius, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    });
  }
}

function chip(hz: number): HTMLElement {
  return h(
    'span',
    { class: 'legend-item', style: `--chip: ${rateColor(hz)}` },
    h('span', { class: 'legend-chip', 'aria-hidden': 'true' }),
    `${hz} Hz`,
  );
}

function legend(): HTMLElement {
  return h(
    'details',
    { class: 'legend' },
    h('summary', {}, 'How to read the panels'),
    h(
      'dl',
      {},
      h('dt', {}, 'Lines'),
      h(
        'dd',
        {},
        'Every position the simulation computed in this round, one line per display. Coinciding lines look like one striped line.',
      ),
      h('dt', {}, 'Runners'),
      h(
        'dd',
        {},
        `Each as its own display last drew it. A 30 Hz display shows an older frame than a 240 Hz one, so moving runners can be a frame apart even when their paths are identical. The fixed-step runners are drawn between their last two ${STEP_MS} ms steps (interpolation).`,
      ),
      h('dt', {}, 'Ticks'),
      h(
        'dd',
        {},
        'The short bar at the top of each arc is the apex; the marks under the floor are the landings, one row per display.',
      ),
      h('dt', {}, 'Apex, landing distance'),
      h(
        'dd',
        {},
        'The highest point of the jump above the floor, and the distance from take-off to landing, as each simulation computed them. Spread is the largest minus the smallest.',
      ),
    ),
  );
}

function why(): HTMLElement {
  return h(
    'section',
    { class: 'why', 'aria-labelledby': 'why-title' },
    h('h2', { id: 'why-title' }, 'Why the variable-Δt jumps differ'),
    h(
      'div',
      { class: 'why-grid' },
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'Euler depends on Δt'),
        h(
          'p',
          {},
          'Each update moves the runner by its velocity times Δt, then gravity bends the velocity. Big steps overshoot the curve differently from small ones, so the apex and the airtime change with the frame rate — by centimetres here, by whole platforms in a real level.',
        ),
        code('vy -= gravity * dt\ny  += vy * dt   // the arc depends on dt'),
      ),
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'Inputs land on frames'),
        h(
          'p',
          {},
          'With one update per frame, a button press takes effect on the next frame — up to 33 ms late at 30 Hz, 4 ms at 240 Hz — and so does letting go of the jump button, which decides how high the jump goes. A fixed step gives each press to the step whose time span contains it, whatever the display.',
        ),
        code(
          '// fixed step: same ticks, same inputs\nwhile (acc >= STEP) { update(STEP, input(tick)); acc -= STEP }',
        ),
      ),
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'Jitter makes it worse'),
        h(
          'p',
          {},
          'Real frames are never exactly 1/60 s. Under a variable Δt the same display gives a slightly different jump each time; drag the jitter slider to 0 and the variable runs still disagree, because the rates differ. Under a fixed step neither matters.',
        ),
      ),
    ),
  );
}

function how(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'movement-how-title' },
    h('h2', { id: 'movement-how-title' }, 'How this page works'),
    h(
      'p',
      {},
      'The four displays are simulated: their frame times are computed from the rate and a seeded jitter, so the numbers repeat on every machine. The page moves a virtual clock forward at real speed and runs the frames due; “Skip +5 s” moves it at once. Changing the jitter or pressing Jump replays every run from zero to the current moment, which lands exactly where a live run would be.',
    ),
    h(
      'p',
      {},
      '“Real clock” adds a fifth run to each loop, driven by this page’s own animation frames. Under the fixed step it still traces the very same jump, to the last bit.',
    ),
  );
}
