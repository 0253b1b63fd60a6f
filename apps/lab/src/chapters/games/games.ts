/**
 * Chapter 9 — Games. The talk's three games, playable with the keyboard (games-input.ts), a
 * FixedLoop on the animation frames of a simulated display (or the real clock), drawn between the
 * last two states. The "variable Δt" switch runs the naive `update(dt)` game instead, so the
 * breakage shows. Every fixed-step game is recorded; after it, watch the replay, download it, or
 * submit the best run. The numbers come from {@link GameSession}; the words from games-text.ts.
 */
import { readReplay } from 'fixedstep';
import { ChapterShell, mountChapter, type ChapterHead } from '../../shell/chapter-shell.js';
import type { SceneCanvas } from '../../ui/canvas.js';
import {
  button,
  group,
  segmented,
  jitterSlider,
  toggle,
  setPressed,
  type Segmented,
  type Slider,
} from '../../ui/controls.js';
import { h, setAttr, setText, setHidden } from '../../ui/dom.js';
import * as fmt from '../../ui/format.js';
import { download } from '../../ui/download.js';
import { Readout } from '../../ui/readout.js';
import { inputKind, type InputKind } from '../../ui/input-kind.js';
import { touchStartLabel } from '../../games-view/touch-pad.js';
import {
  DISPLAY_RATES,
  GAME_IDS,
  gameDef,
  hashHex,
  keyLabel,
  randomSeed,
  replayFileName,
  type DisplayRate,
  type GameId,
} from '../../games-view/games.js';
import { HighscorePanel } from '../../games-view/highscore-panel.js';
import { ASPECT, drawGame } from '../../games-view/render.js';
import { requestWatch, setLastReplay } from '../../games-view/replay-store.js';
import { replayContents } from '../../games-view/replays.js';
import { GameSession, routeOptions, type LoopMode } from './games-lab.js';
import { attachGameInput, attachTouchControls } from './games-input.js';
import {
  ABOUT,
  REFERENCE_APEX,
  afterGameText,
  howItWorks,
  lede,
  rowsFor,
  runAgainHint,
  startHint,
} from './games-text.js';
import '../../games-view/game-stage.css';
import './games.css';

/** Time scales of the fixed loop the chapter offers. */
const SPEEDS = [0.25, 0.5, 1, 2] as const;
type Speed = (typeof SPEEDS)[number];
const NAME_KEY = 'fixedstep.player';

export const mount = mountChapter((root, head) => new GamesChapter(root, head));

/** The settings box and the controls the chapter reads or updates later. */
interface Controls {
  readonly box: HTMLElement;
  readonly rate: Segmented<DisplayRate>;
  readonly speed: Segmented<Speed>;
  readonly step: HTMLButtonElement;
  readonly jitter: Slider;
  readonly bot: HTMLButtonElement;
  readonly name: HTMLInputElement;
}

class GamesChapter {
  readonly shell: ChapterShell;
  private session: GameSession;
  private gameId: GameId;
  private mode: LoopMode;
  private hz: DisplayRate = 60;
  private jitter = 0;
  private speed: Speed = 1;
  private started = false;
  private wasOver = false;
  private readonly ctl: Controls;
  private readonly scene: SceneCanvas;
  private readonly frame: HTMLElement;
  private readonly startOverlay: HTMLElement;
  private readonly startHint = h('p', { class: 'start-hint' });
  private readonly focusHint = h(
    'p',
    { class: 'focus-hint', 'aria-hidden': 'true' },
    'Click the game to control it with the keyboard',
  );
  private readonly readoutList = h('dl', { class: 'readouts game-readouts' });
  private readouts = new Map<string, Readout>();
  private readonly keysList = h('dl', { class: 'keys' });
  private readonly lede = h('p', { class: 'game-lede' });
  private readonly breaksText = h('p', {});
  private readonly fixedText = h('p', {});
  private readonly seedOut = h('span', { class: 'status-item' });
  private readonly after: HTMLElement;
  private readonly afterTitle = h('h3', { id: 'after-title' });
  private readonly afterText = h('p', { class: 'after-text', 'data-testid': 'after-text' });
  private readonly watchBtn = button('Watch replay', 'control-watch-replay', () => {
    this.watchReplay();
  });
  private readonly downloadBtn = button('Download replay (.fsr)', 'control-download', () => {
    const bytes = this.session.replay();
    if (bytes) download(bytes, replayFileName(this.gameId, this.session.seed, new Date()));
  });
  private readonly announce = h('p', { class: 'sr-only', role: 'status', 'aria-live': 'polite' });
  private readonly highscores: HighscorePanel;
  private detachInput: (() => void) | undefined;
  private detachTouch: (() => void) | undefined;
  /** On-screen controls: shown on touch screens (and with `?touch=1`). */
  private readonly touch = h('div', { class: 'touch-controls', 'data-testid': 'touch-controls' });
  /** What this device plays with: the words on the page and where Play goes follow it. */
  private readonly input: InputKind;

