/**
 * The button word: the one definition of how a tick's buttons are packed into 32 bits. Every
 * other module (samplers, replays, the protocol, the relay, games) uses these helpers and never
 * writes the bit layout by hand.
 *
 * Bits 0–15: buttons down at any moment of the tick. Bits 16–31: buttons pressed during it (an
 * edge: exactly one tick sees each press). Button `b` is bit `b` and bit `16 + b`.
 * @module
 */

/** A tick's buttons for one player, packed in a u32 (see the module note). */
export type ButtonInput = number;

/** Buttons a word holds: 0 … 15. */
export const MAX_BUTTONS = 16;
/** The "pressed" bit of button `b` is bit `PRESSED_SHIFT + b`. */
export const PRESSED_SHIFT = 16;
/** The "down" bits of a word. */
export const DOWN_MASK = 0xffff;

function checkButton(button: number): void {
  if (!Number.isInteger(button) || button < 0 || button >= MAX_BUTTONS) {
    throw new RangeError(`button must be an integer from 0 to 15, got ${String(button)}`);
  }
}

/** The "down" bit of `button` (0–15): `1 << button`. */
export function downBit(button: number): number {
  checkButton(button);
  return 1 << button;
}

/** The "pressed" bit of `button` (0–15): `1 << (16 + button)`, unsigned. */
export function pressedBit(button: number): number {
  checkButton(button);
  return (1 << (PRESSED_SHIFT + button)) >>> 0;
}

/** Both bits of `button`: down or pressed during the tick. */
export function anyBit(button: number): number {
  return (downBit(button) | pressedBit(button)) >>> 0;
}

/** Whether `button` (0–15) was down at any moment of the tick. */
export function isDown(input: ButtonInput, button: number): boolean {
  return ((input >>> button) & 1) === 1;
}

/** Whether `button` (0–15) went down during the tick (an edge: exactly one tick sees it). */
export function wasPressed(input: ButtonInput, button: number): boolean {
  return ((input >>> (PRESSED_SHIFT + button)) & 1) === 1;
}

/** Packs `down` and `pressed` bit masks (16 bits each) into a {@link ButtonInput}. */
export function packButtons(down: number, pressed: number): ButtonInput {
  return ((down & DOWN_MASK) | ((pressed & DOWN_MASK) << PRESSED_SHIFT)) >>> 0;
}

/** The "down" mask of a word (bits 0–15). */
export function downMask(input: ButtonInput): number {
  return input & DOWN_MASK;
}

/** The "pressed" mask of a word, shifted down to bits 0–15. */
export function pressedMask(input: ButtonInput): number {
  return (input >>> PRESSED_SHIFT) & DOWN_MASK;
}

/**
 * What a tick's missing input becomes — on the relay after its deadline, in a rollback client's
 * prediction: the player's last input with its "pressed" edges cleared. Held buttons stay held,
 * no press is repeated.
 */
export function heldOnly(last: ButtonInput): ButtonInput {
  return (last & DOWN_MASK) >>> 0;
}

function spread16(v: number): number {
  let x = v & 0xffff;
  x = (x | (x << 8)) & 0x00ff00ff;
  x = (x | (x << 4)) & 0x0f0f0f0f;
  x = (x | (x << 2)) & 0x33333333;
  x = (x | (x << 1)) & 0x55555555;
  return x;
}

function compact16(v: number): number {
  let x = v & 0x55555555;
  x = (x | (x >>> 1)) & 0x33333333;
  x = (x | (x >>> 2)) & 0x0f0f0f0f;
  x = (x | (x >>> 4)) & 0x00ff00ff;
  x = (x | (x >>> 8)) & 0x0000ffff;
  return x;
}

/**
 * Puts each button's "down" and "pressed" bits side by side (bit b → 2b, bit 16 + b → 2b + 1), so
 * the low buttons of a game land in the low bits and their changes fit one varint byte. Replays
 * and the network protocol code button words this way. A bijection on u32.
 */
export function interleave(v: ButtonInput): number {
  return (spread16(v) | (spread16(v >>> PRESSED_SHIFT) << 1)) >>> 0;
}

/** The inverse of {@link interleave}. */
export function deinterleave(w: number): ButtonInput {
  return (compact16(w) | (compact16(w >>> 1) << PRESSED_SHIFT)) >>> 0;
}
