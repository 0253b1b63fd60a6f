import {
  ByteReader,
  ByteWriter,
  DynamicsState,
  HarmonicOscillator,
  INTEGRATOR_INFO,
  INTEGRATOR_METHODS,
  createIntegrator,
  datan2,
  dcos,
  dsin,
  fnv1a64,
  type Integrator,
  type IntegratorMethod,
  type Simulation,
} from 'fixedstep';

/**
 * The physics chapter's spring: one harmonic oscillator `x'' = −ω²x` integrated by several
 * methods side by side, in lockstep, at one fixed step — the talk's "exploding spring" and its
 * alternatives. Shared by the lab (live, step by step) and the CLI's `experiment integrators`
 * (a whole run at once, {@link runIntegratorExperiment}).
 */

export interface OscillatorRaceOptions {
  /** Angular frequency ω = √(k/m). Radians per second, finite and ≥ 0. */
  omega: number;
  /** The fixed step. Seconds, > 0. */
  dt: number;
  /** Start position, metres. Default 1. */
  x0?: number;
  /** Start velocity, metres per second. Default 0. */
  v0?: number;
  /** The methods, in panel order. Default: all six (`INTEGRATOR_METHODS`). */
  methods?: readonly IntegratorMethod[];
  /**
   * A method whose energy ratio E/E₀ passes this stops being stepped ("exploded"), so a page can
   * run for ever without overflowing to Infinity. Default Infinity (never).
   */
  explodeAt?: number;
}

/** One method's lane of an {@link OscillatorRace}. */
export interface RaceLane {
  readonly method: IntegratorMethod;
  readonly integrator: Integrator;
  readonly state: DynamicsState;
  /** Position before the last step, metres (render interpolation; not state). */
  prevX: number;
  /** Velocity before the last step, m/s (render interpolation; not state). */
  prevV: number;
  /** max over the run of |E/E₀ − 1| (Infinity once it is NaN). */
  maxEnergyError: number;
  /** Stopped at `explodeAt`. */
  exploded: boolean;
  /** The tick at which it exploded, or −1. */
  explodedAt: number;
}

const FORMAT = 0x4f524331; // "ORC1"

/**
 * Several integrators on one harmonic oscillator, stepped together: a deterministic
 * {@link Simulation} without inputs. Energy is per unit mass, `E = ½v² + ½ω²x²`; a method's
 * energy ratio is E/E₀ (1 for the exact motion). Simulated time is `tick × dt`.
 */
export class OscillatorRace implements Simulation<unknown> {
  readonly model: HarmonicOscillator;
  readonly omega: number;
  readonly dt: number;
  readonly x0: number;
  readonly v0: number;
  /** E₀, J/kg. */
  readonly energy0: number;
  readonly explodeAt: number;
  readonly lanes: readonly RaceLane[];
  private ticks = 0;
  private readonly writer = new ByteWriter(512);

  constructor(options: OscillatorRaceOptions) {
    const { omega, dt } = options;
    if (!(dt > 0 && dt < Infinity)) {
      throw new RangeError(`OscillatorRace: dt must be finite and > 0 seconds, got ${dt}`);
    }
    this.model = new HarmonicOscillator(omega);
    this.omega = omega;
    this.dt = dt;
    this.x0 = options.x0 ?? 1;
    this.v0 = options.v0 ?? 0;
    this.energy0 = this.model.energy(this.x0, this.v0);
    if (!(this.energy0 > 0 && this.energy0 < Infinity)) {
      throw new RangeError(
        'OscillatorRace: the oscillator needs some energy: x0 and v0 cannot both be 0 (or ω = 0 with v0 = 0)',
      );
    }
    this.explodeAt = options.explodeAt ?? Infinity;
    const methods = options.methods ?? INTEGRATOR_METHODS;
    this.lanes = methods.map((method) => {
      const integrator = createIntegrator(method, this.model);
      const state = this.model.state(this.x0, this.v0);
      integrator.start(state, dt);
      return {
        method,
        integrator,
        state,
        prevX: this.x0,
        prevV: this.v0,
        maxEnergyError: 0,
        exploded: false,
        explodedAt: -1,
      };
    });
  }

  /** ω·dt: compare with each method's `INTEGRATOR_INFO[method].stabilityLimit`. */
  get omegaDt(): number {
    return this.omega * this.dt;
  }

  get tick(): number {
    return this.ticks;
  }

  /** Simulated time, seconds (tick × dt). */
  get time(): number {
    return this.ticks * this.dt;
  }

  /** The lane of `method` (throws if the race does not run it). */
  lane(method: IntegratorMethod): RaceLane {
    const lane = this.lanes.find((l) => l.method === method);
    if (!lane) throw new RangeError(`OscillatorRace: ${method} is not in this race`);
    return lane;
  }

  /** E/E₀ of a lane now. */
  energyRatio(lane: RaceLane): number {
    return this.model.energy(lane.state.x[0]!, lane.state.v[0]!) / this.energy0;
  }