  constructor(root: HTMLElement, head: ChapterHead) {
    const opts = routeOptions(location.hash);
    const forceTouch = new URLSearchParams(location.hash.split('?')[1] ?? '').get('touch') === '1';
    this.input = inputKind(forceTouch);
    this.gameId = opts.game ?? 'runner';
    this.mode = opts.mode ?? 'fixed';
    this.shell = new ChapterShell(root, head, this, {
      lede: lede(this.input),
      timeline: () => this.session,
      restart: () => {
        this.newSession(this.session.seed);
      },
      mode: () => this.modeLine(),
      pausedText: () => (this.started ? ' · paused' : ' · press Play'),
      realClock: {
        title: 'Drive the game with this page’s own animation frames',
        onChange: (on) => {
          this.session.setDisplay(on ? 'real' : { hz: this.hz, jitter: this.jitter });
        },
      },
      startPaused: true,
      driver: { maxRealGapMs: 250 },
    });
    const shell = this.shell;
    this.ctl = this.buildControls(opts.bot ?? false);
    this.highscores = new HighscorePanel({ name: () => this.ctl.name.value });
    this.scene = shell.canvas({ class: 'game-canvas', label: 'The game', testId: 'canvas-game' });
    const play = button('▶ Play', 'control-start', () => {
      this.start();
    });
    play.classList.add('start-btn');
    this.startOverlay = h(
      'div',
      { class: 'start-overlay', 'data-testid': 'start-overlay' },
      play,
      this.startHint,
    );
    this.frame = h(
      'div',
      { class: 'game-frame' },
      this.scene.canvas,
      this.startOverlay,
      this.focusHint,
    );
    // Any touch screen gets the on-screen controls (a touch laptop too, whose main pointer is fine).
    if (this.input !== 'keyboard') this.touch.classList.add('always');
    this.wireCanvas();
    shell.own({
      destroy: () => {
        this.detachInput?.();
        this.detachTouch?.();
      },
    });
    this.after = this.buildAfter();
    shell.append(...this.sections());
    shell.listen(document, 'visibilitychange', () => {
      if (document.hidden && this.started && !this.session.bot) shell.setPaused(true);
    });
    this.session = this.makeSession(opts.seed ?? randomSeed());
    this.afterNewSession();
    if (opts.bot) this.start();
    shell.start();
  }

  // ---------------------------------------------------------------- building

  /** What the panel under the game says and offers after a game (a crash, a game over, End game). */
  private buildAfter(): HTMLElement {
    return h(
      'section',
      {
        class: 'after-game',
        'aria-labelledby': 'after-title',
        'data-testid': 'after-game',
        hidden: true,
      },
      this.afterTitle,
      this.afterText,
      h(
        'div',
        { class: 'after-actions' },
        this.watchBtn,
        this.downloadBtn,
        button('Play again', 'control-play-again', () => {
          this.newSession(randomSeed());
        }),
      ),
    );
  }

  /** The chapter's sections: play (settings, game, numbers, after-game), highscores, the why. */
  private sections(): HTMLElement[] {
    return [
      h(
        'section',
        { class: 'play', 'aria-label': 'Play', 'data-input': this.input },
        this.ctl.box,
        this.frame,
        this.touch,
        h(
          'aside',
          { class: 'game-side', 'aria-label': 'The game’s numbers and keys' },
          h('h3', {}, 'How to play'),
          this.lede,
          this.keysList,
          h('h3', {}, 'Numbers'),
          this.readoutList,
        ),
        this.after,
        this.announce,
      ),
      h('section', { class: 'highscores-section' }, this.highscores.el),
      h(
        'section',
        { class: 'breaks', 'aria-labelledby': 'breaks-title' },
        h('h2', { id: 'breaks-title' }, 'Fixed step or variable Δt'),
        h(
          'div',
          { class: 'why-grid' },
          h('div', { class: 'why-card bad-card' }, h('h3', {}, 'Variable Δt'), this.breaksText),
          h('div', { class: 'why-card fixed-card' }, h('h3', {}, 'Fixed step'), this.fixedText),
        ),
      ),
      howItWorks(),
    ];
  }

