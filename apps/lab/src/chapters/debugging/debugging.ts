/**
 * Chapter 7 — Debugging. One recording of button presses replayed on four displays under a
 * variable Δt and under a fixed step, with every run's state hash: under the fixed step they agree
 * tick for tick. The reader can record their own session. The numbers come from {@link DebugLab};
 * this module builds the page and draws.
 */
import {
  CHART_WINDOW_MS,
  DEFAULT_JITTER,
  DebugLab,
  LOOPS,
  MAX_RECORDING_MS,
  RATES,
  STEP_MS,
  type DebugReadouts,
  type DebugTrack,
  type LoopInfo,
  type Source,
} from './debugging-lab.js';
import {
  JumperButtons,
  demoRecording,
  type MovementLoop,
  type ScriptedInput,
} from '@fixedstep/games';
import { SceneCanvas, View, clearScene } from '../../ui/canvas.js';
import { Chart } from '../../ui/chart.js';
import { TimeControls, button, group, setPressed, slider, toggle } from '../../ui/controls.js';
import { code, h, setAttr, setText } from '../../ui/dom.js';
import { LabDriver } from '../../shell/driver.js';
import * as fmt from '../../ui/format.js';
import { Readout, rateColor } from '../../ui/readout.js';

const SKIP_MS = 5000;
const LEVEL = { x0: 0, x1: 14, y0: -0.15, y1: 2.95 };
const WIDTHS: Readonly<Record<string, number>> = { 30: 7, 60: 5, 144: 3.2, 240: 1.6, real: 1 };
const LOOP_COLORS: Readonly<Record<MovementLoop, string>> = {
  variable: '#f87171',
  fixed: '#38bdf8',
};
const TRAIL_MS = 700;

/** Keys while recording: `KeyboardEvent.code` → button. */
const KEYS: Readonly<Record<string, number>> = {
  ArrowLeft: JumperButtons.left,
  KeyA: JumperButtons.left,
  ArrowRight: JumperButtons.right,
  KeyD: JumperButtons.right,
  Space: JumperButtons.jump,
  ArrowUp: JumperButtons.jump,
  KeyW: JumperButtons.jump,
};

export function mount(root: HTMLElement): () => void {
  const chapter = new DebuggingChapter(root);
  return () => {
    chapter.destroy();
  };
}

function sourceLabel(s: Source, hz = 0): string {
  return s === 'real' ? (hz > 0 ? `yours ≈ ${hz} Hz` : 'yours') : `${s} Hz`;
}

interface RowView {
  readonly row: HTMLTableRowElement;
  readonly label: HTMLElement;
  readonly ticks: Readout;
  readonly score: Readout;
  readonly hash: Readout;
}

interface LoopView {
  readonly info: LoopInfo;
  readonly scene: SceneCanvas;
  readonly rows: Map<Source, RowView>;
  readonly equal: Readout;
  readonly tick: Readout | undefined;
  readonly verdict: HTMLElement;
  readonly legendReal: HTMLElement;
}

