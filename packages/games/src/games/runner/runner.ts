import { ByteReader, ByteWriter, Random, fnv1a64, type ButtonInput } from 'fixedstep';
import type { Game, GameConfig, GameInfo } from '../game.js';

/**
 * The runner of the talk's "SCORE 0 / HIGHSCORE 35730" demo: one player runs to the right at a
 * speed that grows, jumps over (or ducks under) obstacles drawn by a seeded {@link Random}, and
 * scores with distance. A collision ends the run; a jump press half a second later starts the
 * next one. The highscore survives restarts: it is part of the state.
 *
 * Units are metres and seconds. Jump physics is semi-implicit Euler, as on the slides
 * (`velocity += acceleration·dt; position += velocity·dt`): under a fixed step every jump is the
 * same; under a variable Δt (see {@link RunnerGame.update}) its height and length follow the
 * frame rate.
 */

/** Buttons of the runner (bit numbers in a {@link ButtonInput}). */
export const RunnerButtons = { jump: 0, duck: 1 } as const;

/** Ticks per second of the fixed step. */
const TICK_RATE = 60;
/** Gravity, m/s² downwards. */
const GRAVITY = 36;
/** Upward speed a jump gives, m/s. Exact apex v²/2g = 2.03 m, exact airtime 2v/g = 0.672 s. */
const JUMP_SPEED = 12.1;
/** Gravity multiplier while duck is held in the air (a fast fall). */
const FAST_FALL = 3;
/** Player box, m. Ducking (only on the ground) lowers it to DUCK_HEIGHT. */
const PLAYER_WIDTH = 0.6;
const STAND_HEIGHT = 1.2;
const DUCK_HEIGHT = 0.6;
/** Running speed at the start of a run and its cap, m/s; and how fast it grows, m/s². */
const START_SPEED = 10;
const MAX_SPEED = 20;
const ACCELERATION = 0.1;
/** Where the first obstacle of a run stands, m from the start. */
const FIRST_OBSTACLE = 40;
/** Obstacles are placed this far ahead of the player, m (off screen), and dropped this far behind. */
const SPAWN_AHEAD = 60;
const DESPAWN_BEHIND = 10;
/**
 * Clear time between obstacles at the speed the player will have on reaching them, s: from
 * MIN_GAP to a maximum that shrinks from MAX_GAP_SLOW (at START_SPEED) to MAX_GAP_FAST (at
 * MAX_SPEED). MIN_GAP exceeds a jump's airtime, so every course can be cleared.
 */
const MIN_GAP = 0.9;
const MAX_GAP_SLOW = 2.2;
const MAX_GAP_FAST = 1.3;
/** Birds (duck under them) appear from this distance, m, as this share of obstacles. */
const BIRDS_FROM = 300;
const BIRD_SHARE = 0.2;
/** Score points per metre run. */
const SCORE_PER_METRE = 10;
/** Seconds after a crash before a jump press starts the next run. */
const RESTART_DELAY = 0.5;

/** The runner's tuning, for help screens, renderers and bots. Units in the names' comments. */
export const RUNNER_TUNING = Object.freeze({
  /** Ticks per second. */
  tickRate: TICK_RATE,
  /** m/s². */
  gravity: GRAVITY,
  /** m/s. */
  jumpSpeed: JUMP_SPEED,
  /** Gravity multiplier while duck is held in the air. */
  fastFall: FAST_FALL,
  /** m. */
  playerWidth: PLAYER_WIDTH,
  /** m. */
  standHeight: STAND_HEIGHT,
  /** m. */
  duckHeight: DUCK_HEIGHT,
  /** m/s. */
  startSpeed: START_SPEED,
  /** m/s. */
  maxSpeed: MAX_SPEED,
  /** m/s². */
  acceleration: ACCELERATION,
  /** m. */
  firstObstacle: FIRST_OBSTACLE,
  /** m. */
  spawnAhead: SPAWN_AHEAD,
  /** s. */
  minGap: MIN_GAP,
  /** m. */
  birdsFrom: BIRDS_FROM,
  /** Points per metre. */
  scorePerMetre: SCORE_PER_METRE,
  /** s. */
  restartDelay: RESTART_DELAY,
});

/** An obstacle kind: a box `width` × `height` m whose bottom is `bottom` m above the ground. */
export interface ObstacleKind {
  readonly name: string;
  readonly width: number;
  readonly height: number;
  readonly bottom: number;
}