  /** The settings: game, loop, display, player, time, speed — and the seed in the status line. */
  private buildControls(bot: boolean): Controls {
    const shell = this.shell;
    const name = h('input', {
      type: 'text',
      id: 'player-name',
      class: 'text-field name-input',
      maxlength: 32,
      autocomplete: 'nickname',
      placeholder: 'your name',
      value: storedName(),
      'data-testid': 'control-name',
    });
    name.addEventListener('change', () => {
      try {
        localStorage.setItem(NAME_KEY, name.value);
      } catch {
        // No storage: the name still goes with the next submission.
      }
    });
    const seg = <T extends string | number>(
      id: string,
      label: string,
      values: readonly T[],
      selected: T,
      text: (v: T) => string,
      onChange: (v: T) => void,
    ) =>
      segmented<T>({
        name: id,
        label,
        testPrefix: `control-${id.replace('game-', '')}`,
        values,
        selected,
        text,
        onChange,
      });
    const gameSeg = seg<GameId>(
      'game',
      'Game',
      GAME_IDS,
      this.gameId,
      (id) => gameDef(id).info.title,
      (id) => {
        this.gameId = id;
        this.newSession(randomSeed());
      },
    );
    const loop = seg<LoopMode>(
      'game-loop',
      'Loop',
      ['fixed', 'variable'],
      this.mode,
      (m) => (m === 'fixed' ? 'Fixed step' : 'Variable Δt'),
      (m) => {
        this.mode = m;
        this.newSession(this.session.seed);
      },
    );
    loop.el.title = 'Switching the loop starts the game again with the same seed';
    const rate = seg<DisplayRate>(
      'game-hz',
      'Display refresh rate',
      DISPLAY_RATES,
      this.hz,
      (hz) => `${hz} Hz`,
      (hz) => {
        this.hz = hz;
        this.session.setDisplay({ hz, jitter: this.jitter });
      },
    );
    const speed = seg<Speed>(
      'game-speed',
      'Speed of simulated time',
      SPEEDS,
      this.speed,
      (v) => (v === 0.25 ? '¼×' : v === 0.5 ? '½×' : `${v}×`),
      (v) => {
        this.speed = v;
        this.session.setSpeed(v);
      },
    );
    speed.el.title =
      'FixedLoop’s time scale: fewer or more ticks per second, each the same size — slow motion that plays back as the same game';
    const step = button('Step 1 tick', 'control-step-tick', () => {
      this.markStarted();
      shell.setPaused(true);
      this.session.stepTick();
    });
    step.title = 'Pause and run exactly one tick (FixedLoop’s single step)';
    const jitter = jitterSlider({
      id: 'game-jitter',
      percent: 0,
      onChange: (jitter) => {
        this.jitter = jitter;
        if (!shell.real) this.session.setDisplay({ hz: this.hz, jitter: this.jitter });
      },
    });
    const botBtn = toggle('Let the bot play', 'control-bot', bot, (on) => {
      this.session.bot = on;
      if (on) this.start();
    });
    botBtn.title = 'The game’s own bot plays you; its inputs are recorded like yours';
    if (shell.time) shell.time.restartBtn.title = 'The same game again: same seed, same course';
    const newBtn = button('New game', 'control-new-game', () => {
      this.newSession(randomSeed());
    });
    newBtn.title = 'Another seed: another course';
    const endBtn = button('End game', 'control-end', () => {
      this.session.end();
    });
    endBtn.title = 'Stop here and keep the replay';
    const box = shell.controls(
      'Game settings',
      group('Game', gameSeg.el),
      group('Loop', loop.el),
      group('Display', rate.el, shell.clockBtn ?? null),
      jitter.el,
      group(
        'Player',
        botBtn,
        h('label', { for: 'player-name', class: 'sr-only' }, 'Your name (for the highscores)'),
        name,
      ),
      shell.timeGroup(newBtn, endBtn),
      group('Speed', speed.el, step),
      shell.status(this.seedOut),
    );
    box.classList.add('game-controls');
    return { box, rate, speed, step, jitter, bot: botBtn, name };
  }

  private wireCanvas(): void {
    const canvas = this.scene.canvas;
    canvas.tabIndex = 0;
    canvas.setAttribute('role', 'application');
    canvas.setAttribute('aria-roledescription', 'game');
    canvas.addEventListener('pointerdown', () => {
      canvas.focus();
    });
    canvas.addEventListener('focus', () => {
      setHidden(this.focusHint, true);
    });
    canvas.addEventListener('blur', () => {
      setHidden(this.focusHint, !this.started || this.session.bot);
    });
  }

