/**
 * The model behind chapter 9, "Games": one of the talk's games on a simulated display (or the
 * page's real clock), fed by the keyboard through a {@link ButtonSampler} or by the game's bot,
 * stepped by a {@link FixedLoop} — or, with the "variable Δt" switch, by the talk's naive
 * {@link VariableLoop} calling `update(dt)`, so the breakage shows. Every fixed-step game is
 * recorded with a {@link ReplayRecorder}. Also the highscore client. No DOM here: the unit tests
 * drive it exactly as the page does.
 */
import {
  ButtonSampler,
  FixedLoop,
  ReplayRecorder,
  VariableLoop,
  hex64,
  type ButtonInput,
  type Loop,
  type Simulation,
} from 'fixedstep';
import {
  CtfGame,
  GAMES,
  RUNNER_TUNING,
  RunnerGame,
  SurvivalGame,
  replayOptionsFor,
  type Game,
  type GameDefinition,
  type GameInfo,
} from '@fixedstep/games';
import { DisplayClock, type DisplaySpec as ClockDisplaySpec } from '../ui/display-clock.js';

/** The games, in the order the chapter lists them. */
export const GAME_IDS = ['runner', 'ctf', 'survival'] as const;
export type GameId = (typeof GAME_IDS)[number];

/** The simulated display rates on offer. */
export const DISPLAY_RATES = [30, 60, 144, 240] as const;
export type DisplayRate = (typeof DISPLAY_RATES)[number];

/** Which loop runs the game: the production fixed step, or the talk's naive variable Δt. */
export type LoopMode = 'fixed' | 'variable';

/** A simulated display of one of the chapter's rates (see DisplayClock). */
export interface DisplaySpec extends ClockDisplaySpec {
  hz: DisplayRate;
}

/** Checkpoint hashes every second of play, keyframes (seek points) every five. */
export const CHECKPOINT_SECONDS = 1;
export const KEYFRAME_SECONDS = 5;

/** How long a "went through a wall" marker stays on screen, ms of session time. */
export const BREACH_MS = 1500;

/** The registry entry of a game id. */
export function gameDef(id: string): GameDefinition {
  const def = GAMES.find((g) => g.info.id === id);
  if (!def) throw new RangeError(`no game "${id}"`);
  return def;
}

/** The `KeyboardEvent.code` → button map of a game, from its `info.buttons`. */
export function keyMap(info: GameInfo): Record<string, number> {
  const out: Record<string, number> = {};
  for (const b of info.buttons) for (const k of b.keys) out[k] = b.button;
  return out;
}

const KEY_NAMES: Readonly<Record<string, string>> = {
  Space: 'Space',
  ArrowUp: '↑',
  ArrowDown: '↓',
  ArrowLeft: '←',
  ArrowRight: '→',
  ShiftLeft: 'Shift',
  ShiftRight: 'Shift',
  Enter: 'Enter',
};

/** A key code as printed on the key: `KeyW` → `W`, `ArrowUp` → `↑`. */
export function keyLabel(code: string): string {
  if (KEY_NAMES[code]) return KEY_NAMES[code];
  const m = /^(?:Key|Digit)(.)$/.exec(code);
  return m ? m[1]! : code;
}

/** The game's own name for its score (`info.scoreKey`, default `score`). */
export function scoreKeyOf(def: GameDefinition): string {
  return def.info.scoreKey ?? 'score';
}

/** The game's score as the server will rank it, or undefined if its HUD has none. */
export function scoreOf(def: GameDefinition, game: Game): number | undefined {
  return game.hud()[scoreKeyOf(def)];
}

/** Whether the server can rank this game (its HUD has the score key). */
export function isRanked(def: GameDefinition): boolean {
  return scoreOf(def, def.create({ seed: 1, players: 1 })) !== undefined;
}

/** A simulation's hash as 16 hex digits. */
export function hashHex(sim: Pick<Simulation, 'hash'>): string {
  const h = sim.hash();
  return hex64(BigInt.asUintN(64, typeof h === 'bigint' ? h : BigInt(h)));
}

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

