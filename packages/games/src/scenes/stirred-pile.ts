/**
 * A stirred pile: Glenn Fiedler's *Snapshot Compression* scene in the own world — `n` bodies (900
 * in the bench) settled in a box, and a kinematic paddle that sweeps back and forth through the
 * pile's lower half for ever, so a large share of the bodies is always moving. The state is the
 * world's snapshot; its schema quantises positions to 1/512 m and velocities to 1/64 m/s and
 * keeps the solver's memory local (`worldStateColumns`).
 * @module
 */
import {
  BUTTON_WORD,
  bodiesInBox,
  defineGame,
  defineStateSchema,
  worldStateColumns,
  type ButtonInput,
  type GameDefinition,
  type GameSetup,
  type PhysicsWorld,
  type Simulation,
} from 'fixedstep';

/** The paddle's speed, m/s. */
const PADDLE_SPEED = 1.5;
/** The paddle's half extents, metres. */
const PADDLE_HALF_WIDTH = 0.4;
const PADDLE_HALF_HEIGHT = 0.4;
/** Ticks the pile settles before the paddle starts. */
const SETTLE_TICKS = 240;

/** The scene: a world and its paddle (the paddle is a body of the world: its state is the world's). */
export class StirredPile implements Simulation {
  readonly world: PhysicsWorld;
  /** The paddle's body id. */
  readonly paddle: number;
  private readonly left: number;
  private readonly right: number;

  constructor(
    readonly bodies: number,
    seed: number,
  ) {
    this.world = bodiesInBox(bodies, seed);
    const cols = Math.max(10, Math.ceil(1.5 * Math.sqrt(bodies)));
    const half = (cols * 0.4) / 2;
    this.left = -half + PADDLE_HALF_WIDTH + 0.05;
    this.right = half - PADDLE_HALF_WIDTH - 0.05;
    this.paddle = this.world.createBox({
      x: this.left,
      y: PADDLE_HALF_HEIGHT + 0.05,
      vx: 0,
      vy: 0,
      halfWidth: PADDLE_HALF_WIDTH,
      halfHeight: PADDLE_HALF_HEIGHT,
      kinematic: true,
    });
  }

  get tick(): number {
    return this.world.tick;
  }

  step(): void {
    const w = this.world;
    if (w.tick >= SETTLE_TICKS) {
      // Back and forth between the walls: the direction is the paddle's velocity's sign.
      const x = w.x[this.paddle]!;
      let vx = w.vx[this.paddle]!;
      if (vx === 0 || x >= this.right) vx = x >= this.right ? -PADDLE_SPEED : PADDLE_SPEED;
      else if (x <= this.left) vx = PADDLE_SPEED;
      w.setVelocity(this.paddle, vx, 0);
    }
    w.step();
  }

  save(): Uint8Array {
    return this.world.save();
  }

  load(bytes: Uint8Array): void {
    this.world.load(bytes);
  }

  hash(): bigint {
    return this.world.hash();
  }
}

/** The scene's state schema: the world's snapshot, positions to 1/512 m, velocities to 1/16 m/s. */
export const STIRRED_PILE_SCHEMA = defineStateSchema({
  columns: worldStateColumns({ position: 1 / 512, velocity: 1 / 16, extent: 64, maxSpeed: 64 }),
});

/**
 * The same, positions only (Glenn Fiedler's choice for his cubes): velocities stay with each
 * side, positions are predicted from the two snapshots before.
 */
export const STIRRED_PILE_POSITIONS_SCHEMA = defineStateSchema({
  columns: worldStateColumns({ position: 1 / 512, extent: 64, velocities: 'local' }),
});

/**
 * The stirred pile of `bodies` bodies as a game (1 to 4 players; inputs change nothing), its
 * velocities sent (default) or kept by each side (`'local'`, {@link STIRRED_PILE_POSITIONS_SCHEMA}).
 */
export function stirredPileGame(
  bodies: number,
  velocities: 'sent' | 'local' = 'sent',
): Readonly<GameDefinition<ButtonInput, StirredPile>> {
  if (!Number.isInteger(bodies) || bodies < 1 || bodies > 4000) {
    throw new RangeError(
      `stirredPileGame: bodies must be an integer from 1 to 4000, got ${bodies}`,
    );
  }
  return defineGame<ButtonInput, StirredPile>({
    id: 'stirred-pile',
    version: 1,
    tickRate: 60,
    input: BUTTON_WORD,
    minPlayers: 1,
    maxPlayers: 4,
    options: () => Uint8Array.of(bodies & 0xff, bodies >> 8),
    create: (setup: GameSetup) => {
      const o = setup.options;
      return new StirredPile(o.length === 2 ? o[0]! | (o[1]! << 8) : bodies, setup.seed);
    },
    stateSchema: velocities === 'local' ? STIRRED_PILE_POSITIONS_SCHEMA : STIRRED_PILE_SCHEMA,
  });
}
