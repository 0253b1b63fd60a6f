/**
 * The classic input schema, written out by hand: one 32-bit {@link ButtonInput} word of 16 buttons
 * named `b0` … `b15`, no axes. It is exactly what `defineInput({ buttons: ['b0', …, 'b15'] })`
 * builds (a test checks the descriptor, the id and every method against it), but standing alone it
 * keeps `defineInput`'s machinery (validation, descriptors, hashing, axes) out of the bundle of a
 * game that only uses buttons — the `InputSampler` default.
 * @module
 */
import { heldOnly, type ButtonInput } from './buttons.js';
import type { InputSchema } from './input-schema.js';

const NAMES = Object.freeze(Array.from({ length: 16 }, (_, i) => `b${i}`));

function checkWord(v: unknown): number {
  if (!(Number.isInteger(v) && (v as number) >= 0 && (v as number) <= 0xffffffff)) {
    throw new RangeError(`input: a button word must be a u32, got ${String(v)}`);
  }
  return v as number;
}

const noAxis = (axis: number): never => {
  throw new RangeError(`input: BUTTON_WORD has no axes, got axis ${String(axis)}`);
};

/**
 * The classic input: one 32-bit {@link ButtonInput} word of 16 buttons named `b0` … `b15`. Every
 * replay of format 1 and every game written before schemas existed uses it; every u32 is a valid
 * input of it.
 */
export const BUTTON_WORD: InputSchema = Object.freeze({
  words: 1,
  buttons: NAMES,
  axes: Object.freeze([]),
  button: Object.freeze(Object.fromEntries(NAMES.map((n, i) => [n, i]))),
  axis: Object.freeze({}),
  // Version 1; 16 buttons "b0" … "b15"; no axes (see encodeDescriptor in input-schema.ts).
  descriptor: Uint8Array.of(
    1,
    16,
    2,
    98,
    48,
    2,
    98,
    49,
    2,
    98,
    50,
    2,
    98,
    51,
    2,
    98,
    52,
    2,
    98,
    53,
    2,
    98,
    54,
    2,
    98,
    55,
    2,
    98,
    56,
    2,
    98,
    57,
    3,
    98,
    49,
    48,
    3,
    98,
    49,
    49,
    3,
    98,
    49,
    50,
    3,
    98,
    49,
    51,
    3,
    98,
    49,
    52,
    3,
    98,
    49,
    53,
    0,
  ),
  id: 'c0e782f5338e5e9c',
  encode(input: ButtonInput, out: Uint32Array, at: number): void {
    out[at] = checkWord(input);
  },
  decode: (words: ArrayLike<number>, at: number): ButtonInput => words[at]! >>> 0,
  problem: (): undefined => undefined,
  missing(last: ArrayLike<number>, lastAt: number, out: Uint32Array, outAt: number): void {
    out[outAt] = heldOnly(last[lastAt]!);
  },
  writeAxis: (_out: Uint32Array, _at: number, axis: number): void => noAxis(axis),
  neutral: (): ButtonInput => 0,
  quantise: (axis: number): number => noAxis(axis),
  value: (axis: number): number => noAxis(axis),
});
