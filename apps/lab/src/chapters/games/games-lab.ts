/**
 * The model behind chapter 9, "Games": one of the talk's games on a simulated display (or the
 * page's real clock), fed by the keyboard through a {@link ButtonSampler} or by the game's bot,
 * stepped by a {@link FixedLoop} — or, with the "variable Δt" switch, by the talk's naive
 * {@link VariableLoop} calling `update(dt)`, so the breakage shows — either way through the
 * library's {@link FrameStepper}, as a user's game would be (docs/guide/loop.md). Every fixed-step
 * game is recorded with a {@link ReplayRecorder}, and the best run of the session is kept for the
 * highscore table. No DOM here: the unit tests drive it exactly as the page does.
 */
import {
  ButtonSampler,
  FixedLoop,
  FrameStepper,
  ReplayRecorder,
  VariableLoop,
  type ButtonInput,
  type Loop,
} from 'fixedstep';
import {
  CtfGame,
  RUNNER_TUNING,
  RunnerGame,
  SurvivalGame,
  type Game,
  type RegisteredGame,
} from '@fixedstep/games';
import { DisplayClock, OnDisplayClock } from '../../shell/display-clock.js';
import {
  GAME_IDS,
  cleanName,
  scoreOf,
  type Breach,
  type DisplaySpec,
  type GameId,
} from '../../games-view/games.js';
import { labRecording } from '../../games-view/replays.js';

/** Which loop runs the game: the production fixed step, or the talk's naive variable Δt. */
export type LoopMode = 'fixed' | 'variable';

/**
 * The apex of a runner jump taken on flat ground, m, when every update of the jump lasts `dt`
 * seconds: the runner's own semi-implicit Euler (`v -= g·dt; y += v·dt`). Under the fixed step
 * every jump reaches exactly `runnerApex(1/60)`; under a variable Δt the apex follows the frames.
 */
export function runnerApex(dt: number): number {
  let v = RUNNER_TUNING.jumpSpeed;
  let y = 0;
  let top = 0;
  for (;;) {
    v -= RUNNER_TUNING.gravity * dt;
    y += v * dt;
    if (y <= 0) return top;
    if (y > top) top = y;
  }
}

/**
 * A recording the highscore server can rank: the replay up to the end of one run (a runner's crash,
 * a game over, or the moment the player ended the game) and the score its last tick has.
 */
export interface RankedRun {
  /** The score the replay ends on: what the server re-simulates and ranks. */
  score: number;
  /** Ticks recorded up to the end of the run. */
  ticks: number;
  /** The replay file. */
  bytes: Uint8Array;
}

/** A runner jump, measured: its apex (m) and time in the air (s of simulated time). */
export interface JumpMeasure {
  apex: number;
  airtime: number;
}

export interface GameSessionOptions {
  def: RegisteredGame;
  seed: number;
  mode: LoopMode;
  /** The player's name, stored in the replay (trimmed to 32 characters). */
  player: string;
  /** A simulated display, or `'real'` for the page's own animation frames. */
  display: DisplaySpec | 'real';
  /** Start with the bot playing. Default false. */
  bot?: boolean;
}

/**
 * One game being played: the game, its loop, its display, its input and (under the fixed step)
 * its recording. Time is the session's own time line in ms from the start: display frames and
 * input events are both placed on it.
 */
export class GameSession extends OnDisplayClock {
  readonly def: RegisteredGame;
  readonly game: Game;
  readonly mode: LoopMode;
  readonly seed: number;
  readonly player: string;
  readonly loop: Loop;
  readonly sampler = new ButtonSampler();
  /** Runs each display frame's steps, each with the input sampled for its own tick. */
  private readonly stepper: FrameStepper;
  /** The recording (fixed step only: a variable-Δt game cannot be replayed). */
  readonly recorder: ReplayRecorder | undefined;
  /** Let the game's bot play player 0 (the keyboard is then ignored). */
  bot: boolean;
  /** Whether the game has ended (over, or ended by the player); nothing runs after. */
  ended = false;
  /** Display frames taken. */
  frames = 0;
  /** The longest Δt one update was given, s. */
  maxDt = 0;
  /** Button events received from the keyboard. */
  keyEvents = 0;
  /** Runner: jumps taken, the last one measured, the apex of the jump in progress. */
  jumps = 0;
  lastJump: JumpMeasure | undefined;
  /** Things seen going through a wall (the latest, for drawing). */
  readonly breaches: Breach[] = [];
  protected readonly clock: DisplayClock;
  private readonly inputs: ButtonInput[] = [0];
  /** The session time of the display frame being stepped, ms (for the breach markers). */
  private frameMs = 0;
  private airApex = 0;
  private airStart = 0;
  private wasOnGround = true;
  private wasOver = false;
  private simSeconds = 0;
  /** The best run that has ended so far (the runner crashes and runs again: each crash ends one). */
  private best: RankedRun | undefined;

