/**
 * Chapter 4's "a hitch under a variable Δt" section: the talk's spring code under a variable Δt
 * and under a fixed step on one jittery 30 Hz display, x(t) drawn as a strip chart, and a button
 * that makes the display hitch. The model is {@link HitchLab} (physics-lab.ts).
 */
import { h } from '../../ui/dom.js';
import type { SceneCanvas, SceneCanvasAttrs } from '../../ui/canvas.js';
import { introSection } from '../../ui/prose.js';
import { button } from '../../ui/controls.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import {
  HITCH_DISPLAY,
  HITCH_MS,
  HITCH_OMEGA,
  HITCH_WINDOW_S,
  HitchLab,
  type HitchRun,
} from './physics-lab.js';

interface RunView {
  readonly kind: 'variable' | 'fixed';
  readonly scene: SceneCanvas;
  readonly energy: Readout;
  readonly maxDt: Readout;
  readonly omegaDt: Readout;
  readonly color: string;
}

const VIEW = {
  variable: {
    title: 'Variable Δt',
    sub: 'one update per display frame, Δt = the frame’s length',
    color: '#f87171',
  },
  fixed: {
    title: 'Fixed step',
    sub: 'the accumulator pays frames out in steps of 30 ms',
    color: '#38bdf8',
  },
} as const;

export class HitchSection {
  readonly el: HTMLElement;
  readonly lab = new HitchLab();
  private readonly views: RunView[];
  private readonly hitches: Readout;

  /** `canvas` makes a canvas destroyed with the chapter (the shell's). */
  constructor(onChange: () => void, canvas: (attrs: SceneCanvasAttrs) => SceneCanvas) {
    this.views = (['variable', 'fixed'] as const).map((kind) => {
      const scene = canvas({
        class: 'scene hitch-scene',
        label: `x(t) of the spring under the ${VIEW[kind].title.toLowerCase()}, last ${HITCH_WINDOW_S} s`,
        testId: `canvas-hitch-${kind}`,
      });
      return {
        kind,
        scene,
        energy: new Readout('dd', `hitch-${kind}-max-energy`),
        maxDt: new Readout('dd', `hitch-${kind}-max-dt`),
        omegaDt: new Readout('dd', `hitch-${kind}-omega-dt`),
        color: VIEW[kind].color,
      };
    });
    this.hitches = new Readout('span', 'hitch-count');
    const hitchBtn = button(`${HITCH_MS} ms hitch`, 'control-spring-hitch', () => {
      this.lab.addHitch();
      onChange();
    });
    hitchBtn.title = `The display shows no frame for ${HITCH_MS} ms, from now`;
    this.el = introSection(
      'hitch-section',
      'hitch-title',
      'A hitch under a variable Δt',
      `Everything above runs at a fixed step. Here is the talk’s own spring code — v += a·dt; x += v·dt — with a stiffer spring (k = ${HITCH_OMEGA * HITCH_OMEGA} N/m on 1 kg, ω = ${HITCH_OMEGA} rad/s) on a ${HITCH_DISPLAY.hz} Hz display with ±${HITCH_DISPLAY.jitter * 100} % jitter, twice: handed each frame’s Δt, and through the fixed step. Frames of up to 43 ms keep ω·dt under the method’s limit of 2 either way. Then make the display hitch: the variable loop takes one update of ω·dt ≈ 2.8, past the limit, and the spring’s energy jumps — by how much depends on where in its swing it is. The fixed step takes ordinary 30 ms steps and does not notice.`,
      h(
        'div',
        { class: 'controls hitch-controls' },
        h(
          'div',
          { class: 'control-group' },
          h('span', { class: 'control-label' }, 'Display'),
          hitchBtn,
          h('span', { class: 'status-item' }, 'hitches: ', this.hitches.el),
        ),
      ),
      h(
        'div',
        { class: 'panels hitch-panels' },
        this.views.map((v) =>
          h(
            'article',
            { class: 'panel', style: `--accent: ${v.color}`, 'data-panel': `hitch-${v.kind}` },
            h(
              'header',
              { class: 'panel-head' },
              h('h3', {}, VIEW[v.kind].title),
              h('p', {}, VIEW[v.kind].sub),
            ),
            h('div', { class: 'scene-wrap' }, v.scene.canvas),
            h(
              'dl',
              { class: 'readouts' },
              h('dt', { title: 'The largest E/E₀ so far' }, 'Largest E / E₀'),
              v.energy.el,
              h('dt', {}, 'Longest update'),
              v.maxDt.el,
              h(
                'dt',
                { title: 'ω × the longest update: above 2 the method is unstable' },
                'ω·Δt, longest',
              ),
              v.omegaDt.el,
            ),
          ),
        ),
      ),
    );
  }

