/**
 * A Rapier 2D world as a fixedstep {@link Simulation}: one fixed step per tick, inputs applied
 * per tick, `save()`/`load()` through Rapier's snapshots, a canonical hash.
 */
import {
  ByteReader,
  ByteWriter,
  Fnv1a64,
  readVarint,
  varintProblem,
  type Simulation,
} from 'fixedstep';
import type { RigidBody, World } from '@dimforge/rapier2d-deterministic-compat';
import { splitHandle, writeCanonicalState } from './canonical.js';
import { murmur3 } from './checksum.js';
import { loadRapier, readyRapier, type RapierModule } from './rapier.js';

/**
 * A scene: how to build the world, and how the inputs of a tick act on it.
 *
 * Determinism rules for the callbacks (the same as for any fixedstep simulation, see
 * docs/determinism.md): read no clock and no `Math.random`; no `Math.sin/cos/atan2/pow/…` or
 * `**` on the way into Rapier (use `dsin`, `dcos`, `datan2` of `fixedstep`); keep nothing that
 * changes the future outside the world except in the user state ({@link saveState} /
 * {@link loadState}); and hold Rapier objects only by their handles — `load()` replaces the
 * `World` object, so a `RigidBody` or `World` kept from before a load points at a freed world.
 *
 * @typeParam I — one player's input for one tick (a `ButtonInput` number for the network
 *   sessions and replays).
 * @typeParam S — what `build` returns: the handles and plain data the other callbacks need
 *   (one per simulation instance).
 */
export interface RapierSceneDef<I = number, S = undefined> {
  /**
   * The scene's name, written into every `save()`: `load()` refuses a snapshot of another
   * scene. Also the id of its replays and network rooms, by convention.
   */
  readonly id: string;
  /** Version of the scene's rules; a snapshot of another version is refused. Default 1. */
  readonly version?: number;
  /**
   * Ticks per second. Rapier's `integrationParameters.dt` is set once to `1 / tickRate` s (Rapier
   * holds it as an f32) and must not change: `step()` refuses a world whose `dt` was changed.
   * Default 60.
   */
  readonly tickRate?: number;
  /** Players: `step(inputs)` takes exactly this many inputs. Default 1. */
  readonly players?: number;
  /** Gravity, m/s². Default (0, −9.81). */
  readonly gravity?: { readonly x: number; readonly y: number };
  /** Rapier's `numSolverIterations` (its substeps; Rapier's default 4). Default: Rapier's. */
  readonly solverIterations?: number;
  /**
   * Builds the scene into an empty world through Rapier's own API (`rapier.RigidBodyDesc`,
   * `rapier.ColliderDesc`, `rapier.JointData` …; use the module passed here, not another copy).
   * Returns what the other callbacks need: body and joint handles, counters.
   */
  build(world: World, rapier: RapierModule): S;
  /**
   * Applies the inputs of tick `tick` (one per player, index = player) before the world steps:
   * impulses, velocities, motor targets, kinematic targets. Optional (a scene without inputs).
   */
  applyInputs?(world: World, inputs: readonly I[], tick: number, scene: S): void;
  /** Runs after the world stepped to tick `tick`: game rules that read the world (scores …). */
  afterStep?(world: World, tick: number, scene: S): void;
  /**
   * Refuses an input: returns why (e.g. `'not a button mask'`), or undefined when it is good.
   * Default: the input is a number, an array, a `Float32Array`/`Float64Array` or a plain object
   * of them, and every number in it is finite as a 32-bit float (Rapier's: 1e39 would be ∞
   * there); a string, a boolean or another typed array is refused.
   */
  checkInput?(input: I, player: number): string | undefined;
  /**
   * The scene's own state that is not in the world (scores, a `Random`'s words, counters), as
   * canonical bytes (`ByteWriter`). Saved with the snapshot and hashed. Default: none.
   */
  saveState?(scene: S): Uint8Array;
  /** Restores what {@link saveState} wrote; throws a RangeError on bytes it cannot read. */
  loadState?(scene: S, bytes: Uint8Array): void;
}

/** First bytes of every save: `FSRP` (fixedstep + Rapier). */
const MAGIC = 0x50525346;
/** Layout version of the save bytes. */
const FORMAT = 1;
/** Deepest nesting the default input check looks into. */
const INPUT_DEPTH = 4;

const EMPTY = new Uint8Array(0);

/**
 * Largest magnitude Rapier can hold: its numbers are 32-bit floats, so a double beyond f32's range
 * (1e39 is finite here) would become ±∞ inside the world.
 */
