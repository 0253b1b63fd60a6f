import { isDown as isDown_, type ButtonInput, type ByteReader, type ByteWriter } from 'fixedstep';
import type { GameConfig } from '../game.js';
import type { BulletTargets } from '../arena/bullets.js';
import { ArenaGame, ArenaState, arenaInfo } from '../arena/game.js';
import {
  DIR_X as DIR_X_,
  DIR_Y as DIR_Y_,
  ShooterButtons as ShooterButtons_,
  clamp as clamp_,
  isFiniteNumber,
} from '../arena/motion.js';
import { nearestLive as nearestLive_ } from '../arena/seek.js';
import {
  START_X,
  START_Y,
  SURVIVAL as SURVIVAL_,
  SURVIVAL_VERSION,
  SURVIVAL_WALLS,
  waveInterval,
  waveSize,
  waveSpeed,
} from './layout.js';

// Local copies of imported bindings: some loaders (vitest, tsx) read an import through a
// getter on every use, which costs in hot loops.
const isDown = isDown_;
const DIR_X = DIR_X_;
const DIR_Y = DIR_Y_;
const ShooterButtons = ShooterButtons_;
const clamp = clamp_;
const nearestLive = nearestLive_;
const SURVIVAL = SURVIVAL_;
const PLAYERS = SURVIVAL.maxPlayers;
const CAP = SURVIVAL.enemyCapacity;
const PR = SURVIVAL.playerRadius;
const ER = SURVIVAL.enemyRadius;
const MAGIC = 0x31565553; // "SUV1"

/** What the wave machine is doing. */
export const WavePhase = {
  /** Calm before the next wave. */
  breather: 0,
  /** Enemies of the current wave are still arriving (or alive). */
  spawning: 1,
} as const;

/** Survival's identity, for the registry, replays and the lab. */
export const SURVIVAL_INFO = arenaInfo('survival', SURVIVAL_VERSION, 'Survival', PLAYERS);

/** Options of a {@link SurvivalGame} beyond the {@link GameConfig}. */
export interface SurvivalOptions extends GameConfig {
  /** Send waves. Default true. With false, enemies come only from {@link SurvivalGame.spawnEnemy}. */
  waves?: boolean;
  /** Lives per player (1–255). Default 15. */
  lives?: number;
}

/**
 * The whole state, structure of arrays, fixed size: players by slot, enemies and bullets in
 * pools (a new one takes the lowest free slot; a removed one's slot is zeroed). Everything is
 * saved, loaded and hashed except `prevX`/`prevY` (render interpolation only).
 */
export class SurvivalState extends ArenaState {
  /** The current wave (0 before the first). */
  wave = 0;
  /** {@link WavePhase}. */
  phase: number = WavePhase.breather;
  /** Seconds to the next wave (breather) or the next spawn (spawning). */
  timer = 0;
  /** Enemies of the current wave still to come. */
  toSpawn = 0;
  /** Waves cleared. */
  cleared = 0;
  /** Enemies whose path went through a wall (a diagnostic; only possible under `update`). */
  enemiesThroughWalls = 0;
  /** Serial of the next enemy (unique per enemy in a game). */
  nextEnemy = 1;

  readonly lives = new Uint8Array(PLAYERS);
  /** Seconds of invulnerability left. */
  readonly invulnerable = new Float64Array(PLAYERS);

  readonly enemyAlive = new Uint8Array(CAP);
  readonly enemySerial = new Uint32Array(CAP);
  readonly ex = new Float64Array(CAP);
  readonly ey = new Float64Array(CAP);
  readonly evx = new Float64Array(CAP);
  readonly evy = new Float64Array(CAP);
  /** Each enemy's running speed, units per second. */
  readonly espeed = new Float64Array(CAP);
  /** Which way an enemy runs along the wall it is stuck on (±1, 0 when free). */
  readonly eslide = new Int8Array(CAP);
  readonly enemyPrevX = new Float64Array(CAP);
  readonly enemyPrevY = new Float64Array(CAP);
  /** Live enemies. */
  enemies = 0;

  constructor() {
    super({
      magic: MAGIC,
      what: 'survival state',
      slots: PLAYERS,
      maxTeam: 0,
      bulletCapacity: SURVIVAL.bulletCapacity,
      bulletRadius: SURVIVAL.bulletRadius,
    });
  }

