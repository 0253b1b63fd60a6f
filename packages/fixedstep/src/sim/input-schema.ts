/**
 * Input schemas: what one player's input for one tick is made of — buttons, plus quantised axes
 * such as an aim angle or an analog stick — and its canonical encoding in 32-bit words. The same
 * words go to the local step, the replay recorder, lockstep, rollback and the relay; a schema's
 * canonical descriptor travels in replay headers and the protocol's hello, so every side knows it
 * reads the same thing.
 *
 * Layout: word 0 is the {@link ButtonInput} word (buttons down, buttons pressed); axes follow,
 * packed from bit 0 of word 1 upwards, each axis in `bits` consecutive bits of one word (an axis
 * never straddles two words). A schema without axes is one word, and its input is the plain
 * {@link ButtonInput} number — the classic {@link BUTTON_WORD} schema is exactly that.
 *
 * An axis's field reads 0 in an input nobody set (a fresh {@link PlayerInput}, {@link
 * InputSchema.neutral}, a tick before the first sample). A centred axis (the default for a
 * two-sided range such as a stick's −1…1) stores its step as a signed offset from the centre, so
 * that idle field is the centre, exactly; a linear axis stores step 0 as `min`.
 * @module
 */
import { fnv1a64, hex64 } from '../det/hash.js';
import {
  DOWN_MASK,
  MAX_BUTTONS,
  PRESSED_SHIFT,
  heldOnly,
  isDown,
  wasPressed,
  type ButtonInput,
} from './buttons.js';

/**
 * A linear axis: a value from `min` to `max`, both exact, in `2^bits − 1` equal steps (`2^bits`
 * levels: an even number, so the middle of the range is not one of them — 0 on a −1…1 axis reads
 * ±0.0159 at 6 bits). Step 0, the idle field, is `min`: right for a one-sided axis (a throttle,
 * 0…1), wrong for a stick — which is why a two-sided range is {@link CentredAxisSpec centred} by
 * default.
 */
export interface LinearAxisSpec {
  readonly kind: 'linear';
  readonly name: string;
  /** Bits of precision, 1–16. */
  readonly bits: number;
  /** The value of step 0. */
  readonly min: number;
  /** The value of the last step. */
  readonly max: number;
  /** Values within this fraction of the range above `min` quantise to `min` (see {@link AxisDeadZone}). */
  readonly deadZone: number;
}

/**
 * A centred axis: `2^bits − 1` levels (an odd number) evenly from `min` to `max`, both exact, and
 * the centre `(min + max) / 2` exact among them — 0 on a −1…1 axis. The field holds the signed
 * offset from the centre in two's complement, so an input never set (all bits 0) reads the centre;
 * the one pattern that is no level (the most negative) is refused as a problem.
 */
export interface CentredAxisSpec {
  readonly kind: 'centred';
  readonly name: string;
  /** Bits of precision, 2–16 (`2^(bits−1) − 1` steps each side of the centre). */
  readonly bits: number;
  /** The value of the lowest level. */
  readonly min: number;
  /** The value of the highest level. */
  readonly max: number;
  /** Values within this fraction of the half range around the centre quantise to the centre. */
  readonly deadZone: number;
}

/**
 * An angle axis: radians from −π (step 0) upwards in `2^bits` equal steps around the circle
 * (the last step is just below π; π itself wraps to −π).
 */
export interface AngleAxisSpec {
  readonly kind: 'angle';
  readonly name: string;
  /** Bits of precision, 1–16 (10 bits: 0.35° a step). */
  readonly bits: number;
}

/** One axis of a schema. */
export type AxisSpec = LinearAxisSpec | CentredAxisSpec | AngleAxisSpec;

/**
 * An axis's dead zone, a fraction in [0, 1) of its travel from rest (the centre of a centred axis,
 * `min` of a linear one): a value within it quantises to rest, and the travel beyond it is
 * stretched to the whole range, so a worn stick that rests at 0.08 reads exactly 0 and full
 * deflection still reads `max`. Applied where a value is quantised (on the device side, in
 * {@link InputSchema.quantise} / {@link PlayerInput.setAxis} / the samplers): it changes which
 * steps a device sends, not what a step means, so it is not part of the descriptor or the id.
 */
export type AxisDeadZone = number;

