/**
 * Chapter 5 — Replays. A replay is the inputs and the seed, nothing else: open one (the game
 * just played in chapter 9, a bot game recorded here, or a file), verify it, play it back by
 * re-simulation on any display — scrub its timeline, step a tick back or forward, fast-forward —
 * download it, submit its score. The numbers come from {@link ReplayLab}; this module builds the
 * page and draws.
 */
import { ReplayError } from 'fixedstep';
import { SceneCanvas } from '../ui/canvas.js';
import {
  button,
  group,
  segmented,
  setPressed,
  slider,
  toggle,
  type Segmented,
  type Slider,
} from '../ui/controls.js';
import { h, setAttr, setText } from '../ui/dom.js';
import { LabDriver } from '../ui/driver.js';
import * as fmt from '../ui/format.js';
import { Readout, rateColor } from '../ui/readout.js';
import { HighscorePanel } from './games-highscores.js';
import {
  DISPLAY_RATES,
  GAME_IDS,
  GameSession,
  KEYFRAME_SECONDS,
  gameDef,
  randomSeed,
  replayFileName,
  type DisplayRate,
  type GameId,
} from './games-lab.js';
import { ASPECT, drawGame } from './games-render.js';
import { ReplayLab, SPEEDS, describeReplayError, type Source, type Speed } from './replays-lab.js';
import { getLastReplay, setLastReplay } from './replays-store.js';
import './games.css';
import './replays.css';

const SKIP_MS = 5000;
/** Seconds of play in a bot game recorded on this page. */
const BOT_GAME_SECONDS = 60;

export function mount(root: HTMLElement): () => void {
  const chapter = new ReplaysChapter(root);
  return () => {
    chapter.destroy();
  };
}

function sourceLabel(s: Source): string {
  return s === 'real' ? 'your display' : `${s} Hz`;
}

class ReplaysChapter {
  private lab: ReplayLab | undefined;
  private hz: DisplayRate = 60;
  private jitter = 0;
  private real = false;
  private speed: Speed = 1;
  private dragging = false;
  private botGame: GameId = 'runner';
  private readonly driver: LabDriver;
  private readonly scene: SceneCanvas;
  private readonly view: HTMLElement;
  private readonly empty: HTMLElement;
  private readonly lastBtn: HTMLButtonElement;
  private readonly fileInput: HTMLInputElement;
  private readonly error: HTMLElement;
  private readonly errorTitle: HTMLElement;
  private readonly errorDetail: HTMLElement;
  private readonly heading: HTMLElement;
  private readonly subheading: HTMLElement;
  private readonly playBtn: HTMLButtonElement;
  private readonly startBtn: HTMLButtonElement;
  private readonly backBtn: HTMLButtonElement;
  private readonly fwdBtn: HTMLButtonElement;
  private readonly endBtn: HTMLButtonElement;
  private readonly skipBtn: HTMLButtonElement;
  private readonly speedSeg: Segmented<Speed>;
  private readonly rateSeg: Segmented<DisplayRate>;
  private readonly jitterSlider: Slider;
  private readonly clockBtn: HTMLButtonElement;
  private readonly timeline: HTMLInputElement;
  private readonly timelineLabel: HTMLElement;
  private readonly tickOut = new Readout('strong', 'replay-tick');
  private readonly timeOut = new Readout('dd', 'replay-time');
  private readonly hashOut = new Readout('dd', 'replay-hash', { hash: true });
  private readonly hudList: HTMLElement;
  private hudOuts = new Map<string, Readout>();
  private readonly facts: HTMLElement;
  private readonly factOuts = new Map<string, Readout>();
  private readonly verdict: HTMLElement;
  private readonly compareBody: HTMLTableSectionElement;
  private readonly compareNote: HTMLElement;
  private readonly commonTick = new Readout('strong', 'replay-common-tick');
  private readonly displaysEqual = new Readout('span', 'replay-displays-equal');
  private readonly highscores = new HighscorePanel();
  private readonly modeOut: HTMLElement;