  protected override writeBody(w: ByteWriter): void {
    w.u32(this.wave).u8(this.phase).f64(this.timer).u32(this.toSpawn).u32(this.cleared);
    w.u32(this.enemiesThroughWalls).u32(this.nextEnemy);
    w.ints(this.active).ints(this.alive).ints(this.facing).ints(this.lives);
    w.f64s(this.x).f64s(this.y).f64s(this.vx).f64s(this.vy);
    w.f64s(this.cooldown).f64s(this.invulnerable).ints(this.kills);
    w.ints(this.enemyAlive).ints(this.enemySerial);
    w.f64s(this.ex).f64s(this.ey).f64s(this.evx).f64s(this.evy).f64s(this.espeed);
    w.ints(this.eslide);
  }

  protected override readBody(r: ByteReader): void {
    this.wave = r.u32();
    this.phase = r.u8();
    this.timer = r.f64();
    this.toSpawn = r.u32();
    this.cleared = r.u32();
    this.enemiesThroughWalls = r.u32();
    this.nextEnemy = r.u32();
    r.ints(this.active);
    r.ints(this.alive);
    r.ints(this.facing);
    r.ints(this.lives);
    r.f64s(this.x);
    r.f64s(this.y);
    r.f64s(this.vx);
    r.f64s(this.vy);
    r.f64s(this.cooldown);
    r.f64s(this.invulnerable);
    r.ints(this.kills);
    r.ints(this.enemyAlive);
    r.ints(this.enemySerial);
    r.f64s(this.ex);
    r.f64s(this.ey);
    r.f64s(this.evx);
    r.f64s(this.evy);
    r.f64s(this.espeed);
    r.ints(this.eslide);
  }

  protected override validate(players: number): void {
    if (!isFiniteNumber(this.timer)) throw new RangeError('bad wave timer');
    if (this.phase > 1) throw new RangeError(`bad wave phase ${this.phase}`);
    if (this.toSpawn > 1000 || this.wave > 1_000_000) throw new RangeError('bad wave counters');
    for (let s = 0; s < PLAYERS; s++) {
      const active = (this.active[s] === 1) === s < players;
      if (!active || this.alive[s]! > this.active[s]!) {
        throw new RangeError(`player ${s}: bad active/alive flags`);
      }
      if (this.facing[s]! > 7) throw new RangeError(`player ${s}: facing ${this.facing[s]}`);
      if ((this.alive[s] === 1) !== this.lives[s]! > 0) {
        throw new RangeError(`player ${s}: alive with no lives, or lives but dead`);
      }
      for (const a of [this.x, this.y, this.vx, this.vy, this.cooldown, this.invulnerable]) {
        if (!isFiniteNumber(a[s]!)) throw new RangeError(`player ${s}: a number is not finite`);
      }
    }
    let n = 0;
    for (let e = 0; e < CAP; e++) {
      const a = this.enemyAlive[e]!;
      if (a > 1) throw new RangeError(`enemy ${e}: alive flag ${a}`);
      const slide = this.eslide[e]!;
      if (slide < -1 || slide > 1 || (a === 0 && slide !== 0)) {
        throw new RangeError(`enemy ${e}: slide ${slide}`);
      }
      const nums = [this.ex[e]!, this.ey[e]!, this.evx[e]!, this.evy[e]!, this.espeed[e]!];
      if (a === 0) {
        if (this.enemySerial[e] !== 0 || nums.some((v) => v !== 0)) {
          throw new RangeError(`enemy ${e}: an empty slot that is not zeroed`);
        }
        continue;
      }
      n++;
      if (!nums.every(isFiniteNumber) || !(this.espeed[e]! <= SURVIVAL.maxEnemySpeed)) {
        throw new RangeError(`enemy ${e}: a number is not finite or too fast`);
      }
    }
    this.enemies = n;
    this.enemyPrevX.set(this.ex);
    this.enemyPrevY.set(this.ey);
  }

  protected override copyBody(o: this): void {
    this.wave = o.wave;
    this.phase = o.phase;
    this.timer = o.timer;
    this.toSpawn = o.toSpawn;
    this.cleared = o.cleared;
    this.enemiesThroughWalls = o.enemiesThroughWalls;
    this.nextEnemy = o.nextEnemy;
    this.enemies = o.enemies;
    for (const k of [
      'lives',
      'invulnerable',
      'enemyAlive',
      'enemySerial',
      'ex',
      'ey',
      'evx',
      'evy',
      'espeed',
      'eslide',
      'enemyPrevX',
      'enemyPrevY',
    ] as const) {
      this[k].set(o[k]);
    }
  }
}

