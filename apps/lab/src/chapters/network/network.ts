/**
 * Chapter 6 — Network. Two players in one page, each on a machine of its own, talking to the real
 * relay core through simulated links with latency, jitter and loss: lockstep and rollback side by
 * side, same game, same seed, same link. The numbers come from {@link NetworkLab}; this module
 * builds the page and draws. Everything runs on the lab's virtual clock, so the numbers repeat.
 */
import { SceneCanvas } from '../../ui/canvas.js';
import { TimeControls, group, segmented, slider, toggle } from '../../ui/controls.js';
import { h, setAttr } from '../../ui/dom.js';
import { LabDriver } from '../../shell/driver.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { keyMap } from '../../games-view/games.js';
import { ASPECT, drawGame } from '../../games-view/render.js';
import {
  NET_GAMES,
  NET_MODES,
  NetworkLab,
  type MatchReadouts,
  type NetGameId,
  type NetMode,
} from './network-lab.js';
import { OnlinePanel } from './network-online.js';
import '../../games-view/game-stage.css';
import './network.css';

const SKIP_MS = 5000;

export function mount(root: HTMLElement): () => void {
  const chapter = new NetworkChapter(root);
  return () => {
    chapter.destroy();
  };
}

const ABOUT: Readonly<Record<NetMode, { title: string; text: string }>> = {
  lockstep: {
    title: 'Lockstep',
    text: 'A machine steps tick t only once the relay has every player’s input for it. Nothing is guessed, nothing is undone; the price is an input delay of about one round trip.',
  },
  rollback: {
    title: 'Rollback',
    text: 'A machine runs ahead, guessing that the other player keeps holding the same buttons. When the real input differs it loads the saved state of that tick and steps again to now.',
  },
};

interface PanelView {
  canvases: [SceneCanvas, SceneCanvas];
  out: Record<string, Readout>;
  verdict: HTMLElement;
}

class NetworkChapter {
  private readonly lab = new NetworkLab();
  private readonly driver: LabDriver;
  private readonly time: TimeControls;
  private readonly panels = {} as Record<NetMode, PanelView>;
  private readonly cleanups: (() => void)[] = [];
  private readonly online: OnlinePanel;

