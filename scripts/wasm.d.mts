/** Types of scripts/wasm.mjs, for the unit test that checks the committed kernel bytes. */
export function assembleKernels(): Promise<Uint8Array>;
export function kernelsModule(bytes: Uint8Array): string;
