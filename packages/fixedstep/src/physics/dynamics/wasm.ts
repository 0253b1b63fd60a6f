/**
 * The WebAssembly spring kernel (kernels.wat, bytes in kernels-wasm.ts): compiled once, on first
 * use, synchronously (it is a few hundred bytes, well under every engine's limit for compiling on
 * the main thread). Where WebAssembly is missing or refused (a Content-Security-Policy without
 * `wasm-unsafe-eval`), {@link springKernels} returns undefined and SpringModel stays on its
 * JavaScript kernel, which gives the same bits.
 */
import { SPRING_KERNELS_WASM } from './kernels-wasm.js';

/** An instance of the kernels over one memory. Offsets are bytes into that memory. */
export interface SpringKernels {
  /**
   * The kernels' `WebAssembly.Memory`, typed by the one member read from it so the published
   * declarations name no `WebAssembly` type (a Node-only project with `lib: ["ES2022"]` has none).
   */
  readonly memory: { readonly buffer: ArrayBuffer };
  accelerations2(
    springs: number,
    size: number,
    x: number,
    v: number,
    out: number,
    base: number,
    idx: number,
    data: number,
  ): void;
  kickDrift(size: number, x: number, v: number, a: number, kick: number, drift: number): void;
}

let compiled: WebAssembly.Module | null | undefined;

/** Whether the kernels can run here (compiles them the first time). */
export function springKernelsAvailable(): boolean {
  if (compiled === undefined) {
    try {
      compiled =
        typeof WebAssembly === 'object' ? new WebAssembly.Module(SPRING_KERNELS_WASM) : null;
    } catch {
      compiled = null;
    }
  }
  return compiled !== null;
}

/** The kernels over a new memory of `bytes` bytes, or undefined if that cannot be had. */
export function springKernels(bytes: number): SpringKernels | undefined {
  if (!springKernelsAvailable()) return undefined;
  try {
    const memory = new WebAssembly.Memory({ initial: Math.max(1, Math.ceil(bytes / 65536)) });
    const instance = new WebAssembly.Instance(compiled!, { env: { memory } });
    const e = instance.exports as unknown as Omit<SpringKernels, 'memory'>;
    return { memory, accelerations2: e.accelerations2, kickDrift: e.kickDrift };
  } catch {
    // Out of address space for another memory, or instantiation refused: stay in JavaScript.
    return undefined;
  }
}
