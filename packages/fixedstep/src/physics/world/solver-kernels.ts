/**
 * The WebAssembly twins of the world's inner loops — the contact solver's (contact-solver.wat,
 * bytes in contact-solver-wasm.ts) and the broad phase's (broad-phase.wat, in broad-phase-wasm.ts),
 * two modules over one memory laid out as kernel-layout.ts says, each export named after the
 * JavaScript function it twins in contact-solver.ts or broad-phase.ts: compiled once, on first use, synchronously (each under 4 KB, which every
 * Chromium allows on its main thread — recent desktop builds allow 8 MB, some WebViews still only
 * 4 KB; a test holds both there). Where WebAssembly is missing or refused (a
 * Content-Security-Policy without `wasm-unsafe-eval`) or lacks the 128-bit SIMD the velocity sweep
 * uses (Chrome before 91, Firefox before 89, Safari before 16.4), {@link solverKernels} returns
 * undefined and the solver runs its JavaScript loops, which give the same bits.
 */
import { BROAD_PHASE_WASM } from './broad-phase-wasm.js';
import { CONTACT_SOLVER_WASM } from './contact-solver-wasm.js';

/** An instance of the kernels over one memory. Offsets are bytes into that memory. */
export interface SolverKernels {
  /**
   * The kernels' `WebAssembly.Memory`, typed by the members used so the published declarations
   * name no `WebAssembly` type (a Node-only project with `lib: ["ES2022"]` has none).
   */
  readonly memory: { readonly buffer: ArrayBuffer; grow(pages: number): number };
  warmStart(first: number, count: number): void;
  iterateVelocities(first: number, count: number, iterations: number, friction: number): void;
  iteratePositions(
    first: number,
    count: number,
    positions: number,
    iterations: number,
    slop: number,
    beta: number,
  ): void;
  velocitiesIn(slots: number, standIns: number, vx: number, vy: number): void;
  positionsIn(
    slots: number,
    standIns: number,
    at: number,
    x: number,
    y: number,
    startX: number,
    startY: number,
  ): void;
  positionsOut(slots: number, at: number, x: number, y: number): void;
  gridBounds(n: number, x: number, y: number, flags: number, cellOf: number, out: number): void;
  gridCells(
    n: number,
    x: number,
    y: number,
    cellOf: number,
    minX: number,
    minY: number,
    inv: number,
    cols: number,
    cells: number,
    start: number,
    cursor: number,
    items: number,
  ): void;
  velocitiesOut(
    first: number,
    count: number,
    slots: number,
    order: number,
    vx: number,
    vy: number,
    normalImpulse: number,
    tangentImpulse: number,
  ): void;
  preparePositions(
    first: number,
    count: number,
    pairs: number,
    order: number,
    separation: number,
    inverseMass: number,
  ): void;
  planVisits(
    count: number,
    pairs: number,
    slots: number,
    bodyA: number,
    bodyB: number,
    normalX: number,
    normalY: number,
    inverseMass: number,
    cached: number,
    head: number,
    next: number,
    cachedA: number,
    cachedB: number,
    cachedNormal: number,
    cachedTangent: number,
    lastWave: number,
    waveOf: number,
    waveStart: number,
    firstOf: number,
    lastOf: number,
    order: number,
    visits: number,
  ): number;
  /** broad-phase.ts's hashedBodyPairs for a world of circles only. */
  hashedBodyPairs(
    x: number,
    y: number,
    halfWidth: number,
    inverseMass: number,
    flags: number,
    start: number,
    items: number,
    cellX: number,
    cellY: number,
    mask: number,
    rows: number,
    cols: number,
    out: number,
    room: number,
  ): number;
  /** broad-phase.ts's bodyPairs for a world of circles only. */
  bodyPairs(
    x: number,
    y: number,
    halfWidth: number,
    inverseMass: number,
    flags: number,
    start: number,
    items: number,
    rows: number,
    cols: number,
    out: number,
    room: number,
    scratch: number,
  ): number;
}

/** The two modules, compiled (null: they cannot be here; undefined: not tried yet). */
let compiled: [solver: WebAssembly.Module, broadPhase: WebAssembly.Module] | null | undefined;

/**
 * `enabled`: whether new solvers may use the WebAssembly kernels (true); `minContacts`: from how
 * many contacts in a step (256) — below, the JavaScript loops are as fast and a world needs no
 * WebAssembly memory of its own (each reserves address space). Tests change them to run both
 * and compare the bits.
 * @internal
 */
