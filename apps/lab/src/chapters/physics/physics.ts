/**
 * Chapter 4 — Physics. The talk's spring at a fixed step under six integrators side by side, with
 * a live energy plot and the stability limits, and a rope of springs to poke under a chosen
 * integrator; on a simulated display (or the page's real clock). The numbers come from
 * {@link PhysicsLab}; this module only builds the page and draws.
 */
import { INTEGRATOR_INFO, INTEGRATOR_METHODS, type IntegratorMethod } from 'fixedstep';
import {
  ClockPhysics,
  MAX_REAL_FRAME_MS,
  PhysicsLab,
  ROPE_BEADS,
  ROPE_STIFFNESS,
  STEP,
  STIFFNESS,
  X0,
  EXPLODE_AT,
  omegaOf,
  ropeOmegaDt,
  stabilityOf,
  type PhysicsRun,
  type PhysicsSettings,
  type Stability,
} from './physics-lab.js';
import { EnergyChart } from './physics-chart.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import { ideaCards, type IdeaCard } from '../../ui/cards.js';
import { HitchSection } from './physics-hitch.js';
import { LabDriver } from '../../shell/driver.js';
import { TimeControls, button, toggle } from '../../ui/controls.js';
import * as fmt from '../../ui/format.js';
import './physics.css';

const COLORS: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': '#f87171',
  'semi-implicit-euler': '#f5a524',
  'backward-euler': '#a78bfa',
  'position-verlet': '#34d399',
  'velocity-verlet': '#38bdf8',
  rk4: '#f472b6',
};

const SHORT: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': 'Explicit Euler',
  'semi-implicit-euler': 'Semi-implicit',
  'backward-euler': 'Backward Euler',
  'position-verlet': 'Position Verlet',
  'velocity-verlet': 'Velocity Verlet',
  rk4: 'RK4',
};

const UPDATE: Readonly<Record<IntegratorMethod, string>> = {
  'explicit-euler': 'x += v·dt; v += a(x₀)·dt',
  'semi-implicit-euler': 'v += a·dt; x += v·dt',
  'backward-euler': 'v₁ = v₀ + a(x₁)·dt; x₁ = x₀ + v₁·dt',
  'position-verlet': 'x₊ = 2x − x₋ + a·dt²',
  'velocity-verlet': 'v += ½a·dt; x += v·dt; v += ½a·dt',
  rk4: 'four stages, weights 1 2 2 1',
};

const SKIP_MS = 5000;
/** Where the ω·dt ruler ends. */
const RULER_MAX = 4;
/** The oscillator panel: the column of the spring shows ±this many metres. */
const SPRING_VIEW = 1.6;
/** The rope view, metres: centre and half extents. */
const ROPE_VIEW = { cx: 0, cy: -1.1, hw: 4.2, hh: 2.4 };
/** Pokes: the default kick and the most a drag gives, m/s; m/s per metre of drag. */
const POKE_KICK = 4;
const POKE_MAX = 10;
const POKE_PER_M = 4;

type LaneField = 'energy-ratio' | 'max-error' | 'phase' | 'state';

interface LaneView {
  readonly method: IntegratorMethod;
  readonly color: string;
  readonly canvas: HTMLCanvasElement;
  readonly ctx: CanvasRenderingContext2D;
  readonly values: Map<LaneField, HTMLElement>;
  readonly cells: Map<LaneField, HTMLElement>;
  readonly chip: HTMLElement;
  readonly overlay: HTMLElement;
  w: number;
  h: number;
  dpr: number;
}

interface RulerRow {
  readonly method: IntegratorMethod;
  readonly row: HTMLElement;
  readonly verdict: HTMLElement;
}

export function mount(root: HTMLElement): () => void {
  const chapter = new PhysicsChapter(root);
  return () => {
    chapter.destroy();
  };
}

class PhysicsChapter {
  private readonly lab = new PhysicsLab();
  private clock: ClockPhysics | undefined;
  private readonly driver: LabDriver;
  private interpolate = true;
  private readonly lanes: LaneView[] = [];
  private readonly observer: ResizeObserver;
  private readonly cleanups: (() => void)[] = [];
  private chart: EnergyChart | undefined;
  private readonly pos = { x: 0, y: 0 };

  // Controls.
  private readonly stepInput: HTMLInputElement;
  private readonly stepOut: HTMLOutputElement;
  private readonly kInput: HTMLInputElement;
  private readonly kOut: HTMLOutputElement;
  private readonly ropeKInput: HTMLInputElement;
  private readonly ropeKOut: HTMLOutputElement;
  private readonly methodInputs = new Map<IntegratorMethod, HTMLInputElement>();
  private readonly interpBtn: HTMLButtonElement;
  private readonly clockBtn: HTMLButtonElement;
  private readonly time: TimeControls;
  private readonly globals = new Map<string, HTMLElement>();
  private readonly ruler: RulerRow[] = [];
  private readonly rulerMarker: HTMLElement;
  private readonly rulerMarkerLabel: HTMLElement;
  private readonly laneGrid: HTMLElement;
  private readonly hitch: HitchSection;
  private readonly chartHost: HTMLElement;

