/**
 * Chapter 4's rope: a rope of springs under a chosen integrator, its controls, its readouts and its
 * input (click or tap a bead to kick it, drag to throw, arrows on the focused rope). The rope runs
 * inside the chapter's {@link PhysicsRun}; this section reads it and sends it pokes.
 */
import { INTEGRATOR_METHODS, type IntegratorMethod } from 'fixedstep';
import type { RopePoke } from '@fixedstep/games';
import type { ChapterShell } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { button, group, ladderSlider } from '../../ui/controls.js';
import { h, setText, setHidden } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import {
  ROPE_BEADS,
  ROPE_STIFFNESS,
  ropeOmegaDt,
  stabilityOf,
  type PhysicsRun,
  type PhysicsSettings,
} from './physics-lab.js';
import { ROPE_VIEW, drawRope, type DrawnPoke } from './physics-draw.js';
import { COLORS, ROPE_INTRO, SHORT, verdictText } from './physics-text.js';

/** Pokes: the default kick and the most a drag gives, m/s; m/s per metre of drag. */
const POKE_KICK = 4;
const POKE_MAX = 10;
const POKE_PER_M = 4;

/** What the rope section needs from its chapter. */
export interface RopeHost {
  settings(): Readonly<PhysicsSettings>;
  /** The run drawn now (simulated or real clock). */
  run(): PhysicsRun;
  /** Virtual ms now. */
  timeMs(): number;
  change(change: Partial<PhysicsSettings>): void;
  /** Deliver a poke now (and play). */
  poke(p: RopePoke): void;
}

export class RopeSection {
  readonly el: HTMLElement;
  readonly canvas: SceneCanvas;
  private readonly methodInputs = new Map<IntegratorMethod, HTMLInputElement>();
  private readonly stiffness;
  private readonly note = h('span', { class: 'scene-stall', hidden: true });
  private readonly out = {
    omegaDt: new Readout('dd', 'rope-omega-dt'),
    verdict: new Readout('dd', 'rope-verdict'),
    state: new Readout('dd', 'rope-state'),
    energy: new Readout('dd', 'rope-energy'),
    pokes: new Readout('dd', 'rope-pokes'),
  };
  private selected = Math.floor(ROPE_BEADS / 2);
  private drag: { bead: number; x0: number; y0: number; x: number; y: number } | undefined;
  private lastPoke: DrawnPoke | undefined;

  constructor(
    shell: ChapterShell,
    private readonly host: RopeHost,
  ) {
    const s = host.settings();
    this.canvas = shell.canvas({
      class: 'scene rope-scene',
      label:
        'A rope of springs. Arrow keys poke the selected bead; comma and period select another. Click or tap to poke, drag to throw.',
      testId: 'canvas-rope',
    });
    const c = this.canvas.canvas;
    c.tabIndex = 0;
    c.setAttribute('role', 'application');
    c.setAttribute('aria-roledescription', 'rope');
    this.stiffness = ladderSlider({
      id: 'rope-k',
      testId: 'control-rope-stiffness',
      label: 'Links k',
      values: ROPE_STIFFNESS,
      value: s.ropeStiffness,
      unit: 'N/m',
      onChange: (k) => {
        host.change({ ropeStiffness: k });
      },
    });
    const pokeUp = button('Poke ↑', 'control-poke', () => {
      this.poke(this.selected, 0, POKE_KICK);
    });
    pokeUp.title = 'Kick the selected bead upwards (or press an arrow key on the rope)';
    const controls = shell.controls(
      'The rope',
      group('Integrator', this.methodPicker(s.ropeMethod)),
      this.stiffness.el,
      group(
        'Poke',
        button('◀', 'control-bead-prev', () => {
          this.select(this.selected - 1);
        }),
        pokeUp,
        button('▶', 'control-bead-next', () => {
          this.select(this.selected + 1);
        }),
      ),
    );
    const o = this.out;
    const row = (r: Readout, label: string, title: string) => [h('dt', { title }, label), r.el];
    this.el = introSection(
      'rope-section',
      'rope-title',
      'A rope',
      ROPE_INTRO,
      controls,
      h(
        'div',
        { class: 'rope-layout' },
        h(
          'div',
          {},
          h('div', { class: 'scene-wrap' }, c),
          h('p', { class: 'scene-notes' }, this.note),
          h(
            'p',
            { class: 'rope-hint' },
            'Click or tap a bead: a kick up. Drag from a bead: a throw. Keyboard: focus the rope, arrows kick, comma and period pick the bead.',
          ),
        ),
        h(
          'dl',
          { class: 'readouts rope-readouts' },
          row(
            o.omegaDt,
            'Fastest mode ω·dt',
            'ω of the rope’s fastest mode, 2√(k/m), times the step',
          ),
          row(o.verdict, 'Integrator says', 'What the chosen integrator does at this ω·dt'),
          row(o.state, 'State', 'Swinging, or exploded (a bead flew off)'),
          row(o.energy, 'Energy', 'Kinetic + gravitational + elastic, J'),
          row(o.pokes, 'Pokes', 'Pokes delivered so far (one is scripted at 1 s)'),
        ),
      ),
    );
    this.wire();
  }