  constructor(private readonly root: HTMLElement) {
    this.driver = new LabDriver(
      {
        advance: (ms) => {
          this.lab?.advanceBy(ms);
        },
        realFrame: (t) => {
          this.lab?.realFrame(t);
        },
        render: () => {
          this.render();
        },
      },
      { maxRealGapMs: 250 },
    );

    // ------------------------------------------------------------ opening a replay
    this.lastBtn = button('Your last game', 'control-open-last', () => {
      const last = getLastReplay();
      if (last) this.open(last.bytes, last.label);
    });
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
    this.errorTitle = h('strong', {});
    this.errorDetail = h('code', { class: 'error-detail' });
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
    const source = h(
      'section',
      { class: 'replay-source', 'aria-labelledby': 'source-title' },
      h('h2', { id: 'source-title' }, 'Open a replay'),
      h(
        'div',
        { class: 'source-grid' },
        h(
          'div',
          { class: 'source-card' },
          h('h3', {}, 'A game you played'),
          h(
            'p',
            {},
            'Every game of chapter 9 played under the fixed step is recorded. ',
            h('a', { href: '#/games' }, 'Play one'),
            ', then come back — or press “Watch replay” after it.',
          ),
          this.lastBtn,
        ),
        h(
          'div',
          { class: 'source-card' },
          h('h3', {}, 'A bot game'),
          h(
            'p',
            {},
            `The game’s bot plays ${BOT_GAME_SECONDS} s with a new seed, recorded here and now.`,
          ),
          h('div', { class: 'source-row' }, botSeg.el, botBtn),
        ),
        h(
          'div',
          { class: 'source-card' },
          h('h3', {}, h('label', { for: 'replay-file' }, 'A replay file (.fsr)')),
          h(
            'p',
            {},
            'One you downloaded from this page — or anything else, to see how the reader refuses it.',
          ),
          this.fileInput,
        ),
      ),
      this.error,
    );

    // ------------------------------------------------------------ the player
    this.startBtn = button('|◀ Start', 'control-to-start', () => {
      this.lab?.seek(0);
      this.afterChange();
    });
    this.backBtn = button('◀ 1 tick', 'control-step-back', () => {
      this.lab?.stepBack();
      this.afterChange();
    });
    this.backBtn.title = 'One tick back: restore the last keyframe, re-simulate to the tick before';
    this.playBtn = button('▶ Play', 'control-play', () => {
      const lab = this.lab;
      if (!lab) return;
      if (lab.player.isPlaying) lab.pause();
      else lab.play();
      this.afterChange();
    });
    this.fwdBtn = button('1 tick ▶', 'control-step-forward', () => {
      this.lab?.stepForward();
      this.afterChange();
    });
    this.endBtn = button('End ▶|', 'control-to-end', () => {
      const lab = this.lab;
      if (lab) lab.seek(lab.replay.tickCount);
      this.afterChange();
    });
    this.skipBtn = button(`Skip +${SKIP_MS / 1000} s`, 'control-skip', () => {
      this.lab?.advanceBy(SKIP_MS);
      this.afterChange();
    });
    this.skipBtn.title = 'Advance the simulated display by 5 s at once (playback must be on)';
    this.speedSeg = segmented<Speed>({
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
    this.jitterSlider = slider({
      id: 'replay-jitter',
      label: 'Jitter',
      testId: 'control-jitter',
      min: 0,
      max: 30,
      step: 1,
      value: 0,
      text: (v) => `±${v} %`,
      onChange: (v) => {
        this.jitter = v / 100;
        if (!this.real) this.lab?.setDisplay({ hz: this.hz, jitter: this.jitter });
      },
    });
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.real = on;
      this.driver.setReal(on);
      this.lab?.setDisplay(on ? 'real' : { hz: this.hz, jitter: this.jitter });
      this.afterChange();
    });
    this.modeOut = h('span', { class: 'mode' });

    this.timeline = h('input', {
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
    this.timeline.addEventListener('pointerdown', () => {
      this.dragging = true;
    });
    const stopDrag = () => {
      this.dragging = false;
    };
    this.timeline.addEventListener('pointerup', stopDrag);
    this.timeline.addEventListener('pointercancel', stopDrag);
    this.timeline.addEventListener('input', () => {
      this.lab?.seek(Number(this.timeline.value));
      this.render();
    });
    this.timeline.addEventListener('change', () => {
      this.dragging = false;
      this.lab?.seek(Number(this.timeline.value));
      this.afterChange();
    });
    this.timelineLabel = h('span', { class: 'timeline-label' });

    this.scene = new SceneCanvas({
      class: 'game-canvas replay-canvas',
      label: 'The replay',
      testId: 'canvas-replay',
    });
    this.hudList = h('dl', { class: 'readouts game-readouts' });
    this.facts = h('dl', { class: 'readouts game-readouts facts' });
    const factRows: [string, string, string][] = [
      ['game', 'Game', 'The game and its version'],
      ['seed', 'Seed', 'The seed of every random number the game draws'],
      ['players', 'Player', 'Names in the file'],
      ['ticks', 'Ticks', 'Steps recorded'],
      ['length', 'Length', 'Ticks × step'],
      ['size', 'File size', 'The whole file: header, inputs, hashes, keyframes, checksum'],
      ['bpm', 'Per minute', 'File size per minute of play'],
      ['inputs', 'Inputs', 'The recorded inputs alone (run-length coded): what a replay needs'],
      ['hashes', 'Hashes', 'A state hash every second: what proves the replay'],
      ['keyframes', 'Keyframes', 'Snapshots to seek from: what makes seeking fast'],
    ];
    for (const [id, label, title] of factRows) {
      const ro = new Readout('dd', `replay-${id}`, { title });
      this.factOuts.set(id, ro);
      this.facts.append(h('dt', { title }, label), ro.el);
    }
    this.verdict = h('p', { class: 'verdict', 'data-testid': 'replay-verified', 'data-value': '' });
    this.compareBody = h('tbody', {});
    this.compareNote = h('p', { class: 'hs-note' });

    const downloadBtn = button('Download (.fsr)', 'control-download-replay', () => {
      this.download();
    });

    this.heading = h('h2', { id: 'view-title' }, 'Replay');
    this.subheading = h('p', { class: 'section-intro' });
    this.view = h(
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
        { class: 'controls replay-controls', role: 'group', 'aria-label': 'Playback' },
        group('Play', this.startBtn, this.backBtn, this.playBtn, this.fwdBtn, this.endBtn),
        group('Speed', this.speedSeg.el),
        group('Display', this.rateSeg.el, this.clockBtn),
        this.jitterSlider.el,
        group('Time', this.skipBtn, downloadBtn),
        h(
          'div',
          { class: 'timeline-row' },
          h('label', { for: 'replay-timeline', class: 'control-label' }, 'Tick'),
          this.timeline,
          this.timelineLabel,
        ),
        h(
          'div',
          { class: 'status' },
          h('span', { class: 'status-item' }, 'tick ', this.tickOut.el),
          this.modeOut,
        ),
      ),
      h(
        'div',
        { class: 'game-stage' },
        h('div', { class: 'game-frame' }, this.scene.canvas),
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
          this.facts,
          this.verdict,
        ),
      ),
      h(
        'section',
        { class: 'compare', 'aria-labelledby': 'compare-title' },
        h('h3', { id: 'compare-title' }, 'The same states on every display'),
        h(
          'p',
          { class: 'section-intro' },
          'While the replay plays, the page notes the state hash at every checkpoint tick it passes, per display. Play it at 30 Hz, then from the start at 144 Hz: the hashes at the same tick are the same, and the same as the one the file stored when the game was played.',
        ),
        h(
          'p',
          { class: 'compare-head' },
          'Latest tick every display passed: ',
          this.commonTick.el,
          ' · ',
          this.displaysEqual.el,
        ),
        h(
          'table',
          { class: 'data-table compare-table' },
          h(
            'thead',
            {},
            h(
              'tr',
              {},
              h('th', { scope: 'col' }, 'Source'),
              h('th', { scope: 'col' }, 'Hash at that tick'),
            ),
          ),
          this.compareBody,
        ),
        this.compareNote,
      ),
      h('div', { class: 'replay-hs' }, this.highscores.el),
    );

    this.empty = h(
      'p',
      { class: 'replay-empty', 'data-testid': 'replay-empty' },
      'No replay open yet.',
    );

    root.append(
      h(
        'article',
        { class: 'chapter replays-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 5'),
          h('h1', {}, 'Replays'),
          h(
            'p',
            { class: 'lede' },
            'With a fixed step a replay does not store the world: the inputs of every tick and the seeds of the random number generators are enough to compute it again, bit for bit — at any display rate, forwards, backwards, from any tick.',
          ),
        ),
        source,
        this.empty,
        this.view,
        howItWorks(),
      ),
    );