  // The rope.
  private readonly ropeCanvas: HTMLCanvasElement;
  private readonly ropeCtx: CanvasRenderingContext2D;
  private readonly ropeOverlay: HTMLElement;
  private ropeSize = { w: 0, h: 0, dpr: 1 };
  private selected = Math.floor(ROPE_BEADS / 2);
  private drag: { bead: number; x0: number; y0: number; x: number; y: number } | undefined;
  private lastPoke: { bead: number; dvx: number; dvy: number; atMs: number } | undefined;

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
    // ------------------------------------------------------------ spring controls
    this.stepInput = h('input', {
      type: 'range',
      min: STEP.min,
      max: STEP.max,
      step: STEP.step,
      value: s.stepMs,
      id: 'phys-step',
      'data-testid': 'control-step',
      'aria-describedby': 'phys-step-out',
    });
    this.stepOut = h('output', { id: 'phys-step-out', for: 'phys-step' }, `${s.stepMs} ms`);
    this.stepInput.addEventListener('input', () => {
      setText(this.stepOut, `${this.stepInput.value} ms`);
    });
    this.stepInput.addEventListener('change', () => {
      this.change({ stepMs: Number(this.stepInput.value) });
    });
    this.kInput = ladderInput('phys-k', 'control-stiffness', STIFFNESS, s.stiffness);
    this.kOut = h('output', { id: 'phys-k-out', for: 'phys-k' }, `${s.stiffness} N/m`);
    this.kInput.addEventListener('input', () => {
      setText(this.kOut, `${ladderValue(STIFFNESS, this.kInput)} N/m`);
    });
    this.kInput.addEventListener('change', () => {
      this.change({ stiffness: ladderValue(STIFFNESS, this.kInput) });
    });

