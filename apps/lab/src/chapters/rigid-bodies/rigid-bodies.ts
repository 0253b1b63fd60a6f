/**
 * Chapter 10 — Rigid bodies. What the own world cannot: a tower of rotating boxes (Rapier's
 * deterministic build, through `@fixedstep/rapier`) knocked over by a ball you fire, replayed by
 * re-simulation with every tick's hash equal to the live run's, and rolled back over a simulated
 * network with the two machines' hashes equal; then the same scene in the own world beside
 * Rapier's, and what Rapier costs. The numbers come from {@link RigidLab}; the words from
 * rigid-bodies-text.ts.
 *
 * The model (and with it Rapier's WebAssembly, ~2 MB of JavaScript) is a dynamic `import()`: the
 * page is built at once and says it is loading; the simulations start when Rapier is ready. No
 * other chapter's bundle carries Rapier.
 */
import { attachButtons, attachKeyboard } from 'fixedstep';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import { clearScene, type SceneCanvas } from '../../ui/canvas.js';
import { tryCards } from '../../ui/cards.js';
import {
  button,
  group,
  linkSliders,
  segmented,
  toggle,
  type LinkSliders,
  type Segmented,
} from '../../ui/controls.js';
import { h, setAttr, setText } from '../../ui/dom.js';
import { introSection } from '../../ui/prose.js';
import * as fmt from '../../ui/format.js';
import { Readout } from '../../ui/readout.js';
import { aspectOf, drawWorld } from './rigid-bodies-draw.js';
import type { RigidLab, WorldsScene } from './rigid-bodies-lab.js';
import {
  CANNOT,
  KNOCK_INTRO,
  LEDE,
  LIVE_HEAD,
  NET_INTRO,
  REPLAY_HEAD,
  WORLDS_INTRO,
  WORLDS_TITLES,
  costText,
  howItWorks,
  knockNote,
  netVerdict,
  replayVerdict,
  worldNote,
} from './rigid-bodies-text.js';
import './rigid-bodies.css';

export const mount = mountChapter((root, head) => new RigidBodiesChapter(root, head));

type LabModule = typeof import('./rigid-bodies-lab.js');

/** A panel's canvas, the line under it and its readouts. */
interface PanelView {
  canvas: SceneCanvas;
  note: HTMLElement;
  out: Record<string, Readout>;
}

const SCENES: readonly WorldsScene[] = ['knock', 'lean'];

