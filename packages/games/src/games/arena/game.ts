import {
  ByteReader,
  ByteWriter,
  Random,
  fnv1a64,
  isDown as isDown_,
  type ButtonInput,
  type StateSchema,
} from 'fixedstep';
import {
  talkGame,
  type Bot,
  type Game,
  type GameConfig,
  type RegisteredGame,
  type GameInfo,
} from '../game.js';
import { Bullets } from './bullets.js';
import {
  DIR_X as DIR_X_,
  DIR_Y as DIR_Y_,
  SHOOTER_BUTTON_INFO,
  ShooterButtons as ShooterButtons_,
  clamp as clamp_,
  inputDir as inputDir_,
  isFiniteNumber,
} from './motion.js';
import type { Walls } from './walls.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const isDown = isDown_;
const DIR_X = DIR_X_;
const DIR_Y = DIR_Y_;
const ShooterButtons = ShooterButtons_;
const clamp = clamp_;
const inputDir = inputDir_;

/** The fixed step of both shooters: 60 Hz. */
const STEP = 1 / 60;

/** What an arena game's shell needs of its numbers (a layout's constants). */
export interface ArenaSpec {
  /** Field size, arena units. */
  readonly width: number;
  readonly height: number;
  readonly playerRadius: number;
  /** Units per second. */
  readonly playerSpeed: number;
}

/** A shooter's identity, for the registry, replays and the lab: 60 Hz, 1 to `maxPlayers`, ranked by player 0's kills. */
export function arenaInfo(
  id: string,
  version: number,
  title: string,
  maxPlayers: number,
): GameInfo {
  return Object.freeze({
    id,
    version,
    title,
    /** Highscore tables rank by player 0's kills. */
    scoreKey: 'kills',
    stepSeconds: STEP,
    tickRate: 60,
    minPlayers: 1,
    maxPlayers,
    buttons: SHOOTER_BUTTON_INFO,
  });
}

/** How an {@link ArenaState}'s bytes are recognised and checked. */
export interface ArenaStateFormat {
  /** The first four bytes (u32). */
  readonly magic: number;
  /** What the bytes are, for "not a …" errors. */
  readonly what: string;
  /** Player slots. */
  readonly slots: number;
  /** The highest team a bullet may have (0 with no teams). */
  readonly maxTeam: number;
  readonly bulletCapacity: number;
  readonly bulletRadius: number;
}

/**
 * What the state of every arena game has: the clock, the random generator, players by slot
 * (structure of arrays, fixed size) and a bullet pool. Everything is saved, loaded and hashed
 * except `prevX`/`prevY` (render interpolation only).
 *
 * The bytes are a head (magic, players, tick, clock, over flag, generator), the game's own part
 * ({@link writeBody}) and the bullets.
 */
export abstract class ArenaState {
  tick = 0;
  /** Simulated seconds: `tick × step` under `step`, a sum of Δt under `update`. */
  clock = 0;
  over = 0;
  readonly rng = new Random(0);

  /** 1 for a slot in play. */
  readonly active: Uint8Array;
  readonly alive: Uint8Array;
  /** Facing direction 0–7 (see `DIR_X`). */
  readonly facing: Uint8Array;
  readonly x: Float64Array;
  readonly y: Float64Array;
  /** Velocity of the last move, units per second. */
  readonly vx: Float64Array;
  readonly vy: Float64Array;
  /** Seconds until the next shot is allowed. */
  readonly cooldown: Float64Array;
  readonly kills: Uint32Array;
  /** Position before the last step (render interpolation; not saved). */
  readonly prevX: Float64Array;
  readonly prevY: Float64Array;

  readonly bullets: Bullets;

  private readonly format: ArenaStateFormat;

  constructor(format: ArenaStateFormat) {
    this.format = format;
    const n = format.slots;
    this.active = new Uint8Array(n);
    this.alive = new Uint8Array(n);
    this.facing = new Uint8Array(n);
    this.x = new Float64Array(n);
    this.y = new Float64Array(n);
    this.vx = new Float64Array(n);
    this.vy = new Float64Array(n);
    this.cooldown = new Float64Array(n);
    this.kills = new Uint32Array(n);
    this.prevX = new Float64Array(n);
    this.prevY = new Float64Array(n);
    this.bullets = new Bullets(format.bulletCapacity, format.bulletRadius);
  }

  /** Canonical bytes. */
  write(w: ByteWriter, players: number): void {
    w.u32(this.format.magic).u8(players).u32(this.tick).f64(this.clock).u8(this.over);
    w.ints(this.rng.getState());
    this.writeBody(w);
    this.bullets.write(w);
  }