    this.interpBtn = toggle('Interpolation', 'control-interp', true, (on) => {
      this.interpolate = on;
    });
    this.interpBtn.title = 'Draw between the last two steps, at alpha';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setRealClock(on);
    });
    this.clockBtn.title =
      'Drive the fixed-step loop with this page’s own requestAnimationFrame times';
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

    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'The spring' },
      h(
        'div',
        { class: 'control-group' },
        h('label', { class: 'control-label', for: 'phys-step' }, 'Step'),
        this.stepInput,
        this.stepOut,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('label', { class: 'control-label', for: 'phys-k' }, 'Spring k'),
        this.kInput,
        this.kOut,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Draw'),
        this.interpBtn,
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
        h('span', { class: 'status-item' }, 'ω = ', this.global('omega', 'rad/s')),
        h('span', { class: 'status-item' }, 'ω·dt = ', this.global('omega-dt', '')),
        h('span', { class: 'status-item' }, 'steps: ', this.global('ticks', '')),
        this.time.status[1],
      ),
    );
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ stability ruler
    this.rulerMarker = h('div', { class: 'ruler-marker', 'aria-hidden': 'true' });
    this.rulerMarkerLabel = h('span', { class: 'ruler-marker-label' });
    this.rulerMarker.append(this.rulerMarkerLabel);
    const rulerRows = INTEGRATOR_METHODS.map((method) => {
      const info = INTEGRATOR_INFO[method];
      const limit = info.stabilityLimit;
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
    const ruler = h(
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
      rulerRows,
      h('div', { class: 'ruler-overlay' }, this.rulerMarker),
    );

    // ------------------------------------------------------------ lanes
    this.hitch = new HitchSection(() => {
      this.render();
    });
    this.laneGrid = h('div', { class: 'panels lane-panels' });
    for (const method of INTEGRATOR_METHODS) this.laneGrid.append(this.buildLane(method));

    this.chartHost = h('div', {
      class: 'energy-chart',
      role: 'img',
      'aria-label': 'Energy over time of each method, on a log scale',
      'data-testid': 'chart-energy',
    });

    // ------------------------------------------------------------ rope
    this.ropeCanvas = h('canvas', {
      class: 'scene rope-scene',
      tabindex: 0,
      role: 'application',
      'aria-roledescription': 'rope',
      'aria-label':
        'A rope of springs. Arrow keys poke the selected bead; comma and period select another. Click or tap to poke, drag to throw.',
      'data-testid': 'canvas-rope',
    });
    const rctx = this.ropeCanvas.getContext('2d');
    if (!rctx) throw new Error('The lab needs a 2D canvas');
    this.ropeCtx = rctx;
    this.ropeOverlay = h('p', { class: 'stall rope-exploded', hidden: true });
    const methods = h(
      'div',
      { class: 'segmented method-picker', role: 'radiogroup', 'aria-label': 'Rope integrator' },
      INTEGRATOR_METHODS.map((method) => {
        const input = h('input', {
          type: 'radio',
          name: 'rope-method',
          value: method,
          id: `rope-${method}`,
          checked: method === s.ropeMethod,
        });
        input.addEventListener('change', () => {
          if (input.checked) this.change({ ropeMethod: method });
        });
        this.methodInputs.set(method, input);
        return h(
          'label',
          { for: `rope-${method}`, 'data-testid': `control-rope-${method}` },
          input,
          h('span', { style: `--accent: ${COLORS[method]}` }, SHORT[method]),
        );
      }),
    );
    this.ropeKInput = ladderInput(
      'rope-k',
      'control-rope-stiffness',
      ROPE_STIFFNESS,
      s.ropeStiffness,
    );
    this.ropeKOut = h('output', { id: 'rope-k-out', for: 'rope-k' }, `${s.ropeStiffness} N/m`);
    this.ropeKInput.addEventListener('input', () => {
      setText(this.ropeKOut, `${ladderValue(ROPE_STIFFNESS, this.ropeKInput)} N/m`);
    });
    this.ropeKInput.addEventListener('change', () => {
      this.change({ ropeStiffness: ladderValue(ROPE_STIFFNESS, this.ropeKInput) });
    });
    const pokeUp = button('Poke ↑', 'control-poke', () => {
      this.poke(this.selected, 0, POKE_KICK);
    });
    pokeUp.title = 'Kick the selected bead upwards (or press an arrow key on the rope)';
    const ropeControls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'The rope' },
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Integrator'),
        methods,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('label', { class: 'control-label', for: 'rope-k' }, 'Links k'),
        this.ropeKInput,
        this.ropeKOut,
      ),
      h(
        'div',
        { class: 'control-group' },
        h('span', { class: 'control-label' }, 'Poke'),
        button('◀', 'control-bead-prev', () => {
          this.select(this.selected - 1);
        }),
        pokeUp,
        button('▶', 'control-bead-next', () => {
          this.select(this.selected + 1);
        }),
      ),
    );
    ropeControls.addEventListener('click', settle);
    ropeControls.addEventListener('change', settle);
    const ropeReadouts = h(
      'dl',
      { class: 'readouts rope-readouts' },
      this.globalRow(
        'rope-omega-dt',
        'Fastest mode ω·dt',
        'ω of the rope’s fastest mode, 2√(k/m), times the step',
      ),
      this.globalRow(
        'rope-verdict',
        'Integrator says',
        'What the chosen integrator does at this ω·dt',
      ),
      this.globalRow('rope-state', 'State', 'Swinging, or exploded (a bead flew off)'),
      this.globalRow('rope-energy', 'Energy', 'Kinetic + gravitational + elastic, J'),
      this.globalRow('rope-pokes', 'Pokes', 'Pokes delivered so far (one is scripted at 1 s)'),
    );

    // ------------------------------------------------------------ page
    root.append(
      h(
        'article',
        { class: 'chapter physics-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 4'),
          h('h1', {}, 'Physics'),
          h(
            'p',
            { class: 'lede' },
            'A simulation advances positions and velocities in steps: an integrator. The simplest one, Euler’s (move with the old velocity, then update it), is exact only for constant forces. On a spring — the force grows with the stretch — the small error of each step feeds itself: the spring gains energy every step until it blows up. Swap the two lines, as the talk’s own code does, and it holds; push the step or the stiffness too far and every explicit method blows up. A fixed step makes the behaviour at least the same everywhere; the integrator decides whether it is right.',
          ),
        ),
        methodsIntro(),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'spring-title' },
          h('h2', { id: 'spring-title' }, 'One spring, six integrators'),
          h(
            'p',
            { class: 'section-intro' },
            `A 1 kg mass on a spring, pulled ${X0} m and let go: x'' = −ω²x with ω = √(k/m). Each panel integrates the very same spring with the same fixed step; the dashed circle on the right is the exact motion in phase space (x against v/ω), the coloured trace is the method’s. Whether a method survives depends only on ω·dt.`,
          ),
          controls,
          ruler,
          this.laneGrid,
          h('h3', { class: 'chart-heading' }, 'Energy, E / E₀ (log scale)'),
          h('div', { class: 'energy-chart-wrap' }, this.chartHost, energyLegend()),
        ),
        this.hitch.el,
        h(
          'section',
          { class: 'rope-section', 'aria-labelledby': 'rope-title' },
          h('h2', { id: 'rope-title' }, 'A rope'),
          h(
            'p',
            { class: 'section-intro' },
            `${ROPE_BEADS} beads of 100 g on springs, pinned at both ends, under gravity, with the step above. A rope has many modes at once; the fastest, ω ≈ 2√(k/m), decides stability. Poke it; then stiffen the links, or pick another integrator, and poke again.`,
          ),
          ropeControls,
          h(
            'div',
            { class: 'rope-layout' },
            h(
              'div',
              {},
              h('div', { class: 'scene-wrap' }, this.ropeCanvas, this.ropeOverlay),
              h(
                'p',
                { class: 'rope-hint' },
                'Click or tap a bead: a kick up. Drag from a bead: a throw. Keyboard: focus the rope, arrows kick, comma and period pick the bead.',
              ),
            ),
            ropeReadouts,
          ),
        ),
        this.experiments(),
        howItWorks(),
      ),
    );

    // ------------------------------------------------------------ wiring
    this.wireRope();
    this.observer = new ResizeObserver(() => {
      this.resize();
    });
    for (const l of this.lanes) this.observer.observe(l.canvas);
    this.observer.observe(this.chartHost);
    this.observer.observe(this.ropeCanvas);

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

  /** A readout outside the panels: `data-testid="readout-<id>"`. */
  private global(id: string, unit: string): HTMLElement {
    const value = h('span', {});
    const cell = h(
      'span',
      { class: 'clock', 'data-testid': `readout-${id}` },
      value,
      unit ? ` ${unit}` : '',
    );
    this.globals.set(id, value);
    this.globals.set(`${id}:cell`, cell);
    return cell;
  }

  private globalRow(id: string, label: string, title: string): HTMLElement[] {
    const value = h('span', {});
    const dd = h('dd', { 'data-testid': `readout-${id}` }, value);
    this.globals.set(id, value);
    this.globals.set(`${id}:cell`, dd);
    return [h('dt', { title }, label), dd];
  }

  private buildLane(method: IntegratorMethod): HTMLElement {
    const color = COLORS[method];
    const info = INTEGRATOR_INFO[method];
    const canvas = h('canvas', {
      class: 'scene lane-scene',
      role: 'img',
      'aria-label': `The spring under ${info.label}: the mass and its phase portrait`,
      'data-testid': `canvas-${method}`,
    });
    const ctx = canvas.getContext('2d');
    if (!ctx) throw new Error('The lab needs a 2D canvas');
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
    const values = new Map<LaneField, HTMLElement>();
    const cells = new Map<LaneField, HTMLElement>();
    const list = rows
      .map((row) => {
        const text = h('span', {});
        const cell = h('dd', { 'data-testid': `readout-${method}-${row.field}` }, text);
        values.set(row.field, text);
        cells.set(row.field, cell);
        return [h('dt', { title: row.title }, row.label), cell];
      })
      .flat();
    const chip = h('span', { class: 'state-chip', 'data-testid': `readout-${method}-state` });
    cells.set('state', chip);
    values.set('state', chip);
    const overlay = h('p', { class: 'overlay lane-overlay', hidden: true });
    this.lanes.push({
      method,
      color,
      canvas,
      ctx,
      values,
      cells,
      chip,
      overlay,
      w: 0,
      h: 0,
      dpr: 1,
    });
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
        style: `--accent: ${color}`,
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
          chip,
        ),
        h('p', {}, h('code', {}, UPDATE[method]), h('br', {}), `order ${info.order} · ${limit}`),
      ),
      h('div', { class: 'scene-wrap' }, canvas, overlay),
      h('dl', { class: 'readouts' }, list),
    );
  }

  private experiments(): HTMLElement {
    // Each sets everything its text assumes and starts again, whatever was clicked before.
    const run = (
      settings: Partial<PhysicsSettings>,
      playMs: number | undefined,
      show: HTMLElement,
    ) => {
      this.change({
        stepMs: 30,
        stiffness: 20,
        ropeStiffness: 40,
        ropeMethod: 'semi-implicit-euler',
        ...settings,
      });
      this.methodInputs.get(this.lab.settings.ropeMethod)!.checked = true;
      this.lab.restart();
      this.lastPoke = undefined;
      if (playMs !== undefined) {
        this.lab.advanceBy(playMs);
        this.setPaused(true);
      } else {
        this.setPaused(false);
      }
      show.scrollIntoView({ block: 'start', behavior: 'smooth' });
    };
    const items: { title: string; text: string; action: string; run: () => void }[] = [
      {
        title: 'The talk’s exploding spring',
        text: 'k = 20 N/m at the talk’s 30 ms: ω·dt ≈ 0.13, tiny. Explicit Euler still gains 1.8 % per step — ×380 in 10 s — while the talk’s own code (semi-implicit Euler) wobbles within 7 % and velocity Verlet within 0.5 %.',
        action: 'Run 10 s',
        run: () => {
          run({}, 10_000, this.laneGrid);
        },
      },
      {
        title: 'Just past 2',
        text: 'k = 5000 N/m at 30 ms: ω·dt ≈ 2.12. Semi-implicit Euler and both Verlets blow up within the first second; RK4 (limit 2√2) stays bounded but drains the motion away, backward Euler too. Smaller steps, not cleverer code, are what fixes a stiff spring.',
        action: 'k = 5000 N/m',
        run: () => {
          run({ stiffness: 5000 }, undefined, this.laneGrid);
        },
      },
      {
        title: 'A smaller step',
        text: 'The talk’s spring at 15 ms instead of 30 for 10 s. Explicit Euler’s growth per step falls four times and it takes twice the steps: ×20 instead of ×380 — better, still wrong. Everyone else gets closer to 1: the error of the first-order methods halves, the Verlets’ quarters.',
        action: 'Step 15 ms',
        run: () => {
          run({ stepMs: 15 }, 10_000, this.laneGrid);
        },
      },
      {
        title: 'Only backward Euler survives',
        text: 'Stiffen the rope’s links to 1000 N/m at 30 ms: its fastest mode has ω·dt ≈ 6. Every explicit method shreds it within a few steps; backward Euler stays calm — and you can see it drain the swing away.',
        action: 'Stiff rope',
        run: () => {
          run({ ropeStiffness: 1000, ropeMethod: 'backward-euler' }, undefined, this.ropeCanvas);
        },
      },
    ];
    return h(
      'section',
      { class: 'experiments', 'aria-labelledby': 'phys-experiments-title' },
      h('h2', { id: 'phys-experiments-title' }, 'Things to try'),
      h(
        'ol',
        { class: 'experiment-list' },
        items.map((item) => {
          const btn = h('button', { type: 'button', class: 'btn btn-small' }, item.action);
          btn.addEventListener('click', () => {
            if (this.clock) this.setRealClock(false);
            item.run();
            this.refreshControls();
            this.render();
          });
          return h('li', {}, h('h3', {}, item.title), h('p', {}, item.text), btn);
        }),
      ),
    );
  }

  // ---------------------------------------------------------------- the rope's input

  private wireRope(): void {
    const c = this.ropeCanvas;
    const toWorld = (event: PointerEvent) => {
      const rect = c.getBoundingClientRect();
      const s = Math.min(rect.width / (2 * ROPE_VIEW.hw), rect.height / (2 * ROPE_VIEW.hh));
      return {
        x: ROPE_VIEW.cx + (event.clientX - rect.left - rect.width / 2) / s,
        y: ROPE_VIEW.cy - (event.clientY - rect.top - rect.height / 2) / s,
      };
    };
    c.addEventListener('pointerdown', (event) => {
      const p = toWorld(event);
      const bead = this.nearestBead(p.x, p.y);
      this.select(bead);
      this.drag = { bead, x0: p.x, y0: p.y, x: p.x, y: p.y };
      c.setPointerCapture(event.pointerId);
      event.preventDefault();
    });
    c.addEventListener('pointermove', (event) => {
      if (!this.drag) return;
      const p = toWorld(event);
      this.drag.x = p.x;
      this.drag.y = p.y;
    });
    const end = (event: PointerEvent) => {
      const d = this.drag;
      if (!d) return;
      this.drag = undefined;
      if (c.hasPointerCapture(event.pointerId)) c.releasePointerCapture(event.pointerId);
      if (event.type === 'pointercancel') return;
      const dx = d.x - d.x0;
      const dy = d.y - d.y0;
      const len = Math.hypot(dx, dy);
      if (len < 0.15) this.poke(d.bead, 0, POKE_KICK);
      else {
        const speed = Math.min(POKE_MAX, len * POKE_PER_M);
        this.poke(d.bead, (dx / len) * speed, (dy / len) * speed);
      }
    };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointercancel', end);
    c.addEventListener('keydown', (event) => {
      const k = POKE_KICK;
      const moves: Record<string, [number, number]> = {
        ArrowUp: [0, k],
        ArrowDown: [0, -k],
        ArrowLeft: [-k, 0],
        ArrowRight: [k, 0],
      };
      const m = moves[event.key];
      if (m) {
        this.poke(this.selected, m[0], m[1]);
        event.preventDefault();
      } else if (event.key === ',' || event.key === '<') {
        this.select(this.selected - 1);
        event.preventDefault();
      } else if (event.key === '.' || event.key === '>') {
        this.select(this.selected + 1);
        event.preventDefault();
      }
    });
  }

  private nearestBead(x: number, y: number): number {
    const run = this.run();
    const xs = run.rope.x;
    let best = this.selected;
    let bestD = Infinity;
    for (let i = 1; i < ROPE_BEADS - 1; i++) {
      const d = (xs[2 * i]! - x) ** 2 + (xs[2 * i + 1]! - y) ** 2;
      if (d < bestD) {
        bestD = d;
        best = i;
      }
    }
    return best;
  }

  private select(bead: number): void {
    this.selected = Math.min(ROPE_BEADS - 2, Math.max(1, bead));
    this.render();
  }

  private poke(bead: number, dvx: number, dvy: number): void {
    const p = { bead, dvx, dvy };
    if (this.clock) this.clock.poke(p);
    else this.lab.poke(p);
    const t = this.clock ? this.clock.timeMs : this.lab.timeMs;
    this.lastPoke = { ...p, atMs: t };
    if (this.driver.isPaused) this.setPaused(false);
    this.render();
  }

  // ---------------------------------------------------------------- state changes

  private change(change: Partial<PhysicsSettings>): void {
    this.lab.update(change);
    if (this.clock) this.setRealClock(true);
    this.refreshControls();
    this.render();
  }

  private setPaused(paused: boolean): void {
    this.driver.setPaused(paused);
    this.refreshControls();
  }

  private setRealClock(on: boolean): void {
    if (on) {
      this.clock = new ClockPhysics(this.lab.settings);
    } else {
      this.clock = undefined;
    }
    this.driver.setReal(on);
    this.clockBtn.setAttribute('aria-pressed', String(on));
    this.refreshControls();
  }

  private restart(): void {
    this.hitch.restart();
    if (this.clock) this.setRealClock(true);
    else this.lab.restart();
    this.lastPoke = undefined;
    this.refreshControls();
  }

  private refreshControls(): void {
    const s = this.lab.settings;
    if (Number(this.stepInput.value) !== s.stepMs) this.stepInput.value = String(s.stepMs);
    setText(this.stepOut, `${s.stepMs} ms`);
    setLadder(STIFFNESS, this.kInput, s.stiffness);
    setText(this.kOut, `${s.stiffness} N/m`);
    setLadder(ROPE_STIFFNESS, this.ropeKInput, s.ropeStiffness);
    setText(this.ropeKOut, `${s.ropeStiffness} N/m`);
    // The method radios are not set here: this runs inside their own click, and would undo it.
    this.time.refresh(this.driver.isPaused, this.clock === undefined);
  }

  private resize(): void {
    const dpr = Math.min(window.devicePixelRatio || 1, 3);
    for (const l of this.lanes) {
      const rect = l.canvas.getBoundingClientRect();
      const w = Math.max(1, Math.round(rect.width * dpr));
      const hh = Math.max(1, Math.round(rect.height * dpr));
      if (w !== l.w || hh !== l.h) {
        l.canvas.width = w;
        l.canvas.height = hh;
        l.w = w;
        l.h = hh;
        l.dpr = dpr;
      }
    }
    const rr = this.ropeCanvas.getBoundingClientRect();
    const rw = Math.max(1, Math.round(rr.width * dpr));
    const rh = Math.max(1, Math.round(rr.height * dpr));
    if (rw !== this.ropeSize.w || rh !== this.ropeSize.h) {
      this.ropeCanvas.width = rw;
      this.ropeCanvas.height = rh;
      this.ropeSize = { w: rw, h: rh, dpr };
    }
    const cw = Math.floor(this.chartHost.getBoundingClientRect().width);
    if (!this.chart && cw > 0) {
      this.chart = new EnergyChart(
        this.chartHost,
        cw,
        INTEGRATOR_METHODS.map((m) => INTEGRATOR_INFO[m].label),
        INTEGRATOR_METHODS.map((m) => COLORS[m]),
        () => (window.innerWidth < 600 ? 220 : 280),
      );
      this.render();
    } else this.chart?.resize(cw);
  }

  // ---------------------------------------------------------------- the frame

  private run(): PhysicsRun {
    return this.clock ? this.clock.run : this.lab.run;
  }

  private render(): void {
    const run = this.run();
    const t = this.clock ? this.clock.timeMs : this.lab.timeMs;
    this.hitch.render(t);
    const s = this.lab.settings;
    const hz = this.driver.measuredHz;
    this.time.show(
      t,
      this.clock
        ? `real clock · your display ≈ ${hz} Hz${this.driver.isPaused ? ' · paused' : ''}`
        : `simulated display · 60 Hz${this.driver.isPaused ? ' · paused' : ''}`,
    );
    const omega = omegaOf(s.stiffness);
    const omegaDt = run.omegaDt;
    this.putGlobal('omega', omega.toFixed(2), omega);
    this.putGlobal('omega-dt', omegaDt.toFixed(3), omegaDt);
    this.putGlobal('ticks', fmt.count(run.race.tick), run.race.tick);
    this.renderRuler(omegaDt);
    const alpha = this.interpolate ? run.alpha : 1;
    for (const lane of this.lanes) this.drawLane(lane, run, alpha, omegaDt);
    this.chart?.set(run.energy, run.race.time);
    this.drawRope(run, alpha, t);
  }

  private putGlobal(id: string, text: string, value: number | string): void {
    const v = this.globals.get(id);
    const cell = this.globals.get(`${id}:cell`);
    if (!v || !cell) return;
    setText(v, text);
    setAttr(cell, 'data-value', fmt.exact(value));
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

  private drawLane(l: LaneView, run: PhysicsRun, alpha: number, omegaDt: number): void {
    const k = INTEGRATOR_METHODS.indexOf(l.method);
    const lane = run.race.lanes[k];
    if (!lane) return;
    const race = run.race;
    const ratio = race.energyRatio(lane);
    const put = (field: LaneField, text: string, value: number | string) => {
      const el = l.values.get(field);
      const cell = l.cells.get(field);
      if (!el || !cell) return;
      setText(el, text);
      setAttr(cell, 'data-value', fmt.exact(value));
    };
    put('energy-ratio', energyText(ratio), ratio);
    put('max-error', errorText(lane.maxEnergyError), lane.maxEnergyError);
    const phase = race.phaseError(lane);
    const phaseText = Math.abs(phase).toFixed(3);
    put('phase', `${phaseText === '0.000' ? '±' : phase >= 0 ? '+' : '−'}${phaseText} rad`, phase);
    // A method inside its stability limit may still drain the motion (RK4 near 2√2): that is
    // "damped", not "stable" — stable is not the same as right.
    const limitState = stabilityOf(l.method, omegaDt);
    const st: Stability | 'exploded' = lane.exploded
      ? 'exploded'
      : limitState === 'stable' && ratio < 1e-3
        ? 'damped'
        : limitState;
    put('state', st === 'exploded' ? 'exploded' : st === 'grows' ? 'grows' : st, st);
    setAttr(l.chip, 'data-state', st);
    l.cells.get('energy-ratio')?.classList.toggle('warn', !(Math.abs(ratio - 1) < 0.1));
    l.overlay.hidden = !lane.exploded;
    setText(
      l.overlay,
      lane.exploded ? `Exploded at ${(lane.explodedAt * race.dt).toFixed(2)} s: energy ×10⁹` : '',
    );

    // --- the canvas: a spring column on the left, the phase portrait on the right.
    const { ctx, w, h: hh, dpr } = l;
    if (w <= 1 || hh <= 1) return;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#0a1122';
    ctx.fillRect(0, 0, w, hh);
    const x = lane.prevX + (lane.state.x[0]! - lane.prevX) * alpha;
    const v = lane.prevV + (lane.state.v[0]! - lane.prevV) * alpha;
    const omega = race.omega;

    // Zoom out as far as the trace has gone, so an exploding spring stays in view: the dashed
    // exact orbit then shrinks in the middle of the spiral.
    const trails = run.trails;
    const n = trails.size;
    const vs = omega > 0 ? 1 / omega : 1;
    let reach = Math.hypot(x, v * vs);
    for (let j = 0; j < n; j++) {
      const r = Math.hypot(trails.x(k, j), trails.v(k, j) * vs);
      if (r > reach) reach = r;
    }
    const zoom = Number.isFinite(reach) ? Math.max(1, reach / X0) : 1e12;

    // Spring column.
    const colW = Math.round(w * 0.3);
    const cx = colW / 2;
    const top = 8 * dpr;
    const mid = hh / 2;
    const scale = (hh / 2 - 14 * dpr) / (SPRING_VIEW * zoom);
    ctx.fillStyle = 'rgba(141, 160, 189, 0.35)';
    ctx.fillRect(cx - colW * 0.3, top - 3 * dpr, colW * 0.6, 3 * dpr);
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.25)';
    ctx.setLineDash([3 * dpr, 3 * dpr]);
    ctx.beginPath();
    ctx.moveTo(cx - colW * 0.35, mid);
    ctx.lineTo(cx + colW * 0.35, mid);
    ctx.stroke();
    ctx.setLineDash([]);
    const boxH = Math.max(10 * dpr, hh * 0.09);
    const yMass = mid + clamp(x, -SPRING_VIEW * zoom, SPRING_VIEW * zoom) * scale;
    // Zig-zag from the ceiling to the mass.
    const coils = 9;
    const springTop = top;
    const springBottom = Math.max(springTop + 2 * dpr, yMass - boxH / 2);
    ctx.strokeStyle = l.color;
    ctx.lineWidth = 1.5 * dpr;
    ctx.beginPath();
    ctx.moveTo(cx, springTop);
    const amp = colW * 0.16;
    for (let i = 1; i <= 2 * coils; i++) {
      const yy = springTop + ((springBottom - springTop) * i) / (2 * coils + 1);
      ctx.lineTo(cx + (i % 2 === 0 ? -amp : amp), yy);
    }
    ctx.lineTo(cx, springBottom);
    ctx.stroke();
    ctx.fillStyle = l.color;
    ctx.fillRect(cx - colW * 0.22, springBottom, colW * 0.44, boxH);

    // Phase portrait.
    const px0 = colW;
    const pw = w - colW;
    const pcx = px0 + pw / 2;
    const pcy = hh / 2;
    const R = (Math.min(pw, hh) * 0.4) / zoom;
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.18)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(px0 + 6 * dpr, pcy);
    ctx.lineTo(w - 6 * dpr, pcy);
    ctx.moveTo(pcx, 6 * dpr);
    ctx.lineTo(pcx, hh - 6 * dpr);
    ctx.stroke();
    ctx.strokeStyle = 'rgba(226, 232, 240, 0.55)';
    ctx.setLineDash([4 * dpr, 4 * dpr]);
    ctx.beginPath();
    ctx.arc(pcx, pcy, R * X0, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.save();
    ctx.beginPath();
    ctx.rect(px0, 0, pw, hh);
    ctx.clip();
    ctx.strokeStyle = l.color;
    ctx.lineWidth = 1.5 * dpr;
    ctx.beginPath();
    for (let j = 0; j < n; j++) {
      const tx = pcx + clamp(trails.x(k, j) * R, -w, w);
      const ty = pcy - clamp(trails.v(k, j) * vs * R, -hh, hh);
      if (j === 0) ctx.moveTo(tx, ty);
      else ctx.lineTo(tx, ty);
    }
    ctx.globalAlpha = 0.8;
    ctx.stroke();
    ctx.globalAlpha = 1;
    const dx = pcx + clamp(x * R, -w, w);
    const dy = pcy - clamp(v * vs * R, -hh, hh);
    ctx.fillStyle = '#ffffff';
    ctx.beginPath();
    ctx.arc(dx, dy, 3.5 * dpr, 0, 2 * Math.PI);
    ctx.fill();
    ctx.restore();
    ctx.fillStyle = 'rgba(163, 179, 204, 0.8)';
    ctx.font = `${Math.round(10 * dpr)}px system-ui, sans-serif`;
    ctx.textAlign = 'right';
    ctx.textBaseline = 'bottom';
    ctx.fillText('x', w - 5 * dpr, pcy - 2 * dpr);
    ctx.textAlign = 'left';
    ctx.textBaseline = 'top';
    ctx.fillText('v/ω', pcx + 4 * dpr, 4 * dpr);
    if (zoom > 1.25) {
      ctx.fillStyle = '#fcd34d';
      ctx.textBaseline = 'bottom';
      ctx.fillText(`zoomed out ×${zoomText(zoom)}`, 5 * dpr, hh - 4 * dpr);
    }
  }

  private drawRope(run: PhysicsRun, alpha: number, tMs: number): void {
    const rope = run.rope;
    const s = this.lab.settings;
    const rOmegaDt = ropeOmegaDt(s.ropeStiffness, s.stepMs);
    this.putGlobal('rope-omega-dt', rOmegaDt.toFixed(2), rOmegaDt);
    const verdict = stabilityOf(rope.config.integrator, rOmegaDt);
    this.putGlobal('rope-verdict', verdictText(verdict), verdict);
    this.globals
      .get('rope-verdict:cell')
      ?.classList.toggle('warn', verdict === 'unstable' || verdict === 'grows');
    const state = rope.exploded ? 'exploded' : 'swinging';
    this.putGlobal('rope-state', state, state);
    this.globals.get('rope-state:cell')?.classList.toggle('warn', rope.exploded);
    const e = rope.energy();
    this.putGlobal('rope-energy', rope.exploded ? '—' : `${e.toFixed(2)} J`, e);
    this.putGlobal('rope-pokes', fmt.count(rope.pokes), rope.pokes);
    this.ropeOverlay.hidden = !rope.exploded;
    setText(
      this.ropeOverlay,
      rope.exploded
        ? `Exploded after ${(rope.explodedAt * rope.config.dt).toFixed(2)} s: a bead flew ${rope.config.explodeBeyond} m off. Pick another integrator, or soften the links or shorten the step so ω·dt falls inside its limit.`
        : '',
    );

    const { w, h: hh, dpr } = this.ropeSize;
    const ctx = this.ropeCtx;
    if (w <= 1 || hh <= 1) return;
    const sc = Math.min(w / (2 * ROPE_VIEW.hw), hh / (2 * ROPE_VIEW.hh));
    const X = (x: number) => w / 2 + (x - ROPE_VIEW.cx) * sc;
    const Y = (y: number) => hh / 2 - (y - ROPE_VIEW.cy) * sc;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#0a1122';
    ctx.fillRect(0, 0, w, hh);
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.08)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    for (let gx = -4; gx <= 4; gx++) {
      ctx.moveTo(Math.round(X(gx)) + 0.5, 0);
      ctx.lineTo(Math.round(X(gx)) + 0.5, hh);
    }
    for (let gy = -4; gy <= 2; gy++) {
      ctx.moveTo(0, Math.round(Y(gy)) + 0.5);
      ctx.lineTo(w, Math.round(Y(gy)) + 0.5);
    }
    ctx.stroke();

    const color = COLORS[rope.config.integrator];
    const n = rope.count;
    const pts: number[] = [];
    for (let i = 0; i < n; i++) {
      const p = rope.renderPosition(i, rope.exploded ? 1 : alpha, this.pos);
      pts.push(X(clamp(p.x, -1e4, 1e4)), Y(clamp(p.y, -1e4, 1e4)));
    }
    ctx.strokeStyle = color;
    ctx.lineWidth = 2 * dpr;
    ctx.lineJoin = 'round';
    ctx.beginPath();
    for (let i = 0; i < n; i++) {
      if (i === 0) ctx.moveTo(pts[0]!, pts[1]!);
      else ctx.lineTo(pts[2 * i]!, pts[2 * i + 1]!);
    }
    ctx.stroke();
    const beadR = Math.max(3.5 * dpr, 0.07 * sc);
    for (let i = 0; i < n; i++) {
      const bx = pts[2 * i]!;
      const by = pts[2 * i + 1]!;
      const pinned = i === 0 || i === n - 1;
      ctx.beginPath();
      if (pinned) {
        ctx.fillStyle = '#94a3b8';
        ctx.fillRect(bx - 5 * dpr, by - 5 * dpr, 10 * dpr, 10 * dpr);
        continue;
      }
      ctx.arc(bx, by, i === this.selected ? beadR * 1.5 : beadR, 0, 2 * Math.PI);
      ctx.fillStyle = i === this.selected ? '#fde047' : color;
      ctx.fill();
    }

    // The last poke, fading over half a second.
    const lp = this.lastPoke;
    if (lp && tMs - lp.atMs < 600) {
      const fade = 1 - (tMs - lp.atMs) / 600;
      const bx = pts[2 * lp.bead];
      const by = pts[2 * lp.bead + 1];
      if (bx !== undefined && by !== undefined) {
        const len = Math.hypot(lp.dvx, lp.dvy) || 1;
        const L = Math.min(60 * dpr, len * 8 * dpr);
        arrow(ctx, bx, by, bx + (lp.dvx / len) * L, by - (lp.dvy / len) * L, dpr, fade);
      }
    }
    // A drag in progress.
    const d = this.drag;
    if (d) {
      const bx = pts[2 * d.bead];
      const by = pts[2 * d.bead + 1];
      if (bx !== undefined && by !== undefined) {
        arrow(ctx, bx, by, bx + (d.x - d.x0) * sc, by - (d.y - d.y0) * sc, dpr, 0.9);
      }
    }
  }
}

