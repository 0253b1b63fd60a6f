import {
  ByteReader,
  ByteWriter,
  PhysicsWorld,
  Random,
  SimulatedDisplay,
  WORLD_LIMITS,
  fnv1a64,
  maxSafeSpeed,
  minWallSize,
  tunnellingShare,
  type DisplayEvent,
  type Loop,
  type Simulation,
} from 'fixedstep';
import { makeLoop } from './loops.js';

/**
 * The collisions chapter's scene: a firing range. Bodies are fired one after another at a single
 * static wall; each either bounces back or ends up on the far side ("through": it tunnelled). The
 * same range runs under a variable Δt (one step per display frame, as long as the frame) and under
 * a fixed step, each with discrete detection only and with continuous detection (CCD).
 *
 * Units are metres, seconds, metres per second; y points up. The wall's centre is at x = 0, the
 * muzzle at the left edge of the arena.
 */

/** The arena: x in [−{@link RANGE_HALF_WIDTH}, +…], y in [−{@link RANGE_HALF_HEIGHT}, +…]. Metres. */
export const RANGE_HALF_WIDTH = 12;
/** Half the arena's height. Metres. */
export const RANGE_HALF_HEIGHT = 5.5;

/** What a fired body has done so far. */
export const ShotStatus = {
  /** Not yet resolved: on its way to the wall. */
  flying: 1,
  /** Moving back, away from the wall, on its own side. */
  bounced: 2,
  /** Its centre is past the middle of the wall: it went through. */
  through: 3,
} as const;
export type ShotStatus = (typeof ShotStatus)[keyof typeof ShotStatus];

export interface WallRangeOptions {
  /** Speed of every body towards the wall. Metres per second, > 0. */
  speed: number;
  /** Wall thickness. Metres, > 0. */
  wall: number;
  /** Body radius. Metres. Default 0.1. */
  radius?: number;
  /** Continuous collision detection (the world's `ccd: 'auto'`) or none (`'off'`). Default false. */
  ccd?: boolean;
  /**
   * The nominal step, seconds: the world's def starts with it and the muzzle spreads each shot's
   * starting point over one step of travel (`speed × step`), so the phase at which a body first
   * overlaps the wall is uniform. Default 0.03 (the talk's TIME_STEP).
   */
  step?: number;
  /** Time between shots. Seconds. Default 0.1. */
  fireEvery?: number;
  /**
   * Number of lanes (rows) the shots cycle through, so that no two bodies meet: a lane is used
   * again only after `lanes × fireEvery` seconds. Default 18.
   */
  lanes?: number;
  /** Seed of the muzzle's phase spread. Default 1. */
  seed?: number;
}

/** The options with every default filled in. */
export type WallRangeConfig = Required<WallRangeOptions>;

/** {@link WallRangeOptions} with defaults. */
export function wallRangeConfig(options: WallRangeOptions): WallRangeConfig {
  const c: WallRangeConfig = {
    speed: options.speed,
    wall: options.wall,
    radius: options.radius ?? 0.1,
    ccd: options.ccd ?? false,
    step: options.step ?? 0.03,
    fireEvery: options.fireEvery ?? 0.1,
    lanes: options.lanes ?? 18,
    seed: options.seed ?? 1,
  };
  const positive = (v: number) => v > 0 && v < Infinity;
  if (!positive(c.speed) || !positive(c.wall) || !positive(c.radius)) {
    throw new RangeError('WallRange: speed, wall and radius must be finite and > 0');
  }
  if (!positive(c.step) || !positive(c.fireEvery)) {
    throw new RangeError('WallRange: step and fireEvery must be finite and > 0 seconds');
  }
  if (c.wall / 2 + c.radius > RANGE_HALF_WIDTH / 2) {
    throw new RangeError(`WallRange: a wall of ${c.wall} m does not fit in the range`);
  }
  if (!(Number.isInteger(c.lanes) && c.lanes >= 1 && c.lanes <= 32)) {
    throw new RangeError(`WallRange: lanes must be an integer from 1 to 32, got ${c.lanes}`);
  }
  if (2 * RANGE_HALF_HEIGHT < c.lanes * 4 * c.radius) {
    throw new RangeError('WallRange: the lanes do not fit in the range');
  }
  return c;
}