  /** Read and validate {@link write}'s bytes; throws a RangeError naming the first problem. */
  read(bytes: Uint8Array, players: number): void {
    const f = this.format;
    const r = new ByteReader(bytes);
    if (r.u32() !== f.magic) throw new RangeError(`not a ${f.what}`);
    const p = r.u8();
    if (p !== players) {
      throw new RangeError(`the state is of a game for ${p} players, this one has ${players}`);
    }
    this.tick = r.u32();
    this.clock = r.f64();
    this.over = r.u8();
    const rng = new Uint32Array(4);
    r.ints(rng);
    this.rng.setState(rng);
    this.readBody(r);
    this.bullets.read(r, f.slots - 1, f.maxTeam);
    r.end();
    if (!(this.clock >= 0 && isFiniteNumber(this.clock))) throw new RangeError('bad clock');
    if (this.over > 1) throw new RangeError(`bad over flag ${this.over}`);
    this.validate(players);
    this.prevX.set(this.x);
    this.prevY.set(this.y);
  }

  /** Make this state a copy of `o` (used by `load` once the bytes have been validated). */
  copyFrom(o: this): void {
    this.tick = o.tick;
    this.clock = o.clock;
    this.over = o.over;
    this.rng.setState(o.rng.getState());
    for (const k of [
      'active',
      'alive',
      'facing',
      'x',
      'y',
      'vx',
      'vy',
      'cooldown',
      'kills',
      'prevX',
      'prevY',
    ] as const) {
      this[k].set(o[k]);
    }
    this.bullets.copyFrom(o.bullets);
    this.copyBody(o);
  }

  /** The game's part of the bytes, between the head and the bullets. */
  protected abstract writeBody(w: ByteWriter): void;
  /** Read what {@link writeBody} wrote. */
  protected abstract readBody(r: ByteReader): void;
  /** Check the game's rules on what was read (RangeError on the first problem); set derived numbers. */
  protected abstract validate(players: number): void;
  /** Copy the game's own fields of `o`. */
  protected abstract copyBody(o: this): void;
}

/** Scratch for push-out results; never part of any state. */
const moved = new Float64Array(2);

/**
 * The shell of an arena game: config checks, the fixed step and the naive `update`, snapshots
 * and hashes, and walking a player through the walls. The game supplies its state, its rules
 * ({@link advance}) and its HUD.
 *
 * - `step` is the real game: a fixed 1/60 s step with continuous detection for bullets.
 *   Deterministic: same seed and inputs, same bytes.
 * - `update` is the naive game the talk warns about: the same rules for whatever Δt the frame
 *   had, with discrete detection only. Not deterministic across frame rates — the point of the
 *   demo. Do not mix with `step` in one game.
 */
export abstract class ArenaGame<S extends ArenaState> implements Game {
  readonly info: GameInfo;
  /** Human (or externally driven) players: slots 0 … players − 1. */
  readonly players: number;
  readonly seed: number;
  /** The state. Read it freely (renderers, bots); change it only through the game. */
  readonly state: S;
  /** The walls (static). */
  readonly walls: Walls;
  /** The layout's numbers. */
  protected readonly spec: ArenaSpec;

  /** The class's name, for error messages. */
  private readonly label: string;
  private readonly newState: () => S;
  private readonly writer = new ByteWriter(8192);
  private scratch: S | null = null;

  /**
   * After {@link walk} moved a player: true when that move is known to meet no wall — it ended at
   * least its radius from every wall (no wall pushed it), the field's edge did not stop it, and it
   * was shorter than its radius less a unit — so every point of it is more than a unit from every
   * wall, and `Walls.crosses` of it would say false (the tunnelling diagnostic can skip it). A
   * cache of what the step computed, not state.
   */
  protected walkedClear = false;

  /** Checks `config` (a u32 seed, 1 to `info.maxPlayers` players) and seeds a new state. */
  protected constructor(
    label: string,
    info: GameInfo,
    spec: ArenaSpec,
    walls: Walls,
    newState: () => S,
    config: GameConfig,
  ) {
    const { seed, players } = config;
    if (!Number.isInteger(seed) || seed < 0 || seed > 0xffffffff) {
      throw new RangeError(`${label}: seed must be a u32, got ${String(seed)}`);
    }
    if (!Number.isInteger(players) || players < 1 || players > info.maxPlayers) {
      throw new RangeError(
        `${label}: players must be from 1 to ${info.maxPlayers}, got ${String(players)}`,
      );
    }
    this.label = label;
    this.info = info;
    this.spec = spec;
    this.walls = walls;
    this.newState = newState;
    this.seed = seed;
    this.players = players;
    this.state = newState();
    this.state.rng.seed(seed);
  }

  /** Steps (or updates) so far. */
  get tick(): number {
    return this.state.tick;
  }

  /** Whether the match has ended; later steps only count ticks. */
  get over(): boolean {
    return this.state.over === 1;
  }

  /** One fixed step of 1/60 s with continuous detection for bullets. `inputs[p]` drives player p (missing: nothing held). */
  step(inputs: readonly ButtonInput[]): void {
    this.advance(STEP, inputs, true);
    const s = this.state;
    s.tick++;
    s.clock = s.tick * STEP;
  }

  /**
   * True once the match is over: {@link advance} then does nothing (its contract), so a step
   * only counts the tick and sets the clock to tick × step — nothing else in the state changes,
   * whatever the inputs. See `Simulation.frozen`.
   */
  get frozen(): boolean {
    return this.over;
  }