/** The obstacle kinds, by the number stored in the state. */
export const OBSTACLE_KINDS: readonly ObstacleKind[] = Object.freeze([
  Object.freeze({ name: 'small', width: 0.5, height: 0.8, bottom: 0 }),
  Object.freeze({ name: 'tall', width: 0.5, height: 1.4, bottom: 0 }),
  Object.freeze({ name: 'wide', width: 1.6, height: 0.8, bottom: 0 }),
  /** Above a ducking player, below a standing one: duck (or jump high). */
  Object.freeze({ name: 'bird', width: 1.0, height: 0.5, bottom: 0.9 }),
]);
const SMALL = 0;
const TALL = 1;
const WIDE = 2;
const BIRD = 3;
const KINDS = OBSTACLE_KINDS.length;
const KIND_W = Float64Array.from(OBSTACLE_KINDS, (k) => k.width);
const KIND_H = Float64Array.from(OBSTACLE_KINDS, (k) => k.height);
const KIND_Y = Float64Array.from(OBSTACLE_KINDS, (k) => k.bottom);

/** Obstacle ring capacity (a power of two). Gaps are ≥ 9 m, so at most 8 are ever alive. */
const CAPACITY = 16;
const MASK = CAPACITY - 1;

// Input bits: the button down during the tick, or pressed during it.
const JUMP_ANY = (1 << RunnerButtons.jump) | (1 << (16 + RunnerButtons.jump));
const JUMP_PRESSED = 1 << (16 + RunnerButtons.jump);
const DUCK_ANY = (1 << RunnerButtons.duck) | (1 << (16 + RunnerButtons.duck));

// Float64 state slots.
const DIST = 0; // m run in this run (the player's left edge)
const SPEED = 1; // m/s
const Y = 2; // feet above the ground, m
const VY = 3; // m/s, up
const NEXT = 4; // where the next obstacle goes, m
const DEAD_TIME = 5; // s since the crash (0 while running)
const FLOATS = 6;
// Uint32 state slots.
const TICK = 0;
const HIGHSCORE = 1;
const RUNS = 2; // runs started, this one included
const DEAD = 3; // 0 | 1
const GROUND = 4; // 0 | 1
const DUCKING = 5; // 0 | 1 (only on the ground)
const COUNT = 6; // obstacles alive
const HEAD = 7; // ring index of the nearest one
const INTS = 8;

/** "RUN1", the first word of the state bytes. */
const STATE_MAGIC = 0x314e5552;

/** What the registry, the replays and the lab know about the runner. */
export const RUNNER_INFO: GameInfo = Object.freeze({
  id: 'runner',
  version: 1,
  title: 'Runner',
  stepSeconds: 1 / TICK_RATE,
  tickRate: TICK_RATE,
  minPlayers: 1,
  maxPlayers: 1,
  buttons: Object.freeze([
    Object.freeze({
      button: RunnerButtons.jump,
      name: 'jump',
      keys: Object.freeze(['Space', 'ArrowUp', 'KeyW']),
    }),
    Object.freeze({
      button: RunnerButtons.duck,
      name: 'duck',
      keys: Object.freeze(['ArrowDown', 'KeyS']),
    }),
  ]),
});

const STEP = RUNNER_INFO.stepSeconds;

/**
 * The runner game. Its whole state is two small typed arrays, the obstacle ring and the
 * {@link Random}'s four words; a step allocates nothing.
 *
 * Read-only accessors ({@link distance}, {@link obstacleX} …) serve the renderer and the bot.
 */
export class RunnerGame implements Game {
  readonly info = RUNNER_INFO;
  readonly seed: number;

  private readonly f = new Float64Array(FLOATS);
  private readonly u = new Uint32Array(INTS);
  private readonly ox = new Float64Array(CAPACITY);
  private readonly okind = new Uint8Array(CAPACITY);
  private readonly rng: Random;
  /** Distance and height before the last update, for render interpolation (not state). */
  private readonly prev = new Float64Array(2);
  private readonly writer = new ByteWriter(512);
  /**
   * The Δt of the update in progress. Handed over in a typed array, not as an argument: V8 boxes a
   * float argument to a call it does not inline (16 bytes a tick).
   */
  private readonly dt = new Float64Array(1);

  constructor(config: GameConfig) {
    if (config.players !== 1) {
      throw new RangeError(`runner: exactly 1 player, got ${String(config.players)}`);
    }
    if (!Number.isInteger(config.seed) || config.seed < 0 || config.seed > 0xffffffff) {
      throw new RangeError(`runner: seed must be a u32, got ${String(config.seed)}`);
    }
    this.seed = config.seed;
    this.rng = new Random(config.seed);
    this.u[RUNS] = 1;
    this.newRun();
  }

