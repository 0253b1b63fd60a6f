/**
 * Every field kind a wire message is declared with, in one import: the {@link Field} contract
 * (`field.ts`), {@link Layout} (`layout.ts`), scalars (`scalars.ts`) and compounds (`compound.ts`).
 * @module
 */
export * from './field.js';
export * from './layout.js';
export * from './scalars.js';
export * from './compound.js';
