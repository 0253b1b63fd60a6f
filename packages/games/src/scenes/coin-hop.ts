/**
 * Coin hop: the guide's physics snippet as a runnable scene (docs/guide/physics.md, "Ray casts,
 * filters and sensors"). A player box runs right along the floor of the own world; a crate stands
 * in its way and a coin floats above the crate, another lies on the path. The player may jump only
 * when a short ray down from its feet finds ground (the **ground check**); the coins are kinematic
 * **sensors**, collected on the tick their `begin` event names the player. {@link coinHopBot} is a
 * second ray: it jumps when the crate is close ahead.
 *
 * The whole state is the world's snapshot (a collected coin is destroyed), so save, load, hash,
 * replays and rollback need nothing else.
 * @module
 */
import { PhysicsWorld, type RayHit, type Simulation } from 'fixedstep';

/** The player's running speed, m/s (set every tick: the player does not slow on the floor). */
export const COIN_HOP_RUN_SPEED = 4;
/** Upward speed of a jump, m/s. */
export const COIN_HOP_JUMP_SPEED = 7;
/** The player's half extents, metres. */
const PLAYER_HALF_WIDTH = 0.3;
const PLAYER_HALF_HEIGHT = 0.5;
/**
 * The ground check: a ray from just above the feet (the resting overlap is about
 * `def.linearSlop`, 5 mm) this far down, metres. Long enough for a body resting on the floor,
 * short enough that a jump leaves the ground on the next tick.
 */
const GROUND_RAY = 0.06;
const GROUND_RAY_START = 0.01;
/** How far ahead the bot's ray looks for the crate, metres. */
const BOT_LOOKAHEAD = 1.1;

/** The jump bit of a {@link CoinHop} input. */
export const COIN_HOP_JUMP = 1;

/** The scene: a world with the player, a crate, two coins; one input per tick (bit 0: jump). */
export class CoinHop implements Simulation {
  readonly world: PhysicsWorld;
  /** The player's body id. */
  readonly player: number;
  /** The coins' body ids: one on the path, one above the crate. */
  readonly coins: readonly number[];
  /** The crate (a static box) and the floor (a segment): wall ids. */
  readonly crate: number;
  readonly floor: number;
  /** Whether the last step ended with the ground check finding ground. */
  onGround = false;

  constructor() {
    const world = new PhysicsWorld({ timeStep: 1 / 60 });
    this.world = world;
    this.floor = world.addSegment(-2, 0, 30, 0);
    this.crate = world.addStaticBox(8, 0.5, 0.5, 0.5);
    this.player = world.createBox({
      x: 0,
      y: PLAYER_HALF_HEIGHT,
      halfWidth: PLAYER_HALF_WIDTH,
      halfHeight: PLAYER_HALF_HEIGHT,
    });
    this.coins = [
      world.createCircle({ x: 3, y: 0.5, radius: 0.25, kinematic: true, sensor: true }),
      world.createCircle({ x: 8, y: 2.9, radius: 0.3, kinematic: true, sensor: true }),
    ];
    this.onGround = this.groundCheck() !== null;
  }

  get tick(): number {
    return this.world.tick;
  }

  /** The ground under the player's feet (the ray's hit), or null in the air. */
  groundCheck(): RayHit | null {
    const w = this.world;
    const player = this.player;
    const feet = w.y[player]! - PLAYER_HALF_HEIGHT;
    return w.castRayClosest(w.x[player]!, feet + GROUND_RAY_START, 0, -GROUND_RAY, {
      predicate: (body) => body !== player,
    });
  }

  /** Whether coin `k` (0 or 1) has been collected. */
  collected(k: number): boolean {
    return !this.world.isAlive(this.coins[k]!);
  }

  /** Coins collected so far. */
  get score(): number {
    return this.coins.filter((_, k) => this.collected(k)).length;
  }

  /** One tick: run, jump if asked and on the ground, step, collect the coins the player touched. */
  step(inputs: readonly number[]): void {
    const w = this.world;
    const p = this.player;
    const jump = ((inputs[0] ?? 0) & COIN_HOP_JUMP) !== 0 && this.onGround;
    w.setVelocity(p, COIN_HOP_RUN_SPEED, jump ? COIN_HOP_JUMP_SPEED : w.vy[p]!);
    w.step();
    for (const e of w.sensorEvents().begin) {
      if (e.visitor === p && this.coins.includes(e.sensor)) w.destroyBody(e.sensor);
    }
    this.onGround = this.groundCheck() !== null;
  }

  save(): Uint8Array {
    return this.world.save();
  }

  get snapshotSize(): number {
    return this.world.snapshotSize;
  }

  saveInto(out: Uint8Array): number {
    return this.world.saveInto(out);
  }

  load(bytes: Uint8Array): void {
    this.world.load(bytes);
    this.onGround = this.groundCheck() !== null;
  }

  hash(): bigint {
    return this.world.hash();
  }
}

/**
 * A bot for {@link CoinHop}: jump when a ray from the player's centre finds the crate within
 * 1.1 m (`BOT_LOOKAHEAD`) ahead of its front.
 */
export function coinHopBot(scene: CoinHop): number {
  const w = scene.world;
  const p = scene.player;
  const hit = w.castRayClosest(w.x[p]! + PLAYER_HALF_WIDTH, w.y[p]!, BOT_LOOKAHEAD, 0, {
    predicate: (body) => body !== p,
  });
  return hit !== null && hit.wall === scene.crate ? COIN_HOP_JUMP : 0;
}
