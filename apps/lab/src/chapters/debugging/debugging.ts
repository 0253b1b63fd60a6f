/**
 * Chapter 7 — Debugging. One recording of button presses replayed on four displays under a
 * variable Δt and under a fixed step, with every run's state hash: under the fixed step they agree
 * tick for tick. The reader can record their own session. The numbers come from {@link DebugLab};
 * the words from debugging-text.ts; the drawing from debugging-draw.ts.
 */
import {
  CHART_WINDOW_MS,
  DEFAULT_JITTER,
  DebugLab,
  LOOPS,
  MAX_RECORDING_MS,
  STEP_MS,
  type DebugReadouts,
  type LoopInfo,
  sourceLabel,
} from './debugging-lab.js';
import { drawLevel, drawTimeline } from './debugging-draw.js';
import { LOOP_COLORS, runsPanel, type RunsPanel } from '../movement/runs-panel.js';
import {
  BENCH_INTRO,
  LEDE,
  catalogueSize,
  guarantee,
  how,
  verdictText,
  why,
} from './debugging-text.js';
import { JumperButtons, demoRecording } from '@fixedstep/games';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { Chart } from '../../ui/chart.js';
import { button, group, jitterSlider } from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import { headRow } from '../../ui/panel.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import './debugging.css';

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

export const mount = mountChapter((root, head) => new DebuggingChapter(root, head));

function centimetres(m: number): string {
  if (!Number.isFinite(m)) return '—';
  if (m === 0) return '0 cm';
  return `${(m * 100).toFixed(1)} cm`;
}

interface LoopView extends RunsPanel<{ ticks: Readout; score: Readout; hash: Readout }> {
  readonly info: LoopInfo;
  readonly equal: Readout;
  readonly tick: Readout | undefined;
}