/** Half the height of the wall. Metres. */
const WALL_HALF_HEIGHT = 1000;
/** How long a bounced body stays on screen. Seconds. */
const BOUNCED_LIFETIME = 0.35;
/** Anything older than this is removed, whatever it is doing (a body stuck on the wall). Seconds. */
const MAX_LIFETIME = 6;
const FORMAT = 0x57524731; // "WRG1"

/**
 * The firing range as a deterministic {@link Simulation}. {@link step} advances one fixed step
 * (`config.step`); {@link stepBy} advances by any Δt — what a variable-Δt loop does (it sets the
 * world's `timeStep` with `setDef` before each step, which the world allows and keeps deterministic).
 *
 * Shot k leaves at simulated time `k × fireEvery` (at the first step that starts at or after
 * it), in lane `(s·k) mod lanes` (s: the first of 7, 5, 3, 2, 1 coprime with `lanes`, so every
 * lane is used in turn and neighbouring shots are far apart), from `x = −RANGE_HALF_WIDTH − u·speed·step` with u uniform in
 * [0, 1) from a seeded {@link Random}. A body is **through** once its centre is past the wall's
 * middle (x > 0), **bounced** once it moves back on its own side; bounced bodies are removed
 * `BOUNCED_LIFETIME` (0.35 s) later, through bodies when they leave the arena.
 *
 * State ({@link save}): the world, the random generator, simulated time, the counters and what
 * each body slot holds. The positions before the last step ({@link prevX}, {@link prevY}) are for
 * rendering only.
 */
export class WallRange implements Simulation<unknown> {
  readonly config: WallRangeConfig;
  readonly world: PhysicsWorld;
  /** The wall's static shape id. */
  readonly wallId: number;
  /** Positions before the last step, by body id (render interpolation; not state). */
  prevX = new Float64Array(64);
  prevY = new Float64Array(64);
  /** What each body slot holds: a {@link ShotStatus}, 0 for an empty slot. */
  status = new Uint8Array(64);
  /** The shot number of each slot's body. */
  shot = new Uint32Array(64);
  /** Simulated time at which each slot's body was fired and last changed status. Seconds. */
  firedAt = new Float64Array(64);
  changedAt = new Float64Array(64);
  private readonly rng: Random;
  private ticks = 0;
  private t = 0;
  private firedCount = 0;
  private throughCount = 0;
  private bouncedCount = 0;
  private largestStep = 0;
  private uniform = true;
  private readonly laneStride: number;
  private readonly writer = new ByteWriter(4096);

  constructor(options: WallRangeOptions) {
    this.config = wallRangeConfig(options);
    const c = this.config;
    this.world = new PhysicsWorld(
      {
        gravityX: 0,
        gravityY: 0,
        timeStep: c.step,
        restitution: 1,
        restitutionThreshold: 0,
        friction: 0,
        ccd: c.ccd ? 'auto' : 'off',
        enableSleep: false,
      },
      { capacity: 64 },
    );
    // Far taller than the arena: a body deep inside a short wall would be pushed out through its
    // top or bottom face instead of one of the two faces this range is about.
    this.wallId = this.world.addStaticBox(0, 0, c.wall / 2, WALL_HALF_HEIGHT);
    this.rng = new Random(c.seed);
    this.laneStride = [7, 5, 3, 2, 1].find((d) => gcd(d, c.lanes) === 1) ?? 1;
  }

  /** Steps taken. */
  get tick(): number {
    return this.ticks;
  }
  /** Simulated time, seconds: a running sum of the steps (for a fixed step, exactly tick × step). */
  get time(): number {
    return this.t;
  }
  /** Bodies fired so far. */
  get fired(): number {
    return this.firedCount;
  }
  /** Bodies that ended up on the far side of the wall. */
  get through(): number {
    return this.throughCount;
  }
  /** Bodies that bounced back. */
  get bounced(): number {
    return this.bouncedCount;
  }
  /** Bodies fired but not resolved yet. */
  get pending(): number {
    return this.firedCount - this.throughCount - this.bouncedCount;
  }
  /** through / (through + bounced); NaN before any body is resolved. */
  get share(): number {
    const n = this.throughCount + this.bouncedCount;
    return n > 0 ? this.throughCount / n : NaN;
  }
  /** The longest step taken so far. Seconds. */
  get maxStep(): number {
    return this.largestStep;
  }

