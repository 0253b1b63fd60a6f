import type { InputSampler } from '../sim/input.js';

/** The part of a `KeyboardEvent` the keyboard adapter reads. */
export interface KeyboardEventLike {
  readonly code: string;
  readonly timeStamp: number;
  readonly repeat: boolean;
  preventDefault(): void;
}

/** Where keyboard events come from: `window`, `document` or an element. */
export interface KeyboardHost {
  addEventListener(type: 'keydown' | 'keyup', listener: (e: KeyboardEventLike) => void): void;
  removeEventListener(type: 'keydown' | 'keyup', listener: (e: KeyboardEventLike) => void): void;
}

/** Where window focus events come from (to release held keys when focus is lost). */
interface BlurHost {
  addEventListener(type: 'blur', listener: (e: { readonly timeStamp: number }) => void): void;
  removeEventListener(type: 'blur', listener: (e: { readonly timeStamp: number }) => void): void;
}

/**
 * Resolves a button given by name or index against a sampler's schema. Throws a RangeError naming
 * an unknown one.
 */
export function buttonIndex(sampler: InputSampler<unknown>, button: string | number): number {
  const i = typeof button === 'number' ? button : sampler.schema.button[button];
  if (i === undefined || !Number.isInteger(i) || i < 0 || i >= sampler.schema.buttons.length) {
    throw new RangeError(
      `input: unknown button ${JSON.stringify(button)} (the schema has ${sampler.schema.buttons.join(', ') || 'none'})`,
    );
  }
  return i;
}

/**
 * Feeds keyboard events into a sampler, mapping `KeyboardEvent.code` to buttons by name or index
 * (e.g. `{ Space: 'jump', ArrowLeft: 'left' }`). Key repeats are ignored; mapped keys do not
 * scroll the page. When the host loses focus (`blur`), every key it holds is released at that
 * moment, so a key released in another window does not stay down. Returns a function that
 * detaches it.
 *
 * `timeOf` gives an event's time in ms on the loop's time line (default `event.timeStamp`, which
 * shares `performance.now()`'s and `requestAnimationFrame`'s). The time decides which tick sees
 * the key, so it must be on the same time line as the frames the loop is fed: a `timeOf` on
 * another one moves presses to other ticks (the loop warns when an event is more than 5 s ahead
 * of it). Keep the default in a browser — it is when the key was pressed, while
 * `performance.now()` in the handler is when a busy page got to it, later by the length of a
 * long frame. Pass `() => performance.now()` only where the two time lines differ, such as a
 * test under Playwright's `page.clock`, which fakes `performance.now()` but not `event.timeStamp`.
 */
export function attachKeyboard(
  target: KeyboardHost,
  sampler: InputSampler<unknown>,
  keys: Readonly<Record<string, string | number>>,
  timeOf: (e: KeyboardEventLike) => number = (e) => e.timeStamp,
): () => void {
  const map = new Map<string, number>();
  for (const [code, button] of Object.entries(keys)) map.set(code, buttonIndex(sampler, button));
  const held = new Set<string>();
  const onDown = (e: KeyboardEventLike) => {
    const b = map.get(e.code);
    if (b === undefined) return;
    e.preventDefault();
    if (e.repeat || held.has(e.code)) return;
    held.add(e.code);
    sampler.push(timeOf(e), b, true);
  };
  const onUp = (e: KeyboardEventLike) => {
    const b = map.get(e.code);
    if (b === undefined) return;
    e.preventDefault();
    held.delete(e.code);
    sampler.push(timeOf(e), b, false);
  };
  const onBlur = (e: { readonly timeStamp: number }) => {
    for (const code of held) sampler.push(e.timeStamp, map.get(code)!, false);
    held.clear();
  };
  target.addEventListener('keydown', onDown);
  target.addEventListener('keyup', onUp);
  const blurHost = target as unknown as Partial<BlurHost>;
  blurHost.addEventListener?.('blur', onBlur);
  return () => {
    target.removeEventListener('keydown', onDown);
    target.removeEventListener('keyup', onUp);
    blurHost.removeEventListener?.('blur', onBlur);
  };
}
