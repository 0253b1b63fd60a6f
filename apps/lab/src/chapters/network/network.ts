/**
 * Chapter 6 — Network. Two players in one page, each on a machine of its own, over simulated links
 * with latency, jitter and loss, three times side by side — state sync (the server runs the game
 * and sends the world), lockstep and rollback (the relay orders the inputs) — same game, same
 * seed, same link, with a table comparing what each sends, how late each shows an input and what
 * each corrects; and online play through the server (network-online.ts: state sync and lockstep).
 * The numbers come from {@link NetworkLab}; the words from network-text.ts. Everything but the
 * online panels runs on the lab’s virtual clock, so the numbers repeat; the transport panel
 * (network-transports.ts) shows the loss harness’s recorded WebRTC-vs-WebSocket run.
 */
import {
  NET_GAMES,
  NET_MODES,
  NetworkLab,
  type MatchReadouts,
  type ModelNumbers,
  type NetGameId,
  type NetMode,
} from './network-lab.js';
import { OnlinePanel } from './network-online.js';
import { StateOnlinePanel } from './network-state-online.js';
import { TransportsPanel } from './network-transports.js';
import { LagPanel } from './network-lag.js';
import { MEASURED_MODELS_COMMAND, measuredModels } from './measured-models.js';
import {
  ABOUT,
  BENCH_INTRO,
  COMPARE_INTRO,
  GUARANTEE,
  LEDE,
  NEEDS,
  WHEN_TO_USE,
  correctionText,
  latencyText,
  verdictText,
} from './network-text.js';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import { clearScene } from '../../ui/canvas.js';
import { group, linkSliders, segmented, toggle } from '../../ui/controls.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { ScrollBox } from '../../ui/scroll-box.js';
import { keyMap } from '../../games-view/games.js';
import { ASPECT, drawGame } from '../../games-view/render.js';
import '../../games-view/game-stage.css';
import './network.css';

export const mount = mountChapter((root, head) => new NetworkChapter(root, head));

interface PanelView {
  canvases: [SceneCanvas, SceneCanvas];
  out: Record<string, Readout>;
  verdict: HTMLElement;
}

