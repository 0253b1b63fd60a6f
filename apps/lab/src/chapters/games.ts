/**
 * Chapter 9 — Games. The talk's three games, playable with the keyboard: input through a
 * ButtonSampler fed by `attachKeyboard` with the events' own timestamps, a FixedLoop on the
 * animation frames of a simulated display (or the real clock), drawn between the last two states.
 * The "variable Δt" switch runs the naive `update(dt)` game instead, so the breakage shows. Every
 * fixed-step game is recorded; after it, watch the replay, download it, or submit the score.
 * The numbers come from {@link GameSession}; this module builds the page and draws.
 */
import { attachKeyboard } from 'fixedstep';
import { SceneCanvas } from '../ui/canvas.js';
import {
  TimeControls,
  button,
  group,
  segmented,
  setPressed,
  slider,
  toggle,
  type Segmented,
  type Slider,
} from '../ui/controls.js';
import { code, h, setAttr, setText } from '../ui/dom.js';
import { LabDriver } from '../ui/driver.js';
import * as fmt from '../ui/format.js';
import { Readout } from '../ui/readout.js';
import { HighscorePanel } from './games-highscores.js';
import {
  DISPLAY_RATES,
  GAME_IDS,
  GameSession,
  KEYFRAME_SECONDS,
  gameDef,
  hashHex,
  keyLabel,
  keyMap,
  randomSeed,
  replayFileName,
  routeOptions,
  runnerApex,
  type DisplayRate,
  type GameId,
  type LoopMode,
} from './games-lab.js';
import { ASPECT, drawGame } from './games-render.js';
import { setLastReplay } from './replays-store.js';
import './games.css';

const SKIP_MS = 5000;
/** Time scales of the fixed loop the chapter offers. */
const SPEEDS = [0.25, 0.5, 1, 2] as const;
type Speed = (typeof SPEEDS)[number];
const NAME_KEY = 'fixedstep.player';
const REFERENCE_APEX = runnerApex(1 / 60);

export function mount(root: HTMLElement): () => void {
  const chapter = new GamesChapter(root);
  return () => {
    chapter.destroy();
  };
}

/** What each game says about itself on the page. */
const ABOUT: Readonly<Record<GameId, { lede: string; breaks: string; fixed: string }>> = {
  runner: {
    lede: 'Run, jump over the red blocks, duck under the birds. The speed grows; the highscore stays.',
    breaks:
      'Under a variable Δt each jump is integrated with the frame’s own Δt: at 30 Hz it is lower and shorter than at 144 Hz, so the same timing clears a block on one screen and not on another.',
    fixed: `Under the fixed step every jump is the same: apex ${REFERENCE_APEX.toFixed(3)} m, whatever the display.`,
  },
  ctf: {
    lede: 'You are the red player with the white ring. Take the blue flag from the right and bring it home while yours is on its stand. Bots fill both teams.',
    breaks:
      'Under a variable Δt a bullet moves 900 units/s × Δt at once and is only checked where it lands: at 30 Hz that is 30 units, and the 4-unit walls stop almost nothing. Red rings mark each pass.',
    fixed:
      'Under the fixed step bullets are swept (continuous collision detection) and players move 2.67 units a step against 4-unit walls: nothing goes through.',
  },
  survival: {
    lede: 'Waves of enemies run at you. Keep moving, shoot them down, use the walls. Fifteen lives.',
    breaks:
      'Under a variable Δt an enemy pressing on a wall during a long frame jumps past its middle and is pushed out on your side. Red rings mark each pass.',
    fixed:
      'Under the fixed step an enemy moves at most 7 units a step against walls 10 thick (minWallSize = maxSpeed × step): it slides along the wall and comes round its end.',
  },
};

interface Row {
  key: string;
  label: string;
  title?: string;
  hash?: boolean;
}