/** Scratch, never state: push-out results, per-enemy shoves, a nearest distance, a spawn point. */
const moved = new Float64Array(2);
const shoveX = new Float64Array(CAP);
const shoveY = new Float64Array(CAP);
const near = new Float64Array(1);
const edgeX = new Float64Array(1);
const edgeY = new Float64Array(1);
/** An enemy to add: x, y, speed. */
const newEnemy = new Float64Array(3);

/**
 * Survival, as in the talk's demo ("Kills: 0, Lives: 15"): waves of fast enemies, spawned at
 * seeded places along the edges, run straight at the nearest player inside a walled arena; the
 * player (or two, co-op) moves and shoots; an enemy that touches a player costs a life. The game
 * is over when every player has lost every life.
 *
 * - {@link step}: 1/60 s, bullets swept (continuous detection); every wall is 10 units thick or
 *   more, while an enemy moves at most 7 units per step (5.5 running plus 1.5 shoved): the talk's
 *   rule holds, so an enemy pressing on a wall slides along it and never comes through.
 * - {@link update}: the naive game, `v·dt` with discrete detection. An enemy pressing on a wall
 *   during a long frame (a hitch, a slow display) jumps past its middle and is pushed out on the
 *   player's side — the slide's enemies that slip through walls.
 */
export class SurvivalGame extends ArenaGame<SurvivalState> implements BulletTargets {
  /** Whether waves come by themselves. */
  readonly waves: boolean;

  // BulletTargets: the enemies.
  readonly targetCount = CAP;
  readonly targetX = this.state.ex;
  readonly targetY = this.state.ey;
  readonly targetRadius = ER;
  /** The enemies alive when they last moved, in slot order (some may have died since). Not state. */
  readonly targetList = new Int32Array(CAP);
  targetListCount = 0;

  private readonly inputs = new Uint32Array(PLAYERS);
  /** One past the highest slot that may hold an enemy (the slots from here on are empty). Not state. */
  private enemyEnd = 0;
  /** The slots from here on have `enemyPrevX/Y` equal to their (zero) position. Not state. */
  private prevEnd = 0;

  constructor(options: SurvivalOptions) {
    super(
      'SurvivalGame',
      SURVIVAL_INFO,
      SURVIVAL,
      SURVIVAL_WALLS,
      () => new SurvivalState(),
      options,
    );
    const lives = options.lives ?? SURVIVAL.lives;
    if (!Number.isInteger(lives) || lives < 1 || lives > 255) {
      throw new RangeError(`SurvivalGame: lives must be from 1 to 255, got ${String(lives)}`);
    }
    this.waves = options.waves ?? true;
    const s = this.state;
    for (let p = 0; p < this.players; p++) {
      s.active[p] = 1;
      s.alive[p] = 1;
      s.lives[p] = lives;
      s.x[p] = START_X[p]!;
      s.y[p] = START_Y[p]!;
      s.facing[p] = 6; // north
    }
    s.prevX.set(s.x);
    s.prevY.set(s.y);
    s.timer = SURVIVAL.firstWaveDelay;
  }

  /** Player 0's numbers, as on the slide ("Kills: 0, Lives: 15"), and the waves'. */
  override hud(): Readonly<Record<string, number>> {
    const s = this.state;
    return {
      kills: s.kills[0]!,
      lives: s.lives[0]!,
      wave: s.wave,
      cleared: s.cleared,
      enemies: s.enemies,
      throughWalls: s.enemiesThroughWalls + s.bullets.throughWalls,
    };
  }

  /**
   * Add an enemy at (x, y) running at `speed` (capped at `maxEnemySpeed`): for experiments and
   * the lab's set-ups. Returns its slot, or -1 if the pool is full.
   */
  spawnEnemy(x: number, y: number, speed: number): number {
    if (!(isFiniteNumber(x) && isFiniteNumber(y) && speed >= 0)) {
      throw new RangeError('SurvivalGame.spawnEnemy: position and speed must be finite');
    }
    newEnemy[0] = x;
    newEnemy[1] = y;
    newEnemy[2] = speed;
    return this.addEnemy();
  }