    this.driver.start();
    const last = getLastReplay();
    this.lastBtn.disabled = last === undefined;
    if (last) this.open(last.bytes, last.label);
  }

  destroy(): void {
    this.driver.destroy();
    this.scene.destroy();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- opening

  private open(bytes: Uint8Array, label: string): boolean {
    let lab: ReplayLab;
    try {
      lab = new ReplayLab(bytes, label, this.real ? 'real' : { hz: this.hz, jitter: this.jitter });
    } catch (e) {
      this.showError(e);
      return false;
    }
    this.error.hidden = true;
    this.lab = lab;
    lab.setSpeed(this.speed);
    if (this.real) this.driver.restartReal();
    this.empty.hidden = true;
    this.view.hidden = false;
    const f = lab.facts();
    setText(this.heading, `Replay — ${f.title}`);
    setText(
      this.subheading,
      `From ${label}. Press play, drag the timeline, or step a tick at a time.`,
    );
    this.timeline.max = String(f.ticks);
    this.timeline.value = '0';
    const aspect = String(ASPECT[f.gameId] ?? 1.5);
    this.scene.canvas.style.aspectRatio = aspect;
    this.scene.canvas.parentElement?.style.setProperty('--aspect', aspect);
    this.scene.canvas.setAttribute('aria-label', `The replay of ${f.title}`);
    this.writeFacts();
    this.buildHud();
    setAttr(this.verdict, 'data-value', '');
    this.verdict.className = 'verdict';
    setText(this.verdict, 'Verifying: re-simulating every tick…');
    if (lab.def) this.highscores.setGame(lab.def);
    this.highscores.setSubmission(undefined);
    // Verify after the page has drawn the replay once.
    setTimeout(() => {
      if (this.lab === lab) this.showVerification(lab);
    }, 30);
    this.afterChange();
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
    this.error.hidden = false;
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
    if (this.open(bytes, `the file ${file.name}`))
      setLastReplay({ bytes, label: `the file ${file.name}` });
    this.fileInput.value = '';
  }

  private recordBotGame(): void {
    const def = gameDef(this.botGame);
    const seed = randomSeed();
    const session = new GameSession({
      def,
      seed,
      mode: 'fixed',
      player: 'bot',
      display: { hz: 60, jitter: 0 },
      bot: true,
    });
    session.advanceTo(BOT_GAME_SECONDS * 1000 + 1); // the frame at 60 s, give or take a float
    const bytes = session.replay()!;
    const label = `a ${BOT_GAME_SECONDS} s bot game of ${def.info.title} (seed ${seed})`;
    setLastReplay({ bytes, label });
    this.lastBtn.disabled = false;
    this.open(bytes, label);
  }

  private download(): void {
    const lab = this.lab;
    if (!lab) return;
    const blob = new Blob([lab.bytes as Uint8Array<ArrayBuffer>], {
      type: 'application/octet-stream',
    });
    const url = URL.createObjectURL(blob);
    const a = h('a', {
      href: url,
      download: replayFileName(lab.header.gameId, lab.header.seeds[0] ?? 0, new Date()),
    });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => {
      URL.revokeObjectURL(url);
    }, 10_000);
  }

  private writeFacts(): void {
    const lab = this.lab;
    if (!lab) return;
    const f = lab.facts();
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
    put('inputs', `${fmt.count(f.inputBytes)} B`, f.inputBytes);
    put('hashes', `${fmt.count(f.hashBytes)} B`, f.hashBytes);
    put(
      'keyframes',
      f.keyframeEvery > 0
        ? `${f.keyframes} × ${f.keyframeEvery / f.tickRate} s, ${fmt.count(f.keyframeBytes)} B`
        : 'none: seeking re-simulates from tick 0',
      f.keyframes,
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
    if (r.ok) {
      this.verdict.className = 'verdict good';
      setAttr(this.verdict, 'data-value', 'ok');
      setText(
        this.verdict,
        `Verified: re-simulating all ${fmt.count(r.ticks)} ticks reproduced every stored hash (${fmt.count(lab.replay.checkpoints.length)} checkpoints, ${lab.replay.keyframes.length} keyframes) in ${Math.max(1, Math.round(v.ms))} ms.`,
      );
    } else {
      this.verdict.className = 'verdict bad';
      setAttr(this.verdict, 'data-value', 'mismatch');
      setAttr(this.verdict, 'data-tick', String(r.firstMismatchTick));
      setText(
        this.verdict,
        `Does not reproduce: the ${r.kind ?? 'stored'} hash after tick ${r.firstMismatchTick} differs (last good tick ${r.lastGoodTick}). The inputs or the game changed since it was recorded.`,
      );
    }
    if (lab.def && v.score !== undefined && r.ok) {
      this.highscores.setSubmission({ bytes: lab.bytes, score: v.score });
    }
  }

  private buildHud(): void {
    const lab = this.lab;
    if (!lab) return;
    this.hudOuts = new Map();
    const hud = lab.game.hud();
    this.hudList.replaceChildren(
      ...Object.keys(hud).flatMap((k) => {
        const ro = new Readout('dd', `replay-hud-${k}`);
        this.hudOuts.set(k, ro);
        return [h('dt', {}, hudLabel(k)), ro.el];
      }),
    );
  }

  // ---------------------------------------------------------------- drawing

  private afterChange(): void {
    this.refreshControls();
    this.render();
  }

  private refreshControls(): void {
    const lab = this.lab;
    const playing = lab?.player.isPlaying ?? false;
    setText(this.playBtn, playing ? '❚❚ Pause' : '▶ Play');
    setAttr(this.playBtn, 'aria-pressed', String(playing));
    this.rateSeg.setDisabled(this.real);
    this.jitterSlider.input.disabled = this.real;
    this.skipBtn.disabled = this.real || !playing;
    setPressed(this.clockBtn, this.real);
    for (const b of [this.startBtn, this.backBtn, this.playBtn, this.fwdBtn, this.endBtn]) {
      b.disabled = lab === undefined;
    }
  }

  private render(): void {
    const lab = this.lab;
    if (!lab) return;
    const p = lab.player;
    const f = lab.replay;
    const rate = f.header.stepDenominator / f.header.stepNumerator;
    if (!this.dragging && document.activeElement !== this.timeline)
      this.timeline.value = String(p.tick);
    else if (!this.dragging && Number(this.timeline.value) !== p.tick)
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
    const display = this.real
      ? `real clock ≈ ${this.driver.measuredHz} Hz`
      : `simulated ${this.hz} Hz`;
    setText(
      this.modeOut,
      `${display} · ${p.isPlaying ? `playing at ${this.speed}×` : p.ended ? 'at the end' : 'paused'}`,
    );
    const playing = p.isPlaying;
    if (this.playBtn.getAttribute('aria-pressed') !== String(playing)) this.refreshControls();
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
    this.displaysEqual.set(
      c.rows.length === 0
        ? 'play to compare'
        : c.equal
          ? many
            ? 'all equal'
            : 'equal to the file'
          : 'DIFFERENT',
      c.rows.length === 0 ? undefined : c.equal,
    );
    this.displaysEqual.good(c.rows.length > 0 && c.equal);
    this.displaysEqual.warn(c.rows.length > 0 && !c.equal);
    const key = `${c.tick}|${c.rows.map((r) => `${r.source}:${r.hash}`).join(',')}`;
    if (this.compareBody.dataset.key === key) return;
    this.compareBody.dataset.key = key;
    const rows: HTMLTableRowElement[] = [];
    if (c.stored !== undefined)
      rows.push(compareRow('stored in the file', '#94a3b8', c.stored, 'replay-hash-file'));
    for (const r of c.rows) {
      rows.push(
        compareRow(sourceLabel(r.source), rateColor(r.source), r.hash, `replay-hash-${r.source}`),
      );
    }
    this.compareBody.replaceChildren(...rows);
    setText(
      this.compareNote,
      c.rows.length === 0
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

const HUD_LABELS: Readonly<Record<string, string>> = {
  score: 'Score',
  highscore: 'Highscore',
  kills: 'Kills',
  flags: 'Flags captured',
  deaths: 'Deaths',
  red: 'Red captures',
  blue: 'Blue captures',
  timeLeft: 'Time left (s)',
  throughWalls: 'Through walls',
  lives: 'Lives',
  wave: 'Wave',
  cleared: 'Waves cleared',
  enemies: 'Enemies',
};

function hudLabel(k: string): string {
  return HUD_LABELS[k] ?? k;
}

function clock(seconds: number): string {
  if (!Number.isFinite(seconds)) return '—';
  const s = Math.floor(seconds);
  const cs = Math.floor((seconds - s) * 100);
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}.${String(cs).padStart(2, '0')}`;
}

function howItWorks(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'how-title' },
    h('h2', { id: 'how-title' }, 'What is in the file'),
    h(
      'p',
      {},
      'A header (the game and its version, the step, the seed, the players), then the input of every tick, run-length coded: a held button costs a few bytes however long it is held. Then a state hash every second of play, a snapshot (keyframe) every ',
      String(KEYFRAME_SECONDS),
      ' s, and a checksum. Nothing of the world itself but those snapshots.',
    ),
    h(
      'p',
      {},
      'Playing re-simulates: the game is built from the header and stepped with the recorded inputs, and every stored hash it passes is checked. Seeking loads the last keyframe before the target and steps from there; a tick back is a seek. The display only decides how many ticks run per frame — never what a tick does — so a replay is the same at 30 Hz, 144 Hz, 16× or one tick at a time.',
    ),
    h(
      'p',
      {},
      'A highscore server does the same: it re-simulates the submitted replay and ranks the score the replay reaches, not the one claimed. Format: docs/replay-format.md.',
    ),
  );
}