  // ---------------------------------------------------------------- sessions

  private makeSession(seed: number): GameSession {
    const session = new GameSession({
      def: gameDef(this.gameId),
      seed,
      mode: this.mode,
      player: this.ctl.name.value,
      display: this.shell.real ? 'real' : { hz: this.hz, jitter: this.jitter },
      bot: this.ctl.bot.getAttribute('aria-pressed') === 'true',
    });
    session.setSpeed(this.speed);
    return session;
  }

  private newSession(seed: number): void {
    this.session = this.makeSession(seed);
    if (this.shell.real) this.shell.driver.restartReal();
    this.afterNewSession();
    if (this.started) {
      this.shell.setPaused(false);
      if (!this.session.bot) this.scene.canvas.focus();
    }
  }

  private afterNewSession(): void {
    const s = this.session;
    const info = s.def.info;
    this.wasOver = false;
    this.detachInput?.();
    this.detachInput = attachGameInput(this.scene.canvas, s, this.shell.driver, () => {
      if (!this.started) this.start();
    });
    this.detachTouch?.();
    this.detachTouch = attachTouchControls(this.touch, s, this.shell.driver, () => {
      if (!this.started) this.start();
    });
    const aspect = String(ASPECT[info.id] ?? 1.5);
    this.scene.canvas.style.aspectRatio = aspect;
    this.frame.style.setProperty('--aspect', aspect);
    this.scene.canvas.setAttribute(
      'aria-label',
      `${info.title}. ${info.buttons.map((b) => `${b.name}: ${b.keys.map(keyLabel).join(' or ')}`).join('; ')}.`,
    );
    const about = ABOUT[this.gameId];
    setText(this.lede, about.lede);
    setText(this.breaksText, about.breaks);
    setText(this.fixedText, about.fixed);
    setText(
      this.startHint,
      startHint(this.input, keyLabel(info.buttons[0]!.keys[0]!), touchStartLabel(info.id)),
    );
    this.keysList.replaceChildren(
      ...info.buttons.flatMap((b) => [
        h('dt', {}, ...b.keys.map((k) => h('kbd', {}, keyLabel(k)))),
        h('dd', {}, b.name.charAt(0).toUpperCase() + b.name.slice(1)),
      ]),
    );
    this.readouts = new Map();
    this.readoutList.replaceChildren(
      ...rowsFor(this.gameId).flatMap((r) => {
        const ro = new Readout('dd', r.key, { hash: r.hash, title: r.title });
        this.readouts.set(r.key, ro);
        return [h('dt', { title: r.title }, r.label), ro.el];
      }),
    );
    this.highscores.setGame(s.def);
    this.highscores.setSubmission(undefined);
    setHidden(this.after, true);
  }

  private markStarted(): void {
    this.started = true;
    setHidden(this.startOverlay, true);
  }

  /** Play: the game runs, and has the keyboard unless the bot plays. */
  private start(): void {
    this.markStarted();
    this.shell.setPaused(false);
    if (!this.session.bot) this.scene.canvas.focus();
  }

  private watchReplay(): void {
    const bytes = this.session.replay();
    if (!bytes) return;
    this.session.end();
    setLastReplay({ bytes, label: `your last game of ${this.session.def.info.title}` });
    requestWatch();
    location.hash = '#/replays';
  }

  // ---------------------------------------------------------------- after a game

  /** Show (or hide) the after-game panel when the game ends or the runner crashes. */
  private refreshAfter(): void {
    const s = this.session;
    const over = s.ended || s.game.over;
    if (over === this.wasOver) return;
    this.wasOver = over;
    setHidden(this.after, !over);
    // The best run stays on offer while the runner runs again.
    const best = s.bestRun();
    this.highscores.setSubmission(best ? { bytes: best.bytes, score: best.score } : undefined);
    if (!over) return;
    const fixed = s.mode === 'fixed';
    const bytes = fixed ? s.replay() : undefined;
    const t = afterGameText({
      title: s.def.info.title,
      gameId: s.def.info.id,
      fixed,
      runnerCrash: !s.ended && s.game.over,
      input: this.input,
      over: s.game.over,
      ticks: s.game.tick,
      score: s.score,
      hud: s.game.hud(),
      best,
      contents: bytes ? replayContents(readReplay(bytes)) : undefined,
    });
    setText(this.afterTitle, t.heading);
    setText(this.afterText, t.text);
    this.watchBtn.disabled = !fixed;
    this.downloadBtn.disabled = !fixed;
    setText(this.announce, `${t.heading}. ${t.summary}.`);
  }

