/** Types of scripts/wasm.mjs, for the unit tests that check the committed kernel bytes. */

/** A kernel: its folder, its text source, the module written, the constant it exports. */
export interface Kernel {
  readonly dir: string;
  readonly wat: string;
  readonly ts: string;
  readonly name: string;
  /** The layout file (beside the .wat) whose `{{NAME}}` placeholders it uses, if any. */
  readonly layout?: string;
}
export const KERNELS: readonly Kernel[];
export function readLayout(path: string): Map<string, number>;
export function expandKernel(kernel?: Kernel): { text: string; used: Set<string> };
export function unusedLayoutNames(kernels?: readonly Kernel[]): string[];
export function assembleKernels(kernel?: Kernel): Promise<Uint8Array>;
export function kernelsModule(bytes: Uint8Array, kernel?: Kernel): string;
