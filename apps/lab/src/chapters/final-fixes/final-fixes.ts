/**
 * Chapter 8 — Final fixes. Two benches on one virtual clock: a hitch on a slow machine with no
 * clamp on the accumulator (the spiral of death, shown safely), with the clamp, and with
 * FixedLoop; and a clock that jumps backwards. The numbers come from {@link FinalLab}; this module
 * builds the page and draws.
 */
import {
  BACKWARDS_LOOPS,
  FinalLab,
  HISTORY_MS,
  MACHINES,
  POLICIES,
  SPIRAL_LOOPS,
  STALL_WORK_MS,
  type BackwardsReadouts,
  type BenchLoop,
  type BenchRun,
  type SpiralReadouts,
} from './final-fixes-lab.js';
import type { BackwardsLoop, SpiralLoop } from '@fixedstep/games';
import type { OverloadPolicy } from 'fixedstep';
import { drawBall } from '../../ui/ball-view.js';
import { SceneCanvas } from '../../ui/canvas.js';
import { Chart, alignSeries } from '../../ui/chart.js';
import { TimeControls, button, group, segmented, setPressed, toggle } from '../../ui/controls.js';
import { code, h, setAttr, setText } from '../../ui/dom.js';
import { LabDriver } from '../../shell/driver.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';

const SKIP_MS = 5000;
const TRAIL_MS = 600;
const BACK_SIZES = [500, 1500, 5000] as const;

export function mount(root: HTMLElement): () => void {
  const chapter = new FinalFixesChapter(root);
  return () => {
    chapter.destroy();
  };
}

interface PanelView {
  readonly spec: BenchLoop<string>;
  readonly scene: SceneCanvas;
  readonly values: Map<string, Readout>;
  readonly overlay: HTMLElement;
  readonly stall: HTMLElement | undefined;
}

type Row = readonly [id: string, label: string, title: string];

const SPIRAL_ROWS: readonly Row[] = [
  ['steps', 'Steps / frame', 'Updates the last frame asked for'],
  ['max-steps', 'Max steps', 'The most updates one frame asked for'],
  [
    'longest-frame',
    'Longest frame',
    'The longest wait between two frames, the one in progress included',
  ],
  ['fps', 'Frames / s', 'Frames shown over the last 2 s: how responsive the page is'],
  ['ratio', 'Sim / real', 'Simulated time over real time, counting only updates that ran'],
  [
    'owed',
    'Owed',
    `Updates asked for in frames with more than ${STALL_WORK_MS / 1000} s of work, never run`,
  ],
];

const BACKWARDS_ROWS: readonly Row[] = [
  ['sim', 'Sim time', 'Time as the loop has simulated it'],
  ['lag', 'Behind real', 'Display time minus simulated time'],
  ['reversed', 'Went back', 'Did simulated time ever run backwards?'],
  ['frozen', 'Longest freeze', 'The longest display time with no simulated progress'],
  [
    'backward-frames',
    'Back readings',
    'Frames whose clock reading was earlier than the last (FixedLoop counts them)',
  ],
];