function arrow(
  ctx: CanvasRenderingContext2D,
  x0: number,
  y0: number,
  x1: number,
  y1: number,
  dpr: number,
  alpha: number,
): void {
  const len = Math.hypot(x1 - x0, y1 - y0);
  if (len < 2) return;
  const ux = (x1 - x0) / len;
  const uy = (y1 - y0) / len;
  ctx.globalAlpha = alpha;
  ctx.strokeStyle = '#fde047';
  ctx.fillStyle = '#fde047';
  ctx.lineWidth = 2 * dpr;
  ctx.beginPath();
  ctx.moveTo(x0, y0);
  ctx.lineTo(x1, y1);
  ctx.stroke();
  const hs = 7 * dpr;
  ctx.beginPath();
  ctx.moveTo(x1 + ux * 2, y1 + uy * 2);
  ctx.lineTo(x1 - ux * hs - uy * hs * 0.6, y1 - uy * hs + ux * hs * 0.6);
  ctx.lineTo(x1 - ux * hs + uy * hs * 0.6, y1 - uy * hs - ux * hs * 0.6);
  ctx.closePath();
  ctx.fill();
  ctx.globalAlpha = 1;
}

function clamp(v: number, lo: number, hi: number): number {
  return Number.isFinite(v) ? Math.min(hi, Math.max(lo, v)) : v > 0 ? hi : lo;
}