  /**
   * After the end ({@link frozen}): `ticks` steps at once — the tick counted on, the clock
   * tick × step, exactly as that many calls of {@link step} leave them.
   */
  skip(ticks: number): void {
    if (!this.frozen) throw new RangeError(`${this.label}.skip: the match is not over`);
    if (!Number.isInteger(ticks) || ticks < 0) {
      throw new RangeError(
        `${this.label}.skip: ticks must be a non-negative integer, got ${String(ticks)}`,
      );
    }
    const s = this.state;
    s.tick += ticks;
    s.clock = s.tick * STEP;
  }

  /**
   * The naive variable-Δt game (for the lab's demo): advance by `dt` seconds with discrete
   * detection only. Not deterministic across frame rates — the point of the demo. Do not mix with
   * {@link step} in one game.
   */
  update(dt: number, inputs: readonly ButtonInput[]): void {
    if (!(dt >= 0 && isFiniteNumber(dt))) {
      throw new RangeError(
        `${this.label}.update: dt must be a finite number ≥ 0, got ${String(dt)}`,
      );
    }
    this.advance(dt, inputs, false);
    const s = this.state;
    s.tick++;
    s.clock += dt;
  }

  abstract hud(): Readonly<Record<string, number>>;

  save(): Uint8Array {
    this.state.write(this.writer.reset(), this.players);
    return this.writer.finish();
  }

  /** Restore a {@link save}d state of a game with the same number of players; RangeError on bad bytes (the game is then unchanged). */
  load(bytes: Uint8Array): void {
    this.scratch ??= this.newState();
    this.scratch.read(bytes, this.players);
    this.state.copyFrom(this.scratch);
    this.loaded();
  }

  /** After {@link load}: the game's chance to rebuild what it derives from the state (not state). */
  protected loaded(): void {
    // Nothing by default.
  }

  hash(): bigint {
    this.state.write(this.writer.reset(), this.players);
    return fnv1a64(this.writer.peek());
  }

  /**
   * Put a living player somewhere, facing `facing` (0–7): for experiments and the lab's
   * set-ups. Changes the state like a step would (deterministically).
   */
  place(slot: number, x: number, y: number, facing: number): void {
    const s = this.state;
    if (!(slot >= 0 && slot < s.alive.length && s.alive[slot] === 1)) {
      throw new RangeError(`${this.label}.place: slot ${slot} is not a living player`);
    }
    s.x[slot] = x;
    s.y[slot] = y;
    s.prevX[slot] = x;
    s.prevY[slot] = y;
    s.facing[slot] = facing & 7;
  }

  /**
   * The rules: advance everything by `dt` seconds; `continuous` under {@link step}. Once the
   * match is over it must change nothing at all: {@link frozen} and {@link skip} rely on it.
   */
  protected abstract advance(dt: number, inputs: readonly ButtonInput[], continuous: boolean): void;

  /**
   * Move living player `p` as the arrows of `input` ask, for `dt` seconds: it turns to face that
   * way (unless strafing), moves `v·dt`, is pushed out of the walls — discretely: safe at the
   * fixed step, where every wall is thicker than a step of a player — and kept on the field.
   * Returns false when no arrow is held: then it stands, with no velocity.
   */
  protected walk(p: number, input: ButtonInput, dt: number): boolean {
    const s = this.state;
    const d = inputDir(input);
    if (d < 0) {
      s.vx[p] = 0;
      s.vy[p] = 0;
      return false;
    }
    if (!isDown(input, ShooterButtons.strafe)) s.facing[p] = d;
    const spec = this.spec;
    const r = spec.playerRadius;
    const vx = DIR_X[d]! * spec.playerSpeed;
    const vy = DIR_Y[d]! * spec.playerSpeed;
    s.vx[p] = vx;
    s.vy[p] = vy;
    // (The walls' register form: see `Walls`.)
    const q = this.walls.query;
    q[0] = s.x[p]! + vx * dt;
    q[1] = s.y[p]! + vy * dt;
    const pushed = this.walls.pushOutQuery(r, moved);
    // Keep everyone on the field whatever happened (the naive game can push one out of it).
    const x = clamp(moved[0]!, r, spec.width - r);
    const y = clamp(moved[1]!, r, spec.height - r);
    s.x[p] = x;
    s.y[p] = y;
    this.walkedClear = !pushed && x === q[0] && y === q[1] && spec.playerSpeed * dt < r - 1;
    return true;
  }
}

/** A {@link Bot} that plays `input` for instances of `type` and throws a TypeError for any other game. */
export function arenaBot<G extends Game>(
  name: string,
  what: string,
  type: abstract new (...args: never[]) => G,
  input: (game: G, player: number) => ButtonInput,
): Bot {
  return (game: Game, player: number) => {
    if (!(game instanceof type)) throw new TypeError(`${name}: not a ${what} game`);
    return input(game, player);
  };
}

/** A game's registry entry: config bytes are the seed and the player count (1 to `info.maxPlayers`). */
export function arenaDefinition(
  info: GameInfo,
  create: (config: GameConfig) => Game,
  bot: Bot,
  stateSchema?: StateSchema,
): RegisteredGame {
  return talkGame(info, ShooterButtons, create, bot, stateSchema);
}