  constructor(root: HTMLElement) {
    this.driver = new LabDriver({
      advance: (ms) => {
        this.lab.advanceBy(ms);
      },
      realFrame: (t) => {
        this.lab.realFrame(t);
      },
      render: () => {
        this.render();
      },
    });

    const latency = slider({
      id: 'net-latency',
      label: 'Latency',
      testId: 'control-latency',
      min: 0,
      max: 250,
      step: 5,
      value: this.lab.settings.latencyMs,
      text: (v) => `${v} ms`,
      onChange: (v) => {
        this.lab.setLink({ latencyMs: v });
      },
    });
    const jitter = slider({
      id: 'net-jitter',
      label: 'Jitter',
      testId: 'control-jitter',
      min: 0,
      max: 100,
      step: 5,
      value: this.lab.settings.jitterMs,
      text: (v) => `± ${v} ms`,
      onChange: (v) => {
        this.lab.setLink({ jitterMs: v });
      },
    });
    const loss = slider({
      id: 'net-loss',
      label: 'Loss',
      testId: 'control-loss',
      min: 0,
      max: 20,
      step: 1,
      value: Math.round(this.lab.settings.loss * 100),
      text: (v) => `${v} %`,
      onChange: (v) => {
        this.lab.setLink({ loss: v / 100 });
      },
    });
    const game = segmented<NetGameId>({
      name: 'net-game',
      label: 'Game',
      testPrefix: 'control-game',
      values: NET_GAMES,
      selected: this.lab.settings.game,
      text: (g) => (g === 'ctf' ? 'Capture the flag' : 'Survival'),
      onChange: (g) => {
        this.lab.reset({ game: g });
        this.applyAspect();
      },
    });
    const keyboard = toggle('Play player 1', 'control-keyboard', false, (on) => {
      this.lab.reset({ keyboard: on });
    });
    keyboard.title = 'Drive player 1 with the keyboard (WASD or arrows, Space to shoot)';
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.lab.setRealClock(on);
      this.driver.setReal(on);
    });
    this.clockBtn.title =
      'Both machines draw on this page’s own animation frames instead of simulated 60 Hz displays (the links stay simulated)';
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
        if (this.lab.realClock) this.driver.restartReal();
      },
    });
    const controls = h(
      'div',
      { class: 'controls', role: 'group', 'aria-label': 'Link, game and time' },
      latency.el,
      jitter.el,
      loss.el,
      group('Game', game.el, keyboard),
      group('Time', ...this.time.buttons, this.clockBtn),
      h('div', { class: 'status', 'aria-live': 'off' }, ...this.time.status),
    );
    controls.addEventListener('click', () => {
      this.render();
    });

    const duo = h('div', { class: 'duo net-duo' });
    for (const mode of NET_MODES) duo.append(this.buildPanel(mode));

    this.online = new OnlinePanel();

    root.append(
      h(
        'article',
        { class: 'chapter network-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 6'),
          h('h1', {}, 'Network'),
          h(
            'p',
            { class: 'lede' },
            'When every machine steps the same world the same way, players only need to agree on the inputs and the clock — never send the state itself.',
          ),
        ),
        h(
          'p',
          { class: 'guarantee', 'data-testid': 'guarantee' },
          h('strong', {}, 'Inputs, never state: '),
          'each machine sends the relay its player’s buttons for upcoming ticks; the relay puts every player’s input for a tick in one order and sends that order to everyone. Each machine then computes the whole world itself, step by step, and because a fixed step is deterministic every machine computes the same world. To prove it they send a hash of their state now and then — 8 bytes — and the relay compares them.',
        ),
        h(
          'section',
          { class: 'bench', 'aria-labelledby': 'net-bench-title' },
          h('h2', { id: 'net-bench-title' }, 'Two players, one page, a bad network'),
          h(
            'p',
            { class: 'section-intro' },
            'Two bots play the same game over the same simulated network, once with lockstep sessions and once with rollback sessions. Each panel shows both players’ machines. Move the sliders and watch input delay, rollbacks and stalls change — and the hashes stay equal.',
          ),
          controls,
          duo,
        ),
        this.online.el,
      ),
    );

    const onKey = (down: boolean) => (e: KeyboardEvent) => {
      if (!this.lab.settings.keyboard) return;
      const target = e.target as HTMLElement | null;
      if (target && /^(INPUT|TEXTAREA|SELECT)$/.test(target.tagName)) return;
      const b = keyMap(this.lab.matches.lockstep.def.info)[e.code];
      if (b === undefined) return;
      e.preventDefault();
      this.keys = down ? this.keys | (1 << b) : this.keys & ~(1 << b);
      this.lab.setKeys(this.keys);
    };
    const kd = onKey(true);
    const ku = onKey(false);
    window.addEventListener('keydown', kd);
    window.addEventListener('keyup', ku);
    this.cleanups.push(() => {
      window.removeEventListener('keydown', kd);
      window.removeEventListener('keyup', ku);
    });

    this.applyAspect();
    this.driver.start();
  }

  private keys = 0;
  private readonly clockBtn: HTMLButtonElement;

  private buildPanel(mode: NetMode): HTMLElement {
    const canvases: [SceneCanvas, SceneCanvas] = [0, 1].map(
      (i) =>
        new SceneCanvas({
          class: 'scene net-scene',
          label: `${ABOUT[mode].title}: player ${i + 1}’s machine`,
          testId: `canvas-${mode}-${i + 1}`,
        }),
    ) as [SceneCanvas, SceneCanvas];
    const out: Record<string, Readout> = {};
    const row = (label: string, id: string, hash = false) => {
      const r = new Readout('dd', `${mode}-${id}`, { hash });
      out[id] = r;
      return [h('dt', {}, label), r.el];
    };
    const specific =
      mode === 'lockstep'
        ? [row('Input delay, ticks', 'input-delay')]
        : [row('Rollbacks', 'rollbacks'), row('Deepest rollback, ticks', 'max-depth')];
    const verdict = h('p', { class: 'net-verdict', 'data-testid': `verdict-${mode}` });
    this.panels[mode] = { canvases, out, verdict };
    return h(
      'div',
      { class: `panel net-panel net-${mode}` },
      h(
        'div',
        { class: 'panel-head' },
        h('h3', {}, ABOUT[mode].title),
        h('p', {}, ABOUT[mode].text),
      ),
      h(
        'div',
        { class: 'net-machines' },
        canvases.map((c, i) =>
          h('figure', { class: 'net-machine' }, c.canvas, h('figcaption', {}, `Player ${i + 1}`)),
        ),
      ),
      verdict,
      h(
        'dl',
        { class: 'readouts' },
        ...specific.flat(),
        ...row('Stalls', 'stalls'),
        ...row('Round trip', 'rtt'),
        ...row('Messages lost', 'lost'),
        ...row('Checkpoint tick', 'checkpoint'),
        ...row('Player 1 hash', 'hash-1', true),
        ...row('Player 2 hash', 'hash-2', true),
        ...row('Hashes equal', 'hashes-equal'),
      ),
    );
  }

  private applyAspect(): void {
    const a = ASPECT[this.lab.settings.game] ?? 1.5;
    for (const mode of NET_MODES) {
      for (const c of this.panels[mode].canvases) c.canvas.style.setProperty('--aspect', String(a));
    }
  }

  private render(): void {
    const real = this.lab.realClock;
    this.time.refresh(this.driver.isPaused, !real);
    this.time.show(
      this.lab.timeMs,
      `simulated network · ${real ? `real clock, your display ≈ ${this.driver.measuredHz} Hz` : 'simulated 60 Hz displays'}${this.driver.isPaused ? ' · paused' : ''}`,
    );
    const all = this.lab.readouts();
    for (const mode of NET_MODES) this.renderPanel(mode, all[mode]);
  }

  private renderPanel(mode: NetMode, r: MatchReadouts): void {
    const p = this.panels[mode];
    const match = this.lab.matches[mode];
    for (const i of [0, 1] as const) {
      const c = p.canvases[i];
      if (!c.fit()) continue;
      const g = match.game(i);
      if (g) {
        drawGame(c, g, {
          alpha: match.sessions[i].alpha,
          nowMs: match.nowMs,
          badge: { text: `tick ${r.ticks[i]}`, tone: 'info' },
        });
      } else {
        c.ctx.setTransform(1, 0, 0, 1, 0, 0);
        c.ctx.fillStyle = '#0a1122';
        c.ctx.fillRect(0, 0, c.w, c.h);
      }
    }
    const o = p.out;
    o['input-delay']?.set(fmt.count(r.inputDelay), r.inputDelay);
    o.rollbacks?.set(fmt.count(r.rollbacks), r.rollbacks);
    o['max-depth']?.set(fmt.count(r.maxDepth), r.maxDepth);
    o.stalls?.set(fmt.count(r.stalls), r.stalls);
    o.rtt?.set(fmt.millis(r.rttMs), r.rttMs);
    o.lost?.set(`${fmt.count(r.lost)} of ${fmt.count(r.sent)}`, r.lost);
    o.checkpoint?.set(r.checkpoint < 0 ? '—' : fmt.count(r.checkpoint), r.checkpoint);
    o['hash-1']?.set(r.hashes[0] || '—', r.hashes[0]);
    o['hash-2']?.set(r.hashes[1] || '—', r.hashes[1]);
    const started = r.checkpoint >= 0;
    o['hashes-equal']?.set(started ? (r.equal ? 'yes' : 'NO') : '—', started ? r.equal : '');
    o['hashes-equal']?.good(started && r.equal);
    o['hashes-equal']?.warn(started && !r.equal);
    setAttr(p.verdict, 'data-value', String(started && r.equal));
    p.verdict.textContent = !started
      ? 'Connecting and syncing clocks…'
      : r.equal
        ? `Both machines computed the same world at tick ${r.checkpoint}.`
        : r.desyncs > 0
          ? 'The relay saw the machines disagree: a desync.'
          : 'Waiting for both machines to reach the checkpoint…';
    p.verdict.classList.toggle('bad', started && r.desyncs > 0);
  }

  destroy(): void {
    this.driver.destroy();
    this.online.destroy();
    for (const c of this.cleanups) c();
    for (const mode of NET_MODES) for (const c of this.panels[mode].canvases) c.destroy();
  }
}