  /** {@link spawnEnemy} of the enemy in `newEnemy` (x, y, speed: so no number is boxed). */
  private addEnemy(): number {
    const s = this.state;
    for (let e = 0; e < CAP; e++) {
      if (s.enemyAlive[e] !== 0) continue;
      const x = newEnemy[0]!;
      const y = newEnemy[1]!;
      s.enemyAlive[e] = 1;
      s.enemySerial[e] = s.nextEnemy;
      s.nextEnemy = (s.nextEnemy + 1) >>> 0;
      s.ex[e] = x;
      s.ey[e] = y;
      s.enemyPrevX[e] = x;
      s.enemyPrevY[e] = y;
      s.evx[e] = 0;
      s.evy[e] = 0;
      s.espeed[e] = Math.min(newEnemy[2]!, SURVIVAL.maxEnemySpeed);
      s.enemies++;
      if (e >= this.enemyEnd) this.enemyEnd = e + 1;
      return e;
    }
    return -1;
  }

  // --- BulletTargets ---

  canHit(_b: number, t: number): boolean {
    return this.state.enemyAlive[t] === 1;
  }

  hit(b: number, t: number): void {
    const s = this.state;
    const owner = s.bullets.owner[b]!;
    s.kills[owner] = s.kills[owner]! + 1;
    this.removeEnemy(t);
  }

  // --- the rules ---

  protected override advance(dt: number, given: readonly ButtonInput[], continuous: boolean): void {
    const s = this.state;
    if (s.over === 1) return;
    const inputs = this.inputs;
    for (let p = 0; p < PLAYERS; p++) inputs[p] = p < this.players ? (given[p] ?? 0) >>> 0 : 0;
    // Players: timers, movement, fire.
    const bullets = s.bullets;
    for (let p = 0; p < PLAYERS; p++) {
      const x = s.x[p]!;
      const y = s.y[p]!;
      s.prevX[p] = x;
      s.prevY[p] = y;
      if (s.alive[p] === 0) continue;
      s.cooldown[p] = Math.max(0, s.cooldown[p]! - dt);
      s.invulnerable[p] = Math.max(0, s.invulnerable[p]! - dt);
      const input = inputs[p]!;
      this.walk(p, input, dt);
      if (s.cooldown[p]! > 0 || !isDown(input, ShooterButtons.fire)) continue;
      const f = s.facing[p]!;
      const l = bullets.launch;
      l[0] = s.x[p]!;
      l[1] = s.y[p]!;
      l[2] = DIR_X[f]! * SURVIVAL.bulletSpeed;
      l[3] = DIR_Y[f]! * SURVIVAL.bulletSpeed;
      l[4] = SURVIVAL.bulletLife;
      const b = bullets.spawnLaunched(p, 0);
      if (b >= 0) s.cooldown[p] = SURVIVAL.fireCooldown;
    }
    if (this.waves) this.spawnWaves(dt);
    this.moveEnemies(dt);
    bullets.advance(dt, this.walls, this, continuous);
    this.contacts();
    if (this.waves && s.phase === WavePhase.spawning && s.toSpawn === 0 && s.enemies === 0) {
      s.cleared++;
      s.phase = WavePhase.breather;
      s.timer = SURVIVAL.breather;
    }
  }

  private spawnWaves(dt: number): void {
    const s = this.state;
    s.timer -= dt;
    if (s.phase === WavePhase.breather) {
      if (s.timer > 0) return;
      s.wave++;
      s.phase = WavePhase.spawning;
      s.toSpawn = waveSize(s.wave);
      s.timer = 0;
    }
    const interval = waveInterval(s.wave);
    while (s.timer <= 0 && s.toSpawn > 0) {
      if (!this.spawnAtEdge()) break;
      s.toSpawn--;
      s.timer += interval;
    }
    if (s.timer < 0) s.timer = 0;
  }