function zoomText(z: number): string {
  if (z >= 1e4) return fmt.sci(z, 0);
  return z >= 10 ? z.toFixed(0) : z.toFixed(1);
}

/** E/E₀ for a readout: 4 significant digits near 1, then grouped, then powers of ten. */
function energyText(r: number): string {
  if (!Number.isFinite(r)) return '—';
  if (r >= 1e5 || (r > 0 && r < 1e-3)) return `${fmt.sci(r)}×`;
  if (r >= 100) return `${fmt.count(r)}×`;
  return `${r.toFixed(4)}×`;
}

/** max |ΔE| / E₀: a percentage below 10×, a factor above (an explosion). */
function errorText(e: number): string {
  if (!Number.isFinite(e)) return '∞';
  if (e >= 1e5) return `${fmt.sci(e)}×`;
  if (e >= 10) return `${fmt.count(e)}×`;
  return `${(e * 100).toFixed(2)} %`;
}

function verdictText(st: Stability): string {
  switch (st) {
    case 'grows':
      return 'grows at any ω·dt';
    case 'damped':
      return 'stable, damps';
    case 'stable':
      return 'stable';
    case 'unstable':
      return 'explodes';
  }
}

function ladderInput(
  id: string,
  testId: string,
  ladder: readonly number[],
  value: number,
): HTMLInputElement {
  const i = Math.max(0, ladder.indexOf(value));
  return h('input', {
    type: 'range',
    min: 0,
    max: ladder.length - 1,
    step: 1,
    value: i,
    id,
    'data-testid': testId,
    'aria-describedby': `${id}-out`,
    'aria-valuetext': `${value} N/m`,
  });
}