/** The readouts beside the game (test ids `readout-${key}`). */
function rowsFor(id: GameId): Row[] {
  const hud: Row[] =
    id === 'runner'
      ? [
          { key: 'score', label: 'Score' },
          { key: 'highscore', label: 'Highscore' },
          { key: 'jumps', label: 'Jumps' },
          {
            key: 'jump-apex',
            label: 'Last jump apex',
            title: `The highest point of the last jump. Under the fixed step: always ${REFERENCE_APEX.toFixed(3)} m.`,
          },
        ]
      : id === 'ctf'
        ? [
            { key: 'kills', label: 'Kills' },
            { key: 'flags', label: 'Flags captured' },
            { key: 'deaths', label: 'Deaths' },
            { key: 'team-score', label: 'Red : blue' },
          ]
        : [
            { key: 'kills', label: 'Kills' },
            { key: 'lives', label: 'Lives' },
            { key: 'wave', label: 'Wave' },
            { key: 'enemies', label: 'Enemies' },
          ];
  const walls: Row[] =
    id === 'runner'
      ? []
      : [
          {
            key: 'through-walls',
            label: 'Through walls',
            title:
              'Bullets, players or enemies whose path went through a wall (the game’s own count)',
          },
        ];
  return [
    ...hud,
    ...walls,
    { key: 'tick', label: 'Tick', title: 'Updates run so far' },
    { key: 'sim-time', label: 'Sim time', title: 'Simulated time' },
    { key: 'max-dt', label: 'Longest Δt', title: 'The longest Δt one update was given' },
    { key: 'hash', label: 'State hash', title: 'FNV-1a 64 of the game’s state now', hash: true },
    {
      key: 'replay-bytes',
      label: 'Replay so far',
      title: 'The recording: inputs, a hash every second, a snapshot every 5 s',
    },
  ];
}

class GamesChapter {
  private session: GameSession;
  private gameId: GameId;
  private mode: LoopMode;
  private hz: DisplayRate = 60;
  private jitter = 0;
  private real = false;
  private started = false;
  private wasOver = false;
  private readonly driver: LabDriver;
  private readonly scene: SceneCanvas;
  private readonly frame: HTMLElement;
  private readonly time: TimeControls;
  private readonly gameSeg: Segmented<GameId>;
  private readonly loopSeg: Segmented<LoopMode>;
  private readonly rateSeg: Segmented<DisplayRate>;
  private readonly speedSeg: Segmented<Speed>;
  private readonly stepBtn: HTMLButtonElement;
  private speed: Speed = 1;
  private readonly jitterSlider: Slider;
  private readonly clockBtn: HTMLButtonElement;
  private readonly botBtn: HTMLButtonElement;
  private readonly nameInput: HTMLInputElement;
  private readonly startOverlay: HTMLElement;
  private readonly startHint: HTMLElement;
  private readonly focusHint: HTMLElement;
  private readonly readoutList: HTMLElement;
  private readouts = new Map<string, Readout>();
  private readonly keysList: HTMLElement;
  private readonly lede: HTMLElement;
  private readonly breaksText: HTMLElement;
  private readonly fixedText: HTMLElement;
  private readonly seedOut: HTMLElement;
  private readonly after: HTMLElement;
  private readonly afterTitle: HTMLElement;
  private readonly afterText: HTMLElement;
  private readonly watchBtn: HTMLButtonElement;
  private readonly downloadBtn: HTMLButtonElement;
  private readonly againBtn: HTMLButtonElement;
  private readonly announce: HTMLElement;
  private readonly highscores = new HighscorePanel();
  private detachKeys: (() => void) | undefined;
  private readonly cleanups: (() => void)[] = [];

