import {
  ByteReader,
  ByteWriter,
  SpringSystem,
  dsin,
  fnv1a64,
  springChain,
  type IntegratorMethod,
  type Simulation,
  type SpringSystemDef,
} from 'fixedstep';

/**
 * The physics chapter's rope: beads on springs hanging between two pins, under a chosen
 * integrator, that a reader can poke. Units: metres, seconds, kilograms; y points up.
 */

export interface RopeOptions {
  /** The fixed step. Seconds, > 0. */
  dt: number;
  /** Integration method. Default `'semi-implicit-euler'` (the talk's code). */
  integrator?: IntegratorMethod;
  /** Stiffness of each link. N/m. Default 40. */
  stiffness?: number;
  /** Beads, pins included, an integer ≥ 3. Default 16. */
  count?: number;
  /** Mass of each bead. Kilograms. Default 0.1. */
  mass?: number;
  /** Distance between the two pins. Metres. Default 6. */
  span?: number;
  /**
   * Rest length of a link as a share of the pins' spacing, in (0, 1]. Default 0.9: every link is
   * stretched even before it sags, so no link folds through zero length (a spring that does flips
   * its force, and then no integrator behaves).
   */
  restShare?: number;
  /** Damping of each link. N·s/m. Default 0: only the integrator removes energy. */
  damping?: number;
  /** Backward Euler only: Newton iterations per step. Default 1. */
  newtonIterations?: number;
  /**
   * A bead farther than this from the pins, or any non-finite number, means the rope has
   * exploded; it then stops being stepped. Metres. Default 50.
   */
  explodeBeyond?: number;
}

/** {@link RopeOptions} with defaults. */
export type RopeConfig = Required<RopeOptions>;

export function ropeConfig(options: RopeOptions): RopeConfig {
  const c: RopeConfig = {
    dt: options.dt,
    integrator: options.integrator ?? 'semi-implicit-euler',
    stiffness: options.stiffness ?? 40,
    count: options.count ?? 16,
    mass: options.mass ?? 0.1,
    span: options.span ?? 6,
    restShare: options.restShare ?? 0.9,
    damping: options.damping ?? 0,
    newtonIterations: options.newtonIterations ?? 1,
    explodeBeyond: options.explodeBeyond ?? 50,
  };
  if (!(Number.isInteger(c.count) && c.count >= 3 && c.count <= 200)) {
    throw new RangeError(`Rope: count must be an integer from 3 to 200, got ${c.count}`);
  }
  if (!(c.restShare > 0 && c.restShare <= 1)) {
    throw new RangeError(`Rope: restShare must be in (0, 1], got ${c.restShare}`);
  }
  if (!(c.span > 0 && c.span < Infinity && c.explodeBeyond > c.span)) {
    throw new RangeError('Rope: span must be finite and > 0, and explodeBeyond larger than it');
  }
  return c;
}

/**
 * The rope as a {@link SpringSystemDef}: a `springChain` from (−span/2, 0) to (+span/2, 0),
 * both ends pinned, links at rest length `restShare × spacing`, gravity −9.81 m/s².
 */
export function ropeSystemDef(c: RopeConfig): SpringSystemDef {
  const spacing = c.span / (c.count - 1);
  return springChain({
    count: c.count,
    from: [-c.span / 2, 0],
    to: [c.span / 2, 0],
    mass: c.mass,
    stiffness: c.stiffness,
    damping: c.damping,
    restLength: spacing * c.restShare,
    fixed: 'both',
    dt: c.dt,
    integrator: c.integrator,
    newtonIterations: c.newtonIterations,
  });
}

/**
 * ω of the rope's fastest mode, rad/s: a chain of beads of mass m on links of stiffness k has
 * modes up to `2·√(k/m)` (for beads between two pins, `2·√(k/m)·sin(π·n / (2(n+1)))` with n
 * free beads). Compare `omegaMax × dt` with an integrator's stability limit.
 */
export function ropeOmegaMax(c: Pick<RopeConfig, 'stiffness' | 'mass' | 'count'>): number {
  const free = c.count - 2;
  return 2 * Math.sqrt(c.stiffness / c.mass) * dsin((Math.PI * free) / (2 * (free + 1)));
}

/** A poke: a change of one bead's velocity, applied before the step of the tick it is given to. */
export interface RopePoke {
  /** Bead index, 1 … count − 2 (the pins cannot be poked). */
  bead: number;
  /** Velocity change. m/s. */
  dvx: number;
  dvy: number;
}

const FORMAT = 0x52505331; // "RPS1"
/**
 * How the rope settles before it is handed over at rest: backward Euler with long steps (it is
 * stable at any step and damps slow modes fastest when the step is long) and damped links.
 */
const SETTLE_DT = 0.1;
const SETTLE_STEPS = 600;

/**
 * Where the rope hangs at rest: the chain stepped from a straight line with backward Euler,
 * long steps and damped links until it settles (deterministic, so every rope of one config
 * starts alike).
 */
