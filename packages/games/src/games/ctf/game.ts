import {
  dsincos as dsincos_,
  isDown as isDown_,
  type ButtonInput,
  type ByteReader,
  type ByteWriter,
} from 'fixedstep';
import type { GameConfig } from '../game.js';
import type { BulletTargets } from '../arena/bullets.js';
import { ArenaGame, ArenaState, arenaInfo } from '../arena/game.js';
import {
  DIR_X as DIR_X_,
  DIR_Y as DIR_Y_,
  ShooterButtons as ShooterButtons_,
  isFiniteNumber,
} from '../arena/motion.js';
import {
  CTF as CTF_,
  CTF_VERSION,
  CTF_WALLS,
  FLAG_STAND_X as FLAG_STAND_X_,
  FLAG_STAND_Y as FLAG_STAND_Y_,
  SPAWN_X,
  SPAWN_Y,
} from './layout.js';
import { ctfBotInput as ctfBotInput_ } from './bot.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const dsincos = dsincos_;
const isDown = isDown_;
const DIR_X = DIR_X_;
const DIR_Y = DIR_Y_;
const ShooterButtons = ShooterButtons_;
const CTF = CTF_;
const FLAG_STAND_X = FLAG_STAND_X_;
const FLAG_STAND_Y = FLAG_STAND_Y_;
const ctfBotInput = ctfBotInput_;
const SLOTS = CTF.slots;
const R = CTF.playerRadius;
const MAGIC = 0x31465443; // "CTF1"

/** Where a flag is. */
export const FlagState = {
  /** On its stand. */
  home: 0,
  /** Carried by an enemy player ({@link CtfState.flagCarrier}). */
  carried: 1,
  /** Lying where its carrier fell; returns home after {@link CTF.flagReturnTime}. */
  dropped: 2,
} as const;

/** No carrier. */
export const NO_CARRIER = 255;

/** Capture the flag's identity, for the registry, replays and the lab. */
export const CTF_INFO = arenaInfo('ctf', CTF_VERSION, 'Capture the flag', 4);

/** Options of a {@link CtfGame} beyond the {@link GameConfig}. */
export interface CtfOptions extends GameConfig {
  /**
   * Fill the teams up to 4 + 4 with AI bots. Default true. With false only the `players` slots
   * play (for experiments such as the tunnelling test).
   */
  fill?: boolean;
}

/**
 * The whole state of a match, structure of arrays, fixed size. Players by slot (0–7; team =
 * slot & 1, 0 red, 1 blue), flags by team, bullets in a pool. Everything here is saved, loaded
 * and hashed — except `prevX`/`prevY` (render interpolation only).
 */
export class CtfState extends ArenaState {
  /** Captures by team. */
  readonly score = new Uint32Array(2);
  /** Shots fired by everyone. */
  shots = 0;
  /** Times a player's path went through a wall (a diagnostic; only possible under `update`). */
  playersThroughWalls = 0;

  /** Hits left before dying (while alive). */
  readonly health = new Uint8Array(SLOTS);
  /** Seconds until respawn (while dead). */
  readonly respawn = new Float64Array(SLOTS);
  /** Seconds of spawn protection left. */
  readonly protect = new Float64Array(SLOTS);
  readonly deaths = new Uint32Array(SLOTS);
  /** Flags captured. */
  readonly captures = new Uint32Array(SLOTS);

  /** Flags by team: {@link FlagState}, carrier slot (or {@link NO_CARRIER}), position, return timer. */
  readonly flagState = new Uint8Array(2);
  readonly flagCarrier = new Uint8Array(2);
  readonly flagX = new Float64Array(2);
  readonly flagY = new Float64Array(2);
  readonly flagTimer = new Float64Array(2);

  constructor() {
    super({
      magic: MAGIC,
      what: 'capture-the-flag state',
      slots: SLOTS,
      maxTeam: 1,
      bulletCapacity: CTF.bulletCapacity,
      bulletRadius: CTF.bulletRadius,
    });
  }

  protected override writeBody(w: ByteWriter): void {
    w.ints(this.score).u32(this.shots).u32(this.playersThroughWalls);
    w.ints(this.active).ints(this.alive).ints(this.health).ints(this.facing);
    w.f64s(this.x).f64s(this.y).f64s(this.vx).f64s(this.vy);
    w.f64s(this.cooldown).f64s(this.respawn).f64s(this.protect);
    w.ints(this.kills).ints(this.deaths).ints(this.captures);
    w.ints(this.flagState).ints(this.flagCarrier);
    w.f64s(this.flagX).f64s(this.flagY).f64s(this.flagTimer);
  }