  /**
   * Phase of the lane's (x, v/ω) minus the exact phase now, wrapped to (−π, π]. Radians;
   * positive = ahead.
   */
  phaseError(lane: RaceLane): number {
    const { omega, x0, v0 } = this;
    const t = this.ticks * this.dt;
    const c = dcos(omega * t);
    const s = dsin(omega * t);
    const xe = x0 * c + (omega > 0 ? (v0 / omega) * s : v0 * t);
    const ve = -x0 * omega * s + v0 * c;
    const phase = (x: number, v: number) => datan2(omega > 0 ? -v / omega : -v, x);
    return wrapPi(phase(lane.state.x[0]!, lane.state.v[0]!) - phase(xe, ve));
  }

  /** One fixed step of every lane that has not exploded. */
  step(): void {
    const dt = this.dt;
    for (const lane of this.lanes) {
      const { state } = lane;
      lane.prevX = state.x[0]!;
      lane.prevV = state.v[0]!;
      if (lane.exploded) continue;
      lane.integrator.step(state, dt);
      const ratio = this.energyRatio(lane);
      const err = Math.abs(ratio - 1);
      if (Number.isNaN(err)) lane.maxEnergyError = Infinity;
      else if (err > lane.maxEnergyError) lane.maxEnergyError = err;
      if (!(ratio <= this.explodeAt)) {
        lane.exploded = true;
        lane.explodedAt = this.ticks + 1;
      }
    }
    this.ticks++;
  }

  private write(w: ByteWriter): ByteWriter {
    w.u32(FORMAT)
      .f64(this.omega)
      .f64(this.dt)
      .f64(this.x0)
      .f64(this.v0)
      .f64(this.explodeAt)
      .u32(this.lanes.length)
      .u32(this.ticks);
    for (const lane of this.lanes) {
      const { state, integrator } = lane;
      w.u8(INTEGRATOR_METHODS.indexOf(lane.method))
        .u8(lane.exploded ? 1 : 0)
        .f64(lane.explodedAt)
        .f64(lane.maxEnergyError)
        .f64(state.x[0]!)
        .f64(state.v[0]!);
      if (integrator.keepsAcceleration) w.f64(state.a[0]!);
      if (integrator.keepsPreviousPosition) w.f64(state.xPrev[0]!);
    }
    return w;
  }

  save(): Uint8Array {
    return this.write(this.writer.reset()).finish();
  }

  /** Restores {@link save}'s bytes of a race with the same options; throws a RangeError otherwise. */
  load(bytes: Uint8Array): void {
    const r = new ByteReader(bytes);
    const same =
      r.u32() === FORMAT &&
      r.f64() === this.omega &&
      r.f64() === this.dt &&
      r.f64() === this.x0 &&
      r.f64() === this.v0 &&
      r.f64() === this.explodeAt &&
      r.u32() === this.lanes.length;
    if (!same) throw new RangeError('OscillatorRace.load: snapshot of another race');
    const ticks = r.u32();
    const rows = this.lanes.map((lane) => {
      if (r.u8() !== INTEGRATOR_METHODS.indexOf(lane.method)) {
        throw new RangeError('OscillatorRace.load: snapshot of another race');
      }
      const exploded = r.u8() === 1;
      const explodedAt = r.f64();
      const maxErr = r.f64();
      const x = r.f64();
      const v = r.f64();
      const a = lane.integrator.keepsAcceleration ? r.f64() : 0;
      const xPrev = lane.integrator.keepsPreviousPosition ? r.f64() : 0;
      return { exploded, explodedAt, maxErr, x, v, a, xPrev };
    });
    r.end();
    this.ticks = ticks;
    this.lanes.forEach((lane, i) => {
      const row = rows[i]!;
      lane.exploded = row.exploded;
      lane.explodedAt = row.explodedAt;
      lane.maxEnergyError = row.maxErr;
      lane.state.x[0] = row.x;
      lane.state.v[0] = row.v;
      lane.state.a[0] = row.a;
      lane.state.xPrev[0] = row.xPrev;
      lane.prevX = row.x;
      lane.prevV = row.v;
    });
  }

  hash(): bigint {
    return fnv1a64(this.write(this.writer.reset()).peek());
  }
}

const TWO_PI = 2 * Math.PI;

function wrapPi(a: number): number {
  let r = a - TWO_PI * Math.floor((a + Math.PI) / TWO_PI);
  if (r <= -Math.PI) r += TWO_PI;
  return r;
}

/** Whether the oscillator stays bounded under `method` at this ω·dt (see `INTEGRATOR_INFO`). */
export function isStable(method: IntegratorMethod, omegaDt: number): boolean {
  const limit = INTEGRATOR_INFO[method].stabilityLimit;
  return limit > 0 && omegaDt < limit;
}

// ------------------------------------------------------------------ the whole-run experiment