/** A place where something went through a wall, and when (session ms). */
export interface Breach {
  x: number;
  y: number;
  atMs: number;
  /** What went through. */
  what: 'bullet' | 'player' | 'enemy';
}

/** A runner jump, measured: its apex (m) and time in the air (s of simulated time). */
export interface JumpMeasure {
  apex: number;
  airtime: number;
}

export interface GameSessionOptions {
  def: GameDefinition;
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
export class GameSession {
  readonly def: GameDefinition;
  readonly game: Game;
  readonly mode: LoopMode;
  readonly seed: number;
  readonly player: string;
  readonly loop: Loop;
  readonly sampler = new ButtonSampler();
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
  private readonly clock: DisplayClock;
  private readonly inputs: ButtonInput[] = [0];
  private airApex = 0;
  private airStart = 0;
  private wasOnGround = true;
  private simSeconds = 0;

  constructor(options: GameSessionOptions) {
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
      const rate = this.def.info.tickRate;
      this.recorder = new ReplayRecorder(
        replayOptionsFor(this.def, config, [this.player], {
          checkpointEvery: CHECKPOINT_SECONDS * rate,
          keyframeEvery: KEYFRAME_SECONDS * rate,
        }),
      );
      this.recorder.start(this.game);
    }
    this.loop.frame(0);
    this.clock = new DisplayClock(options.display, (t) => {
      this.runFrame(t);
    });
  }

