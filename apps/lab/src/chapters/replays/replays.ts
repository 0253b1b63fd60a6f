/**
 * Chapter 5 — Replays. A replay is the inputs and the seed: open one (a sample recorded when the
 * page opens, the game just played in chapter 9, a bot game recorded here, or a file), verify it,
 * play it back by re-simulation on any display — scrub its timeline, step a tick back or forward,
 * fast-forward — download it, submit its score. The numbers come from {@link ReplayLab}; the words
 * from replays-text.ts.
 */
import { ReplayError } from 'fixedstep';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import {
  button,
  group,
  segmented,
  jitterSlider,
  type Segmented,
  type Slider,
} from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import { download } from '../../ui/download.js';
import * as fmt from '../../ui/format.js';
import { headRow } from '../../ui/panel.js';
import { Readout, rateColor } from '../../ui/readout.js';
import {
  DISPLAY_RATES,
  GAME_IDS,
  gameDef,
  hudLabel,
  randomSeed,
  replayFileName,
  type DisplayRate,
  type GameId,
} from '../../games-view/games.js';
import { HighscorePanel } from '../../games-view/highscore-panel.js';
import { ASPECT, drawGame } from '../../games-view/render.js';
import { getLastReplay, setLastReplay, takeWatchRequest } from '../../games-view/replay-store.js';
import { recordBotGame } from '../../games-view/replays.js';
import { ReplayLab, SPEEDS, describeReplayError, type Source, type Speed } from './replays-lab.js';
import {
  BOT_GAME_SECONDS,
  FACT_ROWS,
  LEDE,
  SAMPLE,
  SAMPLE_LABEL,
  clock,
  verdictText,
  whatIsInTheFile,
} from './replays-text.js';
import '../../games-view/game-stage.css';
import './replays.css';

const SKIP_MS = 5000;

export const mount = mountChapter((root, head) => new ReplaysChapter(root, head));

function sourceLabel(s: Source): string {
  return s === 'real' ? 'your display' : `${s} Hz`;
}

class ReplaysChapter {
  readonly shell: ChapterShell;
  private lab: ReplayLab | undefined;
  private hz: DisplayRate = 60;
  private jitter = 0;
  private speed: Speed = 1;
  private dragging = false;
  private botGame: GameId = 'runner';
  private readonly scene: SceneCanvas;
  private readonly view: HTMLElement;
  private readonly lastBtn: HTMLButtonElement;
  private readonly fileInput: HTMLInputElement;
  private readonly error: HTMLElement;
  private readonly errorTitle = h('strong', {});
  private readonly errorDetail = h('code', { class: 'error-detail' });
  private readonly heading = h('h2', { id: 'view-title' }, 'Replay');
  private readonly subheading = h('p', { class: 'section-intro' });
  private readonly playBtn: HTMLButtonElement;
  private readonly transport: HTMLButtonElement[];
  private readonly skipBtn: HTMLButtonElement;
  private readonly rateSeg: Segmented<DisplayRate>;
  private readonly jitterSlider: Slider;
  private readonly timeline: HTMLInputElement;
  private readonly timelineLabel = h('span', { class: 'timeline-label' });
  private readonly tickOut = new Readout('strong', 'replay-tick');
  private readonly timeOut = new Readout('dd', 'replay-time');
  private readonly hashOut = new Readout('dd', 'replay-hash', { hash: true });
  private readonly hudList = h('dl', { class: 'readouts game-readouts' });
  private hudOuts = new Map<string, Readout>();
  private readonly factOuts = new Map<string, Readout>();
  private readonly verdict = h('p', {
    class: 'verdict',
    'data-testid': 'replay-verified',
    'data-value': '',
  });
  private readonly compareBody = h('tbody', {});
  private readonly compareNote = h('p', { class: 'hs-note' });
  private readonly commonTick = new Readout('strong', 'replay-common-tick');
  private readonly displaysEqual = new Readout('span', 'replay-displays-equal');
  private readonly highscores = new HighscorePanel();
  private readonly modeOut = h('span', { class: 'mode' });
  private readonly how = h('div', {});

