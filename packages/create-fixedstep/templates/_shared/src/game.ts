/**
 * Your game: steer a disc, collect the coins a seeded generator drops, half a minute on the clock
 * (made by `npm create fixedstep`, after the repository's Coin Dash example). The whole game is
 * this file: an input schema, a deterministic simulation, and the definition that the loop, the
 * replays, the network sessions and the server all read. Change it freely — and bump `version`
 * in the definition below when you do: old replays then say they are of another version.
 *
 * Determinism rules it follows: time is `tick / TICK_RATE`, randomness is a seeded `Random` kept
 * in the state, math is + − × ÷ and Math.sqrt, and `save()` writes every bit of state.
 */
import {
  ByteReader,
  ByteWriter,
  Random,
  defineGame,
  defineInput,
  fnv1a64,
  isDown,
  packButtons,
  wasPressed,
  type ButtonInput,
  type GameSetup,
  type Simulation,
} from 'fixedstep';

/** Ticks per second: the one place the rate is written (the loop and the recorder read it). */
export const TICK_RATE = 60;
/** A round lasts half a minute. */
export const ROUND_TICKS = 30 * TICK_RATE;
/** The field, in metres: x from 0 to WIDTH, y from 0 to HEIGHT (y down, as on screen). */
export const WIDTH = 16;
export const HEIGHT = 9;
export const PLAYER_RADIUS = 0.4;
export const COIN_RADIUS = 0.25;
/** Coins on the field at once. */
export const COINS = 5;

const ACCEL = 40; // m/s² while steering
const DRAG = 6; // 1/s: velocity decays by DRAG × dt each tick
const DASH_SPEED = 12; // m/s added by a dash
const DASH_COOLDOWN = TICK_RATE; // ticks

/**
 * What a player sends each tick: four direction buttons and a dash, one word (`ButtonInput`).
 * A schema may also declare quantised axes (a stick, an aim angle); its inputs are then
 * `PlayerInput`s: see the guide's input page.
 */
export const input = defineInput({
  buttons: ['left', 'right', 'up', 'down', 'dash'],
});
const B = input.button;

/** The state of a round, in typed arrays: saving it is copying them. */
export class MyGame implements Simulation<ButtonInput> {
  readonly players: number;
  tick = 0;
  readonly x: Float64Array;
  readonly y: Float64Array;
  readonly vx: Float64Array;
  readonly vy: Float64Array;
  readonly score: Uint32Array;
  /** Ticks until each player may dash again. */
  readonly cooldown: Uint32Array;
  readonly coinX = new Float64Array(COINS);
  readonly coinY = new Float64Array(COINS);
  private readonly rng: Random;

  constructor(setup: GameSetup) {
    this.players = setup.players;
    const n = setup.players;
    this.x = new Float64Array(n);
    this.y = new Float64Array(n);
    this.vx = new Float64Array(n);
    this.vy = new Float64Array(n);
    this.score = new Uint32Array(n);
    this.cooldown = new Uint32Array(n);
    this.rng = new Random(setup.seed);
    for (let p = 0; p < n; p++) {
      this.x[p] = (WIDTH * (p + 1)) / (n + 1);
      this.y[p] = HEIGHT / 2;
    }
    for (let c = 0; c < COINS; c++) this.dropCoin(c);
  }

  get over(): boolean {
    return this.tick >= ROUND_TICKS;
  }

  /** One fixed step: steer, move, bounce off the edges, collect coins. */
  step(inputs: readonly ButtonInput[]): void {
    if (this.over) return; // the round has ended: the state stays as it is
    const dt = 1 / TICK_RATE;
    for (let p = 0; p < this.players; p++) {
      const i = inputs[p]!;
      let ax = (isDown(i, B.right) ? 1 : 0) - (isDown(i, B.left) ? 1 : 0);
      let ay = (isDown(i, B.down) ? 1 : 0) - (isDown(i, B.up) ? 1 : 0);
      const len = Math.sqrt(ax * ax + ay * ay);
      if (len > 1) {
        ax /= len;
        ay /= len;
      }
      this.vx[p] = (this.vx[p]! + ax * ACCEL * dt) * (1 - DRAG * dt);
      this.vy[p] = (this.vy[p]! + ay * ACCEL * dt) * (1 - DRAG * dt);
      if (this.cooldown[p]! > 0) this.cooldown[p]!--;
      else if (wasPressed(i, B.dash) && len > 0) {
        this.vx[p] = this.vx[p]! + ax * DASH_SPEED;
        this.vy[p] = this.vy[p]! + ay * DASH_SPEED;
        this.cooldown[p] = DASH_COOLDOWN;
      }
      this.x[p] = this.x[p]! + this.vx[p]! * dt;
      this.y[p] = this.y[p]! + this.vy[p]! * dt;
      this.bounce(p);
      for (let c = 0; c < COINS; c++) {
        const dx = this.coinX[c]! - this.x[p]!;
        const dy = this.coinY[c]! - this.y[p]!;
        const r = PLAYER_RADIUS + COIN_RADIUS;
        if (dx * dx + dy * dy <= r * r) {
          this.score[p]!++;
          this.dropCoin(c);
        }
      }
    }
    this.tick++;
  }

