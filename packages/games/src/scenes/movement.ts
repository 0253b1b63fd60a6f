import { Random, fnv1a64Hex, isDown, wasPressed, type ButtonInput, type LoopKind } from 'fixedstep';
import type { ScriptedInput } from './loops.js';
import { SceneRig } from './movement-rig.js';

/** Buttons of the jumper scene. */
export const JumperButtons = { left: 0, right: 1, jump: 2, reset: 3 } as const;

export interface JumperConfig {
  /** Width of the level in metres. Default 14. */
  width: number;
  /** Gravity in m/s² (downwards). Default 32. */
  gravity: number;
  /** Upward speed given by a jump, m/s. Default 11. */
  jumpSpeed: number;
  /** Gravity is multiplied by this while rising with the jump button released (a short hop). Default 3. */
  jumpCut: number;
  /** Top running speed, m/s. Default 6. */
  runSpeed: number;
  /** Acceleration towards the running speed on the ground, m/s². Default 36. */
  runAccel: number;
  /** Acceleration towards the running speed in the air, m/s². Default 18. */
  airAccel: number;
  /** Deceleration on the ground with no direction held, m/s². Default 28. */
  brake: number;
  /** Half the runner's width, metres. Default 0.3. */
  halfWidth: number;
  /** The runner's height, metres. Default 0.9. */
  height: number;
  /** Start position (feet), metres. Default 0.6. */
  startX: number;
  /** Coins floating in the level (0 to 8). Default 0. */
  coins: number;
  /** Coin radius, metres. Default 0.3. */
  coinRadius: number;
  /** Coins appear at heights from this, metres. Default 0.5. */
  coinBottom: number;
  /** … up to this, metres. Default 2.6. */
  coinTop: number;
  /** Seed of the coins' random positions. Default 1. */
  seed: number;
}

export function defaultJumperConfig(): JumperConfig {
  return {
    width: 14,
    gravity: 32,
    jumpSpeed: 11,
    jumpCut: 3,
    runSpeed: 6,
    runAccel: 36,
    airAccel: 18,
    brake: 28,
    halfWidth: 0.3,
    height: 0.9,
    startX: 0.6,
    coins: 0,
    coinRadius: 0.3,
    coinBottom: 0.5,
    coinTop: 2.6,
    seed: 1,
  };
}

// Layout of the state vector: the runner, counters, the coins' random generator, the coins.
const X = 0;
const Y = 1;
const VX = 2;
const VY = 3;
const GROUNDED = 4;
const JUMPS = 5;
const SCORE = 6;
const ROUND = 7;
const RNG = 8; // four 32-bit words
const COINS = 12; // x, y per coin
const MAX_COINS = 8;

/**
 * The movement chapter's scene: a runner on flat ground that runs, brakes and jumps (hold the
 * button for a higher jump), with optional coins that reappear at seeded random places when
 * collected. Semi-implicit Euler, like most platformers; every number — the random generator's
 * state included — lives in one Float64Array, so a snapshot is a copy and the hash is over its
 * bytes. Like the ball, it takes whatever Δt a loop hands it: under a fixed step every display
 * runs the same jump, under a variable Δt each display jumps its own.
 */
export class JumperScene {
  readonly config: JumperConfig;
  readonly state: Float64Array;
  /** The state before the last update, for render interpolation. */
  readonly previous: Float64Array;
  private readonly rng: Random;
  private readonly bytes: Uint8Array;