  protected override readBody(r: ByteReader): void {
    r.ints(this.score);
    this.shots = r.u32();
    this.playersThroughWalls = r.u32();
    r.ints(this.active);
    r.ints(this.alive);
    r.ints(this.health);
    r.ints(this.facing);
    r.f64s(this.x);
    r.f64s(this.y);
    r.f64s(this.vx);
    r.f64s(this.vy);
    r.f64s(this.cooldown);
    r.f64s(this.respawn);
    r.f64s(this.protect);
    r.ints(this.kills);
    r.ints(this.deaths);
    r.ints(this.captures);
    r.ints(this.flagState);
    r.ints(this.flagCarrier);
    r.f64s(this.flagX);
    r.f64s(this.flagY);
    r.f64s(this.flagTimer);
  }

  protected override validate(): void {
    for (let s = 0; s < SLOTS; s++) {
      if (this.active[s]! > 1 || this.alive[s]! > this.active[s]!) {
        throw new RangeError(`player ${s}: bad active/alive flags`);
      }
      if (this.health[s]! > CTF.health || (this.alive[s] === 1) !== this.health[s]! > 0) {
        throw new RangeError(`player ${s}: health ${this.health[s]}`);
      }
      if (this.facing[s]! > 7) throw new RangeError(`player ${s}: facing ${this.facing[s]}`);
      for (const a of [
        this.x,
        this.y,
        this.vx,
        this.vy,
        this.cooldown,
        this.respawn,
        this.protect,
      ]) {
        if (!isFiniteNumber(a[s]!)) throw new RangeError(`player ${s}: a number is not finite`);
      }
    }
    for (let t = 0; t < 2; t++) {
      const st = this.flagState[t]!;
      const c = this.flagCarrier[t]!;
      if (st > 2) throw new RangeError(`flag ${t}: state ${st}`);
      if (st === FlagState.carried) {
        if (c >= SLOTS || this.alive[c] !== 1 || (c & 1) === t) {
          throw new RangeError(`flag ${t}: carried by ${c}, who cannot carry it`);
        }
      } else if (c !== NO_CARRIER) {
        throw new RangeError(`flag ${t}: not carried but has carrier ${c}`);
      }
      if (
        !isFiniteNumber(this.flagX[t]!) ||
        !isFiniteNumber(this.flagY[t]!) ||
        !isFiniteNumber(this.flagTimer[t]!)
      ) {
        throw new RangeError(`flag ${t}: a number is not finite`);
      }
    }
  }

  protected override copyBody(o: this): void {
    this.score.set(o.score);
    this.shots = o.shots;
    this.playersThroughWalls = o.playersThroughWalls;
    for (const k of [
      'health',
      'respawn',
      'protect',
      'deaths',
      'captures',
      'flagState',
      'flagCarrier',
      'flagX',
      'flagY',
      'flagTimer',
    ] as const) {
      this[k].set(o[k]);
    }
  }
}

/** Scratch for a sine and cosine; never part of any state. */
const sc = new Float64Array(2);

/**
 * Capture the flag, as in the talk's demo ("Kills: 1, Flags captured: 0"): a top-down arena with
 * walls, some of them thin (4 units), two teams of four (red left, blue right; 1–4 human or
 * bot players on slots 0–3, AI bots on the rest), fast bullets (15 units per step), flags,
 * respawns. One hit kills; a carrier who dies drops the flag where it fell. The match is over
 * when a team reaches the capture limit or time runs out.
 *
 * - {@link step} is the real game: a fixed 1/60 s step, bullets swept against walls and players
 *   (continuous detection), walls that satisfy the talk's rule for every other body
 *   (`minWallSize = maxSpeed × step`: players move 2.67 units per step, the thinnest wall is 4).
 *   Nothing ever passes through a wall. Deterministic: same seed and inputs, same bytes.
 * - {@link update} is the naive game the talk warns about: the same rules, moving everything by
 *   `v·dt` for whatever Δt the frame had, with discrete detection only. At 30 Hz a bullet jumps
 *   30 units a frame and goes through a 4-unit wall more often than not.
 *
 * Hot state is in typed arrays ({@link CtfState}); a step allocates nothing. The AI of the bot
 * slots is {@link ctfBotInput} — the same function the registry's bot uses for human slots —
 * evaluated for every bot before anything moves.
 */
export class CtfGame extends ArenaGame<CtfState> implements BulletTargets {
  /** Whether the other slots are filled with AI bots. */
  readonly fill: boolean;

  // BulletTargets: the players.
  readonly targetCount = SLOTS;
  readonly targetX = this.state.x;
  readonly targetY = this.state.y;
  readonly targetRadius = R;

  private readonly inputs = new Uint32Array(SLOTS);