export function ropeRestPositions(c: RopeConfig): Float64Array {
  const settle = new SpringSystem({
    ...ropeSystemDef({ ...c, damping: 2 }),
    dt: SETTLE_DT,
    integrator: 'backward-euler',
    newtonIterations: 3,
  });
  for (let i = 0; i < SETTLE_STEPS; i++) settle.step();
  return Float64Array.from(settle.state.x);
}

/**
 * The rope as a deterministic {@link Simulation} whose inputs are pokes. It starts hanging at
 * rest ({@link ropeRestPositions}); {@link step} applies the tick's pokes, then one fixed step
 * of the chosen integrator. Once a bead leaves the `explodeBeyond` radius (or a number stops
 * being finite) the rope is marked exploded and no longer stepped.
 */
export class Rope implements Simulation<RopePoke> {
  readonly config: RopeConfig;
  readonly system: SpringSystem;
  /** Total energy at the start, J (kinetic + gravitational + elastic; see `SpringModel.energy`). */
  readonly energy0: number;
  private blown = false;
  private blownAt = -1;
  private poked = 0;
  /** Ticks stepped, frozen ones included (the spring system stops counting when frozen). */
  private ticks = 0;
  private readonly writer = new ByteWriter(1024);

  constructor(options: RopeOptions) {
    this.config = ropeConfig(options);
    this.system = new SpringSystem(ropeSystemDef(this.config));
    this.system.state.x.set(ropeRestPositions(this.config));
    this.system.state.v.fill(0);
    this.system.restart();
    this.energy0 = this.system.energy();
  }

  get tick(): number {
    return this.ticks;
  }
  /** Simulated time, seconds: tick × dt. */
  get time(): number {
    return this.ticks * this.config.dt;
  }
  get exploded(): boolean {
    return this.blown;
  }
  /** The tick at which it exploded, or −1. */
  get explodedAt(): number {
    return this.blownAt;
  }
  /** Pokes applied so far. */
  get pokes(): number {
    return this.poked;
  }
  /** Beads, pins included. */
  get count(): number {
    return this.config.count;
  }
  /** Positions, (x0, y0, x1, y1, …), metres. */
  get x(): Float64Array {
    return this.system.state.x;
  }
  /** Positions before the last step (render interpolation). */
  get previous(): Float64Array {
    return this.system.previous;
  }
  /** Total mechanical energy now, J. */
  energy(): number {
    return this.system.energy();
  }

  /** Pokes, then one step. Pokes at a pin or outside the rope are ignored. */
  step(inputs: readonly RopePoke[] = []): void {
    this.ticks++;
    if (this.blown) {
      // Frozen where it blew up; time still passes.
      this.system.previous.set(this.system.state.x);
      return;
    }
    if (inputs.length > 0) {
      const v = this.system.state.v;
      let applied = false;
      for (const p of inputs) {
        if (!(Number.isInteger(p.bead) && p.bead >= 1 && p.bead <= this.config.count - 2)) continue;
        if (!(Number.isFinite(p.dvx) && Number.isFinite(p.dvy))) continue;
        v[2 * p.bead] = v[2 * p.bead]! + p.dvx;
        v[2 * p.bead + 1] = v[2 * p.bead + 1]! + p.dvy;
        this.poked++;
        applied = true;
      }
      // The Verlets carry memory derived from x and v: re-prime it after the edit.
      if (applied) this.system.restart();
    }
    this.system.step();
    const x = this.system.state.x;
    const r2 = this.config.explodeBeyond * this.config.explodeBeyond;
    for (let i = 0; i < x.length; i += 2) {
      const d2 = x[i]! * x[i]! + x[i + 1]! * x[i + 1]!;
      if (!(d2 <= r2)) {
        this.blown = true;
        this.blownAt = this.ticks;
        break;
      }
    }
  }

  /** Where bead `i` is drawn: between its previous and current position at `alpha`. */
  renderPosition(
    i: number,
    alpha: number,
    out: { x: number; y: number },
  ): { x: number; y: number } {
    const x = this.system.state.x;
    const p = this.system.previous;
    out.x = p[2 * i]! + (x[2 * i]! - p[2 * i]!) * alpha;
    out.y = p[2 * i + 1]! + (x[2 * i + 1]! - p[2 * i + 1]!) * alpha;
    return out;
  }

  private write(w: ByteWriter): ByteWriter {
    const sys = this.system.save();
    return w
      .u32(FORMAT)
      .u8(this.blown ? 1 : 0)
      .f64(this.blownAt)
      .u32(this.poked)
      .u32(this.ticks)
      .u32(sys.length)
      .bytes(sys);
  }

  save(): Uint8Array {
    return this.write(this.writer.reset()).finish();
  }

  /** Restores {@link save}'s bytes of a rope with the same config; throws a RangeError otherwise. */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    if (r.u32() !== FORMAT) throw new RangeError('Rope.load: not a rope snapshot');
    const blown = r.u8() === 1;
    const blownAt = r.f64();
    const poked = r.u32();
    const ticks = r.u32();
    const sys = r.bytes(r.u32());
    r.end();
    this.system.load(sys);
    this.blown = blown;
    this.blownAt = blownAt;
    this.poked = poked;
    this.ticks = ticks;
  }

  hash(): bigint {
    return fnv1a64(this.write(this.writer.reset()).peek());
  }
}