export const solverKernelsSetting = { enabled: true, minContacts: 256 };

let available: boolean | undefined;

/**
 * Whether the world's WebAssembly kernels run here: both modules compile and instantiate (the
 * first call tries once). Where they do not, a PhysicsWorld runs its JavaScript loops,
 * which give the same bits, more slowly.
 */
export function worldKernelsAvailable(): boolean {
  available ??= solverKernels() !== undefined;
  return available;
}

/** The kernels over a new memory, or undefined if they cannot run here. */
export function solverKernels(): SolverKernels | undefined {
  if (compiled === undefined) {
    try {
      compiled =
        typeof WebAssembly === 'object'
          ? [new WebAssembly.Module(CONTACT_SOLVER_WASM), new WebAssembly.Module(BROAD_PHASE_WASM)]
          : null;
    } catch {
      compiled = null;
    }
  }
  if (compiled === null) return undefined;
  try {
    const memory = new WebAssembly.Memory({ initial: 1 });
    const imports = { env: { memory } };
    const solver = new WebAssembly.Instance(compiled[0], imports).exports;
    const broadPhase = new WebAssembly.Instance(compiled[1], imports).exports;
    const e = { ...solver, ...broadPhase } as unknown as Omit<SolverKernels, 'memory'>;
    return {
      memory,
      warmStart: e.warmStart,
      iterateVelocities: e.iterateVelocities,
      iteratePositions: e.iteratePositions,
      bodyPairs: e.bodyPairs,
      hashedBodyPairs: e.hashedBodyPairs,
      planVisits: e.planVisits,
      preparePositions: e.preparePositions,
      velocitiesIn: e.velocitiesIn,
      positionsIn: e.positionsIn,
      positionsOut: e.positionsOut,
      gridBounds: e.gridBounds,
      gridCells: e.gridCells,
      velocitiesOut: e.velocitiesOut,
    };
  } catch {
    // Out of address space for another memory, or instantiation refused: stay in JavaScript.
    return undefined;
  }
}

/**
 * A world's working memory for the kernels: the broad phase and then the solvers lay their columns
 * out in it afresh each pass (its contents need not survive from one to the next). It is the
 * kernels' `WebAssembly.Memory` once they run — they start the first time a step has
 * `solverKernelsSetting.minContacts` contacts — else a plain ArrayBuffer for the JavaScript loops.
 */
export class KernelMemory {
  /** The working memory and views of it. */
  memory = new ArrayBuffer(0);
  f64 = new Float64Array(0);
  i32 = new Int32Array(0);
  /**
   * The WebAssembly loops, whose memory is {@link memory}; null: the JavaScript ones; undefined:
   * not tried yet.
   */
  kernels: SolverKernels | null | undefined = solverKernelsSetting.enabled ? undefined : null;

  /**
   * Room for `bytes` of working memory (its contents need not survive); returns the kernels that
   * run on it (none: the JavaScript loops).
   */
  protected reserve(bytes: number, contacts: number): SolverKernels | null | undefined {
    if (this.kernels === undefined && contacts >= solverKernelsSetting.minContacts) {
      const kernels = solverKernels();
      this.kernels = kernels ?? null;
      if (kernels !== undefined) {
        this.memory = kernels.memory.buffer;
        this.f64 = new Float64Array(this.memory);
        this.i32 = new Int32Array(this.memory);
      }
    }
    if (this.memory.byteLength >= bytes) return this.kernels;
    const size = Math.max((bytes + 7) & ~7, 2 * this.memory.byteLength);
    const kernels = this.kernels;
    if (kernels) {
      try {
        kernels.memory.grow(Math.ceil((size - this.memory.byteLength) / 65536));
        this.memory = kernels.memory.buffer;
      } catch {
        // No more memory for the kernels: go on in JavaScript, which gives the same bits.
        this.kernels = null;
        this.memory = new ArrayBuffer(size);
      }
    } else this.memory = new ArrayBuffer(size);
    this.f64 = new Float64Array(this.memory);
    this.i32 = new Int32Array(this.memory);
    return this.kernels;
  }

  /**
   * The kernels over at least `bytes` of working memory (its contents need not survive), once a
   * step has started them; null while the JavaScript loops run (see {@link kernels}).
   */
  kernelsWith(bytes: number): SolverKernels | null {
    if (!this.kernels) return null;
    return this.reserve(bytes, 0) ?? null;
  }
}