  constructor(private readonly root: HTMLElement) {
    const opts = routeOptions(location.hash);
    this.gameId = opts.game ?? 'runner';
    this.mode = opts.mode ?? 'fixed';
    this.driver = new LabDriver(
      {
        advance: (ms) => {
          this.session.advanceBy(ms);
        },
        realFrame: (t) => {
          this.session.realFrame(t);
        },
        render: () => {
          this.render();
        },
      },
      { maxRealGapMs: 250 },
    );
    this.driver.setPaused(true);

    // ------------------------------------------------------------ controls
    this.gameSeg = segmented<GameId>({
      name: 'game',
      label: 'Game',
      testPrefix: 'control-game',
      values: GAME_IDS,
      selected: this.gameId,
      text: (id) => gameDef(id).info.title,
      onChange: (id) => {
        this.gameId = id;
        this.newSession(randomSeed());
      },
    });
    this.loopSeg = segmented<LoopMode>({
      name: 'game-loop',
      label: 'Loop',
      testPrefix: 'control-loop',
      values: ['fixed', 'variable'],
      selected: this.mode,
      text: (m) => (m === 'fixed' ? 'Fixed step' : 'Variable Δt'),
      onChange: (m) => {
        this.mode = m;
        this.newSession(this.session.seed);
      },
    });
    this.loopSeg.el.title = 'Switching the loop starts the game again with the same seed';
    this.rateSeg = segmented<DisplayRate>({
      name: 'game-hz',
      label: 'Display refresh rate',
      testPrefix: 'control-hz',
      values: DISPLAY_RATES,
      selected: this.hz,
      text: (hz) => `${hz} Hz`,
      onChange: (hz) => {
        this.hz = hz;
        this.session.setDisplay({ hz, jitter: this.jitter });
      },
    });
    this.speedSeg = segmented<Speed>({
      name: 'game-speed',
      label: 'Speed of simulated time',
      testPrefix: 'control-speed',
      values: SPEEDS,
      selected: this.speed,
      text: (v) => (v === 0.25 ? '¼×' : v === 0.5 ? '½×' : `${v}×`),
      onChange: (v) => {
        this.speed = v;
        this.session.setSpeed(v);
      },
    });
    this.speedSeg.el.title =
      'FixedLoop’s time scale: fewer or more ticks per second, each the same size — slow motion that plays back as the same game';
    this.stepBtn = button('Step 1 tick', 'control-step-tick', () => {
      if (!this.started) this.start();
      this.driver.setPaused(true);
      this.session.stepTick();
      this.refreshControls();
      this.render();
    });
    this.stepBtn.title = 'Pause and run exactly one tick (FixedLoop’s single step)';
    this.jitterSlider = slider({
      id: 'game-jitter',
      label: 'Jitter',
      testId: 'control-jitter',
      min: 0,
      max: 30,
      step: 1,
      value: 0,
      text: (v) => `±${v} %`,
      onChange: (v) => {
        this.jitter = v / 100;
        if (!this.real) this.session.setDisplay({ hz: this.hz, jitter: this.jitter });
      },
    });
    this.clockBtn = toggle('Real clock', 'control-real-clock', false, (on) => {
      this.setReal(on);
    });
    this.clockBtn.title = 'Drive the game with this page’s own animation frames';
    this.botBtn = toggle('Let the bot play', 'control-bot', opts.bot ?? false, (on) => {
      this.session.bot = on;
      if (on) this.start();
      this.refreshControls();
    });
    this.botBtn.title = 'The game’s own bot plays you; its inputs are recorded like yours';
    this.nameInput = h('input', {
      type: 'text',
      id: 'player-name',
      class: 'name-input',
      maxlength: 32,
      autocomplete: 'nickname',
      placeholder: 'your name',
      value: storedName(),
      'data-testid': 'control-name',
    });
    this.nameInput.addEventListener('change', () => {
      try {
        localStorage.setItem(NAME_KEY, this.nameInput.value);
      } catch {
        // No storage: the name still goes into the next game's replay.
      }
    });
    this.time = new TimeControls({
      skipMs: SKIP_MS,
      onPause: () => {
        if (!this.started) this.start();
        else this.driver.setPaused(!this.driver.isPaused);
        this.refreshControls();
      },
      onSkip: () => {
        this.session.advanceBy(SKIP_MS);
      },
      onRestart: () => {
        this.newSession(this.session.seed);
      },
    });
    this.time.restartBtn.title = 'The same game again: same seed, same course';
    const newBtn = button('New game', 'control-new-game', () => {
      this.newSession(randomSeed());
    });
    newBtn.title = 'Another seed: another course';
    const endBtn = button('End game', 'control-end', () => {
      this.session.end();
      this.render();
    });
    endBtn.title = 'Stop here and keep the replay';
    this.seedOut = h('span', { class: 'status-item' });

    const controls = h(
      'div',
      { class: 'controls game-controls', role: 'group', 'aria-label': 'Game settings' },
      group('Game', this.gameSeg.el),
      group('Loop', this.loopSeg.el),
      group('Display', this.rateSeg.el, this.clockBtn),
      this.jitterSlider.el,
      group(
        'Player',
        this.botBtn,
        h('label', { for: 'player-name', class: 'sr-only' }, 'Your name (stored in the replay)'),
        this.nameInput,
      ),
      group('Time', ...this.time.buttons, newBtn, endBtn),
      group('Speed', this.speedSeg.el, this.stepBtn),
      h('div', { class: 'status' }, ...this.time.status, this.seedOut),
    );
    const settle = () => {
      this.refreshControls();
      this.render();
    };
    controls.addEventListener('click', settle);
    controls.addEventListener('change', settle);

    // ------------------------------------------------------------ the stage
    this.scene = new SceneCanvas({
      class: 'game-canvas',
      label: 'The game',
      testId: 'canvas-game',
    });
    const canvas = this.scene.canvas;
    canvas.tabIndex = 0;
    canvas.setAttribute('role', 'application');
    canvas.setAttribute('aria-roledescription', 'game');
    const startBtn = h(
      'button',
      { type: 'button', class: 'btn start-btn', 'data-testid': 'control-start' },
      '▶ Play',
    );
    startBtn.addEventListener('click', () => {
      this.start();
      this.refreshControls();
    });
    this.startHint = h('p', { class: 'start-hint' });
    this.startOverlay = h(
      'div',
      { class: 'start-overlay', 'data-testid': 'start-overlay' },
      startBtn,
      this.startHint,
    );
    this.focusHint = h(
      'p',
      { class: 'focus-hint', 'aria-hidden': 'true' },
      'Click the game to control it with the keyboard',
    );
    canvas.addEventListener('pointerdown', () => {
      canvas.focus();
    });
    const onFocus = () => {
      this.focusHint.hidden = true;
    };
    const onBlur = () => {
      this.focusHint.hidden = !this.started || this.session.bot;
      this.session.releaseAll(this.session.timeMs + this.driver.sinceLastFrame());
    };
    canvas.addEventListener('focus', onFocus);
    canvas.addEventListener('blur', onBlur);
    canvas.addEventListener('keydown', (e) => {
      if (e.repeat) return;
      if (keyMap(this.session.def.info)[e.code] !== undefined) {
        this.session.keyEvents++;
        if (!this.started) {
          this.start();
          this.refreshControls();
        }
      }
    });

    this.readoutList = h('dl', { class: 'readouts game-readouts' });
    this.keysList = h('dl', { class: 'keys' });
    this.lede = h('p', { class: 'game-lede' });
    const side = h(
      'aside',
      { class: 'game-side', 'aria-label': 'The game’s numbers and keys' },
      h('h3', {}, 'How to play'),
      this.lede,
      this.keysList,
      h('h3', {}, 'Numbers'),
      this.readoutList,
    );

    // After a game.
    this.afterTitle = h('h3', { id: 'after-title' });
    this.afterText = h('p', { class: 'after-text' });
    this.watchBtn = button('Watch replay', 'control-watch-replay', () => {
      this.watchReplay();
    });
    this.downloadBtn = button('Download replay (.fsr)', 'control-download', () => {
      this.download();
    });
    this.againBtn = button('Play again', 'control-play-again', () => {
      this.newSession(randomSeed());
    });
    this.after = h(
      'section',
      {
        class: 'after-game',
        'aria-labelledby': 'after-title',
        'data-testid': 'after-game',
        hidden: true,
      },
      this.afterTitle,
      this.afterText,
      h('div', { class: 'after-actions' }, this.watchBtn, this.downloadBtn, this.againBtn),
    );
    this.announce = h('p', { class: 'sr-only', role: 'status', 'aria-live': 'polite' });

    this.frame = h('div', { class: 'game-frame' }, canvas, this.startOverlay, this.focusHint);
    this.breaksText = h('p', {});
    this.fixedText = h('p', {});

    // ------------------------------------------------------------ page
    root.append(
      h(
        'article',
        { class: 'chapter games-chapter' },
        h(
          'header',
          { class: 'chapter-head' },
          h('p', { class: 'eyebrow' }, 'Chapter 9'),
          h('h1', {}, 'Games'),
          h(
            'p',
            { class: 'lede' },
            'The talk’s three games — the runner (“SCORE 0 / HIGHSCORE 35730”), capture the flag (“Kills: 1, Flags captured: 0”) and survival (“Kills: 0, Lives: 15”). Play them with the keyboard on any display, then flip the loop to a variable Δt and watch them break.',
          ),
        ),
        h(
          'section',
          { class: 'play', 'aria-label': 'Play' },
          controls,
          this.frame,
          side,
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
      ),
    );

    const onVisibility = () => {
      if (document.hidden && this.started && !this.session.bot) {
        this.driver.setPaused(true);
        this.refreshControls();
      }
    };
    document.addEventListener('visibilitychange', onVisibility);
    this.cleanups.push(() => {
      document.removeEventListener('visibilitychange', onVisibility);
    });

    this.session = this.makeSession(opts.seed ?? randomSeed());
    this.afterNewSession();
    if (opts.bot) this.start();
    this.refreshControls();
    this.driver.start();
  }

  destroy(): void {
    this.driver.destroy();
    this.detachKeys?.();
    this.scene.destroy();
    for (const c of this.cleanups) c();
    this.root.replaceChildren();
  }

  // ---------------------------------------------------------------- sessions

  private makeSession(seed: number): GameSession {
    const session = new GameSession({
      def: gameDef(this.gameId),
      seed,
      mode: this.mode,
      player: this.nameInput.value,
      display: this.real ? 'real' : { hz: this.hz, jitter: this.jitter },
      bot: this.botBtn.getAttribute('aria-pressed') === 'true',
    });
    session.setSpeed(this.speed);
    return session;
  }

  private newSession(seed: number): void {
    this.session = this.makeSession(seed);
    if (this.real) this.driver.restartReal();
    this.afterNewSession();
    if (this.started) {
      this.driver.setPaused(false);
      if (!this.session.bot) this.scene.canvas.focus();
    }
    this.refreshControls();
    this.render();
  }

  private afterNewSession(): void {
    const s = this.session;
    const def = s.def;
    this.wasOver = false;
    this.detachKeys?.();
    this.detachKeys = attachKeyboard(this.scene.canvas, s.sampler, keyMap(def.info), (e) =>
      this.eventTime(e.timeStamp),
    );
    const aspect = String(ASPECT[def.info.id] ?? 1.5);
    this.scene.canvas.style.aspectRatio = aspect;
    this.frame.style.setProperty('--aspect', aspect);
    this.scene.canvas.setAttribute(
      'aria-label',
      `${def.info.title}. ${def.info.buttons.map((b) => `${b.name}: ${b.keys.map(keyLabel).join(' or ')}`).join('; ')}.`,
    );
    const about = ABOUT[this.gameId];
    setText(this.lede, about.lede);
    setText(this.breaksText, about.breaks);
    setText(this.fixedText, about.fixed);
    setText(
      this.startHint,
      `or press ${keyLabel(def.info.buttons[0]!.keys[0]!)} with the game focused · or let the bot play`,
    );
    this.keysList.replaceChildren(
      ...def.info.buttons.flatMap((b) => [
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
    this.highscores.setGame(def);
    this.highscores.setSubmission(undefined);
    this.after.hidden = true;
  }

  /** The session time of an input event (its timestamp on the page's clock). */
  private eventTime(timeStamp: number): number {
    const s = this.session;
    const ago = Math.max(0, performance.now() - timeStamp);
    if (this.driver.isReal) {
      const r = this.driver.realNow();
      return r === undefined ? s.timeMs : s.sessionTimeOfReal(r - ago);
    }
    return s.timeMs + Math.max(0, this.driver.sinceLastFrame() - ago);
  }

  private start(): void {
    if (!this.started) {
      this.started = true;
      this.startOverlay.hidden = true;
    }
    this.driver.setPaused(false);
    if (!this.session.bot) this.scene.canvas.focus();
  }

  private setReal(on: boolean): void {
    this.real = on;
    this.driver.setReal(on);
    this.session.setDisplay(on ? 'real' : { hz: this.hz, jitter: this.jitter });
    setPressed(this.clockBtn, on);
    this.refreshControls();
  }

  // ---------------------------------------------------------------- after a game

  private watchReplay(): void {
    const bytes = this.session.replay();
    if (!bytes) return;
    this.session.end();
    setLastReplay({ bytes, label: `your last game of ${this.session.def.info.title}` });
    location.hash = '#/replays';
  }

  private download(): void {
    const bytes = this.session.replay();
    if (!bytes) return;
    const blob = new Blob([bytes as Uint8Array<ArrayBuffer>], { type: 'application/octet-stream' });
    const url = URL.createObjectURL(blob);
    const a = h('a', {
      href: url,
      download: replayFileName(this.session.def.info.id, this.session.seed, new Date()),
    });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => {
      URL.revokeObjectURL(url);
    }, 10_000);
  }

  /** Show (or hide) the after-game panel when the game ends or the runner crashes. */
  private refreshAfter(): void {
    const s = this.session;
    const over = s.ended || s.game.over;
    if (over === this.wasOver) return;
    this.wasOver = over;
    this.after.hidden = !over;
    if (!over) {
      this.highscores.setSubmission(undefined);
      return;
    }
    const title = s.def.info.title;
    const runnerCrash = !s.ended && s.game.over;
    const score = s.score;
    const fixed = s.mode === 'fixed';
    const bytes = fixed ? s.replay() : undefined;
    setText(this.afterTitle, runnerCrash ? 'Crashed' : s.game.over ? 'Game over' : 'Game ended');
    const summary =
      score !== undefined ? `${title}: ${fmt.count(score)} points` : `${title}: ${hudLine(s)}`;
    setText(
      this.afterText,
      fixed
        ? `${summary} in ${fmt.count(s.game.tick)} ticks. The replay holds only the inputs and the seed (${fmt.count(bytes?.length ?? 0)} bytes) and plays back bit for bit${score !== undefined ? '; submit it below to rank the score' : ''}.${runnerCrash ? ' Press Space to run again — the replay goes on.' : ''}`
        : `${summary}. This game ran under a variable Δt: it was not recorded — its updates depend on the frame times, so no replay could reproduce it. Switch the loop to the fixed step to record.`,
    );
    this.watchBtn.disabled = !fixed;
    this.downloadBtn.disabled = !fixed;
    this.highscores.setSubmission(bytes && score !== undefined ? { bytes, score } : undefined);
    setText(this.announce, `${this.afterTitle.textContent}. ${summary}.`);
  }

  // ---------------------------------------------------------------- drawing

  private refreshControls(): void {
    const paused = this.driver.isPaused;
    this.time.refresh(paused, !this.real);
    this.rateSeg.setDisabled(this.real);
    const fixed = this.session.mode === 'fixed';
    this.speedSeg.setDisabled(!fixed);
    this.stepBtn.disabled = !fixed || this.session.ended;
    this.jitterSlider.input.disabled = this.real;
    setPressed(this.botBtn, this.session.bot);
    this.startOverlay.hidden = this.started;
    this.focusHint.hidden =
      !this.started || this.session.bot || document.activeElement === this.scene.canvas;
  }

  private render(): void {
    const s = this.session;
    const running = this.started && !this.driver.isPaused;
    const display = this.real
      ? `real clock ≈ ${this.driver.measuredHz} Hz`
      : `simulated ${this.hz} Hz${this.jitter > 0 ? ` ±${Math.round(this.jitter * 100)} %` : ''}`;
    this.time.show(
      s.timeMs,
      `${display} · ${s.mode === 'fixed' ? `fixed step, ${s.def.info.tickRate} ticks/s${s.speed !== 1 ? ` at ${s.speed}×` : ''}` : 'variable Δt'}${running ? '' : this.started ? ' · paused' : ' · press Play'}`,
    );
    setText(this.seedOut, `seed ${s.seed}`);
    setAttr(this.seedOut, 'data-value', String(s.seed));
    this.writeReadouts();
    this.refreshAfter();
    if (!this.scene.fit()) return;
    const hint =
      s.def.info.id === 'runner' && s.game.over && !s.ended
        ? this.session.bot
          ? 'the bot runs again'
          : `${keyLabel('Space')} to run again`
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
    put('hash', hashHex(s.game), hashHex(s.game));
    const rec = s.recorder;
    put(
      'replay-bytes',
      rec ? `${fmt.count(rec.inputBytes)} B of inputs` : 'not recorded',
      rec ? rec.inputBytes : undefined,
    );
  }
}

function hudLine(s: GameSession): string {
  return Object.entries(s.game.hud())
    .filter(([k]) => k !== 'timeLeft')
    .map(([k, v]) => `${k} ${v}`)
    .join(', ');
}

function storedName(): string {
  try {
    return localStorage.getItem(NAME_KEY) ?? 'player';
  } catch {
    return 'player';
  }
}

function howItWorks(): HTMLElement {
  return h(
    'section',
    { class: 'how', 'aria-labelledby': 'how-title' },
    h('h2', { id: 'how-title' }, 'How this page works'),
    h(
      'p',
      {},
      'Keys go into a ButtonSampler with the time the browser stamped on the event. Every display frame the FixedLoop says how many 1/60 s steps are due, and each step gets exactly the presses that happened before its end — so a tap is never lost or doubled, whatever the frame rate. The canvas then draws every moving thing between its last two states, at α = accumulator / step.',
    ),
    code(
      'const sampler = new ButtonSampler();\nattachKeyboard(canvas, sampler, keys, (e) => timeOf(e.timeStamp));\n\nconst n = loop.frame(now);\nfor (let j = 0; j < n; j++) {\n  inputs[0] = sampler.sample(loop, j);\n  game.step(inputs);\n  recorder.record(inputs, game);\n}\ndraw(game, loop.alpha);',
    ),
    h(
      'p',
      {},
      `The recording is the replay: the inputs of every tick (run-length coded), the seed, a state hash every second and a snapshot every ${KEYFRAME_SECONDS} s for seeking. “Variable Δt” swaps the FixedLoop for the talk’s naive loop, which calls update(dt) once per frame with that frame’s Δt; it is not recorded, because nothing could replay it.`,
    ),
  );
}