  constructor(options: CtfOptions) {
    super('CtfGame', CTF_INFO, CTF, CTF_WALLS, () => new CtfState(), options);
    this.fill = options.fill ?? true;
    const s = this.state;
    for (let p = 0; p < SLOTS; p++) {
      if (p >= this.players && !this.fill) continue;
      s.active[p] = 1;
      this.spawn(p, p >> 1);
    }
    for (let t = 0; t < 2; t++) this.flagHome(t);
    s.prevX.set(s.x);
    s.prevY.set(s.y);
  }

  /** Player 0's numbers, as on the slide ("Kills: 1, Flags captured: 0"), and the match's. */
  override hud(): Readonly<Record<string, number>> {
    const s = this.state;
    return {
      kills: s.kills[0]!,
      flags: s.captures[0]!,
      deaths: s.deaths[0]!,
      red: s.score[0]!,
      blue: s.score[1]!,
      timeLeft: Math.max(0, Math.ceil(CTF.timeLimit - s.clock)),
      throughWalls: s.bullets.throughWalls + s.playersThroughWalls,
    };
  }

  /** Team of a slot: 0 red, 1 blue. */
  teamOf(slot: number): number {
    return slot & 1;
  }

  /** The team whose flag `slot` carries, or -1. */
  carrying(slot: number): number {
    const s = this.state;
    const t = 1 - (slot & 1);
    return s.flagState[t] === FlagState.carried && s.flagCarrier[t] === slot ? t : -1;
  }

  // --- BulletTargets ---

  canHit(b: number, t: number): boolean {
    return this.state.alive[t] === 1 && (t & 1) !== this.state.bullets.team[b];
  }

  hit(b: number, t: number): void {
    const s = this.state;
    if (s.protect[t]! > 0) return; // spawn protection absorbs it
    const h = s.health[t]! - 1;
    s.health[t] = h;
    if (h === 0) this.kill(t, s.bullets.owner[b]!);
  }

  // --- the rules ---

  protected override advance(dt: number, given: readonly ButtonInput[], continuous: boolean): void {
    const s = this.state;
    if (s.over === 1) return;
    const inputs = this.inputs;
    // Every input first (the bots read the state as it is before anything moves).
    for (let p = 0; p < SLOTS; p++) {
      if (s.active[p] === 0) inputs[p] = 0;
      else if (p < this.players) inputs[p] = (given[p] ?? 0) >>> 0;
      else inputs[p] = ctfBotInput(this, p);
    }
    // Timers and respawns.
    for (let p = 0; p < SLOTS; p++) {
      if (s.active[p] === 0) continue;
      if (s.alive[p] === 0) {
        s.respawn[p] = s.respawn[p]! - dt;
        if (s.respawn[p]! <= 0) this.spawn(p, s.rng.int(4));
        continue;
      }
      s.cooldown[p] = Math.max(0, s.cooldown[p]! - dt);
      s.protect[p] = Math.max(0, s.protect[p]! - dt);
    }
    // Movement: v·dt, then the discrete push-out (safe at the fixed step: see the class doc).
    for (let p = 0; p < SLOTS; p++) {
      const x = s.x[p]!;
      const y = s.y[p]!;
      s.prevX[p] = x;
      s.prevY[p] = y;
      if (s.alive[p] === 0) continue;
      if (!this.walk(p, inputs[p]!, dt)) continue;
      // The tunnelling diagnostic; a move that met no wall (see `walkedClear`) needs no test.
      if (this.walkedClear) continue;
      // (The walls' register form: see `Walls`.)
      const q = this.walls.query;
      q[0] = x;
      q[1] = y;
      q[2] = s.x[p]!;
      q[3] = s.y[p]!;
      if (this.walls.crossesQuery()) s.playersThroughWalls++;
    }
    // Fire.
    const bullets = s.bullets;
    for (let p = 0; p < SLOTS; p++) {
      if (s.alive[p] === 0 || s.cooldown[p]! > 0) continue;
      if (!isDown(inputs[p]!, ShooterButtons.fire)) continue;
      const f = s.facing[p]!;
      // A little spread (seeded): the facing direction turned by up to ±CTF.spread radians.
      dsincos(s.rng.range(-CTF.spread, CTF.spread), sc);
      const ux = DIR_X[f]!;
      const uy = DIR_Y[f]!;
      const c = sc[1]!;
      const sn = sc[0]!;
      // From the shooter's centre: its first move is swept from there, so a player hugging a thin
      // wall cannot shoot through it.
      const l = bullets.launch;
      l[0] = s.x[p]!;
      l[1] = s.y[p]!;
      l[2] = (ux * c - uy * sn) * CTF.bulletSpeed;
      l[3] = (ux * sn + uy * c) * CTF.bulletSpeed;
      l[4] = CTF.bulletLife;
      const b = bullets.spawnLaunched(p, p & 1);
      if (b < 0) continue;
      s.cooldown[p] = CTF.fireCooldown;
      s.protect[p] = 0;
      s.shots++;
    }
    bullets.advance(dt, this.walls, this, continuous);
    this.flags(dt);
    if (s.clock + dt >= CTF.timeLimit) s.over = 1;
  }