const F32_MAX = 3.4028234663852886e38;

/** Why `x` (a leaf of an input) cannot go into Rapier, or undefined when it can. */
function badNumber(x: unknown): string | undefined {
  if (x === undefined || x === null) return `${String(x)}, not a number`;
  if (typeof x !== 'number') {
    // (Objects do not come here: `badLeaf` walks into them.)
    const shown =
      typeof x === 'symbol'
        ? x.toString()
        : typeof x === 'bigint'
          ? `${x.toString()}n`
          : typeof x === 'function'
            ? 'a function'
            : JSON.stringify(x);
    return `${shown} is a ${typeof x}, not a number`;
  }
  if (!Number.isFinite(x)) return `${String(x)} is not finite`;
  if (Math.abs(x) > F32_MAX) return `${String(x)} is beyond Rapier's 32-bit floats (±3.4e38)`;
  return undefined;
}

/**
 * The first leaf of an input that cannot go into Rapier: where it is (`''` for the input itself)
 * and why; undefined when every leaf is a number finite as a 32-bit float. An input is a number,
 * an array, a Float32Array/Float64Array or a plain object of them (nested up to `INPUT_DEPTH`).
 */
function badLeaf(value: unknown, depth: number): { at: string; why: string } | undefined {
  if (typeof value !== 'object' || value === null) {
    const why = badNumber(value);
    return why === undefined ? undefined : { at: '', why };
  }
  if (depth >= INPUT_DEPTH) return { at: '', why: `nested deeper than ${INPUT_DEPTH} levels` };
  if (value instanceof Float32Array || value instanceof Float64Array) {
    for (let i = 0; i < value.length; i++) {
      const why = badNumber(value[i]);
      if (why !== undefined) return { at: `[${i}]`, why };
    }
    return undefined;
  }
  if (ArrayBuffer.isView(value)) {
    return { at: '', why: `a ${value.constructor.name} (use numbers, or a Float64Array)` };
  }
  for (const [key, v] of Object.entries(value)) {
    const inner = badLeaf(v, depth + 1);
    if (inner !== undefined) {
      return { at: (Array.isArray(value) ? `[${key}]` : `.${key}`) + inner.at, why: inner.why };
    }
  }
  return undefined;
}

/**
 * A Rapier 2D world stepped at a fixed rate, as a fixedstep {@link Simulation}: the loop, replays
 * (`ReplayRecorder`, `verifyReplay`), lockstep, rollback and sync-test sessions all take it.
 *
 * - `step(inputs)`: checks the inputs, `applyInputs`, one `world.step()` of `1 / tickRate` s,
 *   `afterStep`.
 * - `save()`: a header (scene id, version and fingerprint, tick, user state, checksum) and
 *   Rapier's snapshot (`world.takeSnapshot()`). Equal histories give equal bytes: Rapier's deterministic
 *   build serialises its state in a defined order, and a restored world steps and saves exactly
 *   like the original (the package's tests and `SyncTestSession` check it every tick).
 * - `load(bytes)`: `World.restoreSnapshot()` into a new world; the old one is freed.
 * - `hash()`: FNV-1a 64 of the canonical state (see `canonical.ts`), not of the snapshot.
 *
 * Create it with {@link createRapierSimulation} (async, loads Rapier), or synchronously with
 * `new RapierSimulation(def)` once `await loadRapier()` has finished (a network session's
 * `createSimulation` callback, a trace scene's `start()`). Call {@link dispose} when done:
 * Rapier's memory lives in WebAssembly, not in the garbage-collected heap.
 */
export class RapierSimulation<I = number, S = undefined> implements Simulation<I> {
  /** The scene's handles and data, as `build` returned them. */
  readonly scene: S;
  /** The scene this simulation runs. */
  readonly def: RapierSceneDef<I, S>;
  /** The fixed step, seconds, as Rapier holds it (an f32: `Math.fround(1 / tickRate)`). */
  readonly dt: number;
  /** Ticks per second. */
  readonly tickRate: number;
  /** Players (inputs per step). */
  readonly players: number;
  /**
   * FNV-1a 64 of the scene's id, version, dt, gravity, solver iterations and canonical state right
   * after `build`: two simulations with the same fingerprint start from the same world under the
   * same settings. Written into `save()`; `load()` refuses another.
   */
  readonly fingerprint: bigint;

  private readonly rapier: RapierModule;
  private currentWorld: World | undefined;
  private ticks = 0;
  private readonly canonical = new ByteWriter(4096);
  private readonly header = new ByteWriter(256);
  private readonly label: string;