  /** One step of the nominal `config.step`. */
  step(): void {
    this.stepBy(this.config.step);
  }

  /**
   * One step of `dt` seconds (a variable-Δt loop's update). Fires the shots due at the current
   * time, moves, then classifies and removes bodies. A `dt` that is not > 0 (or longer
   * than the world's `WORLD_LIMITS.maxTimeStep`, an hour) does nothing.
   */
  stepBy(dt: number): void {
    if (!(dt > 0 && dt <= WORLD_LIMITS.maxTimeStep)) return;
    const c = this.config;
    const world = this.world;
    // Shots due at the start of this step. The epsilon keeps k·fireEvery = t exactly on time
    // despite the running sum's rounding.
    while (this.firedCount * c.fireEvery <= this.t + 1e-9) this.fire();
    const n = world.slotCount;
    const xs = world.x;
    const ys = world.y;
    this.prevX.set(xs.subarray(0, n));
    this.prevY.set(ys.subarray(0, n));
    world.setDef({ timeStep: dt });
    world.step();
    this.ticks++;
    // Time is tick × step while every step is the nominal one (a fixed loop), else a running sum.
    this.uniform = this.uniform && dt === c.step;
    this.t = this.uniform ? this.ticks * c.step : this.t + dt;
    if (dt > this.largestStep) this.largestStep = dt;
    this.classify();
  }

  private fire(): void {
    const c = this.config;
    const k = this.firedCount;
    const lane = (this.laneStride * k) % c.lanes;
    const spacing = (2 * RANGE_HALF_HEIGHT) / c.lanes;
    const y = -RANGE_HALF_HEIGHT + spacing * (lane + 0.5);
    const x = -RANGE_HALF_WIDTH - this.rng.next() * c.speed * c.step;
    const id = this.world.createCircle({ x, y, vx: c.speed, radius: c.radius });
    this.ensure(this.world.slotCount);
    this.status[id] = ShotStatus.flying;
    this.shot[id] = k;
    this.firedAt[id] = this.t;
    this.changedAt[id] = this.t;
    this.prevX[id] = x;
    this.prevY[id] = y;
    this.firedCount++;
  }

  private classify(): void {
    const world = this.world;
    const xs = world.x;
    const vxs = world.vx;
    const t = this.t;
    for (let id = 0; id < world.slotCount; id++) {
      const s = this.status[id]!;
      if (s === 0) continue;
      const x = xs[id]!;
      if (s === ShotStatus.flying) {
        if (x > 0) {
          this.status[id] = ShotStatus.through;
          this.changedAt[id] = t;
          this.throughCount++;
        } else if (vxs[id]! < 0) {
          this.status[id] = ShotStatus.bounced;
          this.changedAt[id] = t;
          this.bouncedCount++;
        }
      }
      const now = this.status[id]!;
      const gone =
        (now === ShotStatus.bounced && t - this.changedAt[id]! > BOUNCED_LIFETIME) ||
        (now === ShotStatus.through && x > RANGE_HALF_WIDTH + 1) ||
        t - this.firedAt[id]! > MAX_LIFETIME;
      if (gone) {
        world.destroyBody(id);
        this.status[id] = 0;
        this.shot[id] = 0;
        this.firedAt[id] = 0;
        this.changedAt[id] = 0;
      }
    }
  }

  private ensure(n: number): void {
    if (n <= this.status.length) return;
    let cap = this.status.length;
    while (cap < n) cap *= 2;
    const grow = <T extends Float64Array | Uint8Array | Uint32Array>(
      a: T,
      make: (n: number) => T,
    ) => {
      const b = make(cap);
      b.set(a);
      return b;
    };
    this.prevX = grow(this.prevX, (m) => new Float64Array(m));
    this.prevY = grow(this.prevY, (m) => new Float64Array(m));
    this.status = grow(this.status, (m) => new Uint8Array(m));
    this.shot = grow(this.shot, (m) => new Uint32Array(m));
    this.firedAt = grow(this.firedAt, (m) => new Float64Array(m));
    this.changedAt = grow(this.changedAt, (m) => new Float64Array(m));
  }

  /** Where to draw body `id`: between its previous and current position at `alpha`, into `out`. */
  renderPosition(
    id: number,
    alpha: number,
    out: { x: number; y: number },
  ): { x: number; y: number } {
    const px = this.prevX[id]!;
    const py = this.prevY[id]!;
    out.x = px + (this.world.x[id]! - px) * alpha;
    out.y = py + (this.world.y[id]! - py) * alpha;
    return out;
  }

