/**
 * The game every engine recipe draws: a ball on a 16 × 9 m field, steered by the arrow keys, with
 * a kick on Space. It is a fixedstep simulation like any other: it never reads a clock, uses
 * `+ − × ÷` only, and `save()` writes every bit of its state.
 */
import {
  ByteReader,
  ByteWriter,
  defineGame,
  defineInput,
  fnv1a64,
  isDown,
  wasPressed,
  type ButtonInput,
  type Simulation,
} from 'fixedstep';

/** The field in metres (y down, as on screen) and the ball's radius. */
export const WIDTH = 16;
export const HEIGHT = 9;
export const RADIUS = 0.5;

const TICK_RATE = 60;
const ACCEL = 30; // m/s² while an arrow key is down
const DRAG = 1.5; // 1/s
const KICK = 6; // m/s upwards per kick

/** Five buttons, one 32-bit word a tick. */
export const input = defineInput({ buttons: ['left', 'right', 'up', 'down', 'kick'] });
const B = input.button;

export class Ball implements Simulation<ButtonInput> {
  tick = 0;
  x = WIDTH / 2;
  y = HEIGHT / 2;
  vx = 0;
  vy = 0;
  /** Kicks so far. */
  kicks = 0;

  step(inputs: readonly ButtonInput[]): void {
    const i = inputs[0] ?? 0;
    const dt = 1 / TICK_RATE;
    const ax = (isDown(i, B.right) ? 1 : 0) - (isDown(i, B.left) ? 1 : 0);
    const ay = (isDown(i, B.down) ? 1 : 0) - (isDown(i, B.up) ? 1 : 0);
    this.vx = (this.vx + ax * ACCEL * dt) * (1 - DRAG * dt);
    this.vy = (this.vy + ay * ACCEL * dt) * (1 - DRAG * dt);
    if (wasPressed(i, B.kick)) {
      this.kicks++;
      this.vy -= KICK;
    }
    this.x += this.vx * dt;
    this.y += this.vy * dt;
    // Bounce off the edges, losing half the speed.
    if (this.x < RADIUS || this.x > WIDTH - RADIUS) {
      this.x = this.x < RADIUS ? RADIUS : WIDTH - RADIUS;
      this.vx = -this.vx / 2;
    }
    if (this.y < RADIUS || this.y > HEIGHT - RADIUS) {
      this.y = this.y < RADIUS ? RADIUS : HEIGHT - RADIUS;
      this.vy = -this.vy / 2;
    }
    this.tick++;
  }

  save(): Uint8Array {
    const w = new ByteWriter(40).u32(this.tick).u32(this.kicks);
    return w.f64(this.x).f64(this.y).f64(this.vx).f64(this.vy).finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    const tick = r.u32('tick');
    const kicks = r.u32('kicks');
    const [x, y, vx, vy] = [r.f64('x'), r.f64('y'), r.f64('vx'), r.f64('vy')];
    r.end();
    Object.assign(this, { tick, kicks, x, y, vx, vy });
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** The definition the loop reads its tick rate from (and replays, sessions, the relay). */
export const ballGame = defineGame<ButtonInput, Ball>({
  id: 'ball',
  version: 1,
  tickRate: TICK_RATE,
  input,
  minPlayers: 1,
  maxPlayers: 1,
  create: () => new Ball(),
});