  constructor(root: HTMLElement, head: ChapterHead) {
    this.shell = new ChapterShell(root, head, this, {
      lede: LEDE,
      timeline: () => this.lab,
      realClock: {
        title: 'Play the replay on this page’s own animation frames',
        onChange: (on) => {
          this.lab?.setDisplay(on ? 'real' : { hz: this.hz, jitter: this.jitter });
        },
      },
      driver: { maxRealGapMs: 250 },
    });
    const shell = this.shell;
    this.lastBtn = button('Your last game', 'control-open-last', () => {
      const last = getLastReplay();
      if (last) this.open(last.bytes, last.label, true);
    });
    this.fileInput = h('input', {
      type: 'file',
      id: 'replay-file',
      accept: '.fsr,application/octet-stream',
      class: 'file-input',
      'data-testid': 'control-load-file',
    });
    this.fileInput.addEventListener('change', () => {
      void this.loadFile();
    });
    this.error = h(
      'div',
      {
        class: 'replay-error verdict bad',
        role: 'alert',
        'data-testid': 'replay-error',
        hidden: true,
      },
      this.errorTitle,
      h('br', {}),
      this.errorDetail,
    );
    const at = (tick: () => number | undefined) => () => {
      const t = tick();
      if (t !== undefined) this.lab?.seek(t);
    };
    const startBtn = button(
      '|◀ Start',
      'control-to-start',
      at(() => 0),
    );
    const backBtn = button('◀ 1 tick', 'control-step-back', () => {
      this.lab?.stepBack();
    });
    backBtn.title =
      'One tick back: restore the last keyframe (or tick 0), re-simulate to the tick before';
    this.playBtn = button('▶ Play', 'control-play', () => {
      const lab = this.lab;
      if (lab?.player.isPlaying) lab.pause();
      else lab?.play();
    });
    const fwdBtn = button('1 tick ▶', 'control-step-forward', () => {
      this.lab?.stepForward();
    });
    const endBtn = button(
      'End ▶|',
      'control-to-end',
      at(() => this.lab?.replay.tickCount),
    );
    this.transport = [startBtn, backBtn, this.playBtn, fwdBtn, endBtn];
    this.skipBtn = button(`Skip +${SKIP_MS / 1000} s`, 'control-skip', () => {
      this.lab?.advanceBy(SKIP_MS);
    });
    this.skipBtn.title = 'Advance the simulated display by 5 s at once (playback must be on)';
    this.rateSeg = segmented<DisplayRate>({
      name: 'replay-hz',
      label: 'Display refresh rate',
      testPrefix: 'control-hz',
      values: DISPLAY_RATES,
      selected: this.hz,
      text: (hz) => `${hz} Hz`,
      onChange: (hz) => {
        this.hz = hz;
        this.lab?.setDisplay({ hz, jitter: this.jitter });
      },
    });
    this.jitterSlider = jitterSlider({
      id: 'replay-jitter',
      percent: 0,
      onChange: (jitter) => {
        this.jitter = jitter;
        if (!shell.real) this.lab?.setDisplay({ hz: this.hz, jitter: this.jitter });
      },
    });
    this.timeline = this.buildTimeline();
    this.scene = shell.canvas({
      class: 'game-canvas replay-canvas',
      label: 'The replay',
      testId: 'canvas-replay',
    });
    this.view = this.buildView();
    shell.append(this.sources(), this.view, this.how);
    shell.start();
    this.openAtLoad();
  }

  // ---------------------------------------------------------------- building