class DebuggingChapter {
  private lab = new DebugLab();
  private interpolate = true;
  private readonly driver: LabDriver;
  private readonly views: LoopView[] = [];
  private readonly time: TimeControls;
  private readonly jitter: ReturnType<typeof slider>;
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly recordBtn: HTMLButtonElement;
  private readonly demoBtn: HTMLButtonElement;
  private readonly padButtons: HTMLButtonElement[] = [];
  private readonly recStatus: HTMLElement;
  private readonly inputsOut: Readout;
  private readonly lengthOut: Readout;
  private readonly divergence: Chart;
  private readonly divVariable: Readout;
  private readonly divFixed: Readout;
  private readonly timeline: SceneCanvas;
  private readonly cleanups: (() => void)[] = [];

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
    this.recordBtn = button('● Record', 'control-record', () => {
      this.toggleRecording();
    });
    this.recordBtn.classList.add('record-btn');
    this.recordBtn.title = 'Record your own inputs (R): run with ← →, jump with Space';
    this.recordBtn.setAttribute('aria-keyshortcuts', 'R');
    this.demoBtn = button('Demo recording', 'control-demo', () => {
      this.lab.load(demoRecording(), true);
      this.afterRestart();
    });
    this.demoBtn.title = 'Replay the built-in recording';
    const pad = (label: string, b: number, testId: string, aria: string) => {
      const btn = h(
        'button',
        { type: 'button', class: 'btn pad-btn', 'data-testid': testId, 'aria-label': aria },
        label,
      );
      const up = () => {
        if (this.lab.press(b, false, this.lateMs())) this.render();
      };
      btn.addEventListener('pointerdown', (e) => {
        e.preventDefault();
        btn.setPointerCapture(e.pointerId);
        if (this.lab.press(b, true, this.lateMs())) this.render();
      });
      btn.addEventListener('pointerup', up);
      btn.addEventListener('pointercancel', up);
      btn.addEventListener('lostpointercapture', up);
      // Keyboard activation (Enter on a focused pad button): a short tap.
      btn.addEventListener('click', (e) => {
        if (e.detail !== 0) return;
        const late = this.lateMs();
        this.lab.press(b, true, late);
        this.lab.press(b, false, late + 150);
      });
      this.padButtons.push(btn);
      return btn;
    };
    this.recStatus = h('span', { class: 'rec-status', 'aria-live': 'polite' });
    this.inputsOut = new Readout('strong', 'recording-inputs');
    this.lengthOut = new Readout('strong', 'recording-length');