  constructor(config: Partial<JumperConfig> = {}) {
    this.config = { ...defaultJumperConfig(), ...config };
    const c = this.config;
    if (!(Number.isInteger(c.coins) && c.coins >= 0 && c.coins <= MAX_COINS)) {
      throw new RangeError(`JumperScene: coins must be an integer from 0 to 8, got ${c.coins}`);
    }
    this.state = new Float64Array(COINS + 2 * c.coins);
    this.previous = new Float64Array(this.state.length);
    this.bytes = new Uint8Array(this.state.buffer);
    this.rng = new Random(c.seed);
    this.state[X] = c.startX;
    this.state[GROUNDED] = 1;
    for (let k = 0; k < c.coins; k++) this.placeCoin(k);
    this.storeRng();
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
  get grounded(): boolean {
    return this.state[GROUNDED] === 1;
  }
  /** Jumps taken so far. */
  get jumps(): number {
    return this.state[JUMPS]!;
  }
  /** Coins collected so far. */
  get score(): number {
    return this.state[SCORE]!;
  }
  /** Resets so far. */
  get round(): number {
    return this.state[ROUND]!;
  }
  /** Number of coins in the level. */
  get coinCount(): number {
    return this.config.coins;
  }
  coinX(k: number): number {
    return this.state[COINS + 2 * k]!;
  }
  coinY(k: number): number {
    return this.state[COINS + 2 * k + 1]!;
  }

  /** One update with Δt `dt` seconds. */
  update(dt: number, input: ButtonInput): void {
    const s = this.state;
    const c = this.config;
    this.previous.set(s);
    if (wasPressed(input, JumperButtons.reset)) {
      s[X] = c.startX;
      s[Y] = 0;
      s[VX] = 0;
      s[VY] = 0;
      s[GROUNDED] = 1;
      s[ROUND] = s[ROUND]! + 1;
      this.previous.set(s); // a teleport: nothing to interpolate
      return;
    }
    let grounded = s[GROUNDED] === 1;
    let vx = s[VX]!;
    let vy = s[VY]!;

    // Run: approach the target speed at a bounded acceleration.
    const dir =
      (isDown(input, JumperButtons.right) ? 1 : 0) - (isDown(input, JumperButtons.left) ? 1 : 0);
    const accel = dir !== 0 ? (grounded ? c.runAccel : c.airAccel) : grounded ? c.brake : 0;
    const dv = dir * c.runSpeed - vx;
    const maxDv = accel * dt;
    vx += dv > maxDv ? maxDv : dv < -maxDv ? -maxDv : dv;

    // Jump on the press, from the ground only; a short hop if the button is let go early.
    if (grounded && wasPressed(input, JumperButtons.jump)) {
      vy = c.jumpSpeed;
      grounded = false;
      s[JUMPS] = s[JUMPS]! + 1;
    }
    let y = s[Y]!;
    if (!grounded) {
      const g = vy > 0 && !isDown(input, JumperButtons.jump) ? c.gravity * c.jumpCut : c.gravity;
      vy -= g * dt;
      y += vy * dt;
      if (y <= 0) {
        y = 0;
        vy = 0;
        grounded = true;
      }
    }
    let x = s[X]! + vx * dt;
    if (x < c.halfWidth) {
      x = c.halfWidth;
      vx = 0;
    } else if (x > c.width - c.halfWidth) {
      x = c.width - c.halfWidth;
      vx = 0;
    }
    s[X] = x;
    s[Y] = y;
    s[VX] = vx;
    s[VY] = vy;
    s[GROUNDED] = grounded ? 1 : 0;

    // Coins: touched ones are scored and reappear elsewhere (the random stream is state too).
    for (let k = 0; k < c.coins; k++) {
      const dx = Math.abs(s[COINS + 2 * k]! - x);
      const dy = Math.abs(s[COINS + 2 * k + 1]! - (y + c.height / 2));
      if (dx < c.coinRadius + c.halfWidth && dy < c.coinRadius + c.height / 2) {
        s[SCORE] = s[SCORE]! + 1;
        this.placeCoin(k);
      }
    }
    this.storeRng();
  }

  /** Interpolated position for rendering. */
  renderX(alpha: number): number {
    return this.previous[X]! + (this.state[X]! - this.previous[X]!) * alpha;
  }
  renderY(alpha: number): number {
    return this.previous[Y]! + (this.state[Y]! - this.previous[Y]!) * alpha;
  }

  /** Canonical bytes of the state (a copy). */
  save(): Uint8Array {
    return this.bytes.slice();
  }

  /** Restore a state from {@link save}. */
  load(bytes: Uint8Array): void {
    if (bytes.length !== this.bytes.length) {
      throw new RangeError(
        `JumperScene.load: expected ${this.bytes.length} bytes, got ${bytes.length}`,
      );
    }
    this.bytes.set(bytes);
    this.rng.setState(this.state.subarray(RNG, RNG + 4));
    this.previous.set(this.state);
  }

  /** FNV-1a 64 of the state bytes, 16 hex digits. */
  hash(): string {
    return fnv1a64Hex(this.bytes);
  }

  private placeCoin(k: number): void {
    const c = this.config;
    // Quantised to centimetres so coin positions print and compare cleanly.
    this.state[COINS + 2 * k] = Math.round(this.rng.range(1, c.width - 1) * 100) / 100;
    this.state[COINS + 2 * k + 1] = Math.round(this.rng.range(c.coinBottom, c.coinTop) * 100) / 100;
  }

  private storeRng(): void {
    const w = this.rng.getState();
    for (let i = 0; i < 4; i++) this.state[RNG + i] = w[i]!;
  }
}

/** One measured jump: from take-off to landing. */
export interface Jump {
  /** Where the runner left the ground, metres. */
  takeoffX: number;
  /** The highest the runner got, metres above the ground. */
  apex: number;
  /** Where it was at the apex, metres. */
  apexX: number;
  /** Where it landed, metres (NaN while in the air). */
  landingX: number;
  /** Horizontal distance covered in the air, metres (NaN while in the air). */
  distance: number;
}

/**
 * Measures jumps by watching the scene after every update: take-off, apex and landing, as the
 * simulation computed them (a variable-Δt loop sees fewer, longer updates than a fixed step).
 */
export class JumpMeter {
  /** Completed jumps, oldest first. */
  readonly jumps: Jump[] = [];
  /** The jump in progress, if any. */
  current: Jump | undefined;
  private seenJumps = 0;
  private seenRound = 0;