  private sources(): HTMLElement {
    const botSeg = segmented<GameId>({
      name: 'bot-game',
      label: 'Game of the bot',
      testPrefix: 'control-bot-game',
      values: GAME_IDS,
      selected: this.botGame,
      text: (id) => gameDef(id).info.title,
      onChange: (id) => {
        this.botGame = id;
      },
    });
    const botBtn = button(`Record ${BOT_GAME_SECONDS} s of the bot`, 'control-record-bot', () => {
      this.recordBotGame();
    });
    const card = (title: Node | string, text: (Node | string)[], ...rest: Node[]) =>
      h('div', { class: 'source-card' }, h('h3', {}, title), h('p', {}, ...text), ...rest);
    const box = h(
      'section',
      { class: 'replay-source', 'aria-labelledby': 'source-title' },
      h('h2', { id: 'source-title' }, 'Open a replay'),
      h(
        'div',
        { class: 'source-grid' },
        card(
          'A game you played',
          [
            'Every game of chapter 9 played under the fixed step is recorded. ',
            h('a', { href: '#/games' }, 'Play one'),
            ', then come back — or press “Watch replay” after it.',
          ],
          this.lastBtn,
        ),
        card(
          'A bot game',
          [`The game’s bot plays ${BOT_GAME_SECONDS} s with a new seed, recorded here and now.`],
          h('div', { class: 'source-row' }, botSeg.el, botBtn),
        ),
        card(
          h('label', { for: 'replay-file' }, 'A replay file (.fsr)'),
          [
            'One you downloaded from this page — or anything else, to see how the reader refuses it.',
          ],
          this.fileInput,
        ),
      ),
      this.error,
    );
    this.shell.settleOn(box);
    return box;
  }

  private buildTimeline(): HTMLInputElement {
    const timeline = h('input', {
      type: 'range',
      min: 0,
      max: 0,
      step: 1,
      value: 0,
      id: 'replay-timeline',
      class: 'replay-timeline',
      'data-testid': 'replay-timeline',
      'aria-label': 'Replay timeline (tick)',
    });
    timeline.addEventListener('pointerdown', () => {
      this.dragging = true;
    });
    const stopDrag = () => {
      this.dragging = false;
    };
    timeline.addEventListener('pointerup', stopDrag);
    timeline.addEventListener('pointercancel', stopDrag);
    timeline.addEventListener('input', () => {
      this.lab?.seek(Number(timeline.value));
      this.render();
    });
    timeline.addEventListener('change', () => {
      this.dragging = false;
      this.lab?.seek(Number(timeline.value));
    });
    return timeline;
  }

  private buildView(): HTMLElement {
    const shell = this.shell;
    const speedSeg = segmented<Speed>({
      name: 'replay-speed',
      label: 'Playback speed',
      testPrefix: 'control-speed',
      values: SPEEDS,
      selected: this.speed,
      text: (v) => `${v}×`,
      onChange: (v) => {
        this.speed = v;
        this.lab?.setSpeed(v);
      },
    });
    const downloadBtn = button('Download (.fsr)', 'control-download-replay', () => {
      const lab = this.lab;
      if (!lab) return;
      download(lab.bytes, replayFileName(lab.header.gameId, lab.header.seeds[0] ?? 0, new Date()));
    });
    const controls = shell.controls(
      'Playback',
      h(
        'div',
        { class: 'timeline-row' },
        h('label', { for: 'replay-timeline', class: 'control-label' }, 'Tick'),
        this.timeline,
        this.timelineLabel,
      ),
      group('Play', ...this.transport),
      group('Speed', speedSeg.el),
      group('Display', this.rateSeg.el, shell.clockBtn ?? null),
      this.jitterSlider.el,
      group('Time', this.skipBtn, downloadBtn),
      h(
        'div',
        { class: 'status' },
        h('span', { class: 'status-item' }, 'tick ', this.tickOut.el),
        this.modeOut,
      ),
    );
    controls.classList.add('replay-controls');
    const facts = h('dl', { class: 'readouts game-readouts facts' });
    for (const [id, label, title] of FACT_ROWS) {
      const ro = new Readout('dd', `replay-${id}`, { title });
      this.factOuts.set(id, ro);
      facts.append(h('dt', { title }, label), ro.el);
    }
    return h(
      'section',
      {
        class: 'replay-view',
        'aria-labelledby': 'view-title',
        'data-testid': 'replay-view',
        hidden: true,
      },
      this.heading,
      this.subheading,
      h(
        'div',
        { class: 'replay-stage' },
        h(
          'div',
          { class: 'replay-main' },
          h('div', { class: 'game-frame' }, this.scene.canvas),
          controls,
        ),
        h(
          'aside',
          { class: 'game-side', 'aria-label': 'The replay at this tick' },
          h('h3', {}, 'At this tick'),
          h(
            'dl',
            { class: 'readouts game-readouts' },
            h('dt', {}, 'Time'),
            this.timeOut.el,
            h('dt', { title: 'FNV-1a 64 of the game’s state at this tick' }, 'State hash'),
            this.hashOut.el,
          ),
          this.hudList,
          h('h3', { class: 'facts-title' }, 'The file'),
          facts,
          this.verdict,
        ),
      ),
      this.compareSection(),
      h('div', { class: 'replay-hs' }, this.highscores.el),
    );
  }