    this.jitter = slider({
      id: 'debug-jitter',
      label: 'Jitter',
      testId: 'control-jitter',
      min: 0,
      max: 30,
      step: 1,
      value: Math.round(DEFAULT_JITTER * 100),
      text: (v) => `±${v} %`,
      onChange: (v) => {
        this.lab.setJitter(v / 100);
      },
    });
    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw the runners between their last two states';
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
        this.lab.restart();
        this.afterRestart();
      },
    });
    this.time.restartBtn.title = 'Replay the recording from the start';

    this.timeline = new SceneCanvas({
      class: 'timeline',
      label: 'The recording: when each button was held',
      testId: 'canvas-recording',
    });

    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'Recording, displays and time' },
      group(
        'Inputs',
        this.recordBtn,
        this.demoBtn,
        h(
          'span',
          { class: 'pad', role: 'group', 'aria-label': 'Buttons for recording' },
          pad('◀', JumperButtons.left, 'control-left', 'Run left'),
          pad('Jump', JumperButtons.jump, 'control-jump', 'Jump'),
          pad('▶', JumperButtons.right, 'control-right', 'Run right'),
        ),
      ),
      this.jitter.el,
      group('Draw', this.interpBtn, this.clockBtn),
      group('Time', ...this.time.buttons),
      h(
        'div',
        { class: 'status', 'aria-live': 'off' },
        ...this.time.status,
        h('span', { class: 'status-item' }, this.inputsOut.el, ' inputs over ', this.lengthOut.el),
        this.recStatus,
      ),
      h('div', { class: 'timeline-wrap' }, this.timeline.canvas),
    );
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ panels
    const duo = h('div', { class: 'duo' });
    for (const info of LOOPS) duo.append(this.buildPanel(info));

    // ------------------------------------------------------------ chart
    this.divergence = new Chart({
      height: 190,
      label: 'How far apart the four displays’ runners are over time, per loop',
      x: { format: (v) => `${Number.isInteger(v) ? v : v.toFixed(1)} s`, label: 'time' },
      y: {
        format: (v) => v.toFixed(0),
        label: 'apart, cm',
        range: (_min, max) => [0, Math.max(10, Math.ceil(max * 1.15))],
      },
      series: LOOPS.map((l) => ({
        label: l.title,
        color: LOOP_COLORS[l.id],
        fill: !l.fixed,
        width: l.fixed ? 2.5 : 1.5,
      })),
    });
    this.divVariable = new Readout('strong', 'variable-divergence');
    this.divFixed = new Readout('strong', 'fixed-divergence');

    root.append(
      h(
        'article',
        { class: 'chapter debugging-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 7'),
          h('h1', {}, 'Debugging'),
          h(
            'p',
            { class: 'lede' },
            'A bug you cannot reproduce is a bug you cannot fix. With a fixed step, the physics always behaves the same way: record the player’s inputs, replay them anywhere, and you get the very same game — down to the last bit of its state.',
          ),
        ),
        h(
          'p',
          { class: 'guarantee', 'data-testid': 'guarantee' },
          h('strong', {}, 'What is guaranteed: '),
          'the same start and the same recorded inputs give the same state bits, tick for tick — at every display rate, under any frame jitter, and in every JavaScript engine. The test suite proves it on every run: Node 20, Chromium 156 (V8), Firefox ESR 153 (SpiderMonkey) and WebKitGTK 2.50 (JavaScriptCore) agree on every tick of 137 354 ticks of scenes and games, and so do displays at 30, 59.94, 60, 144 and 240 Hz. Only the inputs and the random seed need recording; the hash proves the replay is the game.',
        ),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'debug-bench-title' },
          h('h2', { id: 'debug-bench-title' }, 'One recording, four displays'),
          h(
            'p',
            { class: 'section-intro' },
            'A little level with coins that reappear at seeded random places. The recording below — timestamped presses of ←, → and Jump — replays on four simulated displays under each loop. Every run hashes its whole state (runner, coins, score and the random generator) after every update. Press Record to play a session of your own; when you stop, it replays on all four displays.',
          ),
          controls,
          duo,
        ),
        h(
          'section',
          { class: 'divergence', 'aria-labelledby': 'divergence-title' },
          h('h2', { id: 'divergence-title' }, 'How far apart the runs drift'),
          h(
            'p',
            { class: 'section-intro' },
            'The largest distance between any two displays’ runners at the same moment (the fixed-step runs compared at the same tick). Now: variable Δt ',
            this.divVariable.el,
            ', fixed step ',
            this.divFixed.el,
            '.',
          ),
          h('div', { class: 'chart-card' }, this.divergence.el),
        ),
        why(),
        how(),
      ),
    );

    // ------------------------------------------------------------ keyboard
    const onKey = (e: KeyboardEvent) => {
      const target = e.target as HTMLElement | null;
      if (target && (target.tagName === 'INPUT' || target.isContentEditable)) return;
      if (e.type === 'keydown' && e.code === 'KeyR' && !e.repeat && !e.ctrlKey && !e.metaKey) {
        this.toggleRecording();
        this.refreshControls();
        this.render();
        return;
      }
      const b = KEYS[e.code];
      if (b === undefined || this.lab.mode !== 'recording') return;
      e.preventDefault();
      if (e.repeat) return;
      if (this.lab.press(b, e.type === 'keydown', this.lateMs())) this.render();
    };
    window.addEventListener('keydown', onKey);
    window.addEventListener('keyup', onKey);
    this.cleanups.push(() => {
      window.removeEventListener('keydown', onKey);
      window.removeEventListener('keyup', onKey);
    });

    this.refreshControls();
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    for (const c of this.cleanups) c();
    for (const v of this.views) v.scene.destroy();
    this.timeline.destroy();
    this.divergence.destroy();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- building

  private buildPanel(info: LoopInfo): HTMLElement {
    const scene = new SceneCanvas({
      class: 'scene level-scene',
      label: `The four runs of the recording under ${info.title}, drawn over each other`,
      testId: `canvas-${info.id}`,
    });
    const rows = new Map<Source, RowView>();
    const sources: Source[] = [...RATES, 'real'];
    const body = h(
      'tbody',
      {},
      sources.map((src) => {
        const label = h('span', {}, sourceLabel(src));
        const ticks = new Readout('td', `${info.id}-${src}-ticks`);
        const score = new Readout('td', `${info.id}-${src}-score`);
        const hash = new Readout('td', `${info.id}-${src}-hash`, { hash: true });
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
          ticks.el,
          score.el,
          hash.el,
        );
        rows.set(src, { row, label, ticks, score, hash });
        return row;
      }),
    );
    const equal = new Readout('td', `${info.id}-hashes-equal`, { className: 'spread' });
    equal.el.setAttribute('colspan', '3');
    const tick = info.fixed ? new Readout('strong', 'fixed-common-tick') : undefined;
    const verdict = h('p', { class: 'verdict', 'data-testid': `verdict-${info.id}` });
    const legendReal = h(
      'span',
      { class: 'legend-item', style: `--chip: ${rateColor('real')}`, hidden: true },
      h('span', { class: 'legend-chip' }),
      'yours',
    );
    this.views.push({ info, scene, rows, equal, tick, verdict, legendReal });
    return h(
      'section',
      {
        class: 'panel track-panel',
        style: `--accent: ${LOOP_COLORS[info.id]}`,
        'data-panel': info.id,
        'aria-labelledby': `debug-panel-${info.id}`,
      },
      h(
        'header',
        { class: 'panel-head' },
        h('h3', { id: `debug-panel-${info.id}` }, info.title),
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
        { class: 'jump-table hash-table' },
        h(
          'caption',
          {},
          tick
            ? ['State hash after tick ', tick.el, ' — the latest every display has reached']
            : 'State hash now, at each display’s last frame',
        ),
        h(
          'thead',
          {},
          h(
            'tr',
            {},
            h('th', { scope: 'col' }, 'Display'),
            h('th', { scope: 'col' }, info.fixed ? 'Ticks' : 'Updates'),
            h('th', { scope: 'col' }, 'Coins'),
            h('th', { scope: 'col' }, 'Hash'),
          ),
        ),
        body,
        h('tfoot', {}, h('tr', {}, h('th', { scope: 'row' }, 'All equal'), equal.el)),
      ),
      verdict,
    );
  }

  // ---------------------------------------------------------------- state

  /** Virtual time since the last animation frame, so a press lands when it happened. */
  private lateMs(): number {
    if (this.lab.realClock) {
      const now = this.driver.realNow();
      return now === undefined ? 0 : Math.max(0, now - this.lab.timeMs);
    }
    return this.driver.sinceLastFrame();
  }

  private toggleRecording(): void {
    if (this.lab.mode === 'recording') this.lab.stopRecording();
    else {
      this.lab.startRecording();
      this.driver.setPaused(false);
    }
    this.afterRestart();
  }

  /** The lab went back to time zero: so does the real clock. */
  private afterRestart(): void {
    if (this.lab.realClock) this.driver.restartReal();
  }

  private setRealClock(on: boolean): void {
    const s = this.lab.settings;
    const demo = this.lab.demo;
    this.lab = new DebugLab({ jitter: s.jitter, recording: s.recording }, on);
    this.lab.demo = demo;
    this.driver.setReal(on);
    setPressed(this.clockBtn, on);
  }

  private refreshControls(): void {
    const lab = this.lab;
    const recording = lab.mode === 'recording';
    this.time.refresh(this.driver.isPaused, !lab.realClock);
    this.time.skipBtn.disabled = lab.realClock || recording;
    this.jitter.input.disabled = lab.realClock || recording;
    this.jitter.set(Math.round(lab.settings.jitter * 100));
    setText(this.recordBtn, recording ? '■ Stop and replay' : '● Record');
    setAttr(this.recordBtn, 'aria-pressed', String(recording));
    this.demoBtn.disabled = recording;
    for (const b of this.padButtons) b.disabled = !recording;
    for (const v of this.views) {
      const row = v.rows.get('real');
      if (row) row.row.hidden = !lab.realClock;
      v.legendReal.hidden = !lab.realClock;
    }
  }

  // ---------------------------------------------------------------- drawing

  private render(): void {
    const lab = this.lab;
    const hz = this.driver.measuredHz;
    const recording = lab.mode === 'recording';
    const what = recording
      ? 'recording'
      : lab.demo
        ? 'replaying the demo recording'
        : 'replaying your recording';
    this.time.show(
      lab.timeMs,
      `${lab.realClock ? `real clock ≈ ${hz} Hz` : `simulated displays · jitter ±${Math.round(lab.settings.jitter * 100)} %`} · ${what}${this.driver.isPaused ? ' · paused' : ''}`,
    );
    this.inputsOut.set(fmt.count(lab.recordedInputs), lab.recordedInputs);
    this.lengthOut.set(fmt.seconds(lab.recordingMs / 1000), lab.recordingMs);
    setText(
      this.recStatus,
      recording
        ? `● Recording — ← → run, Space jumps; stops by itself at ${MAX_RECORDING_MS / 1000} s`
        : '',
    );
    this.recStatus.hidden = !recording;

    const drawAt = Math.min(
      ...[...lab.tracks('variable'), ...lab.tracks('fixed')].map((t) => t.rig.realMs),
    );
    for (const v of this.views) {
      const r = lab.readouts(v.info.id);
      this.writeReadouts(v, r, hz);
      this.drawLevel(v, lab.tracks(v.info.id), v.info.fixed ? drawAt - STEP_MS : drawAt);
    }
    this.drawTimeline();

    const n = lab.samples.length;
    const lastV = n >= 3 ? lab.samples[n - 2]! : NaN;
    const lastF = n >= 3 ? lab.samples[n - 1]! : NaN;
    this.divVariable.set(centimetres(lastV), Number.isFinite(lastV) ? lastV : undefined);
    this.divFixed.set(centimetres(lastF), Number.isFinite(lastF) ? lastF : undefined);
    const xs: number[] = [];
    const vs: number[] = [];
    const fs: number[] = [];
    const from = lab.timeMs - CHART_WINDOW_MS;
    for (let k = 0; k < n; k += 3) {
      const t = lab.samples[k]!;
      if (t < from) continue;
      xs.push(t / 1000);
      vs.push(lab.samples[k + 1]! * 100);
      fs.push(lab.samples[k + 2]! * 100);
    }
    this.divergence.set([xs, vs, fs], `${n}:${xs[0] ?? 0}`);
  }

  private writeReadouts(v: LoopView, r: DebugReadouts, hz: number): void {
    for (const row of r.rows) {
      const view = v.rows.get(row.source);
      if (!view) continue;
      setText(view.label, sourceLabel(row.source, hz));
      view.ticks.set(fmt.count(row.ticks), row.ticks);
      view.score.set(String(row.score), row.score);
      view.hash.set(row.hash ?? '—', row.hash);
    }
    v.tick?.set(String(r.commonTick), r.commonTick);
    v.equal.set(r.equal ? 'true — one state' : 'false — different states', r.equal);
    v.equal.good(r.equal);
    v.equal.warn(!r.equal);
    const n = r.rows.length;
    const scores = new Set(r.rows.map((x) => x.score));
    const text = r.equal
      ? v.info.fixed
        ? `${n} displays, one hash at every tick: the replay is the game.`
        : `${n} displays agree — for now (nothing has moved yet).`
      : scores.size > 1
        ? `${n} displays, different states — even different scores: ${[...r.rows.map((x) => x.score)].join(' / ')} coins.`
        : `${n} displays, ${new Set(r.rows.map((x) => x.hash)).size} different states from the same inputs.`;
    setText(v.verdict, text);
    v.verdict.classList.toggle('good', r.equal && v.info.fixed);
    v.verdict.classList.toggle('bad', !r.equal);
  }

  private drawLevel(v: LoopView, tracks: DebugTrack[], atMs: number): void {
    const sc = v.scene;
    if (!sc.fit()) return;
    const { ctx, dpr } = sc;
    clearScene(sc);
    const view = new View(sc.w, sc.h, LEVEL.x0, LEVEL.y0, LEVEL.x1, LEVEL.y1);
    view.grid(ctx, 1);
    const px = (x: number) => view.px(x);
    const py = (y: number) => view.py(y);
    ctx.fillStyle = 'rgba(141, 160, 189, 0.08)';
    ctx.fillRect(px(LEVEL.x0), py(0), px(LEVEL.x1) - px(LEVEL.x0), py(LEVEL.y0) - py(0));
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.55)';
    ctx.lineWidth = Math.max(1, dpr);
    ctx.beginPath();
    ctx.moveTo(px(LEVEL.x0), Math.round(py(0)) + 0.5);
    ctx.lineTo(px(LEVEL.x1), Math.round(py(0)) + 0.5);
    ctx.stroke();

    // Coins: a ring per display, nested like the lines.
    for (const t of tracks) {
      const s = t.scene;
      ctx.strokeStyle = rateColor(t.source);
      ctx.lineWidth = Math.max(1, (WIDTHS[String(t.source)] ?? 1) * 0.6 * dpr);
      for (let k = 0; k < s.coinCount; k++) {
        ctx.beginPath();
        ctx.arc(px(s.coinX(k)), py(s.coinY(k)), s.config.coinRadius * view.scale, 0, 2 * Math.PI);
        ctx.stroke();
      }
    }
    // Trails and runners.
    ctx.lineJoin = 'round';
    ctx.lineCap = 'round';
    const half = tracks[0]?.scene.config.height ?? 0.9;
    const pos = tracks.map((t) => t.positionAt(atMs, this.interpolate));
    tracks.forEach((t, i) => {
      const p = t.path;
      const color = rateColor(t.source);
      ctx.strokeStyle = color;
      ctx.lineWidth = (WIDTHS[String(t.source)] ?? 1) * dpr;
      ctx.globalAlpha = 0.8;
      ctx.beginPath();
      let started = false;
      for (let k = 0; k + 2 < p.length; k += 3) {
        const tt = p[k]!;
        if (tt < atMs - TRAIL_MS) continue;
        if (tt > atMs) break;
        const X = px(p[k + 1]!);
        const Y = py(p[k + 2]! + half / 2);
        if (started) ctx.lineTo(X, Y);
        else ctx.moveTo(X, Y);
        started = true;
      }
      if (started) ctx.lineTo(px(pos[i]!.x), py(pos[i]!.y + half / 2));
      ctx.stroke();
    });
    ctx.globalAlpha = 1;
    tracks.forEach((t, i) => {
      const r = pos[i]!;
      const radius = ((WIDTHS[String(t.source)] ?? 1) + 4) * dpr;
      ctx.fillStyle = rateColor(t.source);
      ctx.strokeStyle = '#0a1122';
      ctx.lineWidth = Math.max(1, dpr);
      ctx.beginPath();
      ctx.arc(px(r.x), py(r.y + half / 2), radius, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    });
  }

  private drawTimeline(): void {
    const sc = this.timeline;
    if (!sc.fit()) return;
    const { ctx, dpr } = sc;
    clearScene(sc, '#0a1122');
    const lab = this.lab;
    const events: readonly ScriptedInput[] = lab.recordingEvents();
    const span = Math.max(10_000, lab.recordingMs + 500, lab.timeMs + 500);
    const padL = 52 * dpr;
    const w = sc.w - padL - 8 * dpr;
    const rows: [number, string][] = [
      [JumperButtons.left, '◀ left'],
      [JumperButtons.right, '▶ right'],
      [JumperButtons.jump, 'jump'],
    ];
    const rowH = sc.h / rows.length;
    const x = (t: number) => padL + (t / span) * w;
    ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
    ctx.textBaseline = 'middle';
    rows.forEach(([b, label], i) => {
      const y = i * rowH;
      ctx.fillStyle = 'rgba(163, 179, 204, 0.8)';
      ctx.fillText(label, 6 * dpr, y + rowH / 2);
      ctx.fillStyle = 'rgba(141, 160, 189, 0.08)';
      ctx.fillRect(padL, y + rowH * 0.2, w, rowH * 0.6);
      ctx.fillStyle = b === JumperButtons.jump ? '#fbbf24' : '#7dd3fc';
      let downAt: number | undefined;
      for (const e of events) {
        if (e.button !== b) continue;
        if (e.down) downAt = e.timeMs;
        else if (downAt !== undefined) {
          ctx.fillRect(
            x(downAt),
            y + rowH * 0.2,
            Math.max(2 * dpr, x(e.timeMs) - x(downAt)),
            rowH * 0.6,
          );
          downAt = undefined;
        }
      }
      if (downAt !== undefined) {
        ctx.fillRect(
          x(downAt),
          y + rowH * 0.2,
          Math.max(2 * dpr, x(lab.timeMs) - x(downAt)),
          rowH * 0.6,
        );
      }
    });
    // The play head.
    const hx = Math.min(x(lab.timeMs), padL + w);
    ctx.strokeStyle = lab.mode === 'recording' ? '#f87171' : '#e6edf7';
    ctx.lineWidth = Math.max(1.5, 1.5 * dpr);
    ctx.beginPath();
    ctx.moveTo(hx, 0);
    ctx.lineTo(hx, sc.h);
    ctx.stroke();
  }
}