  constructor(options: GameSessionOptions) {
    super();
    this.def = options.def;
    this.mode = options.mode;
    this.seed = options.seed >>> 0;
    this.player = cleanName(options.player);
    this.bot = options.bot ?? false;
    const config = { seed: this.seed, players: 1 };
    this.game = this.def.create(config);
    this.loop =
      this.mode === 'fixed' ? new FixedLoop({ step: this.def.info.tickRate }) : new VariableLoop();
    if (this.mode === 'fixed') {
      this.recorder = new ReplayRecorder(labRecording(this.def, config, this.player));
      this.recorder.start(this.game);
    }
    this.stepper = new FrameStepper({
      loop: this.loop,
      input: this.sampler,
      update: (dt, human) => {
        this.update(dt, human);
      },
    });
    // The time line's origin, not a frame to step (the talk's variable loop would update once).
    this.loop.frame(0);
    this.clock = new DisplayClock(options.display, (t) => {
      this.runFrame(t);
    });
  }

  /** The display in use. */
  get displaySpec(): DisplaySpec | 'real' {
    return this.clock.displaySpec as DisplaySpec | 'real';
  }

  /** Simulated seconds: tick × step under the fixed step, the sum of every Δt under the variable one. */
  get simTime(): number {
    return this.mode === 'fixed' ? this.game.tick * this.def.info.stepSeconds : this.simSeconds;
  }

  /** How far between the last two states to draw: the loop's alpha (1 under a variable Δt). */
  get alpha(): number {
    return this.mode === 'fixed' && !this.ended ? this.loop.alpha : 1;
  }

  /** The things that went through walls so far, as the game counts them (0 for the runner). */
  get throughWalls(): number | undefined {
    return this.game.hud().throughWalls;
  }

  /** Switch the display (rate, jitter, or the real clock); the game goes on. */
  setDisplay(spec: DisplaySpec | 'real'): void {
    this.clock.setDisplay(spec);
  }

  /** A key went down or up at session time `timeMs`. Ignored once the game has ended. */
  press(timeMs: number, button: number, down: boolean): void {
    if (this.ended) return;
    this.sampler.push(timeMs, button, down);
    this.keyEvents++;
  }

  /** Let go of every button (the window lost focus). */
  releaseAll(timeMs: number): void {
    // An up for a button that is not down changes nothing; a press still queued keeps its tick.
    for (const b of this.def.info.buttons) this.sampler.push(timeMs, b.button, false);
  }

  /**
   * Fixed step only: how fast simulated time runs against the display's (FixedLoop's time
   * scale: more or fewer ticks per second, never a longer or shorter tick, so the recording and
   * its replay stay the same game). Ignored under a variable Δt.
   */
  setSpeed(scale: number): void {
    if (this.loop instanceof FixedLoop) this.loop.setTimeScale(scale);
  }

  /** The time scale (1 under a variable Δt). */
  get speed(): number {
    return this.loop instanceof FixedLoop ? this.loop.timeScale : 1;
  }

  /**
   * Fixed step only: run exactly one tick now, at the session's time (FixedLoop's pause and
   * single step), with every input received up to then. For looking at a game tick by tick while
   * the clock stands still; the time since the last display frame is not simulated (paused
   * time). Returns whether a tick ran.
   */
  stepTick(): boolean {
    const loop = this.loop;
    if (!(loop instanceof FixedLoop) || this.ended) return false;
    const before = this.game.tick;
    loop.pause();
    loop.singleStep();
    this.runFrame(Math.max(this.clock.lastFrameMs, this.clock.timeMs));
    loop.resume();
    return this.game.tick > before;
  }

  /** End the game now (the recording stays as it is). */
  end(): void {
    this.ended = true;
  }

  /** The replay so far (fixed step only). Recording goes on if the game does. */
  replay(): Uint8Array | undefined {
    return this.recorder?.finish();
  }

  /**
   * The best run of this session, for the highscore table: the highest score among the runs that
   * ended (each runner crash ends one) and, once the game has ended or is over, the run it ended
   * in — each as the replay up to that run's last tick, so the server's re-simulation ends on
   * exactly that score. Ties keep the earlier run. Undefined under a variable Δt (not recorded),
   * for a game without a score, and while the first run is still going.
   */
  bestRun(): RankedRun | undefined {
    const score = this.score;
    const rec = this.recorder;
    if (!rec || score === undefined) return undefined;
    const now = this.ended || this.game.over;
    if (now && (this.best === undefined || score > this.best.score)) {
      return { score, ticks: rec.tickCount, bytes: rec.finish() };
    }
    return this.best;
  }