export interface IntegratorExperimentOptions {
  /** Angular frequency ω, rad/s. */
  omega: number;
  /** Step, s. */
  dt: number;
  /** Simulated time, s. */
  duration: number;
  /** Start position (m) and velocity (m/s). */
  x0: number;
  v0: number;
  methods: readonly IntegratorMethod[];
  /** Keep every `sampleEvery`-th step in the series (for CSV and plots). Default: ~500 samples. */
  sampleEvery?: number;
}

export interface IntegratorResult {
  method: IntegratorMethod;
  label: string;
  order: number;
  stabilityLimit: number;
  /** E(T) / E(0). */
  energyRatio: number;
  /** max over the run of |E(t)/E(0) − 1|. */
  maxEnergyError: number;
  /** Phase of the numerical (x, v/ω) minus the exact phase at the end, wrapped to (−π, π], rad. */
  phaseError: number;
  /** Sampled series: time (s), x (m), energy ratio. */
  t: number[];
  x: number[];
  energy: number[];
}

export interface IntegratorExperiment {
  options: IntegratorExperimentOptions;
  steps: number;
  results: IntegratorResult[];
}

/**
 * The talk's integrator experiment: the spring of k/m = 20 (ω = √20 rad/s, a period of 1.4 s)
 * stepped every 30 ms for 10 s from rest at x = 1 m — the defaults of
 * `fixedstep experiment integrators`.
 */
export const TALK_INTEGRATOR_EXPERIMENT = {
  omega: Math.sqrt(20),
  dt: 0.03,
  duration: 10,
  x0: 1,
  v0: 0,
} as const;

/**
 * Runs each method on `x'' = −ω²x` for `duration` (rounded to whole steps) and measures energy
 * drift and phase error against the exact solution — an {@link OscillatorRace} run to the end.
 */
export function runIntegratorExperiment(
  options: IntegratorExperimentOptions,
): IntegratorExperiment {
  const { omega, dt, duration, x0, v0 } = options;
  const steps = Math.max(1, Math.round(duration / dt));
  const every = options.sampleEvery ?? Math.max(1, Math.ceil(steps / 500));
  const race = new OscillatorRace({ omega, dt, x0, v0, methods: options.methods });
  const series = race.lanes.map(() => ({ t: [0], x: [x0], energy: [1] }));
  for (let n = 1; n <= steps; n++) {
    race.step();
    if (n % every === 0 || n === steps) {
      race.lanes.forEach((lane, i) => {
        const s = series[i]!;
        s.t.push(n * dt);
        s.x.push(lane.state.x[0]!);
        s.energy.push(race.energyRatio(lane));
      });
    }
  }
  const results = race.lanes.map((lane, i): IntegratorResult => {
    const info = INTEGRATOR_INFO[lane.method];
    const s = series[i]!;
    return {
      method: lane.method,
      label: info.label,
      order: info.order,
      stabilityLimit: info.stabilityLimit,
      energyRatio: s.energy[s.energy.length - 1]!,
      maxEnergyError: lane.maxEnergyError,
      phaseError: race.phaseError(lane),
      t: s.t,
      x: s.x,
      energy: s.energy,
    };
  });
  return { options, steps, results };
}

/**
 * The talk's own spring code — `v += a·dt; x += v·dt` (semi-implicit Euler) on `x'' = −ω²x` —
 * as a {@link SteppedScene} for {@link SceneRig}: it takes whatever Δt its loop hands it, so the
 * same spring can run under a fixed step and under a variable Δt side by side. Stable while
 * ω·dt < 2; one longer update (a hitch, under a variable Δt) multiplies its energy. Only
 * `+ − ×`, so deterministic.
 */
export class TalkSpring {
  readonly omega: number;
  x: number;
  v: number;
  /** Position before the last update (render interpolation). */
  prevX: number;
  /** E₀ = ½v² + ½ω²x² at the start, per kilogram. */
  readonly energy0: number;
  /** The longest Δt it was given, s. */
  maxDt = 0;
  /** The largest E/E₀ reached. */
  maxRatio = 1;
  /** Updates taken and simulated time (the sum of the Δts), s. */
  updates = 0;
  time = 0;

  constructor(omega: number, x0 = 1, v0 = 0) {
    if (!(omega > 0 && omega < Infinity)) {
      throw new RangeError(`TalkSpring: ω must be finite and > 0, got ${omega}`);
    }
    this.omega = omega;
    this.x = x0;
    this.v = v0;
    this.prevX = x0;
    this.energy0 = 0.5 * v0 * v0 + 0.5 * omega * omega * x0 * x0;
  }

  /** E/E₀ now. */
  get energyRatio(): number {
    return (0.5 * this.v * this.v + 0.5 * this.omega * this.omega * this.x * this.x) / this.energy0;
  }

  update(dt: number): void {
    if (!(dt > 0 && dt < Infinity)) return;
    this.prevX = this.x;
    this.v += -this.omega * this.omega * this.x * dt;
    this.x += this.v * dt;
    this.updates++;
    this.time += dt;
    if (dt > this.maxDt) this.maxDt = dt;
    const r = this.energyRatio;
    if (r > this.maxRatio) this.maxRatio = r;
  }
}