  private bounce(p: number): void {
    const lo = PLAYER_RADIUS;
    if (this.x[p]! < lo) {
      this.x[p] = lo;
      this.vx[p] = -this.vx[p]! * 0.5;
    } else if (this.x[p]! > WIDTH - lo) {
      this.x[p] = WIDTH - lo;
      this.vx[p] = -this.vx[p]! * 0.5;
    }
    if (this.y[p]! < lo) {
      this.y[p] = lo;
      this.vy[p] = -this.vy[p]! * 0.5;
    } else if (this.y[p]! > HEIGHT - lo) {
      this.y[p] = HEIGHT - lo;
      this.vy[p] = -this.vy[p]! * 0.5;
    }
  }

  private dropCoin(c: number): void {
    this.coinX[c] = this.rng.range(1, WIDTH - 1);
    this.coinY[c] = this.rng.range(1, HEIGHT - 1);
  }

  save(): Uint8Array {
    const w = new ByteWriter(64 + this.players * 48);
    w.u32(this.tick).u8(this.players).ints(this.rng.getState());
    w.f64s(this.x).f64s(this.y).f64s(this.vx).f64s(this.vy);
    w.ints(this.score).ints(this.cooldown).f64s(this.coinX).f64s(this.coinY);
    return w.finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    const tick = r.u32('tick');
    if (r.u8('players') !== this.players) {
      throw new RangeError(`MyGame.load: a save of another player count`);
    }
    const rng = new Uint32Array(4);
    r.ints(rng);
    r.f64s(this.x);
    r.f64s(this.y);
    r.f64s(this.vx);
    r.f64s(this.vy);
    r.ints(this.score);
    r.ints(this.cooldown);
    r.f64s(this.coinX);
    r.f64s(this.coinY);
    r.end();
    this.rng.setState(rng);
    this.tick = tick;
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/**
 * The game as every fixedstep tool takes it: `new FixedLoop({ step: myGame })`,
 * `ReplayRecorder.forGame(myGame, …)`, `verifyReplay(bytes, myGame)`,
 * `new RollbackSession({ game: myGame, … })`, `fixedstep serve --games …`,
 * `fixedstep replay verify --games …`.
 */
export const myGame = defineGame<ButtonInput, MyGame>({
  id: 'my-game',
  version: 1,
  title: 'My game',
  tickRate: TICK_RATE,
  input,
  minPlayers: 1,
  maxPlayers: 4,
  create: (setup) => new MyGame(setup),
  score: (game) => game.score[0]!,
  isOver: (game) => game.over,
  bot(game, p) {
    // Head for the nearest coin, on the direction buttons.
    let best = 0;
    let bestD = Infinity;
    for (let c = 0; c < COINS; c++) {
      const dx = game.coinX[c]! - game.x[p]!;
      const dy = game.coinY[c]! - game.y[p]!;
      const d = dx * dx + dy * dy;
      if (d < bestD) {
        bestD = d;
        best = c;
      }
    }
    const dx = game.coinX[best]! - game.x[p]!;
    const dy = game.coinY[best]! - game.y[p]!;
    let down = 0;
    if (Math.abs(dx) > PLAYER_RADIUS) down |= 1 << (dx > 0 ? B.right : B.left);
    if (Math.abs(dy) > PLAYER_RADIUS) down |= 1 << (dy > 0 ? B.down : B.up);
    return packButtons(down, 0);
  },
});

/** What `fixedstep serve --games <this module>` loads. */
export default [myGame];