  /** The score the server would rank, now. */
  get score(): number | undefined {
    return scoreOf(this.def, this.game);
  }

  private runFrame(t: number): void {
    if (this.ended) return;
    this.frames++;
    this.frameMs = t;
    this.stepper.frame(t);
  }

  /**
   * One step of the frame: `human` is the keys' input for this tick — sampled even when the bot
   * plays, so presses never pile up. A shooter's game over ends the session: the frame's steps
   * after it do nothing.
   */
  private update(dt: number, human: ButtonInput): void {
    if (this.ended) return;
    const game = this.game;
    this.inputs[0] = this.bot ? this.def.bot(game, 0) : human;
    if (this.mode === 'fixed') {
      game.step(this.inputs);
      this.recorder?.record(this.inputs, game);
    } else {
      game.update(dt, this.inputs);
      this.simSeconds += dt;
      if (dt > this.maxDt) this.maxDt = dt;
    }
    this.afterUpdate(this.frameMs);
    if (game.over && !(game instanceof RunnerGame)) this.ended = true;
  }

  /** A run just ended (a runner crash, a game over): keep its replay if it is the best yet. */
  private runEnded(): void {
    const score = this.score;
    const rec = this.recorder;
    if (!rec || score === undefined) return;
    if (this.best === undefined || score > this.best.score) {
      this.best = { score, ticks: rec.tickCount, bytes: rec.finish() };
    }
  }

  private afterUpdate(t: number): void {
    const game = this.game;
    if (game.over && !this.wasOver) this.runEnded();
    this.wasOver = game.over;
    if (game instanceof RunnerGame) {
      const ground = game.onGround;
      if (this.wasOnGround && !ground && !game.over) {
        this.jumps++;
        this.airApex = 0;
        this.airStart = this.simTime;
      }
      if (!ground) this.airApex = Math.max(this.airApex, game.y);
      if (!this.wasOnGround && ground && !game.over) {
        this.lastJump = { apex: this.airApex, airtime: this.simTime - this.airStart };
      }
      this.wasOnGround = ground || game.over;
      return;
    }
    if (game instanceof CtfGame) {
      const s = game.state;
      this.checkBullets(game.walls, s.bullets, t);
      for (let p = 0; p < s.x.length; p++) {
        if (s.alive[p] === 1 && game.walls.crosses(s.prevX[p]!, s.prevY[p]!, s.x[p]!, s.y[p]!)) {
          this.breach(s.x[p]!, s.y[p]!, t, 'player');
        }
      }
      return;
    }
    if (game instanceof SurvivalGame) {
      const s = game.state;
      this.checkBullets(game.walls, s.bullets, t);
      for (let e = 0; e < s.enemyAlive.length; e++) {
        if (s.enemyAlive[e] !== 1) continue;
        if (game.walls.crosses(s.enemyPrevX[e]!, s.enemyPrevY[e]!, s.ex[e]!, s.ey[e]!)) {
          this.breach(s.ex[e]!, s.ey[e]!, t, 'enemy');
        }
      }
    }
  }

  private checkBullets(walls: CtfGame['walls'], b: CtfGame['state']['bullets'], t: number): void {
    for (let i = 0; i < b.capacity; i++) {
      if (b.alive[i] !== 1) continue;
      if (walls.crosses(b.prevX[i]!, b.prevY[i]!, b.x[i]!, b.y[i]!)) {
        this.breach(b.x[i]!, b.y[i]!, t, 'bullet');
      }
    }
  }

  private breach(x: number, y: number, atMs: number, what: Breach['what']): void {
    this.breaches.push({ x, y, atMs, what });
    if (this.breaches.length > 64) this.breaches.splice(0, this.breaches.length - 64);
  }
}

/** Options in the route: `#/games?game=ctf&seed=7&bot=1`. */
export function routeOptions(hash: string): {
  game?: GameId;
  seed?: number;
  bot?: boolean;
  mode?: LoopMode;
} {
  const q = hash.indexOf('?');
  if (q < 0) return {};
  const p = new URLSearchParams(hash.slice(q + 1));
  const out: { game?: GameId; seed?: number; bot?: boolean; mode?: LoopMode } = {};
  const g = p.get('game');
  if (g && (GAME_IDS as readonly string[]).includes(g)) out.game = g as GameId;
  const s = p.get('seed');
  if (s !== null && /^\d{1,10}$/.test(s) && Number(s) <= 0xffffffff) out.seed = Number(s);
  if (p.get('bot') === '1') out.bot = true;
  const m = p.get('loop');
  if (m === 'fixed' || m === 'variable') out.mode = m;
  return out;
}