  // ---------------------------------------------------------------- drawing

  private modeLine(): string {
    const s = this.session;
    const display = this.shell.real
      ? `real clock ≈ ${this.shell.measuredHz} Hz`
      : `simulated ${this.hz} Hz${this.jitter > 0 ? ` ±${Math.round(this.jitter * 100)} %` : ''}`;
    const loop =
      s.mode === 'fixed'
        ? `fixed step, ${s.def.info.tickRate} ticks/s${s.speed !== 1 ? ` at ${s.speed}×` : ''}`
        : 'variable Δt';
    return `${display} · ${loop}`;
  }

  /** Bring the controls up to date (the shell calls it after every change). */
  refreshControls(): void {
    const shell = this.shell;
    if (!shell.paused && !this.started) this.markStarted();
    this.ctl.rate.setDisabled(shell.real);
    const fixed = this.session.mode === 'fixed';
    this.ctl.speed.setDisabled(!fixed);
    this.ctl.step.disabled = !fixed || this.session.ended;
    this.ctl.jitter.input.disabled = shell.real;
    setPressed(this.ctl.bot, this.session.bot);
    setHidden(this.startOverlay, this.started);
    this.focusHint.hidden =
      !this.started || this.session.bot || document.activeElement === this.scene.canvas;
  }

  /** Draw the current state and write the readouts (the shell calls it every frame). */
  render(): void {
    const s = this.session;
    setText(this.seedOut, `seed ${s.seed}`);
    setAttr(this.seedOut, 'data-value', String(s.seed));
    this.writeReadouts();
    this.refreshAfter();
    if (!this.scene.fit()) return;
    const hint =
      s.def.info.id === 'runner' && s.game.over && !s.ended
        ? s.bot
          ? 'the bot runs again'
          : runAgainHint(this.input, keyLabel('Space'))
        : undefined;
    drawGame(this.scene, s.game, {
      alpha: s.alpha,
      nowMs: s.timeMs,
      breaches: s.breaches,
      badge:
        s.mode === 'fixed'
          ? { text: `FIXED STEP · ${s.def.info.tickRate} Hz`, tone: 'good' }
          : { text: 'VARIABLE Δt', tone: 'bad' },
      hint,
    });
  }

  private writeReadouts(): void {
    const s = this.session;
    const hud = s.game.hud();
    const put = (key: string, text: string, value: number | string | undefined) => {
      this.readouts.get(key)?.set(text, value);
    };
    for (const k of [
      'score',
      'highscore',
      'kills',
      'flags',
      'deaths',
      'lives',
      'wave',
      'enemies',
    ]) {
      const v = hud[k];
      if (v !== undefined) put(k, fmt.count(v), v);
    }
    if (hud.red !== undefined)
      put('team-score', `${hud.red} : ${hud.blue}`, `${hud.red}:${hud.blue}`);
    const walls = s.throughWalls;
    if (walls !== undefined) {
      put('through-walls', fmt.count(walls), walls);
      this.readouts.get('through-walls')?.warn(walls > 0);
    }
    put('jumps', fmt.count(s.jumps), s.jumps);
    const jump = s.lastJump;
    put('jump-apex', jump ? `${jump.apex.toFixed(3)} m` : '—', jump?.apex);
    this.readouts
      .get('jump-apex')
      ?.warn(jump !== undefined && Math.abs(jump.apex - REFERENCE_APEX) > 1e-9);
    put('tick', fmt.count(s.game.tick), s.game.tick);
    put('sim-time', fmt.seconds(s.simTime), s.simTime);
    const maxDt = s.mode === 'fixed' ? s.def.info.stepSeconds : s.maxDt;
    put('max-dt', fmt.millis(maxDt * 1000), maxDt * 1000);
    const hash = hashHex(s.game);
    put('hash', hash, hash);
    const rec = s.recorder;
    put(
      'replay-bytes',
      rec ? `${fmt.count(rec.inputBytes)} B of inputs` : 'not recorded',
      rec ? rec.inputBytes : undefined,
    );
  }
}

function storedName(): string {
  try {
    return localStorage.getItem(NAME_KEY) ?? 'player';
  } catch {
    return 'player';
  }
}
