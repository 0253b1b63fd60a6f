/** Types of scripts/wasm.mjs, for the unit tests that check the committed kernel bytes. */

/** A kernel: its folder, its text source, the module written, the constant it exports. */
export interface Kernel {
  readonly dir: string;
  readonly wat: string;
  readonly ts: string;
  readonly name: string;
}
export const KERNELS: readonly Kernel[];
export function assembleKernels(kernel?: Kernel): Promise<Uint8Array>;
export function kernelsModule(bytes: Uint8Array, kernel?: Kernel): string;