class DebuggingChapter {
  readonly shell: ChapterShell;
  private lab = new DebugLab();
  private readonly views: LoopView[] = [];
  private readonly jitter;
  private readonly recordBtn: HTMLButtonElement;
  private readonly demoBtn: HTMLButtonElement;
  private readonly padButtons: HTMLButtonElement[] = [];
  private readonly recStatus = h('span', { class: 'rec-status', 'aria-live': 'polite' });
  private readonly inputsOut = new Readout('strong', 'recording-inputs');
  private readonly lengthOut = new Readout('strong', 'recording-length');
  private readonly divergence: Chart;
  private readonly divVariable = new Readout('strong', 'variable-divergence');
  private readonly divFixed = new Readout('strong', 'fixed-divergence');
  private readonly timeline: SceneCanvas;

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      restart: () => {
        this.lab.restart();
      },
      mode: () => this.modeLine(),
      realClock: {
        title: 'Add a fifth run per loop, fed this page’s own animation frames',
        onChange: (on) => {
          const s = this.lab.settings;
          const demo = this.lab.demo;
          this.lab = new DebugLab({ jitter: s.jitter, recording: s.recording }, on);
          this.lab.demo = demo;
        },
      },
      interpolation: { title: 'Draw the runners between their last two states' },
      driver: { maxRealGapMs: 200 },
    });
    const shell = this.shell;
    if (shell.time) shell.time.restartBtn.title = 'Replay the recording from the start';
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
    this.jitter = jitterSlider({
      id: 'debug-jitter',
      percent: Math.round(DEFAULT_JITTER * 100),
      onChange: (jitter) => {
        this.lab.setJitter(jitter);
      },
    });
    this.timeline = shell.canvas({
      class: 'timeline',
      label: 'The recording: when each button was held',
      testId: 'canvas-recording',
    });
    this.divergence = this.divergenceChart();
    shell.append(
      h(
        'p',
        { class: 'guarantee', 'data-testid': 'guarantee' },
        h('strong', {}, 'What is guaranteed: '),
        guarantee(catalogueSize()),
      ),
      introSection(
        'bench',
        'debug-bench-title',
        'One recording, four displays',
        BENCH_INTRO,
        this.controls(),
        h(
          'div',
          { class: 'duo' },
          LOOPS.map((info) => this.buildPanel(info)),
        ),
      ),
      introSection(
        'divergence',
        'divergence-title',
        'How far apart the runs drift',
        [
          'The largest distance between any two displays’ runners at the same moment (the fixed-step runs compared at the same tick). Now: variable Δt ',
          this.divVariable.el,
          ', fixed step ',
          this.divFixed.el,
          '.',
        ],
        h('div', { class: 'chart-card' }, this.divergence.el),
      ),
      why(),
      how(),
    );
    shell.listen(window, 'keydown', this.onKey);
    shell.listen(window, 'keyup', this.onKey);
    shell.start();
  }

  // ---------------------------------------------------------------- building

  private controls(): HTMLElement {
    const shell = this.shell;
    const pad = (label: string, b: number, testId: string, aria: string) => {
      const btn = h(
        'button',
        { type: 'button', class: 'btn pad-btn', 'data-testid': testId, 'aria-label': aria },
        label,
      );
      const up = () => {
        this.lab.press(b, false, this.lateMs());
      };
      btn.addEventListener('pointerdown', (e) => {
        e.preventDefault();
        btn.setPointerCapture(e.pointerId);
        this.lab.press(b, true, this.lateMs());
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
    return shell.controls(
      'Recording, displays and time',
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
      shell.drawGroup(),
      shell.timeGroup(),
      shell.status(
        h('span', { class: 'status-item' }, this.inputsOut.el, ' inputs over ', this.lengthOut.el),
        this.recStatus,
      ),
      h('div', { class: 'timeline-wrap' }, this.timeline.canvas),
    );
  }

  private divergenceChart(): Chart {
    return this.shell.own(
      new Chart({
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
      }),
    );
  }

  private buildPanel(info: LoopInfo): HTMLElement {
    const equal = new Readout('td', `${info.id}-hashes-equal`, { className: 'spread' });
    equal.el.setAttribute('colspan', '3');
    const tick = info.fixed ? new Readout('strong', 'fixed-common-tick') : undefined;
    const built = runsPanel(this.shell, info, {
      sceneClass: 'scene level-scene',
      sceneLabel: `The four runs of the recording under ${info.title}, drawn over each other`,
      cells: (src) => ({
        ticks: new Readout('td', `${info.id}-${src}-ticks`),
        score: new Readout('td', `${info.id}-${src}-score`),
        hash: new Readout('td', `${info.id}-${src}-hash`, { hash: true }),
      }),
      tableClass: 'jump-table hash-table',
      caption: tick
        ? ['State hash after tick ', tick.el, ' — the latest every display has reached']
        : 'State hash now, at each display’s last frame',
      head: headRow('Display', info.fixed ? 'Ticks' : 'Updates', 'Coins', 'Hash'),
      foot: h('tfoot', {}, h('tr', {}, h('th', { scope: 'row' }, 'All equal'), equal.el)),
      headingId: `debug-panel-${info.id}`,
    });
    this.views.push({ ...built, info, equal, tick });
    return built.element;
  }

  // ---------------------------------------------------------------- input

  private readonly onKey = (e: KeyboardEvent): void => {
    const target = e.target as HTMLElement | null;
    if (target && (target.tagName === 'INPUT' || target.isContentEditable)) return;
    if (e.type === 'keydown' && e.code === 'KeyR' && !e.repeat && !e.ctrlKey && !e.metaKey) {
      this.toggleRecording();
      this.shell.refresh();
      return;
    }
    const b = KEYS[e.code];
    if (b === undefined || this.lab.mode !== 'recording') return;
    e.preventDefault();
    if (e.repeat) return;
    this.lab.press(b, e.type === 'keydown', this.lateMs());
  };

  /** Virtual time since the last animation frame, so a press lands when it happened. */
  private lateMs(): number {
    if (this.lab.realClock) {
      const now = this.shell.driver.realNow();
      return now === undefined ? 0 : Math.max(0, now - this.lab.timeMs);
    }
    return this.shell.driver.sinceLastFrame();
  }

  private toggleRecording(): void {
    if (this.lab.mode === 'recording') this.lab.stopRecording();
    else {
      this.lab.startRecording();
      this.shell.setPaused(false);
    }
    this.afterRestart();
  }

  /** The lab went back to time zero: so does the real clock. */
  private afterRestart(): void {
    if (this.lab.realClock) this.shell.driver.restartReal();
  }

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const lab = this.lab;
    const recording = lab.mode === 'recording';
    if (this.shell.time) this.shell.time.skipBtn.disabled = lab.realClock || recording;
    this.jitter.input.disabled = lab.realClock || recording;
    this.jitter.set(Math.round(lab.settings.jitter * 100));
    setText(this.recordBtn, recording ? '■ Stop and replay' : '● Record');
    setAttr(this.recordBtn, 'aria-pressed', String(recording));
    this.demoBtn.disabled = recording;
    for (const b of this.padButtons) b.disabled = !recording;
    for (const v of this.views) {
      const row = v.rows.get('real');
      if (row) row.row.hidden = !lab.realClock;
      setHidden(v.legendReal, !lab.realClock);
    }
  }

  // ---------------------------------------------------------------- drawing

  private modeLine(): string {
    const lab = this.lab;
    const what =
      lab.mode === 'recording'
        ? 'recording'
        : lab.demo
          ? 'replaying the demo recording'
          : 'replaying your recording';
    const display = this.shell.display(
      `simulated displays · jitter ±${Math.round(lab.settings.jitter * 100)} %`,
    );
    return `${display} · ${what}`;
  }

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const lab = this.lab;
    const recording = lab.mode === 'recording';
    this.inputsOut.set(fmt.count(lab.recordedInputs), lab.recordedInputs);
    this.lengthOut.set(fmt.seconds(lab.recordingMs / 1000), lab.recordingMs);
    setText(
      this.recStatus,
      recording
        ? `● Recording — ← → run, Space jumps; stops by itself at ${MAX_RECORDING_MS / 1000} s`
        : '',
    );
    setHidden(this.recStatus, !recording);
    const drawAt = Math.min(
      ...[...lab.tracks('variable'), ...lab.tracks('fixed')].map((t) => t.rig.realMs),
    );
    for (const v of this.views) {
      const r = lab.readouts(v.info.id);
      this.writeReadouts(v, r);
      drawLevel(
        v.scene,
        lab.tracks(v.info.id),
        v.info.fixed ? drawAt - STEP_MS : drawAt,
        this.shell.interpolate,
      );
    }
    drawTimeline(this.timeline, lab);
    this.renderDivergence();
  }

  private renderDivergence(): void {
    const lab = this.lab;
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

  private writeReadouts(v: LoopView, r: DebugReadouts): void {
    const hz = this.shell.measuredHz;
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
    setText(v.verdict, verdictText(v.info, r, centimetres));
    v.verdict.classList.toggle('good', r.equal && v.info.fixed);
    v.verdict.classList.toggle('bad', !r.equal);
  }
}
