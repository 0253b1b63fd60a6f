/**
 * Every field kind a wire message is declared with, in one import: the {@link Field} contract and
 * {@link Layout} (`field.ts`), scalars (`scalars.ts`) and compounds (`compound.ts`).
 * @module
 */
export * from './field.js';
export * from './scalars.js';
export * from './compound.js';