  private write(w: ByteWriter): ByteWriter {
    const c = this.config;
    const world = this.world.save();
    const n = this.world.slotCount;
    w.u32(FORMAT)
      .f64(c.speed)
      .f64(c.wall)
      .f64(c.radius)
      .u8(c.ccd ? 1 : 0)
      .f64(c.step)
      .f64(c.fireEvery)
      .u32(c.lanes)
      .u32(c.seed >>> 0)
      .u32(this.ticks)
      .f64(this.t)
      .u32(this.firedCount)
      .u32(this.throughCount)
      .u32(this.bouncedCount)
      .f64(this.largestStep)
      .u8(this.uniform ? 1 : 0)
      .ints(this.rng.getState())
      .u32(n)
      .ints(this.status.subarray(0, n))
      .ints(this.shot.subarray(0, n))
      .f64s(this.firedAt.subarray(0, n))
      .f64s(this.changedAt.subarray(0, n))
      .u32(world.length)
      .bytes(world);
    return w;
  }

  /** The whole state as canonical bytes (config first, so a snapshot loads only into its twin). */
  save(): Uint8Array {
    return this.write(this.writer.reset()).finish();
  }

  /** Restores a state from {@link save} of a range with the same config; throws a RangeError otherwise. */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32() !== FORMAT) throw new RangeError('WallRange.load: not a wall range snapshot');
    const c = this.config;
    const same =
      r.f64() === c.speed &&
      r.f64() === c.wall &&
      r.f64() === c.radius &&
      r.u8() === (c.ccd ? 1 : 0) &&
      r.f64() === c.step &&
      r.f64() === c.fireEvery &&
      r.u32() === c.lanes &&
      r.u32() === c.seed >>> 0;
    if (!same) throw new RangeError('WallRange.load: snapshot of another configuration');
    const ticks = r.u32();
    const t = r.f64();
    const fired = r.u32();
    const through = r.u32();
    const bounced = r.u32();
    const largest = r.f64();
    const uniform = r.u8() === 1;
    const rng = new Uint32Array(4);
    r.ints(rng);
    const n = r.u32();
    const status = new Uint8Array(n);
    const shot = new Uint32Array(n);
    const firedAt = new Float64Array(n);
    const changedAt = new Float64Array(n);
    r.ints(status);
    r.ints(shot);
    r.f64s(firedAt);
    r.f64s(changedAt);
    const world = r.bytes(r.u32());
    r.end();
    this.world.load(world);
    this.ensure(Math.max(n, this.world.slotCount));
    this.status.fill(0);
    this.shot.fill(0);
    this.firedAt.fill(0);
    this.changedAt.fill(0);
    this.status.set(status);
    this.shot.set(shot);
    this.firedAt.set(firedAt);
    this.changedAt.set(changedAt);
    this.ticks = ticks;
    this.t = t;
    this.firedCount = fired;
    this.throughCount = through;
    this.bouncedCount = bounced;
    this.largestStep = largest;
    this.uniform = uniform;
    this.rng.setState(rng);
    const xs = this.world.x;
    const ys = this.world.y;
    for (let id = 0; id < this.world.slotCount; id++) {
      this.prevX[id] = xs[id]!;
      this.prevY[id] = ys[id]!;
    }
  }

  /** FNV-1a 64 of {@link save}'s bytes. */
  hash(): bigint {
    return fnv1a64(this.write(this.writer.reset()).peek());
  }
}

function gcd(a: number, b: number): number {
  while (b !== 0) [a, b] = [b, a % b];
  return a;
}

/** The numbers of the rule of thumb at a setting (see fixedstep's `minWallSize`). */
export interface WallRule {
  /** The talk's `minWallSize = speed × step`: thinner walls can be jumped over unseen. Metres. */
  minWall: number;
  /** `speed × step`: how far a body moves in one step. Metres. */
  stepDistance: number;
  /** The fastest speed that always bounces off this wall: `(wall/2 + radius) / step`. m/s. */
  maxSafeSpeed: number;
  /** The thinnest wall that always gives a correct bounce: `2·(speed·step − radius)`, ≥ 0. Metres. */
  bounceWall: number;
  /** Share of bodies that end on the far side under discrete detection (uniform phase). */
  theoryShare: number;
  /** The talk's rule holds: wall ≥ speed × step. */
  ruleHolds: boolean;
}