  // ------------------------------------------------------------------ Simulation

  get tick(): number {
    return this.u[TICK]!;
  }

  /** One fixed step of 1/60 s. Player 0's input; a missing input counts as no buttons. */
  step(inputs: readonly ButtonInput[]): void {
    this.dt[0] = STEP;
    this.advance(inputs[0] ?? 0);
  }

  /**
   * Advance by `dt` seconds — the variable-Δt demo. Not deterministic across frame rates: a jump
   * under a 20 Hz Δt is lower and shorter than under 60 Hz, and a long Δt tunnels through
   * obstacles. A Δt that is 0, negative or NaN advances nothing but the tick count.
   */
  update(dt: number, inputs: readonly ButtonInput[]): void {
    this.dt[0] = dt;
    this.advance(inputs[0] ?? 0);
  }

  /**
   * The canonical state bytes, little-endian (84 bytes + 9 per obstacle): u32 "RUN1", tick,
   * highscore, runs started; u8 crashed, on the ground, ducking; f64 distance, speed, height,
   * vertical speed, next obstacle at, seconds since the crash; the RNG's four u32 words; u8 obstacle
   * count, then per obstacle, nearest first, u8 kind and f64 left edge.
   */
  save(): Uint8Array {
    return this.write().finish();
  }

  /** Restore a state from {@link save}; throws a RangeError (and changes nothing) on bad bytes. */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    const bad = (what: string): never => {
      throw new RangeError(`RunnerGame.load: ${what}`);
    };
    if (r.u32() !== STATE_MAGIC) bad('not runner state bytes (bad magic)');
    const u = new Uint32Array(INTS);
    const f = new Float64Array(FLOATS);
    u[TICK] = r.u32();
    u[HIGHSCORE] = r.u32();
    u[RUNS] = r.u32();
    u[DEAD] = r.u8();
    u[GROUND] = r.u8();
    u[DUCKING] = r.u8();
    r.f64s(f);
    const words = new Uint32Array(4);
    r.ints(words);
    const count = r.u8();
    if (count > CAPACITY) bad(`${count} obstacles, at most ${CAPACITY}`);
    const ox = new Float64Array(count);
    const kinds = new Uint8Array(count);
    for (let k = 0; k < count; k++) {
      kinds[k] = r.u8();
      ox[k] = r.f64();
    }
    r.end();

    for (const slot of [DEAD, GROUND, DUCKING]) if (u[slot]! > 1) bad('a flag is not 0 or 1');
    if (u[RUNS] === 0) bad('no run started');
    // Finite, and canonical (save() writes -0 as +0): accepted bytes save back unchanged.
    for (let i = 0; i < FLOATS; i++) {
      if (!Number.isFinite(f[i]) || Object.is(f[i], -0)) bad('a number is not finite or is -0');
    }
    if (!(f[DIST]! >= 0)) bad('negative distance');
    if (!(f[SPEED]! >= START_SPEED && f[SPEED]! <= MAX_SPEED)) bad('speed out of range');
    if (!(f[Y]! >= 0)) bad('below the ground');
    if (u[GROUND] === 1 && (f[Y] !== 0 || f[VY] !== 0)) bad('on the ground but off it');
    if (u[DUCKING] === 1 && u[GROUND] === 0) bad('ducking in the air');
    if (!(f[DEAD_TIME]! >= 0) || (u[DEAD] === 0 && f[DEAD_TIME] !== 0)) bad('bad crash time');
    if ((words[0]! | words[1]! | words[2]! | words[3]!) === 0) bad('all-zero random state');
    for (let k = 0; k < count; k++) {
      if (kinds[k]! >= KINDS) bad(`obstacle kind ${kinds[k]!}`);
      if (!Number.isFinite(ox[k]) || Object.is(ox[k], -0)) bad('an obstacle is not at a number');
      if (k > 0 && ox[k]! < ox[k - 1]!) bad('obstacles out of order');
    }