  /** Builds the scene. Needs `await loadRapier()` to have finished (else a clear Error). */
  constructor(def: RapierSceneDef<I, S>) {
    const id: unknown = def.id;
    this.label = `RapierSimulation "${String(id)}"`;
    this.rapier = readyRapier(this.label);
    if (typeof def.id !== 'string' || def.id === '' || def.id.length > 200) {
      throw new RangeError(
        `RapierSimulation: the scene id must be a string of 1 to 200 characters, got ${String(id)}`,
      );
    }
    const version = def.version ?? 1;
    this.tickRate = def.tickRate ?? 60;
    this.players = def.players ?? 1;
    if (!(Number.isInteger(version) && version >= 0 && version <= 0xffffffff)) {
      throw new RangeError(`${this.label}: version must be a u32, got ${String(version)}`);
    }
    if (!(Number.isFinite(this.tickRate) && this.tickRate >= 1 && this.tickRate <= 10_000)) {
      throw new RangeError(
        `${this.label}: tickRate must be from 1 to 10000 Hz, got ${String(this.tickRate)}`,
      );
    }
    if (!(Number.isInteger(this.players) && this.players >= 1 && this.players <= 64)) {
      throw new RangeError(
        `${this.label}: players must be an integer from 1 to 64, got ${String(this.players)}`,
      );
    }
    const gravity = def.gravity ?? { x: 0, y: -9.81 };
    if (!(Number.isFinite(gravity.x) && Number.isFinite(gravity.y))) {
      throw new RangeError(
        `${this.label}: gravity must be finite, got (${String(gravity.x)}, ${String(gravity.y)})`,
      );
    }
    const iterations = def.solverIterations;
    if (
      iterations !== undefined &&
      !(Number.isInteger(iterations) && iterations >= 1 && iterations <= 64)
    ) {
      throw new RangeError(
        `${this.label}: solverIterations must be an integer from 1 to 64, got ${String(iterations)}`,
      );
    }
    this.def = def;
    this.dt = Math.fround(1 / this.tickRate);
    const world = new this.rapier.World({ x: gravity.x, y: gravity.y });
    this.currentWorld = world;
    try {
      world.timestep = this.dt;
      if (iterations !== undefined) world.numSolverIterations = iterations;
      this.scene = def.build(world, this.rapier);
      const f = new Fnv1a64();
      const head = new ByteWriter(64).str(def.id).u32(version).f64(this.dt);
      head
        .f64(gravity.x)
        .f64(gravity.y)
        .u32(iterations ?? 0);
      f.update(head.peek());
      f.update(this.canonicalState());
      this.fingerprint = f.digest();
    } catch (e) {
      world.free();
      this.currentWorld = undefined;
      throw e;
    }
  }

  /** Ticks stepped so far. Simulated time is `tick / tickRate` s. */
  get tick(): number {
    return this.ticks;
  }

  /**
   * The Rapier world, to read (positions for rendering, ray casts) or to change between ticks.
   * A new object after every `load()`: do not keep it across one. Changing the world outside
   * `applyInputs` is deterministic only if every peer and every replay does the same at the same
   * tick — prefer doing it in `applyInputs`.
   */
  get world(): World {
    return this.live();
  }

  /**
   * The rigid body with `handle` in the current world — the way to reach a body across `load()`s
   * (handles survive a load; `RigidBody` objects do not: one kept from before a load points into a
   * freed world, and Rapier answers "null pointer passed to rust"). Throws a RangeError naming the
   * handle when the world has no such body (removed, or never made).
   */
  body(handle: number): RigidBody {
    const world = this.live();
    // (Rapier packs a handle's index and generation into the bits of a double: not an integer.)
    if (typeof handle !== 'number' || Number.isNaN(handle)) {
      throw new RangeError(`${this.label}.body: a handle is a number, got ${String(handle)}`);
    }
    // A handle packs an index and a generation: a removed body's handle is no longer in the set.
    if (!world.bodies.contains(handle)) {
      throw new RangeError(
        `${this.label}.body: no rigid body with handle ${handle} (${describeHandle(handle)}) in the world at tick ${this.ticks} (removed, or never made)`,
      );
    }
    return world.getRigidBody(handle);
  }

  /** Whether {@link dispose} was called. */
  get disposed(): boolean {
    return this.currentWorld === undefined;
  }

  private live(): World {
    const w = this.currentWorld;
    if (w === undefined) throw new Error(`${this.label} was disposed: it cannot be used any more`);
    return w;
  }

