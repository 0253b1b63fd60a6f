import {
  ByteReader,
  ByteWriter,
  fnv1a64Hex,
  isDown,
  wasPressed,
  type ButtonInput,
} from 'fixedstep';

/** Buttons of the ball scene. */
export const BallButtons = { throw: 0, left: 1, right: 2 } as const;

export interface BallConfig {
  /** Box width in metres. Default 12. */
  width: number;
  /** Box height in metres. Default 7. */
  height: number;
  /** Ball radius in metres. Default 0.3. */
  radius: number;
  /** Gravity in m/s² (downwards). Default 9.81. */
  gravity: number;
  /** Share of speed kept at each bounce (0–1). Default 0.8. */
  restitution: number;
  /** Velocity added by a throw, m/s. Default (3.5, 8). */
  throwVx: number;
  throwVy: number;
  /**
   * A bounce that leaves the floor slower than this, m/s, ends on the floor at rest. It must
   * exceed what one step of gravity gives a ball lying on the floor (g·dt·e: 0.13 m/s at 60 Hz,
   * 0.39 m/s at 20 Hz), or a resting ball would bounce every other step. Default 0.5.
   */
  restSpeed: number;
  /** Horizontal acceleration while left/right is held, m/s². Default 6. */
  push: number;
  /** Start position, metres. Default (1.5, 0.3). */
  startX: number;
  startY: number;
}

export function defaultBallConfig(): BallConfig {
  return {
    width: 12,
    height: 7,
    radius: 0.3,
    gravity: 9.81,
    restitution: 0.8,
    throwVx: 3.5,
    throwVy: 8,
    restSpeed: 0.5,
    push: 6,
    startX: 1.5,
    startY: 0.3,
  };
}

// Layout of the state vector.
const X = 0;
const Y = 1;
const VX = 2;
const VY = 3;
const BOUNCES = 4;
const THROWS = 5;

/**
 * The loop chapter's scene: a ball thrown in a box, bouncing off floor, walls and ceiling under
 * gravity. Semi-implicit Euler; every number lives in one Float64Array, so a snapshot is a copy
 * and the hash is over its bytes. It takes whatever Δt a loop hands it — which is the point: under
 * a fixed step it traces the same path at every frame rate, under a variable Δt it does not.
 */
export class BallScene {
  readonly config: BallConfig;
  /** x, y, vx, vy, bounces, throws. */
  readonly state = new Float64Array(6);
  /** The state before the last update, for render interpolation. */
  readonly previous = new Float64Array(6);
  private readonly writer = new ByteWriter(64);

  constructor(config: Partial<BallConfig> = {}) {
    this.config = { ...defaultBallConfig(), ...config };
    this.state[X] = this.config.startX;
    this.state[Y] = this.config.startY;
    this.previous.set(this.state);
  }

  get x(): number {
    return this.state[X]!;
  }
  get y(): number {
    return this.state[Y]!;
  }
  get vx(): number {
    return this.state[VX]!;
  }
  get vy(): number {
    return this.state[VY]!;
  }
  get bounces(): number {
    return this.state[BOUNCES]!;
  }

  /** One update with Δt `dt` seconds. */
  update(dt: number, input: ButtonInput): void {
    const s = this.state;
    const c = this.config;
    this.previous.set(s);
    if (wasPressed(input, BallButtons.throw)) {
      s[VX] = s[VX]! + c.throwVx;
      s[VY] = s[VY]! + c.throwVy;
      s[THROWS] = s[THROWS]! + 1;
    }
    let ax = 0;
    if (isDown(input, BallButtons.left)) ax -= c.push;
    if (isDown(input, BallButtons.right)) ax += c.push;
    let vx = s[VX]! + ax * dt;
    let vy = s[VY]! - c.gravity * dt;
    let x = s[X]! + vx * dt;
    let y = s[Y]! + vy * dt;
    const r = c.radius;
    const e = c.restitution;
    let bounces = s[BOUNCES]!;
    if (y < r) {
      y = r + (r - y) * e;
      vy = -vy * e;
      if (vy < c.restSpeed) {
        vy = 0; // at rest on the floor
        y = r;
      } else bounces++;
    } else if (y > c.height - r) {
      y = c.height - r - (y - (c.height - r)) * e;
      vy = -vy * e;
      bounces++;
    }
    if (x < r) {
      x = r + (r - x) * e;
      vx = -vx * e;
      bounces++;
    } else if (x > c.width - r) {
      x = c.width - r - (x - (c.width - r)) * e;
      vx = -vx * e;
      bounces++;
    }
    // A huge Δt can reflect a body past the opposite wall: keep it in the box.
    x = Math.min(Math.max(x, r), c.width - r);
    y = Math.min(Math.max(y, r), c.height - r);
    if (y <= r && vy === 0) vx *= 1 - Math.min(1, 0.8 * dt); // rolling friction
    s[X] = x;
    s[Y] = y;
    s[VX] = vx;
    s[VY] = vy;
    s[BOUNCES] = bounces;
  }

  /** Interpolated position for rendering. */
  renderX(alpha: number): number {
    return this.previous[X]! + (this.state[X]! - this.previous[X]!) * alpha;
  }
  renderY(alpha: number): number {
    return this.previous[Y]! + (this.state[Y]! - this.previous[Y]!) * alpha;
  }

  /** Canonical bytes of the state (a copy): little-endian, -0 as +0, one NaN. */
  save(): Uint8Array {
    return this.writer.reset().f64s(this.state).finish();
  }

  /** Restore a state from {@link save}. */
  load(bytes: Uint8Array): void {
    if (bytes.length !== this.state.length * 8) {
      throw new RangeError(
        `BallScene.load: expected ${this.state.length * 8} bytes, got ${bytes.length}`,
      );
    }
    new ByteReader(bytes).f64s(this.state);
    this.previous.set(this.state);
  }

  /** FNV-1a 64 of the state bytes, 16 hex digits. */
  hash(): string {
    return fnv1a64Hex(this.writer.reset().f64s(this.state).peek());
  }
}