class RigidBodiesChapter {
  readonly shell: ChapterShell;
  private lab: RigidLab | undefined;
  private mod: LabModule | undefined;
  private destroyed = false;
  private unwire: (() => void)[] = [];
  private readonly state = new Readout('span', 'rapier-state');
  private readonly fireBtn = button('Fire', 'control-fire', () => undefined);
  private readonly replayBtn: HTMLButtonElement;
  private readonly netFire: [HTMLButtonElement, HTMLButtonElement];
  private readonly live: PanelView;
  private readonly replay: PanelView;
  private readonly replayVerdict = h('p', { class: 'verdict', 'data-testid': 'replay-verdict' });
  private readonly machines: [PanelView, PanelView];
  private readonly net: Record<string, Readout> = {};
  private readonly netVerdict = h('p', { class: 'verdict', 'data-testid': 'net-verdict' });
  private readonly worlds: [PanelView, PanelView];
  private readonly worldsIntro = h('p', { class: 'section-intro' });
  private readonly cost = h('p', { class: 'rigid-cost', 'data-testid': 'cost' });
  private linkSliders: LinkSliders | undefined;
  private readonly botsBtn: HTMLButtonElement;
  private readonly sceneSeg: Segmented<WorldsScene>;
  private shownScene: WorldsScene | undefined;

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      restart: () => {
        this.lab?.restart();
        this.wire();
      },
      mode: () =>
        this.lab === undefined
          ? 'loading Rapier…'
          : this.shell.display('simulated display · 60 Hz'),
      realClock: {
        title:
          'Everything on this page steps on your display’s own animation frames (the network’s links stay simulated)',
        onChange: (on) => {
          this.lab?.setRealClock(on);
        },
      },
      interpolation: {
        title:
          'Draw every body between its last two ticks, positions and angles, at the loop’s alpha',
      },
    });
    const shell = this.shell;
    this.fireBtn.classList.add('btn-fire');
    this.onKeyboardClick(this.fireBtn, (t, down) => this.lab?.fire(t, down));
    this.fireBtn.title = 'Launch the ball at the tower (or press F, or tap the tower)';
    this.replayBtn = button('▶ Replay', 'control-replay', () => {
      this.lab?.startReplay();
    });
    this.replayBtn.title = 'Play the recording so far from its first tick, by re-simulation';
    this.netFire = [0, 1].map((i) => {
      const b = button(`Fire player ${i + 1}`, `control-net-fire-${i + 1}`, () => undefined);
      b.classList.add('btn-fire');
      this.onKeyboardClick(b, (t, down) => this.lab?.net.press(i === 0 ? 0 : 1, t, down));
      return b;
    }) as [HTMLButtonElement, HTMLButtonElement];
    this.botsBtn = toggle('Bots fire', 'control-bots', true, (on) => {
      this.lab?.setBots(on);
    });
    this.botsBtn.title = 'Player 1 fires at 1 s, 5 s, 9 s …, player 2 at 3 s, 7 s, 11 s …';

    this.live = this.panel('live', 'The live tower: tap it to fire');
    this.replay = this.panel('replay', 'The replay of the live tower');
    this.machines = [0, 1].map((i) =>
      this.panel(`net-${i + 1}`, `The tower on the machine of player ${i + 1}`),
    ) as [PanelView, PanelView];
    this.worlds = [
      this.panel('worlds-rapier', 'The scene in Rapier'),
      this.panel('worlds-own', 'The scene in fixedstep’s own world'),
    ];
    this.sceneSeg = segmented<WorldsScene>({
      name: 'rigid-worlds-scene',
      label: 'Scene',
      testPrefix: 'control-scene',
      values: SCENES,
      selected: 'knock',
      text: (s) => WORLDS_TITLES[s],
      onChange: (s) => {
        this.lab?.setWorldsScene(s);
      },
    });

    const controls = shell.controls(
      'Time and drawing',
      shell.drawGroup(),
      shell.timeGroup(),
      shell.status(h('span', { class: 'status-item' }, 'Rapier: ', this.state.el)),
    );
    this.state.set('loading…', 'loading');
    shell.append(
      controls,
      this.knockSection(),
      this.netSection(),
      this.worldsSection(),
      tryCards('rigid-try-title', [
        {
          title: 'Knock it over, replay it',
          text: 'From the start: fire at once, let 3 s run, then replay the recording. Every tick of the replay has the live run’s hash.',
          action: 'Fire and replay',
          testId: 'try-replay',
          run: () => {
            const lab = this.lab;
            if (!lab) return;
            if (this.shell.real) this.shell.setReal(false);
            lab.restart();
            this.wire();
            lab.fire(0, true);
            lab.fire(50, false);
            lab.advanceBy(3000);
            lab.startReplay();
            this.shell.setPaused(false);
          },
        },
        {
          title: 'A terrible network',
          text: '250 ms each way, ± 100 ms of jitter, 20 % of messages lost: rollbacks get deeper, the hashes stay equal.',
          action: 'Make it terrible',
          testId: 'try-network',
          run: () => {
            this.setLink({ latencyMs: 250, jitterMs: 100, loss: 0.2 });
          },
        },
        {
          title: 'The leaning tower',
          text: 'A tower whose centre of mass is 2 m past its base: Rapier’s topples, the own world’s stays up.',
          action: 'Lean it',
          testId: 'try-lean',
          run: () => {
            this.sceneSeg.select('lean');
            this.lab?.setWorldsScene('lean');
          },
        },
      ]),
      howItWorks(),
    );
    shell.own({
      destroy: () => {
        this.destroyed = true;
        this.unwireAll();
        this.lab?.dispose();
      },
    });
    shell.start();
    void this.load();
  }

  /**
   * A Fire button clicked from the keyboard (Enter or Space: a click with no pointer) presses and
   * lets go of FIRE at once, through the same sampler as a pointer (`press`).
   */
  private onKeyboardClick(b: HTMLButtonElement, press: (timeMs: number, down: boolean) => void) {
    b.addEventListener('click', (e) => {
      if (e.detail !== 0) return; // a pointer's click: attachButtons had its down and up
      const t = this.eventTime(e.timeStamp);
      press(t, true);
      press(t, false);
    });
  }

  /** Loads the model and Rapier's WebAssembly, then starts the simulations. */
  private async load(): Promise<void> {
    try {
      const mod = await import('./rigid-bodies-lab.js');
      const lab = await mod.openRigidLab();
      if (this.destroyed) {
        lab.dispose();
        return;
      }
      this.mod = mod;
      this.lab = lab;
      if (this.shell.real) lab.setRealClock(true);
      this.setAspect(this.live, mod.TOWER_BOUNDS);
      this.setAspect(this.replay, mod.TOWER_BOUNDS);
      for (const m of this.machines) this.setAspect(m, mod.DUEL_BOUNDS);
      this.wire();
      this.state.set('ready', 'ready');
      this.shell.redraw();
    } catch (e) {
      this.state.set(`failed: ${e instanceof Error ? e.message : String(e)}`, 'failed');
      this.state.warn(true);
    }
  }

  private setAspect(p: PanelView, bounds: readonly [number, number, number, number]): void {
    p.canvas.canvas.style.setProperty('--aspect', aspectOf(bounds).toFixed(3));
  }

  /**
   * The time of an input event stamped `timeStamp` on the lab's time line: on the real clock its
   * place on the real time line; on the simulated display the lab's time plus the real time since
   * the last frame (0 while paused, so a press during a pause lands on the next tick).
   */
  private eventTime(timeStamp: number): number {
    const lab = this.lab;
    if (!lab) return 0;
    const driver = this.shell.driver;
    const ago = Math.max(0, performance.now() - timeStamp);
    if (driver.isReal) {
      const r = driver.realNow();
      return r === undefined ? lab.timeMs : lab.timeOfReal(r - ago);
    }
    return lab.timeMs + Math.max(0, driver.sinceLastFrame() - ago);
  }

  /** Wire the Fire buttons, the tower canvas and the F key to the current model's samplers. */
  private wire(): void {
    this.unwireAll();
    const lab = this.lab;
    const mod = this.mod;
    if (!lab || !mod) return;
    const timeOf = (e: { readonly timeStamp: number }) => this.eventTime(e.timeStamp);
    const fire = mod.FIRE;
    this.unwire.push(
      attachButtons(
        lab.knock.sampler,
        [
          { element: this.fireBtn, button: fire },
          { element: this.live.canvas.canvas, button: fire },
        ],
        timeOf,
      ),
      attachKeyboard(window, lab.knock.sampler, { KeyF: fire }, timeOf),
      attachButtons(lab.net.samplers[0], [{ element: this.netFire[0], button: fire }], timeOf),
      attachButtons(lab.net.samplers[1], [{ element: this.netFire[1], button: fire }], timeOf),
    );
  }

  private unwireAll(): void {
    for (const u of this.unwire) u();
    this.unwire = [];
  }

  private setLink(c: { latencyMs?: number; jitterMs?: number; loss?: number }): void {
    this.lab?.setLink(c);
    const s = this.lab?.linkSettings;
    if (!s) return;
    this.linkSliders?.set(s);
  }

  /** A panel's canvas (labelled `label`), the line under it, and room for its readouts. */
  private panel(id: string, label: string): PanelView {
    const canvas = this.shell.canvas({
      class: 'scene rigid-scene',
      label,
      testId: `canvas-${id}`,
    });
    const note = h('p', { class: 'scene-notes rigid-note', 'data-testid': `note-${id}` });
    return { canvas, note, out: {} };
  }

  /** A readout row of `p`: its label and cell (`readout-${prefix}-${id}`). */
  private row(p: PanelView, prefix: string, id: string, label: string, hash = false): Node[] {
    const r = new Readout('dd', `${prefix}-${id}`, { hash });
    p.out[id] = r;
    return [h('dt', {}, label), r.el];
  }

  private panelEl(
    p: PanelView,
    cls: string,
    title: string,
    text: string,
    extra: (Node | null)[],
    rows: Node[],
  ): HTMLElement {
    return h(
      'div',
      { class: `panel ${cls}` },
      h('div', { class: 'panel-head' }, h('h3', {}, title), h('p', {}, text)),
      h('div', { class: 'scene-wrap' }, p.canvas.canvas),
      p.note,
      extra.length > 0 ? h('div', { class: 'rigid-actions' }, ...extra) : null,
      h('dl', { class: 'readouts' }, ...rows),
    );
  }

  private knockSection(): HTMLElement {
    const live = this.live;
    const rp = this.replay;
    return introSection(
      'bench',
      'rigid-knock-title',
      'Knock it over, then replay it',
      KNOCK_INTRO,
      h(
        'div',
        { class: 'duo' },
        this.panelEl(
          live,
          'rigid-live',
          'Live',
          LIVE_HEAD,
          [this.fireBtn],
          [
            ...this.row(live, 'knock', 'tick', 'Tick'),
            ...this.row(live, 'knock', 'shots', 'Shots'),
            ...this.row(live, 'knock', 'turned', 'Boxes turned past 10°'),
            ...this.row(live, 'knock', 'top', 'Top of the tower'),
            ...this.row(live, 'knock', 'hash', 'Hash', true),
            ...this.row(live, 'knock', 'replay-bytes', 'Recording'),
          ],
        ),
        h(
          'div',
          { class: 'panel rigid-replay' },
          h('div', { class: 'panel-head' }, h('h3', {}, 'Replay'), h('p', {}, REPLAY_HEAD)),
          h('div', { class: 'scene-wrap' }, rp.canvas.canvas),
          rp.note,
          h('div', { class: 'rigid-actions' }, this.replayBtn),
          h(
            'dl',
            { class: 'readouts' },
            ...this.row(rp, 'replay', 'tick', 'Tick'),
            ...this.row(rp, 'replay', 'hash', 'Replay’s hash', true),
            ...this.row(rp, 'replay', 'live-hash', 'Live run’s hash, same tick', true),
            ...this.row(rp, 'replay', 'compared', 'Ticks compared'),
            ...this.row(rp, 'replay', 'different', 'Ticks that differ'),
            ...this.row(rp, 'replay', 'checkpoints', 'File’s hashes reproduced'),
            ...this.row(rp, 'replay', 'bytes', 'File'),
          ),
          this.replayVerdict,
        ),
      ),
    );
  }

  private netSection(): HTMLElement {
    const s = this.lab?.linkSettings ?? { latencyMs: 80, jitterMs: 20, loss: 0.02 };
    this.linkSliders = linkSliders({
      idPrefix: 'rigid',
      link: s,
      onChange: (c) => {
        this.lab?.setLink(c);
      },
    });
    const { latency, jitter, loss } = this.linkSliders;
    const controls = this.shell.controls(
      'The link',
      latency.el,
      jitter.el,
      loss.el,
      group('Players', this.botsBtn),
    );
    const machine = (i: 0 | 1): HTMLElement => {
      const p = this.machines[i];
      const pre = `net-${i + 1}`;
      return this.panelEl(
        p,
        `rigid-machine rigid-machine-${i + 1}`,
        `Machine of player ${i + 1}`,
        i === 0 ? 'Fires the blue ball, from the left.' : 'Fires the violet ball, from the right.',
        [this.netFire[i]],
        [
          ...this.row(p, pre, 'tick', 'Tick'),
          ...this.row(p, pre, 'shots', 'Shots (player 1, 2)'),
          ...this.row(p, pre, 'rollbacks', 'Rollbacks'),
          ...this.row(p, pre, 'max-depth', 'Deepest rollback'),
          ...this.row(p, pre, 'resimulated', 'Ticks re-simulated'),
          ...this.row(p, pre, 'rtt', 'Round trip'),
        ],
      );
    };
    const r = (id: string, label: string, hash = false) => {
      const out = new Readout('dd', `net-${id}`, { hash });
      this.net[id] = out;
      return [h('dt', {}, label), out.el];
    };
    return introSection(
      'bench',
      'rigid-net-title',
      'Rolled back over a bad network',
      NET_INTRO,
      controls,
      h('div', { class: 'duo' }, machine(0), machine(1)),
      h(
        'div',
        { class: 'panel rigid-net-sum' },
        h(
          'dl',
          { class: 'readouts' },
          ...r('checkpoint', 'Confirmed checkpoint tick'),
          ...r('hash-1', 'Player 1’s machine, hash there', true),
          ...r('hash-2', 'Player 2’s machine, hash there', true),
          ...r('equal', 'Hashes equal'),
          ...r('lost', 'Messages lost'),
        ),
        this.netVerdict,
      ),
    );
  }

  private worldsSection(): HTMLElement {
    const again = button('Run again', 'control-worlds-again', () => {
      const lab = this.lab;
      lab?.setWorldsScene(lab.worldsSceneName);
    });
    const side = (i: 0 | 1): HTMLElement => {
      const p = this.worlds[i];
      const pre = i === 0 ? 'worlds-rapier' : 'worlds-own';
      return this.panelEl(
        p,
        i === 0 ? 'rigid-world-rapier' : 'rigid-world-own',
        i === 0 ? 'Rapier' : 'fixedstep’s own world',
        i === 0
          ? 'Bodies with an angle: contacts at corners push them round.'
          : 'Axis-aligned boxes: every contact pushes straight, nothing turns.',
        [],
        [
          ...this.row(p, pre, 'turned', 'Boxes turned past 10°'),
          ...this.row(p, pre, 'top', 'Top of the tower'),
          ...this.row(p, pre, 'bytes', 'Snapshot now'),
          ...this.row(p, pre, 'bytes-per-body', 'Per body'),
        ],
      );
    };
    return h(
      'section',
      { class: 'bench', 'aria-labelledby': 'rigid-worlds-title' },
      h('h2', { id: 'rigid-worlds-title' }, 'What the own world cannot'),
      h('p', { class: 'guarantee', 'data-testid': 'cannot' }, CANNOT),
      this.shell.controls('The scene', group('Scene', this.sceneSeg.el, again)),
      this.worldsIntro,
      h('div', { class: 'duo' }, side(0), side(1)),
      this.cost,
    );
  }

  // ------------------------------------------------------------------------------ drawing

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const lab = this.lab;
    const mod = this.mod;
    const all = [this.live, this.replay, ...this.machines, ...this.worlds];
    if (!lab || !mod) {
      for (const p of all) if (p.canvas.fit()) clearScene(p.canvas);
      return;
    }
    const interp = this.shell.interpolate;
    const alpha = (a: number) => (interp ? a : 1);
    const turnedRad = mod.TURNED_RAD;

    // The live tower.
    const k = lab.knock;
    const kr = k.readouts();
    drawWorld(this.live.canvas, {
      bounds: mod.TOWER_BOUNDS,
      statics: mod.TOWER_STATICS,
      shapes: k.track.shapes,
      poses: k.track.poses(alpha(k.loop.alpha)),
      turnedRad,
      label: `tick ${kr.tick}`,
    });
    setText(this.live.note, knockNote(kr));
    const lo = this.live.out;
    lo.tick?.set(fmt.count(kr.tick), kr.tick);
    lo.shots?.set(fmt.count(kr.shots), kr.shots);
    lo.turned?.set(`${kr.turned} of ${kr.boxes}`, kr.turned);
    lo.top?.set(`${kr.top.toFixed(2)} m`, kr.top);
    lo.hash?.set(kr.hash, kr.hash);
    lo['replay-bytes']?.set(`${fmt.count(kr.replayBytes)} B`, kr.replayBytes);

    // The replay.
    const run = lab.replay;
    const ro = this.replay.out;
    if (run) {
      const rr = run.readouts();
      drawWorld(this.replay.canvas, {
        bounds: mod.TOWER_BOUNDS,
        statics: mod.TOWER_STATICS,
        shapes: run.track.shapes,
        poses: run.track.poses(alpha(run.alpha)),
        turnedRad,
        label: `replay · tick ${rr.tick} of ${rr.ticks}`,
      });
      setText(
        this.replay.note,
        rr.ended ? 'Played to its end.' : `Re-simulating: tick ${rr.tick} of ${rr.ticks}`,
      );
      ro.tick?.set(`${fmt.count(rr.tick)} of ${fmt.count(rr.ticks)}`, rr.tick);
      ro.hash?.set(rr.hash, rr.hash);
      ro['live-hash']?.set(rr.liveHash || '—', rr.liveHash);
      ro.compared?.set(fmt.count(rr.compared), rr.compared);
      ro.different?.set(fmt.count(rr.different), rr.different);
      ro.different?.warn(rr.different > 0);
      ro.checkpoints?.set(
        `${fmt.count(rr.checkpoints - rr.mismatches)} of ${fmt.count(rr.checkpoints)}`,
        rr.checkpoints - rr.mismatches,
      );
      ro.bytes?.set(`${fmt.count(rr.bytes)} B (${fmt.count(rr.bytesPerSecond)} B/s)`, rr.bytes);
      const good = rr.different === 0 && rr.mismatches === 0;
      setText(this.replayVerdict, replayVerdict(rr));
      setAttr(this.replayVerdict, 'data-value', String(good && rr.ended));
      this.replayVerdict.classList.toggle('good', good);
      this.replayVerdict.classList.toggle('bad', !good);
    } else {
      if (this.replay.canvas.fit()) clearScene(this.replay.canvas);
      setText(this.replay.note, 'Nothing replayed yet.');
      setText(this.replayVerdict, replayVerdict(undefined));
      setAttr(this.replayVerdict, 'data-value', '');
      this.replayVerdict.classList.remove('good', 'bad');
      for (const r of Object.values(ro)) r.set('—', '');
    }

    // The network.
    const net = lab.net;
    const nr = net.readouts();
    for (const slot of [0, 1] as const) {
      const p = this.machines[slot];
      const m = nr.machines[slot];
      const drawn = net.machine(slot);
      if (drawn) {
        drawWorld(p.canvas, {
          bounds: mod.DUEL_BOUNDS,
          statics: mod.DUEL_STATICS,
          shapes: drawn.track.shapes,
          poses: drawn.track.poses(alpha(net.alpha(slot))),
          turnedRad,
          label: `tick ${m.tick}`,
        });
      } else if (p.canvas.fit()) clearScene(p.canvas);
      setText(
        p.note,
        m.slot < 0
          ? 'Connecting…'
          : `${fmt.plural(m.rollbacks, 'rollback')}, the deepest ${fmt.plural(m.maxDepth, 'tick')}`,
      );
      const o = p.out;
      o.tick?.set(fmt.count(m.tick), m.tick);
      o.shots?.set(`${m.shots[0]}, ${m.shots[1]}`, m.shots[0] + m.shots[1]);
      o.rollbacks?.set(fmt.count(m.rollbacks), m.rollbacks);
      o['max-depth']?.set(fmt.plural(m.maxDepth, 'tick'), m.maxDepth);
      o.resimulated?.set(fmt.count(m.resimulated), m.resimulated);
      o.rtt?.set(fmt.millis(m.rttMs), m.rttMs);
    }
    const started = nr.checkpoint >= 0;
    this.net.checkpoint?.set(started ? fmt.count(nr.checkpoint) : '—', nr.checkpoint);
    this.net['hash-1']?.set(nr.hashes[0] || '—', nr.hashes[0]);
    this.net['hash-2']?.set(nr.hashes[1] || '—', nr.hashes[1]);
    this.net.equal?.set(started ? (nr.equal ? 'yes' : 'NO') : '—', started ? nr.equal : '');
    this.net.equal?.good(started && nr.equal);
    this.net.equal?.warn(started && !nr.equal);
    this.net.lost?.set(`${fmt.count(nr.lost)} of ${fmt.count(nr.sent)}`, nr.lost);
    setText(this.netVerdict, netVerdict(nr));
    setAttr(this.netVerdict, 'data-value', String(started && nr.equal));
    this.netVerdict.classList.toggle('good', started && nr.equal);
    this.netVerdict.classList.toggle('bad', nr.desyncs > 0);

    // The two worlds.
    const w = lab.worlds;
    const wr = w.readouts();
    setText(this.worldsIntro, WORLDS_INTRO[w.scene]);
    if (this.shownScene !== w.scene) {
      this.shownScene = w.scene;
      for (const p of this.worlds) this.setAspect(p, w.bounds);
    }
    for (const i of [0, 1] as const) {
      const p = this.worlds[i];
      const r = wr[i];
      drawWorld(p.canvas, {
        bounds: w.bounds,
        statics: w.statics,
        shapes: w.tracks[i].shapes,
        poses: w.tracks[i].poses(alpha(w.loop.alpha)),
        turnedRad,
        label: `${(r.tick / mod.TICK_RATE).toFixed(1)} s`,
      });
      setText(p.note, worldNote(r, i === 0));
      const o = p.out;
      o.turned?.set(`${r.turned} of ${r.boxes}`, r.turned);
      o.top?.set(`${r.top.toFixed(2)} m`, r.top);
      o.bytes?.set(`${fmt.count(r.snapshotBytes)} B`, r.snapshotBytes);
      o['bytes-per-body']?.set(`${fmt.count(r.bytesPerBody)} B`, r.bytesPerBody);
    }
    setText(this.cost, costText(wr[0], wr[1]));
  }
}