  /** Bring the controls to the settings (the method radios too: call outside their own clicks). */
  show(settings: Readonly<PhysicsSettings>, radios: boolean): void {
    this.stiffness.set(settings.ropeStiffness);
    const input = this.methodInputs.get(settings.ropeMethod);
    if (radios && input) input.checked = true;
  }

  /** Forget the last poke's arrow (a fresh run). */
  forgetPoke(): void {
    this.lastPoke = undefined;
  }

  render(alpha: number): void {
    const host = this.host;
    const rope = host.run().rope;
    const s = host.settings();
    const o = this.out;
    const rOmegaDt = ropeOmegaDt(s.ropeStiffness, s.stepMs);
    o.omegaDt.set(rOmegaDt.toFixed(2), rOmegaDt);
    const verdict = stabilityOf(rope.config.integrator, rOmegaDt);
    o.verdict.set(verdictText(verdict), verdict);
    o.verdict.warn(verdict === 'unstable' || verdict === 'grows');
    const state = rope.exploded ? 'exploded' : 'swinging';
    o.state.set(state, state);
    o.state.warn(rope.exploded);
    const e = rope.energy();
    o.energy.set(rope.exploded ? '—' : `${e.toFixed(2)} J`, e);
    o.pokes.set(fmt.count(rope.pokes), rope.pokes);
    setHidden(this.note, !rope.exploded);
    setText(
      this.note,
      rope.exploded
        ? `Exploded after ${(rope.explodedAt * rope.config.dt).toFixed(2)} s: a bead flew ${rope.config.explodeBeyond} m off. Pick another integrator, or soften the links or shorten the step so ω·dt falls inside its limit.`
        : '',
    );
    drawRope(this.canvas, rope, alpha, host.timeMs(), this.selected, this.lastPoke, this.drag);
  }

  private methodPicker(selected: IntegratorMethod): HTMLElement {
    return h(
      'div',
      { class: 'segmented method-picker', role: 'radiogroup', 'aria-label': 'Rope integrator' },
      INTEGRATOR_METHODS.map((method) => {
        const input = h('input', {
          type: 'radio',
          name: 'rope-method',
          value: method,
          id: `rope-${method}`,
          checked: method === selected,
        });
        input.addEventListener('change', () => {
          if (input.checked) this.host.change({ ropeMethod: method });
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
  }

  private wire(): void {
    const c = this.canvas.canvas;
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
      if (m) this.poke(this.selected, m[0], m[1]);
      else if (event.key === ',' || event.key === '<') this.select(this.selected - 1);
      else if (event.key === '.' || event.key === '>') this.select(this.selected + 1);
      else return;
      event.preventDefault();
    });
  }

  private nearestBead(x: number, y: number): number {
    const xs = this.host.run().rope.x;
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
  }

  private poke(bead: number, dvx: number, dvy: number): void {
    const p = { bead, dvx, dvy };
    this.host.poke(p);
    this.lastPoke = { ...p, atMs: this.host.timeMs() };
  }
}