  restart(): void {
    this.lab.restart();
  }

  /** Catch up with the chapter's clock and draw. */
  render(timeMs: number): void {
    this.lab.advanceTo(timeMs);
    this.hitches.set(String(this.lab.hitches.length), this.lab.hitches.length);
    for (const v of this.views) this.draw(v, this.lab.run(v.kind));
  }

  private draw(v: RunView, run: HitchRun): void {
    const s = run.rig.scene;
    const ratio = s.maxRatio;
    v.energy.set(ratio >= 1e4 ? `${fmt.sci(ratio)}×` : `${ratio.toFixed(2)}×`, ratio);
    v.energy.warn(ratio > 2);
    v.maxDt.set(fmt.millis(s.maxDt * 1000), s.maxDt * 1000);
    const od = s.omega * s.maxDt;
    v.omegaDt.set(od.toFixed(2), od);
    v.omegaDt.warn(od >= 2);

    if (!v.scene.fit()) return; // no size yet, or off screen
    const { ctx, dpr, w, h: hh } = v.scene;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#0a1122';
    ctx.fillRect(0, 0, w, hh);
    const { t, x } = run.trace;
    const now = s.time;
    const t0 = Math.max(0, now - HITCH_WINDOW_S);
    // Zoom out to whatever x reached in the window, so a blown-up swing stays in view.
    let reach = 1;
    for (let i = 0; i < t.length; i++) {
      if (t[i]! >= t0 && Math.abs(x[i]!) > reach) reach = Math.abs(x[i]!);
    }
    const mid = hh / 2;
    const sy = (hh / 2 - 10 * dpr) / reach;
    const sx = w / HITCH_WINDOW_S;
    ctx.strokeStyle = 'rgba(141, 160, 189, 0.25)';
    ctx.lineWidth = dpr;
    ctx.beginPath();
    ctx.moveTo(0, mid);
    ctx.lineTo(w, mid);
    ctx.stroke();
    // The hitches in the window.
    ctx.fillStyle = 'rgba(253, 224, 71, 0.18)';
    for (const at of this.lab.hitches) {
      const a = (at / 1000 - t0) * sx;
      if (a > w || a + (HITCH_MS / 1000) * sx < 0) continue;
      ctx.fillRect(a, 0, (HITCH_MS / 1000) * sx, hh);
    }
    ctx.strokeStyle = v.color;
    ctx.lineWidth = 1.6 * dpr;
    ctx.beginPath();
    let started = false;
    for (let i = 0; i < t.length; i++) {
      if (t[i]! < t0) continue;
      const px = (t[i]! - t0) * sx;
      const py = mid - x[i]! * sy;
      if (started) ctx.lineTo(px, py);
      else ctx.moveTo(px, py);
      started = true;
    }
    ctx.stroke();
    ctx.fillStyle = 'rgba(226, 232, 240, 0.75)';
    ctx.font = `${11 * dpr}px system-ui, sans-serif`;
    ctx.fillText(
      reach > 1.05 ? `x(t), zoomed out ×${reach.toFixed(reach < 10 ? 1 : 0)}` : 'x(t)',
      6 * dpr,
      14 * dpr,
    );
  }
}