/**
 * How {@link defineInput} is told an axis: `{ angle: bits }`, or `{ min, max, bits }` with
 * optional `centred` and `deadZone`. `centred` defaults to true for a two-sided range (`min` =
 * −`max`, such as a stick's −1…1, at 2 bits or more) and false otherwise; `centred: false` on a
 * two-sided range is the even quantisation every such axis had before centred axes (its replays
 * keep verifying).
 */
export type AxisDefinition =
  | { readonly angle: number }
  | {
      readonly min: number;
      readonly max: number;
      readonly bits: number;
      readonly centred?: boolean;
      readonly deadZone?: AxisDeadZone;
    };

/** What {@link defineInput} takes. */
export interface InputDefinition<B extends string = string, A extends string = string> {
  /** Button names, at most 16; a button's index is its position. */
  readonly buttons?: readonly B[];
  /** Axes by name, in the order given (the order is part of the encoding). */
  readonly axes?: Readonly<Record<A, AxisDefinition>>;
}

/**
 * What one player's input for one tick is, and how it is encoded. Built by {@link defineInput}
 * (or read back from a descriptor by {@link inputSchemaFromDescriptor}).
 *
 * @typeParam I — the input a simulation's `step` receives per player: a {@link ButtonInput}
 * number for a schema without axes, a {@link PlayerInput} otherwise.
 */
export interface InputSchema<I = ButtonInput> {
  /** u32 words per player per tick (1 without axes). */
  readonly words: number;
  /** Button names; a button's index is its bit. */
  readonly buttons: readonly string[];
  /** Axes in encoding order. */
  readonly axes: readonly AxisSpec[];
  /** Button index by name. */
  readonly button: Readonly<Record<string, number>>;
  /** Axis index by name. */
  readonly axis: Readonly<Record<string, number>>;
  /** The canonical descriptor bytes (carried in replays and the protocol). */
  readonly descriptor: Uint8Array;
  /** FNV-1a 64 of the descriptor, 16 hex digits: two sides agree on a schema iff ids are equal. */
  readonly id: string;
  /** Write `input` as {@link words} words at `out[at …]`. Throws a RangeError for an input the schema cannot hold. */
  encode(input: I, out: Uint32Array, at: number): void;
  /** The input held in `words[at …]` (a fresh value; the words are not kept). */
  decode(words: ArrayLike<number>, at: number): I;
  /** What is wrong with `words[at …]` as an input of this schema (bits it does not define), or undefined. */
  problem(words: ArrayLike<number>, at: number): string | undefined;
  /**
   * The input of a tick nobody sent, from the player's last one: held buttons stay held, presses
   * are not repeated, axes keep their value. Writes `out[outAt …]`.
   */
  missing(last: ArrayLike<number>, lastAt: number, out: Uint32Array, outAt: number): void;
  /** Set axis `axis`'s step in the words `out[at …]`, leaving everything else as it is. */
  writeAxis(out: Uint32Array, at: number, axis: number, step: number): void;
  /** The input with nothing pressed and every axis's field 0 (a centred axis at its centre). */
  neutral(): I;
  /** Axis `axis`'s step (an integer) for a value — device-side quantisation (clamped; angles wrap). */
  quantise(axis: number, value: number): number;
  /** Axis `axis`'s value at step `step`: `+ − × ÷` only, the same in every engine. */
  value(axis: number, step: number): number;
}

const TWO_PI = 2 * Math.PI;

/**
 * A player's input of a schema with axes: the button word and the axis steps. Simulations read it
 * with {@link isDown}, {@link wasPressed} and {@link axis}; the values are deterministic.
 */
export class PlayerInput {
  /** The button word (see {@link ButtonInput}). */
  buttons: ButtonInput = 0;
  /**
   * Each axis's field as encoded (an integer from 0 to 2^bits − 1), in schema order: the step of a
   * linear or angle axis, the two's-complement offset from the centre of a centred one (0: the
   * centre).
   */
  readonly steps: Uint32Array;

  constructor(readonly schema: InputSchema<PlayerInput>) {
    this.steps = new Uint32Array(schema.axes.length);
  }

  /** Whether button `button` (an index, see {@link InputSchema.button}) was down during the tick. */
  isDown(button: number): boolean {
    return isDown(this.buttons, button);
  }

  /** Whether button `button` went down during the tick. */
  wasPressed(button: number): boolean {
    return wasPressed(this.buttons, button);
  }