class FinalFixesChapter {
  private lab = new FinalLab();
  private interpolate = true;
  private readonly driver: LabDriver;
  private readonly time: TimeControls;
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly machine: ReturnType<typeof segmented<number>>;
  private readonly policy: ReturnType<typeof segmented<OverloadPolicy>>;
  private readonly backSize: ReturnType<typeof segmented<number>>;
  private readonly spiralPanels: PanelView[] = [];
  private readonly backPanels: PanelView[] = [];
  private readonly stepsChart: Chart;
  private readonly simChart: Chart;
  private readonly eventsOut: HTMLElement;
  private readonly clockReading: Readout;
  private readonly clockNote: HTMLElement;
  private readonly scratch: number[] = [];

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
      { maxRealGapMs: 250 },
    );

    // ------------------------------------------------------------ time bar
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
    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw the fixed-step balls between their last two states';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setRealClock(on);
    });
    this.clockBtn.title = 'Feed both benches this page’s own animation frames';
    const timebar = h(
      'div',
      { class: 'controls timebar', role: 'group', 'aria-label': 'Time' },
      group('Time', ...this.time.buttons),
      group('Draw', this.interpBtn, this.clockBtn),
      h('div', { class: 'status status-inline', 'aria-live': 'off' }, ...this.time.status),
    );

    // ------------------------------------------------------------ spiral controls
    const s = this.lab.settings;
    this.machine = segmented({
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
      const label = this.machine.inputs.get(m.costMs)?.parentElement;
      if (label) label.title = m.title;
    }
    this.policy = segmented({
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
    this.eventsOut = h('ul', { class: 'event-list', 'aria-label': 'Hitches so far' });
    const spiralControls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'The slow machine' },
      group('Machine', this.machine.el),
      group('FixedLoop', this.policy.el),
      group('Trouble', hitch, breakpoint),
      h(
        'div',
        { class: 'status' },
        h('span', { class: 'status-item' }, 'Each update simulates 30 ms.'),
        this.eventsOut,
      ),
    );

    // ------------------------------------------------------------ backwards controls
    this.backSize = segmented({
      name: 'back-size',
      label: 'How far the clock jumps back',
      testPrefix: 'control-back',
      values: BACK_SIZES,
      selected: s.backMs,
      text: (ms) => `${ms / 1000} s`,
      onChange: (ms) => {
        this.lab.update({ backMs: ms });
      },
    });
    const jumpBack = button('Set the clock back now', 'control-jump-back', () => {
      this.lab.jumpBack();
    });
    jumpBack.title = 'The wall clock the loops read jumps back, as after a time-server correction';
    this.clockReading = new Readout('span', 'backwards-clock', { className: 'clock' });
    this.clockNote = h('span', { class: 'status-item' });
    const backControls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'The wall clock' },
      group('Jump', this.backSize.el, jumpBack),
      h(
        'div',
        { class: 'status' },
        h('span', { class: 'status-item' }, 'the wall clock reads ', this.clockReading.el),
        this.clockNote,
      ),
    );

    for (const c of [timebar, spiralControls, backControls]) {
      c.addEventListener('click', () => {
        this.refreshControls();
        this.render();
      });
      c.addEventListener('change', () => {
        this.refreshControls();
        this.render();
      });
    }

    // ------------------------------------------------------------ panels and charts
    const spiralGrid = h(
      'div',
      { class: 'panels panels-3' },
      SPIRAL_LOOPS.map((spec) => this.buildPanel(spec, SPIRAL_ROWS, '', this.spiralPanels, true)),
    );
    const backGrid = h(
      'div',
      { class: 'panels panels-4' },
      BACKWARDS_LOOPS.map((spec) =>
        this.buildPanel(spec, BACKWARDS_ROWS, 'backwards-', this.backPanels, false),
      ),
    );
    this.stepsChart = new Chart({
      height: 220,
      label: 'Updates asked for by each display frame over time, for the three loops',
      x: { format: (v) => `${v} s`, label: 'time' },
      y: {
        scale: 'asinh',
        label: 'steps per frame',
        format: (v) => fmt.count(v),
        range: (_min, max) => [0, Math.max(200, max * 1.5)],
        splits: (_min, max) =>
          [0, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10_000, 20_000, 50_000].filter(
            (v) => v <= max,
          ),
        size: 44,
      },
      series: [
        ...SPIRAL_LOOPS.map((l) => ({
          label: l.title,
          color: l.color,
          stepped: true,
          gaps: false,
          width: 2,
        })),
        {
          label: 'page stalls above this',
          color: '#f87171',
          dash: [5, 4],
          width: 1.25,
          gaps: false,
        },
      ],
    });
    this.simChart = new Chart({
      height: 220,
      label:
        'How far each loop’s simulated time is behind the display’s time, and how far the wall clock is',
      x: { format: (v) => `${v} s`, label: 'display time' },
      y: {
        format: (v) => `${v} s`,
        label: 'behind the display',
        size: 44,
        range: (min, max) => [Math.min(0, min), Math.max(2, max * 1.15)],
      },
      series: [
        ...BACKWARDS_LOOPS.map((l) => ({
          label: l.title,
          color: l.color,
          gaps: false,
          width: l.id === 'fixed' ? 1.5 : 2,
          dash: l.id === 'fixed' ? [6, 4] : undefined,
        })),
        { label: 'the wall clock', color: '#94a3b8', dash: [2, 4], width: 1.25, gaps: false },
      ],
    });

    root.append(
      h(
        'article',
        { class: 'chapter final-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 8'),
          h('h1', {}, 'Final fixes'),
          h(
            'p',
            { class: 'lede' },
            'The accumulator on the slides has two holes. A frame that comes very late makes it owe more steps than a slow machine can pay, and paying them makes the next frame later still: the spiral of death. A clock that jumps back hands it a negative Δt. Two lines close both holes.',
          ),
        ),
        h(
          'div',
          { class: 'why-grid code-pair' },
          h(
            'div',
            { class: 'why-card' },
            h('h3', {}, 'On the slides'),
            code(
              'dt = now - last; last = now\naccumulator += dt\nwhile (accumulator > STEP) {\n  update(STEP); accumulator -= STEP\n}',
            ),
          ),
          h(
            'div',
            { class: 'why-card fixed-card' },
            h('h3', {}, 'With the final fixes'),
            code(
              '// time never runs backwards\ndt = max(0, now - last); last = now\n// never more than 1 s owed\naccumulator = clamp(accumulator + dt, 0, 1.0)\nwhile (accumulator > STEP) {\n  update(STEP); accumulator -= STEP\n}',
            ),
          ),
        ),
        timebar,
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'spiral-title' },
          h('h2', { id: 'spiral-title' }, 'A hitch on a slow machine'),
          h(
            'p',
            { class: 'section-intro' },
            'The ball of chapter 1 on a 60 Hz display, on a machine where an update may cost more than the 30 ms it simulates. At t = 1 s the page stalls for a second. Without the clamp the loop owes 33 steps, paying them takes 1.3 s, so the next frame owes 44, then 58, 78… — until a frame would take longer than a browser lets a page hang. Here nothing hangs: the display is simulated, the steps beyond 5 s of work are counted, not run.',
          ),
          spiralControls,
          spiralGrid,
          h('div', { class: 'chart-card' }, h('h3', {}, 'Steps per frame'), this.stepsChart.el),
        ),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'backwards-title' },
          h('h2', { id: 'backwards-title' }, 'A clock that jumps backwards'),
          h(
            'p',
            { class: 'section-intro' },
            'A loop that reads the wall clock (Date.now) sees it jump when the system clock is corrected; some timer sources misbehave too. At t = 3 s the clock is set back by 1.5 s. A variable Δt takes one negative step and time runs backwards; the slides’ accumulator goes into debt and the game freezes until the clock catches up; with max(0, Δt) nothing happens at all.',
          ),
          backControls,
          backGrid,
          h(
            'div',
            { class: 'chart-card' },
            h('h3', {}, 'How far behind the display each loop’s time is'),
            this.simChart.el,
          ),
        ),
        how(),
      ),
    );

    this.refreshControls();
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    for (const p of [...this.spiralPanels, ...this.backPanels]) p.scene.destroy();
    this.stepsChart.destroy();
    this.simChart.destroy();
    this.root.replaceChildren();
  }

  private buildPanel(
    spec: BenchLoop<string>,
    rows: readonly Row[],
    prefix: string,
    into: PanelView[],
    stall: boolean,
  ): HTMLElement {
    const scene = new SceneCanvas({
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
    const overlay = h('p', { class: 'overlay', hidden: true, 'aria-hidden': 'true' });
    const stallEl = stall
      ? h(
          'p',
          {
            class: 'stall',
            role: 'status',
            'data-testid': `readout-${prefix}${spec.id}-stalled`,
            'data-value': 'false',
            hidden: true,
          },
          'Stalled',
        )
      : undefined;
    into.push({ spec, scene, values, overlay, stall: stallEl });
    return h(
      'section',
      {
        class: 'panel',
        style: `--accent: ${spec.color}`,
        'data-panel': `${prefix}${spec.id}`,
        'aria-labelledby': `panel-${prefix}${spec.id}`,
      },
      h(
        'header',
        { class: 'panel-head' },
        h('h3', { id: `panel-${prefix}${spec.id}` }, spec.title),
        h('p', {}, spec.tagline),
      ),
      h('div', { class: 'scene-wrap' }, scene.canvas, overlay, stallEl ?? null),
      dl,
    );
  }

  // ---------------------------------------------------------------- state

  private setRealClock(on: boolean): void {
    this.lab = new FinalLab({ ...this.lab.settings }, on);
    this.driver.setReal(on);
    setPressed(this.clockBtn, on);
  }

  private refreshControls(): void {
    const lab = this.lab;
    const s = lab.settings;
    // (The segmented controls are not re-selected here: this runs during their own clicks.)
    this.time.refresh(this.driver.isPaused, !lab.realClock);
    this.eventsOut.replaceChildren(
      ...s.hitches.map((e) =>
        h(
          'li',
          { class: 'event event-hitch' },
          `${e.durationMs / 1000} s hitch at ${(e.atMs / 1000).toFixed(1)} s`,
        ),
      ),
    );
  }

  // ---------------------------------------------------------------- drawing

  private render(): void {
    const lab = this.lab;
    const t = lab.timeMs;
    this.time.show(
      t,
      lab.realClock
        ? `real clock · your display ≈ ${this.driver.measuredHz} Hz${this.driver.isPaused ? ' · paused' : ''}`
        : `simulated 60 Hz display${this.driver.isPaused ? ' · paused' : ''}`,
    );
    const hitch = lab.activeHitch();
    lab.spiral.forEach((run, i) => {
      const p = this.spiralPanels[i];
      if (p) this.drawSpiral(p, run, lab.spiralReadouts(run), hitch !== undefined);
    });
    lab.backwards.forEach((run, i) => {
      const p = this.backPanels[i];
      if (p) this.drawBackwards(p, run, lab.backwardsReadouts(run));
    });
    const reading = lab.clockReading;
    this.clockReading.set(fmt.seconds(reading / 1000), reading);
    const behind = t - reading;
    setText(
      this.clockNote,
      behind > 0
        ? `${fmt.seconds(behind / 1000)} behind the display’s time`
        : 'in step with the display',
    );
    this.clockNote.classList.toggle('warn-text', behind > 0);
    this.drawCharts(t);
  }

  private drawSpiral(
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
    const overlay = hitch
      ? 'Hitch: no frames'
      : r.busyMs > 250
        ? `Busy: next frame in ${fmt.seconds(r.busyMs / 1000)}`
        : '';
    p.overlay.hidden = overlay === '';
    setText(p.overlay, overlay);
    if (p.stall) {
      p.stall.hidden = !r.stalled;
      setAttr(p.stall, 'data-value', String(r.stalled));
      setText(
        p.stall,
        r.stalled ? `Would have stalled: ${fmt.count(r.owed)} steps owed, never run` : 'Stalled',
      );
    }
    this.drawRun(p, run);
  }

  private drawBackwards(p: PanelView, run: BenchRun<BackwardsLoop>, r: BackwardsReadouts): void {
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
    const overlay =
      r.reversed && run.frames.length >= 8 && isGoingBack(run)
        ? 'Time runs backwards'
        : run.frozenUntil(this.lab.timeMs) > 200 && this.lab.timeMs - lastProgress(run) > 200
          ? 'Frozen: paying back the clock'
          : '';
    p.overlay.hidden = overlay === '';
    setText(p.overlay, overlay);
    this.drawRun(p, run);
  }

  private drawRun(p: PanelView, run: BenchRun<string>): void {
    const ball = run.ballAt(this.interpolate);
    const pts = run.trailPoints(run.rig.realMs, TRAIL_MS, this.interpolate, this.scratch);
    drawBall(p.scene, { ...ball, radius: run.scene.config.radius }, run.spec.color, pts);
  }

  private drawCharts(t: number): void {
    const lab = this.lab;
    const from = Math.max(0, t - HISTORY_MS);
    const end = Math.max(t, 20_000);
    const series = lab.spiral.map((run) => {
      const xs: number[] = [];
      const ys: number[] = [];
      const f = run.frames;
      for (let k = 0; k < f.length; k += 4) {
        if (f[k]! < from) continue;
        xs.push(f[k]! / 1000);
        ys.push(f[k + 1]!);
      }
      return { xs, ys };
    });
    const guard = Math.floor(STALL_WORK_MS / lab.settings.costMs);
    const aligned = alignSeries([...series, { xs: [from / 1000, end / 1000], ys: [guard, guard] }]);
    this.stepsChart.set(aligned, `${t}:${lab.settings.costMs}:${aligned[0]?.length ?? 0}`);

    const back = lab.backwards.map((run) => {
      const xs: number[] = [];
      const ys: number[] = [];
      const f = run.frames;
      for (let k = 0; k < f.length; k += 4) {
        if (f[k]! < from) continue;
        xs.push(f[k]! / 1000);
        ys.push(f[k]! / 1000 - f[k + 2]!);
      }
      return { xs, ys };
    });
    const first = lab.backwards[0];
    const clock = { xs: [] as number[], ys: [] as number[] };
    if (first) {
      const f = first.frames;
      for (let k = 0; k < f.length; k += 4) {
        if (f[k]! < from) continue;
        clock.xs.push(f[k]! / 1000);
        clock.ys.push((f[k]! - f[k + 3]!) / 1000);
      }
    }
    this.simChart.set(alignSeries([...back, clock]), `${t}:${first?.frames.length ?? 0}`);
  }
}

/** Whether the run's simulated time went down within its last few frames. */
function isGoingBack(run: BenchRun<string>): boolean {
  const f = run.frames;
  const n = f.length;
  for (let k = Math.max(4, n - 4 * 30); k < n; k += 4)
    if (f[k + 2]! < f[k - 2]! - 1e-9) return true;
  return false;
}

/** Display time of the run's last frame that advanced simulated time. */
function lastProgress(run: BenchRun<string>): number {
  const f = run.frames;
  for (let k = f.length - 4; k >= 4; k -= 4) if (f[k + 2]! > f[k - 2]! + 1e-9) return f[k]!;
  return 0;
}

function how(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'final-how-title' },
    h('h2', { id: 'final-how-title' }, 'How this page works'),
    h(
      'p',
      {},
      'The displays are simulated and a virtual clock runs them at real speed; “Skip +5 s” jumps it. On the slow machine the simulated display waits for the work each frame asked for, as a real page would — but the page never does more than 5 s of it in one frame, so a spiral costs nothing here. What a real page would have run in vain is shown as owed.',
    ),
    h(
      'p',
      {},
      'Changing the machine, the policy or the jump size, and every hitch or clock jump you add, replays both benches from zero to the current moment. “Real clock” feeds them this page’s own animation frames instead: the slow machine still delays its own frames, the wall clock still jumps.',
    ),
    h(
      'p',
      {},
      'FixedLoop goes beyond the talk’s two lines: it clamps at 0.25 s by default (15 steps at 60 Hz rather than 60), caps the steps of one frame (8) and says what happens to the rest — catch up later, drop them, or reset — counting every dropped millisecond. Pick a policy above and watch its frame rate and its sim / real ratio.',
    ),
  );
}