function ladderValue(ladder: readonly number[], input: HTMLInputElement): number {
  return ladder[Math.min(ladder.length - 1, Math.max(0, Number(input.value)))] ?? ladder[0]!;
}

function setLadder(ladder: readonly number[], input: HTMLInputElement, value: number): void {
  const i = ladder.indexOf(value);
  if (i >= 0 && Number(input.value) !== i) input.value = String(i);
  setAttr(input, 'aria-valuetext', `${value} N/m`);
}

function methodsIntro(): HTMLElement {
  const cards: IdeaCard[] = [
    {
      title: 'Explicit Euler',
      color: COLORS['explicit-euler'],
      text: 'Both updates from the old state. On a spring every step multiplies the energy by 1 + (ω·dt)², at any step size: this is the spring that explodes.',
      snippet: 'position += velocity * dt\nvelocity += acceleration * dt',
    },
    {
      title: 'The talk’s code: semi-implicit Euler',
      color: COLORS['semi-implicit-euler'],
      text: 'Swap the two lines — velocity first, then move with the new velocity — and the energy stays bounded while ω·dt < 2. The slides’ own loop is this one: it wobbles but holds at the talk’s spring, and explodes only for stiff springs. The explosion the talk shows is what card 1 does.',
      snippet: 'velocity += acceleration * dt\nposition += velocity * dt',
    },
    {
      title: 'The alternatives',
      color: COLORS['velocity-verlet'],
      text: 'Backward (implicit) Euler solves for the end of the step: never unstable, but it drains energy. Verlet and velocity Verlet are second order and keep energy for ever below ω·dt = 2. RK4 is the most accurate per step, costs four force evaluations and slowly loses energy.',
      snippet: 'v += ½a·dt;  x += v·dt\na = force(x) / m\nv += ½a·dt   // velocity Verlet',
    },
  ];
  return ideaCards({
    id: 'methods-title',
    title: 'Integrators',
    cards,
    listClass: 'method-cards',
  });
}