  /** The value of axis `axis` (an index, see {@link InputSchema.axis}), deterministic. */
  axis(axis: number): number {
    return this.schema.value(axis, this.steps[axis]!);
  }

  /** Set axis `axis` from a value (quantised: clamped, angles wrapped). Returns this. */
  setAxis(axis: number, value: number): this {
    this.steps[axis] = this.schema.quantise(axis, value);
    return this;
  }
}

const NAME = /^[A-Za-z0-9_.-]{1,32}$/;

function fail(message: string): never {
  throw new RangeError(`defineInput: ${message}`);
}

/** Where each axis lives: word and bit offset. */
interface Slot {
  word: number;
  shift: number;
  mask: number;
}

class Schema implements InputSchema<unknown> {
  readonly words: number;
  readonly button: Readonly<Record<string, number>>;
  readonly axis: Readonly<Record<string, number>>;
  readonly descriptor: Uint8Array;
  readonly id: string;
  private readonly slots: readonly Slot[];
  private readonly buttonMask: number;
  /** Per word after the first: the bits an axis uses. */
  private readonly usedBits: Uint32Array;
  private readonly plain: boolean;

  constructor(
    readonly buttons: readonly string[],
    readonly axes: readonly AxisSpec[],
  ) {
    const slots: Slot[] = [];
    let word = 1;
    let shift = 0;
    for (const a of axes) {
      if (shift + a.bits > 32) {
        word++;
        shift = 0;
      }
      slots.push({ word, shift, mask: a.bits === 32 ? 0xffffffff : (1 << a.bits) - 1 });
      shift += a.bits;
    }
    this.slots = slots;
    this.words = axes.length === 0 ? 1 : word + 1;
    this.plain = axes.length === 0;
    const n = buttons.length;
    const low = n === 0 ? 0 : n >= MAX_BUTTONS ? DOWN_MASK : (1 << n) - 1;
    this.buttonMask = (low | (low << PRESSED_SHIFT)) >>> 0;
    this.usedBits = new Uint32Array(this.words);
    for (const s of slots)
      this.usedBits[s.word] = (this.usedBits[s.word]! | (s.mask << s.shift)) >>> 0;
    this.button = Object.freeze(Object.fromEntries(buttons.map((b, i) => [b, i])));
    this.axis = Object.freeze(Object.fromEntries(axes.map((a, i) => [a.name, i])));
    this.descriptor = encodeDescriptor(buttons, axes);
    this.id = hex64(fnv1a64(this.descriptor));
  }

  encode(input: unknown, out: Uint32Array, at: number): void {
    if (this.plain) {
      const v = input as number;
      if (!(Number.isInteger(v) && v >= 0 && v <= 0xffffffff)) {
        throw new RangeError(`input: a button word must be a u32, got ${String(v)}`);
      }
      if ((v & ~this.buttonMask) !== 0) {
        throw new RangeError(`input: 0x${v.toString(16)} uses buttons this schema does not define`);
      }
      out[at] = v;
      return;
    }
    if (!(input instanceof PlayerInput)) {
      throw new RangeError('input: a schema with axes encodes PlayerInput values');
    }
    const b = input.buttons;
    if (!(Number.isInteger(b) && b >= 0 && b <= 0xffffffff) || (b & ~this.buttonMask) !== 0) {
      throw new RangeError(`input: button word ${String(b)} does not fit this schema`);
    }
    out[at] = b;
    for (let w = 1; w < this.words; w++) out[at + w] = 0;
    for (let i = 0; i < this.slots.length; i++) {
      const s = this.slots[i]!;
      const q = input.steps[i]!;
      if (q > s.mask || this.notALevel(i, q))
        throw new RangeError(`input: axis ${this.axes[i]!.name} step ${q} out of range`);
      out[at + s.word] = (out[at + s.word]! | (q << s.shift)) >>> 0;
    }
  }

  decode(words: ArrayLike<number>, at: number): unknown {
    if (this.plain) return words[at]! >>> 0;
    const p = new PlayerInput(this as InputSchema<PlayerInput>);
    p.buttons = words[at]! >>> 0;
    for (let i = 0; i < this.slots.length; i++) {
      const s = this.slots[i]!;
      p.steps[i] = (words[at + s.word]! >>> s.shift) & s.mask;
    }
    return p;
  }