function centimetres(m: number): string {
  if (!Number.isFinite(m)) return '—';
  if (m === 0) return '0 cm';
  return `${(m * 100).toFixed(1)} cm`;
}

function why(): HTMLElement {
  return h(
    'section',
    { class: 'why', 'aria-labelledby': 'debug-why-title' },
    h('h2', { id: 'debug-why-title' }, 'Why this matters when something goes wrong'),
    h(
      'div',
      { class: 'why-grid' },
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'A bug report is a recording'),
        h(
          'p',
          {},
          'A player hits a bug on a 144 Hz laptop; you debug on a 60 Hz desktop. Under a fixed step their recorded inputs replay into the very same states on your machine, tick by tick, so the bug happens again — under your debugger, as often as you like.',
        ),
      ),
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'Hashes find the first wrong tick'),
        h(
          'p',
          {},
          'Hash the state every tick and two runs can be compared cheaply: the first tick whose hashes differ is where the behaviour changed. Replays, network peers and tests all use the same check.',
        ),
        code(`for each tick:\n  step(inputs[tick])\n  if (hash() !== recorded[tick]) stop()`),
      ),
      h(
        'div',
        { class: 'why-card' },
        h('h3', {}, 'What breaks it'),
        h(
          'p',
          {},
          `A variable Δt (shown above), reading a clock or Math.random inside a step, engine-dependent maths (Math.sin may differ in the last bit between browsers), iterating over things in an order that can change. fixedstep’s lint rules and its determinism guard catch these in simulation code.`,
        ),
      ),
    ),
  );
}

function how(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'debug-how-title' },
    h('h2', { id: 'debug-how-title' }, 'How this page works'),
    h(
      'p',
      {},
      `The four displays are simulated (rate plus seeded jitter), and a virtual clock runs them at real speed; “Skip +5 s” jumps it. The fixed-step runs use FixedLoop with a ${STEP_MS} ms step; each press goes to the tick whose time span contains it, whatever the display. Their hashes are compared at the latest tick all four have reached. The variable-Δt runs have no ticks, so their states are compared as they are now.`,
    ),
    h(
      'p',
      {},
      'While you record, your presses reach every run at the same virtual time. When you stop, the recording replays from zero. “Real clock” adds a fifth run per loop, driven by this page’s own animation frames.',
    ),
  );
}