  /** One fixed step with one input per player. Throws, before changing anything, on bad inputs. */
  step(inputs: readonly I[]): void {
    const world = this.live();
    if (!Array.isArray(inputs) || inputs.length !== this.players) {
      throw new RangeError(
        `${this.label}: step() needs ${this.players} input(s), one per player, got ` +
          (Array.isArray(inputs) ? `${inputs.length}` : String(inputs)),
      );
    }
    const def = this.def;
    for (let p = 0; p < inputs.length; p++) {
      const input = inputs[p] as I;
      if (def.checkInput) {
        const why = def.checkInput(input, p);
        if (why !== undefined) {
          throw new RangeError(
            `${this.label}: bad input of player ${p} at tick ${this.ticks}: ${why}`,
          );
        }
      } else {
        const bad = badLeaf(input, 0);
        if (bad !== undefined) {
          throw new RangeError(
            `${this.label}: bad input of player ${p} at tick ${this.ticks}` +
              `${bad.at === '' ? '' : ` at input${bad.at}`}: ${bad.why}`,
          );
        }
      }
    }
    if (world.timestep !== this.dt) {
      throw new Error(
        `${this.label}: world.timestep is ${world.timestep} s, but the simulation steps at ` +
          `${this.dt} s (1 / ${this.tickRate}): do not change it`,
      );
    }
    if (this.ticks >= 0xffffffff) throw new RangeError(`${this.label}: tick would pass 2^32 − 1`);
    this.def.applyInputs?.(world, inputs, this.ticks, this.scene);
    try {
      world.step();
    } catch (e) {
      // A panic inside Rapier's WebAssembly arrives as a RuntimeError (`unreachable`).
      throw new Error(
        `${this.label}: Rapier failed in step ${this.ticks} ` +
          `(${e instanceof Error ? e.message : String(e)}): its world may be damaged; load a good ` +
          'snapshot or dispose it',
        { cause: e },
      );
    }
    this.ticks++;
    this.def.afterStep?.(world, this.ticks, this.scene);
  }

  private userState(): Uint8Array {
    const def = this.def;
    if (!def.saveState) return EMPTY;
    const bytes = def.saveState(this.scene);
    if (!(bytes instanceof Uint8Array)) {
      throw new TypeError(`${this.label}: saveState() must return a Uint8Array`);
    }
    return bytes;
  }

  /**
   * The canonical state bytes (see `canonical.ts`): what {@link hash} hashes and the determinism
   * suite compares. A view into a buffer reused by the next call: copy it to keep it.
   */
  canonicalState(): Uint8Array {
    const world = this.live();
    return writeCanonicalState(this.canonical.reset(), world, this.ticks, this.userState()).peek();
  }

  /** FNV-1a 64 of {@link canonicalState}. */
  hash(): bigint {
    return new Fnv1a64().update(this.canonicalState()).digest();
  }

  /**
   * The whole state: a header — magic `FSRP`, format, scene id, version and fingerprint, tick,
   * user state, a MurmurHash3 checksum of user state and snapshot — then Rapier's snapshot.
   * Costs one `takeSnapshot()` (~1 KB per body) and the checksum.
   */
  save(): Uint8Array {
    const world = this.live();
    const user = this.userState();
    const head = this.header
      .reset()
      .u32(MAGIC)
      .u8(FORMAT)
      .str(this.def.id)
      .u32(this.def.version ?? 1)
      .u64(this.fingerprint)
      .u32(this.ticks)
      .varint(user.length)
      .bytes(user);
    const snapshot = world.takeSnapshot();
    head.u32(murmur3(snapshot, murmur3(user))).varint(snapshot.length);
    const out = new Uint8Array(head.length + snapshot.length);
    out.set(head.peek(), 0);
    out.set(snapshot, head.length);
    return out;
  }