  problem(words: ArrayLike<number>, at: number): string | undefined {
    const b = words[at]! >>> 0;
    if ((b & ~this.buttonMask) !== 0) {
      return `button word 0x${b.toString(16)} sets bits of buttons the game does not define`;
    }
    for (let w = 1; w < this.words; w++) {
      const v = words[at + w]! >>> 0;
      if ((v & ~this.usedBits[w]!) !== 0) {
        return `axis word ${w} 0x${v.toString(16)} sets bits no axis uses`;
      }
    }
    for (let i = 0; i < this.slots.length; i++) {
      const s = this.slots[i]!;
      const q = (words[at + s.word]! >>> s.shift) & s.mask;
      if (this.notALevel(i, q)) {
        return `axis ${this.axes[i]!.name} field 0x${q.toString(16)} is no level of a centred axis`;
      }
    }
    return undefined;
  }

  missing(last: ArrayLike<number>, lastAt: number, out: Uint32Array, outAt: number): void {
    out[outAt] = heldOnly(last[lastAt]!);
    for (let w = 1; w < this.words; w++) out[outAt + w] = last[lastAt + w]!;
  }

  writeAxis(out: Uint32Array, at: number, axis: number, step: number): void {
    const s = this.slots[axis];
    if (
      s === undefined ||
      !(Number.isInteger(step) && step >= 0 && step <= s.mask) ||
      this.notALevel(axis, step)
    ) {
      throw new RangeError(`input: cannot set axis ${String(axis)} to step ${String(step)}`);
    }
    const i = at + s.word;
    out[i] = ((out[i]! & ~(s.mask << s.shift)) | (step << s.shift)) >>> 0;
  }

  neutral(): unknown {
    return this.decode(new Uint32Array(this.words), 0);
  }

  quantise(axis: number, value: number): number {
    const a = this.axisSpec(axis);
    const top = a.bits === 32 ? 0xffffffff : (1 << a.bits) - 1;
    if (!Number.isFinite(value)) return 0;
    if (a.kind === 'angle') {
      const n = top + 1;
      const turns = (value + Math.PI) / TWO_PI;
      const q = Math.round((turns - Math.floor(turns)) * n);
      return q >= n ? 0 : q;
    }
    if (a.kind === 'centred') {
      // Travel from the centre in [−1, 1], the dead zone taken off, rounded half away from the
      // centre (the same both sides), stored in two's complement.
      const half = 1 << (a.bits - 1);
      const radius = (a.max - a.min) / 2; // measured from the centre: −v and v mirror exactly
      const t = pastDeadZone((value - (a.min + radius)) / radius, a.deadZone);
      const k = Math.round(Math.abs(t) * (half - 1));
      return t < 0 && k > 0 ? 2 * half - k : k;
    }
    const t = pastDeadZone((value - a.min) / (a.max - a.min), a.deadZone);
    return t <= 0 ? 0 : t >= 1 ? top : Math.round(t * top);
  }

  value(axis: number, step: number): number {
    const a = this.axisSpec(axis);
    if (a.kind === 'angle')
      return -Math.PI + step * (TWO_PI / (a.bits === 32 ? 4294967296 : 1 << a.bits));
    if (a.kind === 'centred') {
      const half = 1 << (a.bits - 1);
      const k = step >= half ? step - 2 * half : step; // the signed offset from the centre
      if (k === 0) return a.min + (a.max - a.min) / 2;
      if (k >= half - 1) return a.max;
      if (k <= 1 - half) return a.min;
      return a.min + ((k + half - 1) * (a.max - a.min)) / (2 * (half - 1));
    }
    const top = a.bits === 32 ? 0xffffffff : (1 << a.bits) - 1;
    return step >= top ? a.max : a.min + (step * (a.max - a.min)) / top;
  }

  /** Whether `field` is the one bit pattern of centred axis `axis` that is no level. */
  private notALevel(axis: number, field: number): boolean {
    const a = this.axes[axis];
    return a?.kind === 'centred' && field === 1 << (a.bits - 1);
  }

  private axisSpec(axis: number): AxisSpec {
    const a = this.axes[axis];
    if (a === undefined) {
      throw new RangeError(
        `input: axis must be an index from 0 to ${this.axes.length - 1}, got ${String(axis)}`,
      );
    }
    return a;
  }
}