    this.u.set(u);
    this.f.set(f);
    this.rng.setState(words);
    this.u[COUNT] = count;
    this.u[HEAD] = 0;
    this.ox.fill(0);
    this.okind.fill(0);
    this.ox.set(ox);
    this.okind.set(kinds);
    this.prev[0] = f[DIST]!;
    this.prev[1] = f[Y]!;
  }

  hash(): bigint {
    return fnv1a64(this.write().peek());
  }

  // ------------------------------------------------------------------ Game

  get over(): boolean {
    return this.u[DEAD] === 1;
  }

  hud(): Readonly<Record<string, number>> {
    return { score: this.score, highscore: this.highscore };
  }

  // ------------------------------------------------------------------ reading

  /** Points of the current run: metres run × `scorePerMetre` of {@link RUNNER_TUNING}, floored. */
  get score(): number {
    return Math.floor(this.f[DIST]! * SCORE_PER_METRE);
  }
  /** The best score of every run that has ended. */
  get highscore(): number {
    return this.u[HIGHSCORE]!;
  }
  /** Runs started, the current one included. */
  get runs(): number {
    return this.u[RUNS]!;
  }
  /** Metres run in this run: the player's left edge. */
  get distance(): number {
    return this.f[DIST]!;
  }
  /** Running speed, m/s. */
  get speed(): number {
    return this.f[SPEED]!;
  }
  /** Height of the player's feet above the ground, m. */
  get y(): number {
    return this.f[Y]!;
  }
  /** Vertical speed, m/s (up is positive). */
  get vy(): number {
    return this.f[VY]!;
  }
  get onGround(): boolean {
    return this.u[GROUND] === 1;
  }
  get ducking(): boolean {
    return this.u[DUCKING] === 1;
  }
  /** The player's height now, m. */
  get playerHeight(): number {
    return this.u[DUCKING] === 1 ? DUCK_HEIGHT : STAND_HEIGHT;
  }
  /** Whether a jump press now starts the next run. */
  get canRestart(): boolean {
    return this.u[DEAD] === 1 && this.f[DEAD_TIME]! >= RESTART_DELAY;
  }
  /** Obstacles alive, nearest first (index 0 … count − 1 for the accessors below). */
  get obstacleCount(): number {
    return this.u[COUNT]!;
  }
  /** Left edge of obstacle `k`, m (same axis as {@link distance}). */
  obstacleX(k: number): number {
    return this.ox[(this.u[HEAD]! + k) & MASK]!;
  }
  /** Kind of obstacle `k`: an index into {@link OBSTACLE_KINDS}. */
  obstacleKind(k: number): number {
    return this.okind[(this.u[HEAD]! + k) & MASK]!;
  }
  /** Interpolated distance for rendering (`alpha` from the loop). */
  renderDistance(alpha: number): number {
    return this.prev[0]! + (this.f[DIST]! - this.prev[0]!) * alpha;
  }
  /** Interpolated height for rendering. */
  renderY(alpha: number): number {
    return this.prev[1]! + (this.f[Y]! - this.prev[1]!) * alpha;
  }

  // ------------------------------------------------------------------ the simulation

  /** One update of `this.dt[0]` seconds. */
  private advance(input: number): void {
    const dt = this.dt[0]!;
    const f = this.f;
    const u = this.u;
    u[TICK] = (u[TICK]! + 1) >>> 0;
    this.prev[0] = f[DIST]!;
    this.prev[1] = f[Y]!;
    if (!(dt > 0)) return;
    if (u[DEAD] === 1) {
      f[DEAD_TIME] = f[DEAD_TIME]! + dt;
      if (f[DEAD_TIME] >= RESTART_DELAY && (input & JUMP_PRESSED) !== 0) {
        this.newRun();
        u[RUNS] = u[RUNS]! + 1;
      }
      return;
    }
    const duck = (input & DUCK_ANY) !== 0;
    let ground = u[GROUND] === 1;
    let y = f[Y]!;
    let vy = f[VY]!;
    if (ground && (input & JUMP_ANY) !== 0) {
      vy = JUMP_SPEED;
      ground = false;
    }
    let speed = f[SPEED]! + ACCELERATION * dt;
    if (speed > MAX_SPEED) speed = MAX_SPEED;
    const dist = f[DIST]! + speed * dt;
    if (!ground) {
      vy -= (duck ? GRAVITY * FAST_FALL : GRAVITY) * dt;
      y += vy * dt;
      if (y <= 0) {
        y = 0;
        vy = 0;
        ground = true;
      }
    }
    const ducking = ground && duck;
    f[SPEED] = speed;
    f[DIST] = dist;
    f[Y] = y;
    f[VY] = vy;
    u[GROUND] = ground ? 1 : 0;
    u[DUCKING] = ducking ? 1 : 0;
    this.refreshObstacles();

    // Discrete collision at the end of the update, as in the talk: a long enough Δt tunnels.
    const top = y + (ducking ? DUCK_HEIGHT : STAND_HEIGHT);
    const right = dist + PLAYER_WIDTH;
    const head = u[HEAD]!;
    const n = u[COUNT]!;
    for (let k = 0; k < n; k++) {
      const i = (head + k) & MASK;
      const x = this.ox[i]!;
      if (x >= right) break;
      const kind = this.okind[i]!;
      if (x + KIND_W[kind]! <= dist) continue;
      const bottom = KIND_Y[kind]!;
      if (y < bottom + KIND_H[kind]! && top > bottom) {
        this.crash();
        break;
      }
    }
  }

  private crash(): void {
    this.u[DEAD] = 1;
    this.f[DEAD_TIME] = 0;
    const score = this.score;
    if (score > this.u[HIGHSCORE]!) this.u[HIGHSCORE] = score;
  }

  /**
   * A fresh run: the player at 0, the obstacles from FIRST_OBSTACLE on. The RNG runs on (each run
   * has a new course); the highscore, the run count and the tick stay.
   */
  private newRun(): void {
    const f = this.f;
    const u = this.u;
    f.fill(0);
    f[SPEED] = START_SPEED;
    f[NEXT] = FIRST_OBSTACLE;
    u[DEAD] = 0;
    u[GROUND] = 1;
    u[DUCKING] = 0;
    u[COUNT] = 0;
    u[HEAD] = 0;
    this.ox.fill(0);
    this.okind.fill(0);
    this.prev[0] = 0;
    this.prev[1] = 0;
    this.refreshObstacles();
  }

  /** Drop the obstacles left behind; place new ones up to SPAWN_AHEAD metres ahead. */
  private refreshObstacles(): void {
    const f = this.f;
    const u = this.u;
    const dist = f[DIST]!;
    while (u[COUNT]! > 0) {
      const i = u[HEAD]!;
      if (this.ox[i]! + KIND_W[this.okind[i]!]! >= dist - DESPAWN_BEHIND) break;
      u[HEAD] = (i + 1) & MASK;
      u[COUNT] = u[COUNT]! - 1;
    }
    // Only a huge variable Δt can leave the spawn point behind the player: resume ahead of it.
    if (f[NEXT]! < dist) f[NEXT] = dist + SPAWN_AHEAD / 2;
    while (u[COUNT]! < CAPACITY && f[NEXT]! < dist + SPAWN_AHEAD) this.spawn();
  }

  private spawn(): void {
    const f = this.f;
    const u = this.u;
    const rng = this.rng;
    const x = f[NEXT]!;
    const r = rng.next();
    let kind: number;
    if (x >= BIRDS_FROM && r < BIRD_SHARE) kind = BIRD;
    else if (r < 0.5) kind = SMALL;
    else if (r < 0.75) kind = TALL;
    else kind = WIDE;
    const slot = (u[HEAD]! + u[COUNT]!) & MASK;
    this.ox[slot] = x;
    this.okind[slot] = kind;
    u[COUNT] = u[COUNT]! + 1;
    // The gap is a time at the speed the player will have when it gets there.
    const speed = f[SPEED]!;
    let arrival = speed + (ACCELERATION * (x - f[DIST]!)) / speed;
    if (arrival > MAX_SPEED) arrival = MAX_SPEED;
    const hard = (arrival - START_SPEED) / (MAX_SPEED - START_SPEED);
    const maxGap = MAX_GAP_SLOW + (MAX_GAP_FAST - MAX_GAP_SLOW) * hard;
    f[NEXT] = x + KIND_W[kind]! + arrival * rng.range(MIN_GAP, maxGap);
  }

  /** The canonical state bytes, in the reused writer. */
  private write(): ByteWriter {
    const w = this.writer.reset();
    const u = this.u;
    const f = this.f;
    w.u32(STATE_MAGIC).u32(u[TICK]!).u32(u[HIGHSCORE]!).u32(u[RUNS]!);
    w.u8(u[DEAD]!).u8(u[GROUND]!).u8(u[DUCKING]!);
    for (let i = 0; i < FLOATS; i++) w.f64(f[i]!);
    w.ints(this.rng.getState());
    const n = u[COUNT]!;
    w.u8(n);
    for (let k = 0; k < n; k++) {
      const i = (u[HEAD]! + k) & MASK;
      w.u8(this.okind[i]!).f64(this.ox[i]!);
    }
    return w;
  }
}