  private compareSection(): HTMLElement {
    return h(
      'section',
      { class: 'compare', 'aria-labelledby': 'compare-title' },
      h('h3', { id: 'compare-title' }, 'The same states on every display'),
      h(
        'p',
        { class: 'section-intro' },
        'While the replay plays, the page notes the state hash at every checkpoint tick it passes, per display, and compares the latest tick two displays have both passed. Play it at 30 Hz, then from the start at 144 Hz: the hashes at the same tick are the same, and the same as the one the file stored when the game was played.',
      ),
      h(
        'p',
        { class: 'compare-head' },
        'Latest checkpoint compared: ',
        this.commonTick.el,
        ' · ',
        this.displaysEqual.el,
      ),
      h(
        'table',
        { class: 'data-table compare-table' },
        headRow('Source', 'Hash at that tick'),
        this.compareBody,
      ),
      this.compareNote,
    );
  }

  // ---------------------------------------------------------------- opening

  /**
   * What is open when the chapter opens: the game just played if the reader pressed "Watch
   * replay" (playing, in view), else the last replay of this tab, else the sample.
   */
  private openAtLoad(): void {
    const watch = takeWatchRequest();
    const last = getLastReplay();
    this.lastBtn.disabled = last === undefined;
    if (last) {
      this.open(last.bytes, last.label, watch);
      return;
    }
    const def = gameDef(SAMPLE.game);
    const bytes = recordBotGame(def, SAMPLE.seed, SAMPLE.seconds * def.info.tickRate);
    this.open(bytes, SAMPLE_LABEL, false);
  }

  /**
   * Open `bytes`: show the replay and play it. `bringIntoView` scrolls the player to the top of
   * the window (the reader asked for this replay). False if the file could not be opened.
   */
  private open(bytes: Uint8Array, label: string, bringIntoView: boolean): boolean {
    let lab: ReplayLab;
    try {
      lab = new ReplayLab(
        bytes,
        label,
        this.shell.real ? 'real' : { hz: this.hz, jitter: this.jitter },
      );
    } catch (e) {
      this.showError(e);
      return false;
    }
    setHidden(this.error, true);
    this.lab = lab;
    lab.setSpeed(this.speed);
    if (this.shell.real) this.shell.driver.restartReal();
    setHidden(this.view, false);
    const f = lab.facts();
    setText(this.heading, `Replay — ${f.title}`);
    setText(
      this.subheading,
      `From ${label}. Pause it, drag the timeline, or step a tick at a time.`,
    );
    this.timeline.max = String(f.ticks);
    this.timeline.value = '0';
    const aspect = String(ASPECT[f.gameId] ?? 1.5);
    this.scene.canvas.style.aspectRatio = aspect;
    this.scene.canvas.parentElement?.style.setProperty('--aspect', aspect);
    this.scene.canvas.setAttribute('aria-label', `The replay of ${f.title}`);
    this.writeFacts();
    this.buildHud();
    this.how.replaceChildren(whatIsInTheFile(f));
    setAttr(this.verdict, 'data-value', '');
    this.verdict.className = 'verdict';
    setText(this.verdict, 'Verifying: re-simulating every tick…');
    if (lab.def) this.highscores.setGame(lab.def);
    this.highscores.setSubmission(undefined);
    // Verify after the page has drawn the replay once.
    setTimeout(() => {
      if (this.lab === lab) this.showVerification(lab);
    }, 30);
    lab.play();
    this.shell.setPaused(false);
    if (bringIntoView) this.view.scrollIntoView({ block: 'start' });
    return true;
  }