class NetworkChapter {
  readonly shell: ChapterShell;
  private readonly lab = new NetworkLab();
  private readonly panels = {} as Record<NetMode, PanelView>;
  private readonly compareOut = {} as Record<NetMode, Record<string, Readout>>;
  private keys = 0;

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      restart: () => {
        this.lab.restart();
      },
      mode: () =>
        `simulated network · ${this.shell.real ? `real clock, your display ≈ ${this.shell.measuredHz} Hz` : 'simulated 60 Hz displays'}`,
      realClock: {
        title:
          'Both machines draw on this page’s own animation frames instead of simulated 60 Hz displays (the links stay simulated)',
        onChange: (on) => {
          this.lab.setRealClock(on);
        },
      },
    });
    const shell = this.shell;
    const online = shell.own(new OnlinePanel());
    const stateOnline = shell.own(new StateOnlinePanel());
    const transports = shell.own(new TransportsPanel());
    const lag = shell.own(new LagPanel());
    shell.append(
      h(
        'p',
        { class: 'guarantee', 'data-testid': 'guarantee' },
        h('strong', {}, 'Two ways to agree: '),
        GUARANTEE,
      ),
      introSection(
        'bench',
        'net-bench-title',
        'Two players, one page, a bad network',
        BENCH_INTRO,
        this.controls(),
        h(
          'div',
          { class: 'duo net-duo' },
          NET_MODES.map((mode) => this.buildPanel(mode)),
        ),
        this.buildComparison(),
        transports.el,
      ),
      lag.el,
      stateOnline.el,
      online.el,
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
    shell.listen(window, 'keydown', onKey(true));
    shell.listen(window, 'keyup', onKey(false));
    this.applyAspect();
    shell.start();
  }

  private controls(): HTMLElement {
    const s = this.lab.settings;
    const link = linkSliders({
      idPrefix: 'net',
      link: s,
      onChange: (c) => {
        this.lab.setLink(c);
      },
    });
    const game = segmented<NetGameId>({
      name: 'net-game',
      label: 'Game',
      testPrefix: 'control-game',
      values: NET_GAMES,
      selected: s.game,
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
    return this.shell.controls(
      'Link, game and time',
      link.latency.el,
      link.jitter.el,
      link.loss.el,
      group('Game', game.el, keyboard),
      this.shell.timeGroup(this.shell.clockBtn!),
      this.shell.status(),
    );
  }

  private buildComparison(): HTMLElement {
    const head = [
      'Model',
      'Up, B/s',
      'Down, B/s',
      'Input → own screen',
      'Input → other screen',
      'Corrections seen',
    ];
    const rows = NET_MODES.map((mode) => {
      const cells: Record<string, Readout> = {};
      for (const id of ['up', 'down', 'own', 'other', 'corrections']) {
        cells[id] = new Readout('td', `compare-${mode}-${id}`);
      }
      this.compareOut[mode] = cells;
      return h(
        'tr',
        {},
        h('th', { scope: 'row' }, ABOUT[mode].title),
        ...['up', 'down', 'own', 'other', 'corrections'].map((id) => cells[id]!.el),
      );
    });
    return h(
      'section',
      { class: 'net-compare', 'aria-labelledby': 'net-compare-title' },
      h('h3', { id: 'net-compare-title' }, 'The three models, measured'),
      h('p', { class: 'section-intro' }, COMPARE_INTRO),
      this.scrollBox(
        h(
          'table',
          { class: 'data-table net-compare-table', 'data-testid': 'net-compare' },
          h(
            'thead',
            {},
            h(
              'tr',
              {},
              head.map((t) => h('th', { scope: 'col' }, t)),
            ),
          ),
          h('tbody', {}, rows),
        ),
        'The three models, measured in this page',
        'net-compare-box',
      ),
      this.buildMeasured(),
      h(
        'dl',
        { class: 'net-needs' },
        NET_MODES.flatMap((mode) => [
          h('dt', {}, `${ABOUT[mode].title} needs`),
          h('dd', { 'data-testid': `needs-${mode}` }, NEEDS[mode]),
        ]),
      ),
      h('h3', {}, 'When to use which'),
      h(
        'ul',
        { class: 'net-when', 'data-testid': 'when-to-use' },
        WHEN_TO_USE.map((w) => h('li', {}, h('strong', {}, `${ABOUT[w.mode].title}: `), w.text)),
      ),
    );
  }

  /** `table` in a {@link ScrollBox} owned by the chapter: on a phone it scrolls, and says so. */
  private scrollBox(table: HTMLElement, label: string, testId: string): HTMLElement {
    return this.shell.own(new ScrollBox(table, label, testId)).el;
  }

  /**
   * The same models over real transports — WebRTC through TURN and the kernel's TCP, on the loss
   * harness's link — as the benchmark measured them (a page cannot make those links): recorded
   * numbers, labelled as such.
   */
  private buildMeasured(): HTMLElement {
    const m = measuredModels();
    const ms = (x: number) => (Number.isFinite(x) ? fmt.millis(x) : '—');
    return h(
      'div',
      { class: 'net-measured', 'data-testid': 'net-measured' },
      h(
        'p',
        { class: 'section-intro' },
        `Measured by the benchmark, not in this page: player 2 on a real link of ${m.results[0]?.link.latencyMs ?? '?'} ± ${m.results[0]?.link.jitterMs ?? '?'} ms each way with ${100 * (m.results[0]?.link.loss ?? 0)} % loss (the loss harness), player 1 on the machine running the room, ${m.seconds} s of each model (${MEASURED_MODELS_COMMAND}, ${m.date.slice(0, 10)}). Bytes are player 2's messages; “wire” is what crossed its link, headers and acknowledgements included.`,
      ),
      this.scrollBox(
        h(
          'table',
          { class: 'data-table net-compare-table' },
          h(
            'thead',
            {},
            h(
              'tr',
              {},
              [
                'Transport, model',
                'Up / down, B/s',
                'Wire up / down, B/s',
                'Input → own screen',
                'Input → other screen',
                'Render delay',
                'Corrections seen',
              ].map((t) => h('th', { scope: 'col' }, t)),
            ),
          ),
          h(
            'tbody',
            {},
            m.results.flatMap((r) =>
              r.rows.map((row) =>
                h(
                  'tr',
                  {},
                  h('th', { scope: 'row' }, `${r.transport}: ${ABOUT[row.model].title}`),
                  h(
                    'td',
                    {},
                    `${fmt.count(Math.round(row.upBytesPerSecond))} / ${fmt.count(Math.round(row.downBytesPerSecond))}`,
                  ),
                  h(
                    'td',
                    {},
                    `${fmt.count(Math.round(row.wireUpBytesPerSecond))} / ${fmt.count(Math.round(row.wireDownBytesPerSecond))}`,
                  ),
                  h('td', {}, ms(row.ownLatencyMs)),
                  h('td', {}, ms(row.otherLatencyMs)),
                  h('td', {}, row.model === 'statesync' ? ms(row.renderDelayMs) : '—'),
                  h(
                    'td',
                    {},
                    `${fmt.count(row.corrections)} (up to ${row.largestCorrection.toFixed(1)} units)`,
                  ),
                ),
              ),
            ),
          ),
        ),
        'The three models over real transports, as the benchmark measured them',
        'net-measured-box',
      ),
    );
  }

  private buildPanel(mode: NetMode): HTMLElement {
    const canvases = [0, 1].map((i) =>
      this.shell.canvas({
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
      mode === 'statesync'
        ? [
            row('Render delay', 'render-delay'),
            row('Prediction lead, ticks', 'lead'),
            row('Snapshots received', 'snapshots'),
          ]
        : mode === 'lockstep'
          ? [row('Input delay, ticks', 'input-delay')]
          : [row('Rollbacks', 'rollbacks'), row('Deepest rollback, ticks', 'max-depth')];
    const hashLabel = mode === 'statesync' ? 'server world hash' : 'hash';
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
        ...row(`Player 1 ${hashLabel}`, 'hash-1', true),
        ...row(`Player 2 ${hashLabel}`, 'hash-2', true),
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

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const all = this.lab.readouts();
    for (const mode of NET_MODES) this.renderPanel(mode, all[mode]);
    for (const n of this.lab.compare()) this.renderCompare(n);
  }

  private renderCompare(n: ModelNumbers): void {
    const o = this.compareOut[n.mode];
    o.up?.set(fmt.count(Math.round(n.upBytesPerSecond)), n.upBytesPerSecond);
    o.down?.set(fmt.count(Math.round(n.downBytesPerSecond)), n.downBytesPerSecond);
    o.own?.set(latencyText(n.ownLatencyMs), Number.isFinite(n.ownLatencyMs) ? n.ownLatencyMs : '');
    o.other?.set(
      latencyText(n.otherLatencyMs),
      Number.isFinite(n.otherLatencyMs) ? n.otherLatencyMs : '',
    );
    o.corrections?.set(correctionText(n), n.corrections);
  }

  private renderPanel(mode: NetMode, r: MatchReadouts): void {
    const p = this.panels[mode];
    const match = this.lab.match(mode);
    for (const i of [0, 1] as const) {
      const c = p.canvases[i];
      if (!c.fit()) continue;
      const v = match.view(i);
      if (v) {
        drawGame(c, v.game, {
          alpha: v.alpha,
          nowMs: match.nowMs,
          badge: { text: `tick ${v.tick}`, tone: 'info' },
          you: v.slot,
        });
      } else clearScene(c);
    }
    const o = p.out;
    o['input-delay']?.set(fmt.count(r.inputDelay), r.inputDelay);
    o.rollbacks?.set(fmt.count(r.rollbacks), r.rollbacks);
    o['max-depth']?.set(fmt.count(r.maxDepth), r.maxDepth);
    o['render-delay']?.set(fmt.millis(r.renderDelayMs), r.renderDelayMs);
    o.lead?.set(fmt.count(r.lead), r.lead);
    o.snapshots?.set(fmt.count(r.snapshots), r.snapshots);
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
    setText(p.verdict, verdictText(mode, r));
    p.verdict.classList.toggle('bad', started && r.desyncs > 0);
  }
}