  /** The session's clock: ms from the start (the last time it was advanced to). */
  get timeMs(): number {
    return this.clock.timeMs;
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

  /** Simulated display: move the clock to `ms`, taking every display frame due by then. */
  advanceTo(ms: number): void {
    this.clock.advanceTo(ms);
  }

  advanceBy(ms: number): void {
    this.clock.advanceBy(ms);
  }

  /** Real clock: one display frame at `realMs` on the driver's time line (see DisplayClock). */
  realFrame(realMs: number): void {
    this.clock.realFrame(realMs);
  }

  /** The session time of a real-clock reading (for stamping input events). */
  sessionTimeOfReal(realMs: number): number {
    return this.clock.timeOfReal(realMs);
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

  /** The score the server would rank, now. */
  get score(): number | undefined {
    return scoreOf(this.def, this.game);
  }

  private runFrame(t: number): void {
    if (this.ended) return;
    this.frames++;
    const loop = this.loop;
    const n = loop.frame(t);
    const game = this.game;
    for (let j = 0; j < n; j++) {
      // Sample even when the bot plays, so key presses never pile up.
      const human = this.sampler.sample(loop, j);
      this.inputs[0] = this.bot ? this.def.bot(game, 0) : human;
      if (this.mode === 'fixed') {
        game.step(this.inputs);
        this.recorder?.record(this.inputs, game);
      } else {
        const dt = loop.dt;
        game.update(dt, this.inputs);
        this.simSeconds += dt;
        if (dt > this.maxDt) this.maxDt = dt;
      }
      this.afterUpdate(t);
      if (game.over && !(game instanceof RunnerGame)) {
        this.ended = true;
        break;
      }
    }
  }

  private afterUpdate(t: number): void {
    const game = this.game;
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

/** A name as the replay header stores it: printable, trimmed, at most 32 characters. */
export function cleanName(name: string): string {
  const printable = Array.from(name)
    .filter((ch) => ch >= ' ' && ch !== '\u007f')
    .join('')
    .trim();
  return Array.from(printable).slice(0, 32).join('') || 'player';
}

/** A fresh random seed (u32). Seeds only pick the course: the game stays deterministic. */
export function randomSeed(): number {
  const a = new Uint32Array(1);
  crypto.getRandomValues(a);
  return a[0]!;
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

// ------------------------------------------------------------------ replays: size and names

/** Bytes per minute of play of a replay of `bytes` bytes and `ticks` ticks at `tickRate` Hz. */
export function bytesPerMinute(bytes: number, ticks: number, tickRate: number): number {
  const minutes = ticks / tickRate / 60;
  return minutes > 0 ? bytes / minutes : NaN;
}

/** A file name for a replay: `runner-seed-123-2024-05-01T10-20-30.fsr`. */
export function replayFileName(gameId: string, seed: number, when: Date): string {
  const stamp = when.toISOString().slice(0, 19).replace(/:/g, '-');
  return `${gameId}-seed-${seed}-${stamp}.fsr`;
}

// ------------------------------------------------------------------ the highscore client

/** A highscore entry as the server sends it. */
export interface HighscoreRow {
  game: string;
  name: string;
  score: number;
  ticks: number;
  seed: number;
  finalHash: string;
  replayId: string;
  at: string;
}

export type SubmitResult =
  | { kind: 'accepted'; rank: number; entry: HighscoreRow }
  | { kind: 'refused'; status: number; code: string; error: string }
  | { kind: 'unavailable'; reason: string };

export type TableResult =
  | { kind: 'ok'; entries: HighscoreRow[] }
  | { kind: 'refused'; status: number; code: string; error: string }
  | { kind: 'unavailable'; reason: string };

/** The API's address, relative to the page (so a lab served under a prefix still finds it). */
export const HIGHSCORE_PATH = 'api/highscores';

type FetchLike = (url: string, init?: RequestInit) => Promise<Response>;

const UNAVAILABLE =
  'This copy of the lab has no highscore server (a static host?). Run `fixedstep serve` to rank scores.';

async function jsonBody(res: Response): Promise<Record<string, unknown> | undefined> {
  const type = res.headers.get('content-type') ?? '';
  if (!type.includes('application/json')) return undefined;
  try {
    const body: unknown = await res.json();
    return typeof body === 'object' && body !== null
      ? (body as Record<string, unknown>)
      : undefined;
  } catch {
    return undefined;
  }
}

function refusal(status: number, body: Record<string, unknown>) {
  return {
    kind: 'refused' as const,
    status,
    code: typeof body.code === 'string' ? body.code : 'ERROR',
    error: typeof body.error === 'string' ? body.error : `HTTP ${status}`,
  };
}

/**
 * Submit a replay with the score it claims: `POST api/highscores?score=N`, the replay as the
 * body. The server re-simulates the replay and accepts the score only if the replay reaches it.
 */
export async function submitScore(
  bytes: Uint8Array,
  score: number,
  fetchFn: FetchLike = (u, i) => fetch(u, i),
): Promise<SubmitResult> {
  let res: Response;
  try {
    res = await fetchFn(`${HIGHSCORE_PATH}?score=${encodeURIComponent(String(score))}`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/octet-stream' },
      body: bytes as Uint8Array<ArrayBuffer>,
    });
  } catch (e) {
    return { kind: 'unavailable', reason: `The highscore server cannot be reached: ${String(e)}` };
  }
  const body = await jsonBody(res);
  if (!body) return { kind: 'unavailable', reason: UNAVAILABLE };
  if (res.status === 201 && typeof body.rank === 'number' && typeof body.entry === 'object') {
    return { kind: 'accepted', rank: body.rank, entry: body.entry as HighscoreRow };
  }
  return refusal(res.status, body);
}

/** The best `limit` scores of a game: `GET api/highscores?game=…&limit=…`. */
export async function fetchHighscores(
  game: string,
  limit = 10,
  fetchFn: FetchLike = (u, i) => fetch(u, i),
): Promise<TableResult> {
  let res: Response;
  try {
    res = await fetchFn(`${HIGHSCORE_PATH}?game=${encodeURIComponent(game)}&limit=${limit}`, {
      headers: { Accept: 'application/json' },
    });
  } catch (e) {
    return { kind: 'unavailable', reason: `The highscore server cannot be reached: ${String(e)}` };
  }
  const body = await jsonBody(res);
  if (!body) return { kind: 'unavailable', reason: UNAVAILABLE };
  if (res.ok && Array.isArray(body.entries)) {
    return { kind: 'ok', entries: body.entries as HighscoreRow[] };
  }
  return refusal(res.status, body);
}