/**
 * The descriptor's layout version. Centred axes did not change it: each axis already carries a
 * kind byte (0 linear, 1 angle; 2 centred, new), so a descriptor of linear and angle axes — every
 * replay and hello written before centred axes — is byte for byte what it was, keeps its id, and
 * decodes with the quantisation it was recorded with; a library that predates centred axes
 * refuses kind 2 by name ("unknown kind 2") rather than misreading it.
 */
const DESCRIPTOR_VERSION = 1;

const KIND_BYTE = { linear: 0, angle: 1, centred: 2 } as const;

// Written by hand rather than with ByteWriter: names are ASCII (checked), every count fits a
// byte, and the input pipeline then stays small in a game's bundle (see bench bundle-size).
function encodeDescriptor(buttons: readonly string[], axes: readonly AxisSpec[]): Uint8Array {
  const out: number[] = [DESCRIPTOR_VERSION, buttons.length];
  const str = (s: string) => {
    out.push(s.length);
    for (let i = 0; i < s.length; i++) out.push(s.charCodeAt(i));
  };
  const f64 = (v: number) => {
    const b = new Uint8Array(8);
    new DataView(b.buffer).setFloat64(0, v === 0 ? 0 : v, true);
    out.push(...b);
  };
  for (const b of buttons) str(b);
  out.push(axes.length);
  for (const a of axes) {
    str(a.name);
    out.push(KIND_BYTE[a.kind], a.bits);
    if (a.kind !== 'angle') {
      f64(a.min);
      f64(a.max);
    }
  }
  return Uint8Array.from(out);
}

/** Most axes a schema may have. */
export const MAX_AXES = 16;

function checkSpec(buttons: readonly string[], axes: readonly AxisSpec[]): void {
  if (buttons.length > MAX_BUTTONS) fail(`at most ${MAX_BUTTONS} buttons, got ${buttons.length}`);
  if (axes.length > MAX_AXES) fail(`at most ${MAX_AXES} axes, got ${axes.length}`);
  const seen = new Set<string>();
  for (const name of [...buttons, ...axes.map((a) => a.name)]) {
    if (typeof name !== 'string' || !NAME.test(name)) {
      fail(`names must be 1-32 of A-Z a-z 0-9 _ - ., got ${JSON.stringify(name)}`);
    }
    if (seen.has(name)) fail(`the name "${name}" is used twice`);
    seen.add(name);
  }
  for (const a of axes) {
    if (!Number.isInteger(a.bits) || a.bits < 1 || a.bits > 16) {
      fail(`axis ${a.name}: bits must be an integer from 1 to 16, got ${String(a.bits)}`);
    }
    if (a.kind === 'angle') continue;
    if (!(Number.isFinite(a.min) && Number.isFinite(a.max) && a.min < a.max)) {
      fail(`axis ${a.name}: needs finite min < max, got ${String(a.min)} and ${String(a.max)}`);
    }
    if (a.kind === 'centred' && a.bits < 2) {
      fail(`axis ${a.name}: a centred axis needs 2 bits or more, got ${a.bits}`);
    }
    if (!(typeof a.deadZone === 'number' && a.deadZone >= 0 && a.deadZone < 1)) {
      fail(`axis ${a.name}: deadZone must be a number in [0, 1), got ${String(a.deadZone)}`);
    }
  }
}

/**
 * Declares an input schema: button names (at most 16) and quantised axes.
 *
 * @example
 * const input = defineInput({ buttons: ['left', 'right', 'jump'] });       // InputSchema<ButtonInput>
 * const twinStick = defineInput({
 *   buttons: ['fire'],
 *   axes: { aim: { angle: 10 }, moveX: { min: -1, max: 1, bits: 8, deadZone: 0.1 } },
 * });                                                                       // InputSchema<PlayerInput>
 * twinStick.axis.aim; // 0 — read it in step() with input.axis(twinStick.axis.aim)
 * new PlayerInput(twinStick).axis(twinStick.axis.moveX); // 0: a centred axis rests at its centre
 */
