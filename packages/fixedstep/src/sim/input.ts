import type { Loop } from '../time/loop.js';

/**
 * A tick's input for one player, packed in a 32-bit unsigned integer:
 * bits 0–15 — buttons down at any moment of the tick; bits 16–31 — buttons pressed during it.
 * Compact, so replays and network messages stay small.
 */
export type ButtonInput = number;

/** Whether `button` (0–15) was down at any moment of the tick. */
export function isDown(input: ButtonInput, button: number): boolean {
  return ((input >>> button) & 1) === 1;
}

/** Whether `button` (0–15) went down during the tick (an edge: exactly one tick sees it). */
export function wasPressed(input: ButtonInput, button: number): boolean {
  return ((input >>> (16 + button)) & 1) === 1;
}

/** Packs `down` and `pressed` bit masks (16 bits each) into a {@link ButtonInput}. */
export function packButtons(down: number, pressed: number): ButtonInput {
  return ((down & 0xffff) | ((pressed & 0xffff) << 16)) >>> 0;
}

/**
 * Turns timestamped button events into per-tick inputs.
 *
 * Each event goes to the tick whose time span contains it — the loop says where each tick of the
 * current frame ends ({@link Loop.isBeforeUpdateEnd}) — so which tick sees a press does not depend
 * on the frame rate. A press and release between two ticks reaches exactly one tick (as down and
 * pressed); a press is never lost and never doubled. Events must be on the loop's time line
 * (in a browser, `event.timeStamp` and the `requestAnimationFrame` timestamp share one).
 *
 * Allocates only when its queue must grow.
 */
export class ButtonSampler {
  private times = new Float64Array(64);
  private codes = new Uint8Array(64);
  private head = 0;
  private size = 0;
  private held = 0;
  private lastTime = -Infinity;

  /**
   * Record that `button` (0–15) went down or up at `timeMs`. Events must come in time order; an
   * earlier time than the previous event is treated as equal to it.
   */
  push(timeMs: number, button: number, down: boolean): void {
    if (!Number.isInteger(button) || button < 0 || button > 15) {
      throw new RangeError(
        `ButtonSampler: button must be an integer from 0 to 15, got ${String(button)}`,
      );
    }
    const t = Number.isFinite(timeMs) && timeMs > this.lastTime ? timeMs : this.lastTime;
    this.lastTime = t;
    if (this.size === this.times.length) this.grow();
    const i = (this.head + this.size) % this.times.length;
    this.times[i] = t;
    this.codes[i] = button | (down ? 0x80 : 0);
    this.size++;
  }

  /**
   * The input of update `j` of the loop's current frame: consumes every queued event that happened
   * before that update ends.
   */
  sample(loop: Pick<Loop, 'isBeforeUpdateEnd'>, j: number): ButtonInput {
    let down = this.held;
    let pressed = 0;
    const cap = this.times.length;
    while (this.size > 0) {
      const t = this.times[this.head]!;
      if (!loop.isBeforeUpdateEnd(t, j)) break;
      const code = this.codes[this.head]!;
      const bit = 1 << (code & 0x0f);
      if (code & 0x80) {
        if ((this.held & bit) === 0) pressed |= bit;
        this.held |= bit;
        down |= bit;
      } else {
        this.held &= ~bit;
      }
      this.head = (this.head + 1) % cap;
      this.size--;
    }
    return packButtons(down, pressed);
  }

  /** Buttons held right now (after the last sampled event). */
  get heldMask(): number {
    return this.held;
  }

  /** Events waiting for a tick. */
  get pending(): number {
    return this.size;
  }

  /** Forget all queued events and held buttons (e.g. when the window loses focus). */
  clear(): void {
    this.head = 0;
    this.size = 0;
    this.held = 0;
  }

  private grow(): void {
    const n = this.times.length;
    const times = new Float64Array(n * 2);
    const codes = new Uint8Array(n * 2);
    for (let k = 0; k < this.size; k++) {
      const i = (this.head + k) % n;
      times[k] = this.times[i]!;
      codes[k] = this.codes[i]!;
    }
    this.times = times;
    this.codes = codes;
    this.head = 0;
  }
}

interface KeyboardHost {
  addEventListener(type: 'keydown' | 'keyup', listener: (e: KeyboardEventLike) => void): void;
  removeEventListener(type: 'keydown' | 'keyup', listener: (e: KeyboardEventLike) => void): void;
}
interface KeyboardEventLike {
  readonly code: string;
  readonly timeStamp: number;
  readonly repeat: boolean;
  preventDefault(): void;
}

/**
 * Feeds keyboard events into a sampler, mapping `KeyboardEvent.code` to buttons
 * (e.g. `{ Space: 0, ArrowLeft: 1 }`). Returns a function that detaches it.
 */
export function attachKeyboard(
  target: KeyboardHost,
  sampler: ButtonSampler,
  keys: Readonly<Record<string, number>>,
  timeOf: (e: KeyboardEventLike) => number = (e) => e.timeStamp,
): () => void {
  const onDown = (e: KeyboardEventLike) => {
    const b = keys[e.code];
    if (b === undefined) return;
    e.preventDefault();
    if (!e.repeat) sampler.push(timeOf(e), b, true);
  };
  const onUp = (e: KeyboardEventLike) => {
    const b = keys[e.code];
    if (b === undefined) return;
    e.preventDefault();
    sampler.push(timeOf(e), b, false);
  };
  target.addEventListener('keydown', onDown);
  target.addEventListener('keyup', onUp);
  return () => {
    target.removeEventListener('keydown', onDown);
    target.removeEventListener('keyup', onUp);
  };
}