/** The rule of thumb and its correct-bounce refinement at a speed, wall, radius and step. */
export function wallRule(speed: number, wall: number, radius: number, step: number): WallRule {
  const d = speed * step;
  return {
    minWall: minWallSize(speed, step),
    stepDistance: d,
    maxSafeSpeed: maxSafeSpeed(wall, radius, step),
    bounceWall: Math.max(0, 2 * (d - radius)),
    theoryShare: tunnellingShare(speed, wall, radius, step),
    ruleHolds: wall >= d,
  };
}

/** How the range's time advances: one variable step per display frame, or a fixed step. */
export type RangeLoopKind = 'variable' | 'fixed';

export interface WallRangeRigOptions {
  loop: RangeLoopKind;
  /** The fixed loop's step, ms. Default 30 (the talk's). */
  stepMs?: number;
  /** The simulated display (see fixedstep's `SimulatedDisplay`). */
  display: { hz: number; jitter?: number; seed?: number; events?: DisplayEvent[] };
  /** The range; the rig runs it twice, without and with CCD (`ccd` is ignored). */
  range: Omit<WallRangeOptions, 'ccd'>;
}

/**
 * A loop, a simulated display and two twin ranges — one with discrete detection only, one with
 * CCD — that take exactly the same steps. {@link frame} takes the display's next frame;
 * {@link frameAt} takes a frame time from elsewhere (a page's real clock). Under `'variable'` each
 * frame is one step as long as the frame; under `'fixed'` a `FixedLoop` pays frames out in
 * steps of `stepMs`.
 */
export class WallRangeRig {
  readonly kind: RangeLoopKind;
  readonly loop: Loop;
  readonly display: SimulatedDisplay;
  /** Discrete detection only. */
  readonly discrete: WallRange;
  /** Continuous detection. */
  readonly continuous: WallRange;
  /** Real time of the last frame, ms from the start. */
  realMs = 0;
  /** Frames seen. */
  frames = 0;
  /** The longest step taken, seconds. */
  maxDt = 0;
  private pending: { time: number; wasHidden: boolean };
  private readonly startMs: number;

  constructor(options: WallRangeRigOptions) {
    this.kind = options.loop;
    const stepMs = options.stepMs ?? 30;
    this.loop =
      options.loop === 'variable'
        ? makeLoop({ kind: 'variable' })
        : makeLoop({ kind: 'fixed', stepMs });
    this.display = new SimulatedDisplay(options.display);
    const range = { ...options.range, step: stepMs / 1000 };
    this.discrete = new WallRange({ ...range, ccd: false });
    this.continuous = new WallRange({ ...range, ccd: true });
    this.startMs = this.display.now;
    this.pending = this.display.next(0);
  }

  /** When the simulated display's next frame comes, ms from the start. */
  get nextFrameAt(): number {
    return this.pending.time - this.startMs;
  }

  /** Interpolation factor for drawing: the fixed loop's alpha; 1 (the current state) for variable Δt. */
  get alpha(): number {
    return this.kind === 'fixed' ? this.loop.alpha : 1;
  }

  /** Advance one frame of the simulated display. Returns the number of steps run. */
  frame(): number {
    const n = this.frameAt(this.pending.time - this.startMs);
    this.pending = this.display.next(0);
    return n;
  }

  /** Advance one display frame at `tMs` from the start (not earlier than the last). Steps run. */
  frameAt(tMs: number): number {
    this.realMs = tMs;
    this.frames++;
    const n = this.loop.frame(tMs);
    const dt = this.loop.dt;
    let ran = 0;
    for (let j = 0; j < n; j++) {
      if (!(dt > 0)) continue; // a variable loop's first frame has Δt = 0
      this.discrete.stepBy(dt);
      this.continuous.stepBy(dt);
      ran++;
    }
    if (ran > 0 && dt > this.maxDt) this.maxDt = dt;
    return ran;
  }

  /** Advance frames of the simulated display until `ms` more of real time have passed. */
  runFor(ms: number): void {
    const end = this.realMs + ms;
    while (this.nextFrameAt <= end) this.frame();
  }
}