function energyLegend(): HTMLElement {
  return h(
    'ul',
    { class: 'chart-legend energy-legend' },
    INTEGRATOR_METHODS.map((m) =>
      h(
        'li',
        {},
        h('span', { class: 'line-swatch', style: `--swatch: ${COLORS[m]}`, 'aria-hidden': 'true' }),
        INTEGRATOR_INFO[m].label,
      ),
    ),
  );
}

function howItWorks(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'phys-how-title' },
    h('h2', { id: 'phys-how-title' }, 'How this page works'),
    h(
      'p',
      {},
      `The six panels are one deterministic simulation: fixedstep’s integrators on one harmonic oscillator, stepped in lockstep by a fixed-step loop (FixedLoop) with the step you chose. Energy is ½v² + ½ω²x² per kilogram; a method whose energy passes ${fmt.sci(EXPLODE_AT, 0)} times the start is stopped and marked exploded. The rope is a SpringSystem (fixedstep’s springs) that starts hanging at rest.`,
    ),
    h(
      'p',
      {},
      'The display is simulated, as in chapter 1, so every number repeats. The loop draws each mass and bead between its last two steps, at α = accumulator / step. Changing the step, a stiffness or the rope’s integrator rebuilds everything and replays it — pokes included — from zero to the current moment. “Real clock” drives the loop with this page’s own frame times.',
    ),
  );
}