  /**
   * Restores a state from {@link save}. Refuses (RangeError, state unchanged) bytes that are not
   * a save of this package, of another scene, version or tick rate, or that Rapier cannot read.
   */
  load(bytes: Uint8Array): void {
    const old = this.live();
    if (!(bytes instanceof Uint8Array)) {
      throw new TypeError(`${this.label}: load() takes the Uint8Array of save()`);
    }
    const fail = (why: string): never => {
      throw new RangeError(`${this.label}: cannot load these ${bytes.length} bytes: ${why}`);
    };
    let parsed: { tick: number; user: Uint8Array; snapshot: Uint8Array };
    try {
      parsed = this.parseSave(bytes, fail);
    } catch (e) {
      // A read past the end (ByteReader's RangeError) is a truncated save.
      if (e instanceof RangeError && !e.message.startsWith(this.label)) fail(e.message);
      throw e;
    }
    const { tick, user, snapshot } = parsed;
    let world: World | null;
    try {
      world = this.rapier.World.restoreSnapshot(snapshot);
    } catch (e) {
      return fail(
        `Rapier could not read the snapshot (${e instanceof Error ? e.message : String(e)})`,
      );
    }
    // Rapier returns null (the typings say World) for bytes it cannot deserialise.
    if ((world as World | null) === null) return fail('Rapier could not read the snapshot');
    if (world.timestep !== this.dt) {
      const dt = world.timestep;
      world.free();
      fail(`the snapshot steps at ${dt} s, this simulation at ${this.dt} s`);
    }
    try {
      if (this.def.loadState) this.def.loadState(this.scene, user.slice());
      else if (user.length !== 0)
        fail(`it has ${user.length} bytes of user state, this scene none`);
    } catch (e) {
      world.free();
      throw e;
    }
    this.currentWorld = world;
    this.ticks = tick;
    old.free();
  }

  private parseSave(
    bytes: Uint8Array,
    fail: (why: string) => never,
  ): { tick: number; user: Uint8Array; snapshot: Uint8Array } {
    const r = new ByteReader(bytes);
    if (bytes.length < 4 || r.u32() !== MAGIC) fail('not a Rapier simulation save (no FSRP magic)');
    const format = r.u8();
    if (format !== FORMAT) fail(`save format ${format}, this build reads ${FORMAT}`);
    const idLength = readLength(r, bytes, 'scene id', fail);
    if (idLength > 800) fail(`a scene id of ${idLength} bytes`);
    const id = new TextDecoder().decode(r.bytes(idLength));
    if (id !== this.def.id) fail(`it is a save of scene "${id}", this is "${this.def.id}"`);
    const version = r.u32();
    if (version !== (this.def.version ?? 1)) {
      fail(`it is version ${version} of "${id}", this is version ${this.def.version ?? 1}`);
    }
    const lo = r.u32();
    const fingerprint = (BigInt(r.u32()) << 32n) | BigInt(lo);
    if (fingerprint !== this.fingerprint) {
      fail(
        `its scene fingerprint ${fingerprint.toString(16)} is not this one's ` +
          `${this.fingerprint.toString(16)}: "${id}" was built differently (other parameters, ` +
          'bodies or tick rate)',
      );
    }
    const tick = r.u32();
    const user = r.bytes(readLength(r, bytes, 'user state', fail));
    const checksum = r.u32();
    const snapshotLength = readLength(r, bytes, 'snapshot', fail);
    if (snapshotLength !== r.remaining) {
      fail(`the snapshot should be ${snapshotLength} bytes, ${r.remaining} follow`);
    }
    const snapshot = r.bytes(snapshotLength);
    const actual = murmur3(snapshot, murmur3(user));
    if (actual !== checksum) {
      fail(
        `its checksum is ${checksum.toString(16)}, its bytes give ${actual.toString(16)}: ` +
          'corrupted or cut',
      );
    }
    return { tick, user, snapshot };
  }

  /** Frees Rapier's memory. Every later call throws; calling it twice is harmless. */
  dispose(): void {
    this.currentWorld?.free();
    this.currentWorld = undefined;
  }
}

/** Reads a canonical varint length that fits in what follows it. */
function readLength(
  r: ByteReader,
  bytes: Uint8Array,
  what: string,
  fail: (why: string) => never,
): number {
  const at = { pos: r.offset };
  const n = readVarint(at, bytes, bytes.length);
  if (n < 0) return fail(`the ${what} length: ${varintProblem(n)}`);
  r.bytes(at.pos - r.offset);
  if (n > r.remaining) return fail(`the ${what} is ${n} bytes, only ${r.remaining} follow`);
  return n;
}

/**
 * Loads Rapier (once) and builds `def` into a new {@link RapierSimulation}. Everything after this
 * promise is synchronous: more simulations of any scene can then be made with
 * `new RapierSimulation(def)`.
 */
export async function createRapierSimulation<I = number, S = undefined>(
  def: RapierSceneDef<I, S>,
): Promise<RapierSimulation<I, S>> {
  await loadRapier();
  return new RapierSimulation(def);
}

/** A body handle's index and generation, as Rapier packs them into a double's bits. */
function describeHandle(handle: number): string {
  const [index, generation] = splitHandle(handle);
  return `index ${index}, generation ${generation}`;
}