  private showError(e: unknown): void {
    const d = describeReplayError(e);
    setText(
      this.errorTitle,
      this.lab ? `${d.title} (Still showing the replay opened before.)` : d.title,
    );
    setText(this.errorDetail, d.detail);
    setAttr(this.error, 'data-code', e instanceof ReplayError ? e.code : 'ERROR');
    setHidden(this.error, false);
  }

  private async loadFile(): Promise<void> {
    const file = this.fileInput.files?.[0];
    if (!file) return;
    let bytes: Uint8Array;
    try {
      bytes = new Uint8Array(await file.arrayBuffer());
    } catch (e) {
      this.showError(e);
      return;
    }
    const label = `the file ${file.name}`;
    if (this.open(bytes, label, true)) setLastReplay({ bytes, label });
    this.fileInput.value = '';
    this.shell.refresh();
  }

  private recordBotGame(): void {
    const def = gameDef(this.botGame);
    const seed = randomSeed();
    const bytes = recordBotGame(def, seed, BOT_GAME_SECONDS * def.info.tickRate);
    const label = `a ${BOT_GAME_SECONDS} s bot game of ${def.info.title} (seed ${seed})`;
    setLastReplay({ bytes, label });
    this.lastBtn.disabled = false;
    this.open(bytes, label, true);
  }

  private writeFacts(): void {
    const lab = this.lab;
    if (!lab) return;
    const f = lab.facts();
    const c = f.contents;
    const put = (id: string, text: string, value: number | string | undefined) => {
      this.factOuts.get(id)?.set(text, value);
    };
    put('game', `${f.title} v${f.gameVersion}`, f.gameId);
    put('seed', String(f.seed ?? '—'), f.seed);
    put('players', f.players.join(', '), f.players.join(','));
    put('ticks', `${fmt.count(f.ticks)} at ${f.tickRate} Hz`, f.ticks);
    put('length', clock(f.seconds), f.seconds);
    put('size', `${fmt.count(f.bytes)} B`, f.bytes);
    put(
      'bpm',
      Number.isFinite(f.bytesPerMinute) ? `${fmt.count(f.bytesPerMinute)} B/min` : '—',
      Math.round(f.bytesPerMinute),
    );
    put('inputs', `${fmt.count(c.inputs)} B`, c.inputs);
    put('hashes', `${fmt.count(c.hashes)} B`, c.hashes);
    put(
      'keyframes',
      c.keyframeCount > 0
        ? `${c.keyframeCount} × ${f.keyframeEvery / f.tickRate} s, ${fmt.count(c.keyframes)} B`
        : 'none: seeking re-simulates',
      c.keyframeCount,
    );
  }

  private showVerification(lab: ReplayLab): void {
    let v;
    try {
      v = lab.verify();
    } catch (e) {
      this.verdict.className = 'verdict bad';
      setAttr(this.verdict, 'data-value', 'error');
      setText(this.verdict, `Could not verify: ${describeReplayError(e).detail}`);
      return;
    }
    const r = v.result;
    this.verdict.className = r.ok ? 'verdict good' : 'verdict bad';
    setAttr(this.verdict, 'data-value', r.ok ? 'ok' : 'mismatch');
    if (!r.ok) setAttr(this.verdict, 'data-tick', String(r.firstMismatchTick));
    setText(
      this.verdict,
      verdictText(v, lab.replay.checkpoints.length, lab.replay.keyframes.length),
    );
    if (lab.def && v.score !== undefined && r.ok) {
      this.highscores.setSubmission({ bytes: lab.bytes, score: v.score });
    }
  }

  private buildHud(): void {
    const lab = this.lab;
    if (!lab) return;
    this.hudOuts = new Map();
    this.hudList.replaceChildren(
      ...Object.keys(lab.game.hud()).flatMap((k) => {
        const ro = new Readout('dd', `replay-hud-${k}`);
        this.hudOuts.set(k, ro);
        return [h('dt', {}, hudLabel(k)), ro.el];
      }),
    );
  }