  private flags(dt: number): void {
    const s = this.state;
    const pr2 = CTF.pickupRadius * CTF.pickupRadius;
    for (let t = 0; t < 2; t++) {
      if (s.flagState[t] === FlagState.carried) {
        const c = s.flagCarrier[t]!;
        s.flagX[t] = s.x[c]!;
        s.flagY[t] = s.y[c]!;
        continue;
      }
      if (s.flagState[t] === FlagState.dropped) {
        s.flagTimer[t] = s.flagTimer[t]! - dt;
        if (s.flagTimer[t]! <= 0) {
          this.flagHome(t);
          continue;
        }
      }
      // Who touches it first, in slot order. A flag at home does nothing for its own team, so
      // only the other team's slots (every other one) need a look then.
      const home = s.flagState[t] === FlagState.home;
      for (let p = home ? 1 - t : 0; p < SLOTS; p += home ? 2 : 1) {
        if (s.alive[p] === 0) continue;
        const ex = s.x[p]! - s.flagX[t]!;
        const ey = s.y[p]! - s.flagY[t]!;
        if (ex * ex + ey * ey > pr2) continue;
        if ((p & 1) === t) {
          // Own flag: touching it where it fell sends it home.
          if (s.flagState[t] === FlagState.dropped) {
            this.flagHome(t);
            break;
          }
          continue;
        }
        s.flagState[t] = FlagState.carried;
        s.flagCarrier[t] = p;
        s.flagTimer[t] = 0;
        s.flagX[t] = s.x[p]!;
        s.flagY[t] = s.y[p]!;
        s.protect[p] = 0;
        break;
      }
    }
    // Captures: a carrier at its own stand while its own flag is home.
    const cr2 = CTF.captureRadius * CTF.captureRadius;
    for (let t = 0; t < 2; t++) {
      if (s.flagState[t] !== FlagState.carried) continue;
      const c = s.flagCarrier[t]!;
      const own = c & 1;
      if (s.flagState[own] !== FlagState.home) continue;
      const ex = s.x[c]! - FLAG_STAND_X[own]!;
      const ey = s.y[c]! - FLAG_STAND_Y[own]!;
      if (ex * ex + ey * ey > cr2) continue;
      s.score[own] = s.score[own]! + 1;
      s.captures[c] = s.captures[c]! + 1;
      this.flagHome(t);
      if (s.score[own] >= CTF.captureLimit) s.over = 1;
    }
  }

  private flagHome(t: number): void {
    const s = this.state;
    s.flagState[t] = FlagState.home;
    s.flagCarrier[t] = NO_CARRIER;
    s.flagX[t] = FLAG_STAND_X[t]!;
    s.flagY[t] = FLAG_STAND_Y[t]!;
    s.flagTimer[t] = 0;
  }

  private kill(victim: number, killer: number): void {
    const s = this.state;
    s.alive[victim] = 0;
    s.health[victim] = 0;
    s.vx[victim] = 0;
    s.vy[victim] = 0;
    s.cooldown[victim] = 0;
    s.protect[victim] = 0;
    s.respawn[victim] = CTF.respawnTime;
    s.deaths[victim] = s.deaths[victim]! + 1;
    s.kills[killer] = s.kills[killer]! + 1;
    const t = 1 - (victim & 1);
    if (s.flagState[t] === FlagState.carried && s.flagCarrier[t] === victim) {
      s.flagState[t] = FlagState.dropped;
      s.flagCarrier[t] = NO_CARRIER;
      s.flagX[t] = s.x[victim]!;
      s.flagY[t] = s.y[victim]!;
      s.flagTimer[t] = CTF.flagReturnTime;
    }
  }

  private spawn(p: number, point: number): void {
    const s = this.state;
    const t = p & 1;
    s.alive[p] = 1;
    s.health[p] = CTF.health;
    s.x[p] = SPAWN_X[t]![point]!;
    s.y[p] = SPAWN_Y[t]![point]!;
    s.prevX[p] = s.x[p]!;
    s.prevY[p] = s.y[p]!;
    s.vx[p] = 0;
    s.vy[p] = 0;
    s.facing[p] = t === 0 ? 0 : 4;
    s.cooldown[p] = 0;
    s.respawn[p] = 0;
    s.protect[p] = CTF.protectTime;
  }
}