  /** One enemy of the current wave at a seeded place along the edges, away from the players. */
  private spawnAtEdge(): boolean {
    const s = this.state;
    const rng = s.rng;
    const lo = SURVIVAL.border + 16;
    let x = 0;
    let y = 0;
    for (let attempt = 0; attempt < 4; attempt++) {
      const edge = rng.int(4);
      const along = rng.next();
      if (edge < 2) {
        x = lo + along * (SURVIVAL.width - 2 * lo);
        y = edge === 0 ? lo : SURVIVAL.height - lo;
      } else {
        x = edge === 2 ? lo : SURVIVAL.width - lo;
        y = lo + along * (SURVIVAL.height - 2 * lo);
      }
      edgeX[0] = x;
      edgeY[0] = y;
      nearestLive(edgeX, edgeY, 0, s.alive, s.x, s.y, near);
      if (near[0]! > 180 * 180) break;
    }
    newEnemy[0] = x;
    newEnemy[1] = y;
    newEnemy[2] = waveSpeed(s.wave) * (0.85 + 0.3 * rng.next());
    return this.addEnemy() >= 0;
  }

  /**
   * Every enemy runs straight at the nearest living player (along a wall that blocks it);
   * enemies that overlap shove each other apart (at most `maxShove` per step); the walls push
   * them out — discretely: that is where the naive game lets them through.
   */
  private moveEnemies(dt: number): void {
    const s = this.state;
    // The live enemies, in slot order: every loop below visits them in that order (for the shoves,
    // pairs in the order of the slots), as loops over every slot would.
    const live = this.targetList;
    const end = this.enemyEnd;
    let n = 0;
    for (let e = 0; e < end; e++) if (s.enemyAlive[e] !== 0) live[n++] = e;
    this.targetListCount = n;
    // Every slot's previous position is its position now: from the prevEnd-th slot on, both are
    // zero already.
    for (let e = 0, copy = end > this.prevEnd ? end : this.prevEnd; e < copy; e++) {
      s.enemyPrevX[e] = s.ex[e]!;
      s.enemyPrevY[e] = s.ey[e]!;
    }
    this.prevEnd = end;
    if (n === 0) return;
    for (let k = 0; k < n; k++) {
      shoveX[live[k]!] = 0;
      shoveY[live[k]!] = 0;
    }
    // Shoves, pair by pair in slot order, from the positions at the start of the step.
    const d2max = 4 * ER * ER;
    for (let a = 0; a < n; a++) {
      const i = live[a]!;
      const xi = s.ex[i]!;
      const yi = s.ey[i]!;
      for (let b = a + 1; b < n; b++) {
        const j = live[b]!;
        const dx = s.ex[j]! - xi;
        const dy = s.ey[j]! - yi;
        const d2 = dx * dx + dy * dy;
        if (d2 >= d2max) continue;
        let nx = 1;
        let ny = 0;
        let push = ER;
        if (d2 > 0) {
          const d = Math.sqrt(d2);
          nx = dx / d;
          ny = dy / d;
          push = ER - d / 2;
        }
        shoveX[i] = shoveX[i]! - nx * push;
        shoveY[i] = shoveY[i]! - ny * push;
        shoveX[j] = shoveX[j]! + nx * push;
        shoveY[j] = shoveY[j]! + ny * push;
      }
    }
    for (let k = 0; k < n; k++) {
      const e = live[k]!;
      const x = s.ex[e]!;
      const y = s.ey[e]!;
      let vx = 0;
      let vy = 0;
      const p = nearestLive(s.ex, s.ey, e, s.alive, s.x, s.y, near);
      if (p >= 0) {
        const dx = s.x[p]! - x;
        const dy = s.y[p]! - y;
        const d = Math.sqrt(dx * dx + dy * dy);
        if (d > 0) {
          vx = (dx / d) * s.espeed[e]!;
          vy = (dy / d) * s.espeed[e]!;
        }
      }
      s.evx[e] = vx;
      s.evy[e] = vy;
      let sx = shoveX[e]!;
      let sy = shoveY[e]!;
      const sl2 = sx * sx + sy * sy;
      if (sl2 > SURVIVAL.maxShove * SURVIVAL.maxShove) {
        const k = SURVIVAL.maxShove / Math.sqrt(sl2);
        sx *= k;
        sy *= k;
      }
      // (The walls' register forms: see `Walls`.)
      const q = this.walls.query;
      q[0] = x + vx * dt + sx;
      q[1] = y + vy * dt + sy;
      // Whether the last push-out left the point as it was (it was at least ER from every wall).
      let unpushed = !this.walls.pushOutQuery(ER, moved);
      // Nearly head-on into a wall (it let through less than a quarter of the run)? Run along
      // it instead, and keep to that side until free: the way the wall already deflects it (or,
      // dead straight, the way the enemy's serial picks), else the other way.
      const want = (vx * vx + vy * vy) * dt;
      const mx = moved[0]! - x;
      const my = moved[1]! - y;
      if (want > 0 && (mx * vx + my * vy) * 4 < want) {
        let side = s.eslide[e]!;
        if (side === 0) {
          const along = mx * -vy + my * vx;
          side = along > 1e-9 ? 1 : along < -1e-9 ? -1 : (s.enemySerial[e]! & 1) === 0 ? 1 : -1;
        }
        for (let k = 0; k < 2; k++) {
          const sgn = k === 0 ? side : -side;
          const wx = -vy * sgn;
          const wy = vx * sgn;
          q[0] = x + wx * dt + sx;
          q[1] = y + wy * dt + sy;
          unpushed = !this.walls.pushOutQuery(ER, moved);
          if (((moved[0]! - x) * wx + (moved[1]! - y) * wy) * 2 >= want) {
            vx = wx;
            vy = wy;
            s.eslide[e] = sgn;
            break;
          }
        }
        s.evx[e] = vx;
        s.evy[e] = vy;
      } else {
        s.eslide[e] = 0;
      }
      const nx = clamp(moved[0]!, ER, SURVIVAL.width - ER);
      const ny = clamp(moved[1]!, ER, SURVIVAL.height - ER);
      // The tunnelling diagnostic. A move that ended where it was headed, at least ER from every
      // wall, and was shorter than ER less a unit has every point more than a unit from every
      // wall: it crossed none, and needs no test.
      const ox = nx - x;
      const oy = ny - y;
      const short = ox * ox + oy * oy < (ER - 1) * (ER - 1);
      if (!(unpushed && nx === moved[0] && ny === moved[1] && short)) {
        q[0] = x;
        q[1] = y;
        q[2] = nx;
        q[3] = ny;
        if (this.walls.crossesQuery()) s.enemiesThroughWalls++;
      }
      s.ex[e] = nx;
      s.ey[e] = ny;
    }
  }

