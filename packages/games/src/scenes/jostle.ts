/**
 * Jostle: bodies in a box pushed about by random forces every tick — a state where everything
 * moves all the time, the worst case for snapshot deltas (the state-sync bench's second scene).
 * Written only against the library's public API, as a user's game would be.
 * @module
 */
import {
  BUTTON_WORD,
  ByteReader,
  ByteWriter,
  Random,
  defineGame,
  defineStateSchema,
  fnv1a64,
  type ButtonInput,
  type GameDefinition,
  type GameSetup,
  type Simulation,
} from 'fixedstep';

/** "JOSL". */
const MAGIC = 0x4c534f4a;
/** The box's side, units. */
export const JOSTLE_SIZE = 100;
/** Largest random acceleration on each axis, units/s². */
const PUSH = 60;
/** Velocity kept per tick (a little drag keeps speeds bounded). */
const KEEP = 0.99;
/** Fastest a body may go, units/s (the schema's range). */
export const JOSTLE_MAX_SPEED = 80;
const STEP = 1 / 60;

/** Bodies under random forces in a box; the state is bodies' positions and velocities and the generator. */
export class JostleScene implements Simulation {
  tick = 0;
  readonly x: Float64Array;
  readonly y: Float64Array;
  readonly vx: Float64Array;
  readonly vy: Float64Array;
  private readonly rng: Random;
  private readonly writer = new ByteWriter(256);

  constructor(
    readonly bodies: number,
    seed: number,
  ) {
    this.x = new Float64Array(bodies);
    this.y = new Float64Array(bodies);
    this.vx = new Float64Array(bodies);
    this.vy = new Float64Array(bodies);
    this.rng = new Random(seed);
    for (let i = 0; i < bodies; i++) {
      this.x[i] = this.rng.range(10, JOSTLE_SIZE - 10);
      this.y[i] = this.rng.range(10, JOSTLE_SIZE - 10);
    }
  }

  step(): void {
    const r = this.rng;
    for (let i = 0; i < this.bodies; i++) {
      let vx = (this.vx[i]! + r.range(-PUSH, PUSH) * STEP) * KEEP;
      let vy = (this.vy[i]! + r.range(-PUSH, PUSH) * STEP) * KEEP;
      vx = Math.max(-JOSTLE_MAX_SPEED, Math.min(JOSTLE_MAX_SPEED, vx));
      vy = Math.max(-JOSTLE_MAX_SPEED, Math.min(JOSTLE_MAX_SPEED, vy));
      let x = this.x[i]! + vx * STEP;
      let y = this.y[i]! + vy * STEP;
      if (x < 0 || x > JOSTLE_SIZE) {
        vx = -vx;
        x = Math.max(0, Math.min(JOSTLE_SIZE, x));
      }
      if (y < 0 || y > JOSTLE_SIZE) {
        vy = -vy;
        y = Math.max(0, Math.min(JOSTLE_SIZE, y));
      }
      this.x[i] = x;
      this.y[i] = y;
      this.vx[i] = vx;
      this.vy[i] = vy;
    }
    this.tick++;
  }

  save(): Uint8Array {
    const w = this.writer.reset();
    w.u32(MAGIC).u16(this.bodies).u32(this.tick).ints(this.rng.getState());
    w.f64s(this.x).f64s(this.y).f64s(this.vx).f64s(this.vy);
    return w.finish();
  }

  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32() !== MAGIC) throw new RangeError('not a jostle state');
    const n = r.u16();
    if (n !== this.bodies)
      throw new RangeError(`a state of ${n} bodies, this scene has ${this.bodies}`);
    const tick = r.u32();
    const rng = new Uint32Array(4);
    r.ints(rng);
    const cols = [this.x, this.y, this.vx, this.vy].map((a) => new Float64Array(a.length));
    for (const c of cols) r.f64s(c);
    r.end();
    for (const c of cols) {
      for (const v of c) if (!Number.isFinite(v)) throw new RangeError('a number is not finite');
    }
    this.tick = tick;
    this.rng.setState(rng);
    this.x.set(cols[0]!);
    this.y.set(cols[1]!);
    this.vx.set(cols[2]!);
    this.vy.set(cols[3]!);
  }

  hash(): bigint {
    return fnv1a64(this.save());
  }
}

/** The schema of a jostle state: positions to 1/128 unit (0.13 % of the box), velocities to 1/16 unit/s. */
export const JOSTLE_SCHEMA = defineStateSchema({
  columns: [
    { name: 'magic', type: 'u32', group: 'head' },
    { name: 'bodies', type: 'u16', group: 'head' },
    { name: 'tick', type: 'u32', group: 'head' },
    // The server's generator stays with the server (a client predicts with its own).
    { name: 'rng', type: 'u32', count: 4, local: true },
    ...(['x', 'y'] as const).map((name) => ({
      name,
      type: 'f64' as const,
      count: { of: 'bodies', max: 4096 },
      group: 'bodies',
      precision: 1 / 128,
      min: -1,
      max: JOSTLE_SIZE + 1,
      rate: `v${name}`,
    })),
    ...(['vx', 'vy'] as const).map((name) => ({
      name,
      type: 'f64' as const,
      count: { of: 'bodies', max: 4096 },
      group: 'bodies',
      precision: 1 / 16,
      min: -JOSTLE_MAX_SPEED,
      max: JOSTLE_MAX_SPEED,
    })),
  ],
});

/** Jostle as a game of `bodies` bodies (1 to 4 players; their inputs change nothing). */
export function jostleGame(bodies: number): Readonly<GameDefinition<ButtonInput, JostleScene>> {
  if (!Number.isInteger(bodies) || bodies < 1 || bodies > 4096) {
    throw new RangeError(`jostleGame: bodies must be an integer from 1 to 4096, got ${bodies}`);
  }
  return defineGame<ButtonInput, JostleScene>({
    id: 'jostle',
    version: 1,
    tickRate: 60,
    input: BUTTON_WORD,
    minPlayers: 1,
    maxPlayers: 4,
    options: () => Uint8Array.of(bodies & 0xff, bodies >> 8),
    create: (setup: GameSetup) => {
      const o = setup.options;
      const n = o.length === 2 ? o[0]! | (o[1]! << 8) : bodies;
      return new JostleScene(n, setup.seed);
    },
    stateSchema: JOSTLE_SCHEMA,
  });
}