export function defineInput<B extends string>(
  definition: InputDefinition<B, never> & { readonly axes?: undefined },
): InputSchema & { readonly button: Readonly<Record<B, number>> };
export function defineInput<B extends string, A extends string>(
  definition: InputDefinition<B, A> & { readonly axes: Readonly<Record<A, AxisDefinition>> },
): InputSchema<PlayerInput> & {
  readonly button: Readonly<Record<B, number>>;
  readonly axis: Readonly<Record<A, number>>;
};
export function defineInput(definition: InputDefinition): InputSchema<unknown> {
  const given: unknown = definition; // JavaScript callers may pass anything
  if (typeof given !== 'object' || given === null) fail('expects { buttons, axes }');
  const buttons = [...(definition.buttons ?? [])];
  const axes: AxisSpec[] = [];
  for (const [name, d] of Object.entries<AxisDefinition>(definition.axes ?? {})) {
    if ('angle' in d) {
      axes.push(Object.freeze({ kind: 'angle', name, bits: d.angle }));
      continue;
    }
    const { min, max, bits } = d;
    const centred = d.centred ?? (min === -max && bits >= 2);
    const deadZone = d.deadZone ?? 0;
    axes.push(
      Object.freeze({ kind: centred ? 'centred' : 'linear', name, bits, min, max, deadZone }),
    );
  }
  checkSpec(buttons, axes);
  return new Schema(Object.freeze(buttons), Object.freeze(axes));
}

/**
 * `t`, a travel from rest (in [−1, 1] for a centred axis, [0, 1] for a linear one, or beyond,
 * clamped later), with the dead zone `dz` taken off: 0 within it, the rest stretched to the range.
 */
function pastDeadZone(t: number, dz: number): number {
  const m = Math.min(1, Math.abs(t));
  if (m <= dz) return 0;
  const out = dz === 0 ? m : (m - dz) / (1 - dz);
  return t < 0 ? -out : out;
}

export { BUTTON_WORD } from './button-word.js';

/**
 * The schema a descriptor describes (from a replay header or a hello). Throws a RangeError naming
 * what is wrong with bytes that are not a valid descriptor.
 */
export function inputSchemaFromDescriptor(bytes: Uint8Array): InputSchema<unknown> {
  const bad = (why: string): never => {
    throw new RangeError(`input schema descriptor: ${why}`);
  };
  let pos = 0;
  const u8 = (): number => (pos < bytes.length ? bytes[pos++]! : bad('ends early'));
  const str = (): string => {
    const n = u8();
    if (n > 32 || pos + n > bytes.length) bad('a name runs past the end');
    const s = new TextDecoder('utf-8', { fatal: false }).decode(bytes.subarray(pos, pos + n));
    pos += n;
    return s;
  };
  const f64 = (): number => {
    if (pos + 8 > bytes.length) bad('ends early');
    const v = new DataView(bytes.buffer, bytes.byteOffset + pos, 8).getFloat64(0, true);
    pos += 8;
    return v;
  };
  if (u8() !== DESCRIPTOR_VERSION) bad(`unknown descriptor version ${bytes[0]}`);
  const nb = u8();
  if (nb > MAX_BUTTONS) bad(`${nb} buttons`);
  const buttons: string[] = [];
  for (let i = 0; i < nb; i++) buttons.push(str());
  const na = u8();
  if (na > MAX_AXES) bad(`${na} axes`);
  const axes: AxisSpec[] = [];
  for (let i = 0; i < na; i++) {
    const name = str();
    const kind = u8();
    const bits = u8();
    if (kind === KIND_BYTE.angle) axes.push(Object.freeze({ kind: 'angle', name, bits }));
    else if (kind === KIND_BYTE.linear || kind === KIND_BYTE.centred) {
      const k = kind === KIND_BYTE.linear ? 'linear' : 'centred';
      axes.push(Object.freeze({ kind: k, name, bits, min: f64(), max: f64(), deadZone: 0 }));
    } else bad(`axis ${name} has unknown kind ${kind}`);
  }
  if (pos !== bytes.length) bad(`${bytes.length - pos} bytes left over`);
  try {
    checkSpec(buttons, axes);
  } catch (e) {
    bad((e as Error).message);
  }
  const schema = new Schema(Object.freeze(buttons), Object.freeze(axes));
  // Canonical: the bytes must be exactly what the schema writes (no other spelling of one schema).
  if (
    schema.descriptor.length !== bytes.length ||
    schema.descriptor.some((b, i) => b !== bytes[i])
  ) {
    bad('not canonical');
  }
  return schema;
}
