/**
 * Per-tick input sampling: device events, each with a timestamp, go to the tick whose time span
 * contains them — so which tick sees a press never depends on the frame rate.
 * @module
 */
import type { Loop } from '../time/loop.js';
import { MAX_BUTTONS, packButtons, type ButtonInput } from './buttons.js';
import { BUTTON_WORD } from './button-word.js';
import type { InputSchema } from './input-schema.js';

const DOWN = 0x80;
const UP = 0x40;
const AXIS = 0xc0;

/**
 * Turns timestamped device events into per-tick inputs of a schema.
 *
 * Each event goes to the tick whose time span contains it — the loop says where each tick of the
 * current frame ends ({@link Loop.isBeforeUpdateEnd}) — so which tick sees an event does not
 * depend on the frame rate:
 * - a button press and release between two ticks reach exactly one tick (as down and pressed);
 *   a press is never lost and never doubled;
 * - an axis takes the last value set before the tick ends (values are quantised when set).
 *
 * Events must be on the loop's time line: in a browser, `event.timeStamp` and the
 * `requestAnimationFrame` timestamp share one (`performance.now()`). The loop warns when they
 * clearly do not (see `FixedLoopOptions.onWarning`).
 *
 * Allocates only when its queue must grow, and in {@link sample} for schemas with axes (one
 * {@link PlayerInput} a tick; {@link sampleWords} allocates nothing).
 *
 * @typeParam I — the schema's input type: a {@link ButtonInput} number without axes.
 */
export class InputSampler<I = ButtonInput> {
  /** The schema of the inputs it makes. */
  readonly schema: InputSchema<I>;
  private times = new Float64Array(64);
  private codes = new Uint8Array(64);
  private values = new Uint32Array(64);
  private head = 0;
  private size = 0;
  private held = 0;
  private lastTime = -Infinity;
  /** The words of the last sampled tick (axes carry over between ticks). */
  private readonly current: Uint32Array;
  private readonly buttonCount: number;

  constructor(schema?: InputSchema<I>) {
    this.schema = schema ?? (BUTTON_WORD as unknown as InputSchema<I>);
    this.current = new Uint32Array(this.schema.words);
    this.buttonCount = Math.min(MAX_BUTTONS, this.schema.buttons.length);
  }

  /**
   * Record that `button` (an index, see `schema.button`) went down or up at `timeMs`. Events come
   * in time order; an earlier time than the previous event counts as equal to it.
   */
  push(timeMs: number, button: number, down: boolean): void {
    if (!Number.isInteger(button) || button < 0 || button >= this.buttonCount) {
      throw new RangeError(
        `InputSampler: button must be an integer from 0 to ${this.buttonCount - 1}, got ${String(button)}`,
      );
    }
    this.enqueue(timeMs, button | (down ? DOWN : UP), 0);
  }

  /**
   * Record that axis `axis` (an index, see `schema.axis`) took `value` at `timeMs` (in the axis's
   * units: radians for an angle; quantised now, so the tick sees exactly what a replay stores).
   */
  setAxis(timeMs: number, axis: number, value: number): void {
    if (!Number.isInteger(axis) || axis < 0 || axis >= this.schema.axes.length) {
      throw new RangeError(
        `InputSampler: axis must be an integer from 0 to ${this.schema.axes.length - 1}, got ${String(axis)}`,
      );
    }
    this.enqueue(timeMs, AXIS | axis, this.schema.quantise(axis, value));
  }

  private enqueue(timeMs: number, code: number, value: number): void {
    const t = Number.isFinite(timeMs) && timeMs > this.lastTime ? timeMs : this.lastTime;
    this.lastTime = t;
    if (this.size === this.times.length) this.grow();
    const i = (this.head + this.size) % this.times.length;
    this.times[i] = t;
    this.codes[i] = code;
    this.values[i] = value;
    this.size++;
  }

  /**
   * The input of update `j` of the loop's current frame: consumes every queued event that happened
   * before that update ends. For a schema with axes this is a fresh {@link PlayerInput}.
   */
  sample(loop: Pick<Loop, 'isBeforeUpdateEnd'>, j: number): I {
    this.advance(loop, j);
    return this.schema.decode(this.current, 0);
  }

  /** {@link sample} as words, written to `out[at …]` (the schema's `words` of them). Allocates nothing. */
  sampleWords(loop: Pick<Loop, 'isBeforeUpdateEnd'>, j: number, out: Uint32Array, at = 0): void {
    this.advance(loop, j);
    out.set(this.current, at);
  }

  private advance(loop: Pick<Loop, 'isBeforeUpdateEnd'>, j: number): void {
    let down = this.held;
    let pressed = 0;
    const cap = this.times.length;
    const words = this.current;
    while (this.size > 0) {
      const t = this.times[this.head]!;
      if (!loop.isBeforeUpdateEnd(t, j)) break;
      const code = this.codes[this.head]!;
      const kind = code & 0xc0;
      if (kind === AXIS) {
        this.schema.writeAxis(words, 0, code & 0x3f, this.values[this.head]!);
      } else {
        const bit = 1 << (code & 0x0f);
        if (kind === DOWN) {
          if ((this.held & bit) === 0) pressed |= bit;
          this.held |= bit;
          down |= bit;
        } else {
          this.held &= ~bit;
        }
      }
      this.head = (this.head + 1) % cap;
      this.size--;
    }
    words[0] = packButtons(down, pressed);
  }

  /** Buttons held right now (after the last sampled event), as a down mask. */
  get heldMask(): number {
    return this.held;
  }

  /** Events waiting for a tick. */
  get pending(): number {
    return this.size;
  }

  /** Forget all queued events and held buttons (e.g. when the window loses focus). Axes keep their value. */
  clear(): void {
    this.head = 0;
    this.size = 0;
    this.held = 0;
  }

  private grow(): void {
    const n = this.times.length;
    const times = new Float64Array(n * 2);
    const codes = new Uint8Array(n * 2);
    const values = new Uint32Array(n * 2);
    for (let k = 0; k < this.size; k++) {
      const i = (this.head + k) % n;
      times[k] = this.times[i]!;
      codes[k] = this.codes[i]!;
      values[k] = this.values[i]!;
    }
    this.times = times;
    this.codes = codes;
    this.values = values;
    this.head = 0;
  }
}

/** An {@link InputSampler} of the classic {@link BUTTON_WORD} schema: 16 buttons, one u32 a tick. */
export class ButtonSampler extends InputSampler {
  constructor() {
    super(BUTTON_WORD);
  }
}