  observe(scene: JumperScene): void {
    if (scene.round !== this.seenRound) {
      this.seenRound = scene.round;
      this.current = undefined; // reset mid-air: that jump never landed
    }
    if (scene.jumps !== this.seenJumps) {
      this.seenJumps = scene.jumps;
      this.current = {
        takeoffX: scene.previous[X]!,
        apex: scene.y,
        apexX: scene.x,
        landingX: NaN,
        distance: NaN,
      };
    }
    const j = this.current;
    if (!j) return;
    if (scene.y > j.apex) {
      j.apex = scene.y;
      j.apexX = scene.x;
    }
    if (scene.grounded) {
      j.landingX = scene.x;
      j.distance = Math.abs(scene.x - j.takeoffX);
      this.jumps.push(j);
      this.current = undefined;
    }
  }
}

/** How often the movement script repeats, ms: one run-up, one jump, a stop, a reset. */
export const MOVEMENT_PERIOD_MS = 2500;

/**
 * One round of the movement script, from `t0`: run right, jump (button held 180 ms), land, let go
 * and brake. Rounds after the first start with a reset to the start line.
 */
export function movementRound(t0 = 0): ScriptedInput[] {
  const out: ScriptedInput[] = [];
  if (t0 > 0) {
    out.push({ timeMs: t0, button: JumperButtons.reset, down: true });
    out.push({ timeMs: t0 + 40, button: JumperButtons.reset, down: false });
  }
  out.push(
    { timeMs: t0 + 100, button: JumperButtons.right, down: true },
    { timeMs: t0 + 450, button: JumperButtons.jump, down: true },
    { timeMs: t0 + 630, button: JumperButtons.jump, down: false },
    { timeMs: t0 + 1250, button: JumperButtons.right, down: false },
  );
  return out;
}

/** The movement script repeated every {@link MOVEMENT_PERIOD_MS} up to `untilMs`. */
export function movementScript(untilMs: number): ScriptedInput[] {
  const out: ScriptedInput[] = [];
  for (let t0 = 0; t0 < untilMs; t0 += MOVEMENT_PERIOD_MS) out.push(...movementRound(t0));
  return out;
}

/** The loops the movement chapter compares. */
export type MovementLoop = 'variable' | 'fixed';

export interface MovementRunOptions {
  loop: MovementLoop;
  hz: number;
  /** Frame jitter as a fraction of the period. Default 0.2. */
  jitter?: number;
  /** Seed of the jitter. Default: derived from the rate. */
  seed?: number;
  /** Fixed step, ms. Default 30 (the talk's TIME_STEP). */
  stepMs?: number;
  /** How long to run, ms of display time. Default one round. */
  durationMs?: number;
  script?: ScriptedInput[];
}

export interface MovementRun {
  rig: SceneRig<JumperScene>;
  meter: JumpMeter;
  /** Every state the simulation computed: x, y pairs, one per update. */
  path: number[];
}

/** The seed of a display's jitter, so every rate jitters its own way but repeatably. */
export function jitterSeed(hz: number): number {
  return hz * 7 + 1;
}

/** Which loop kind a movement/debugging comparison runs. */
export function loopKindOf(loop: MovementLoop): LoopKind {
  return loop === 'fixed' ? 'fixed' : 'variable';
}

/**
 * The movement scene builder, shared by the lab, the tests and the benchmark: the jumper on one
 * simulated display under one loop, run headless for a while.
 */
export function runMovement(options: MovementRunOptions): MovementRun {
  const meter = new JumpMeter();
  const path: number[] = [];
  const duration = options.durationMs ?? MOVEMENT_PERIOD_MS;
  const rig = new SceneRig({
    loop: { kind: loopKindOf(options.loop), stepMs: options.stepMs ?? 30 },
    display: {
      hz: options.hz,
      jitter: options.jitter ?? 0.2,
      seed: options.seed ?? jitterSeed(options.hz),
    },
    scene: new JumperScene(),
    script: options.script ?? movementScript(duration),
    onUpdate: (scene) => {
      meter.observe(scene);
      path.push(scene.x, scene.y);
    },
  });
  rig.runFor(duration);
  return { rig, meter, path };
}