  // ---------------------------------------------------------------- drawing

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const lab = this.lab;
    const real = this.shell.real;
    const playing = lab?.player.isPlaying ?? false;
    setText(this.playBtn, playing ? '❚❚ Pause' : '▶ Play');
    setAttr(this.playBtn, 'aria-pressed', String(playing));
    this.rateSeg.setDisabled(real);
    this.jitterSlider.input.disabled = real;
    this.skipBtn.disabled = real || !playing;
    for (const b of this.transport) b.disabled = lab === undefined;
  }

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const lab = this.lab;
    if (!lab) return;
    const p = lab.player;
    const f = lab.replay;
    const rate = f.header.stepDenominator / f.header.stepNumerator;
    if (!this.dragging && Number(this.timeline.value) !== p.tick)
      this.timeline.value = String(p.tick);
    this.tickOut.set(`${fmt.count(p.tick)} / ${fmt.count(f.tickCount)}`, p.tick);
    setText(this.timelineLabel, `${clock(p.tick / rate)} / ${clock(f.tickCount / rate)}`);
    this.timeOut.set(clock(p.tick / rate), p.tick / rate);
    const hash = lab.hashNow();
    this.hashOut.set(hash, hash);
    const hud = lab.game.hud();
    for (const [k, ro] of this.hudOuts) {
      const v = hud[k];
      ro.set(v === undefined ? '—' : fmt.count(v), v);
    }
    setText(
      this.modeOut,
      `${this.shell.display(`simulated ${this.hz} Hz`)} · ${p.isPlaying ? `playing at ${this.speed}×` : p.ended ? 'at the end' : 'paused'}`,
    );
    if (this.playBtn.getAttribute('aria-pressed') !== String(p.isPlaying)) this.refreshControls();
    this.writeCompare();
    if (!this.scene.fit()) return;
    drawGame(this.scene, lab.game, {
      alpha: lab.alpha,
      nowMs: lab.timeMs,
      badge: { text: `REPLAY · ${this.speed}× · tick ${p.tick}`, tone: 'info' },
      hint: p.ended ? 'the end of the replay' : undefined,
    });
  }

  private writeCompare(): void {
    const lab = this.lab;
    if (!lab) return;
    const c = lab.compare();
    this.commonTick.set(c.tick >= 0 ? fmt.count(c.tick) : '—', c.tick >= 0 ? c.tick : undefined);
    const many = c.rows.length > 1;
    const none = c.rows.length === 0;
    this.displaysEqual.set(
      none ? 'play to compare' : !c.equal ? 'DIFFERENT' : many ? 'all equal' : 'equal to the file',
      none ? undefined : c.equal,
    );
    this.displaysEqual.good(!none && c.equal);
    this.displaysEqual.warn(!none && !c.equal);
    const key = `${c.tick}|${c.rows.map((r) => `${r.source}:${r.hash}`).join(',')}`;
    if (this.compareBody.dataset.key === key) return;
    this.compareBody.dataset.key = key;
    const rows: HTMLTableRowElement[] = [];
    if (c.stored !== undefined) {
      rows.push(compareRow('stored in the file', '#94a3b8', c.stored, 'replay-hash-file'));
    }
    for (const r of c.rows) {
      rows.push(
        compareRow(sourceLabel(r.source), rateColor(r.source), r.hash, `replay-hash-${r.source}`),
      );
    }
    this.compareBody.replaceChildren(...rows);
    setText(
      this.compareNote,
      none
        ? 'Press play to start comparing.'
        : many
          ? ''
          : 'Now pick another display rate, go to the start and play again.',
    );
  }
}

function compareRow(label: string, color: string, hash: string, id: string): HTMLTableRowElement {
  const ro = new Readout('td', id, { hash: true });
  ro.set(hash, hash);
  return h(
    'tr',
    {},
    h('th', { scope: 'row' }, h('span', { class: 'rate-dot', style: `--chip: ${color}` }), label),
    ro.el,
  );
}