  /** An enemy touching a player that can be hurt costs that player a life and is gone. */
  private contacts(): void {
    const s = this.state;
    const r = PR + ER;
    // The enemies alive when they moved (none has come since), in slot order.
    const live = this.targetList;
    for (let k = 0; k < this.targetListCount; k++) {
      const e = live[k]!;
      if (s.enemyAlive[e] === 0) continue;
      for (let p = 0; p < PLAYERS; p++) {
        if (s.alive[p] === 0 || s.invulnerable[p]! > 0) continue;
        const dx = s.x[p]! - s.ex[e]!;
        const dy = s.y[p]! - s.ey[e]!;
        if (dx * dx + dy * dy >= r * r) continue;
        this.removeEnemy(e);
        const lives = s.lives[p]! - 1;
        s.lives[p] = lives;
        s.invulnerable[p] = SURVIVAL.invulnerableTime;
        if (lives === 0) {
          s.alive[p] = 0;
          s.vx[p] = 0;
          s.vy[p] = 0;
          s.cooldown[p] = 0;
          s.invulnerable[p] = 0;
          if (s.alive[0] === 0 && s.alive[1] === 0) s.over = 1;
        }
        break;
      }
    }
  }

  private removeEnemy(e: number): void {
    const s = this.state;
    if (s.enemyAlive[e] === 0) return;
    s.enemyAlive[e] = 0;
    s.enemySerial[e] = 0;
    s.ex[e] = 0;
    s.ey[e] = 0;
    s.evx[e] = 0;
    s.evy[e] = 0;
    s.espeed[e] = 0;
    s.eslide[e] = 0;
    s.enemies--;
    while (this.enemyEnd > 0 && s.enemyAlive[this.enemyEnd - 1] === 0) this.enemyEnd--;
  }

  protected override loaded(): void {
    const s = this.state;
    this.enemyEnd = CAP;
    while (this.enemyEnd > 0 && s.enemyAlive[this.enemyEnd - 1] === 0) this.enemyEnd--;
    // Loading set every enemy's previous position to its position.
    this.prevEnd = this.enemyEnd;
  }
}
