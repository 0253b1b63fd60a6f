import type { InputSampler } from '../sim/input.js';
import { buttonIndex } from './keyboard.js';

/** The part of a `PointerEvent` the touch adapters read. */
export interface PointerEventLike {
  readonly pointerId: number;
  readonly clientX: number;
  readonly clientY: number;
  readonly timeStamp: number;
  preventDefault(): void;
}

/** An element that takes pointer (mouse, pen, touch) events: an on-screen button or stick. */
export interface PointerTarget {
  addEventListener(
    type: 'pointerdown' | 'pointermove' | 'pointerup' | 'pointercancel' | 'lostpointercapture',
    listener: (e: PointerEventLike) => void,
  ): void;
  removeEventListener(
    type: 'pointerdown' | 'pointermove' | 'pointerup' | 'pointercancel' | 'lostpointercapture',
    listener: (e: PointerEventLike) => void,
  ): void;
  setPointerCapture?(pointerId: number): void;
  getBoundingClientRect(): { left: number; top: number; width: number; height: number };
}

/** One on-screen button: the element and the schema button (name or index) it holds. */
export interface OnScreenButton {
  element: PointerTarget;
  button: string | number;
}

const COS_67_5 = 0.3826834323650898;
const POINTER_EVENTS = ['pointerdown', 'pointerup', 'pointercancel', 'lostpointercapture'] as const;

/**
 * On-screen buttons for touch (and mouse): each element holds its button down while at least one
 * pointer presses it, with the event's timestamp — so a tap reaches exactly one tick, like a key.
 * Several fingers on several buttons work at once. Give the elements `touch-action: none` in CSS
 * so a press never scrolls or zooms the page. Returns a function that detaches them.
 *
 * `timeOf` gives an event's time in ms on the loop's time line (default `event.timeStamp`; see
 * {@link attachKeyboard} for when to pass another).
 */
export function attachButtons(
  sampler: InputSampler<unknown>,
  buttons: readonly OnScreenButton[],
  timeOf: (e: PointerEventLike) => number = (e) => e.timeStamp,
): () => void {
  const detach: (() => void)[] = [];
  for (const { element, button } of buttons) {
    const b = buttonIndex(sampler, button);
    const pointers = new Set<number>();
    const down = (e: PointerEventLike) => {
      e.preventDefault();
      element.setPointerCapture?.(e.pointerId);
      if (pointers.size === 0) sampler.push(timeOf(e), b, true);
      pointers.add(e.pointerId);
    };
    const up = (e: PointerEventLike) => {
      if (!pointers.delete(e.pointerId)) return;
      if (pointers.size === 0) sampler.push(timeOf(e), b, false);
    };
    element.addEventListener('pointerdown', down);
    for (const type of POINTER_EVENTS.slice(1)) element.addEventListener(type, up);
    detach.push(() => {
      element.removeEventListener('pointerdown', down);
      for (const type of POINTER_EVENTS.slice(1)) element.removeEventListener(type, up);
    });
  }
  return () => {
    for (const d of detach) d();
  };
}

/** Which axes and buttons a virtual stick drives. Each is a schema name or index. */
export interface StickBinding {
  /** A linear axis for the horizontal deflection, −1 (left) … 1 (right). */
  x?: string | number;
  /** A linear axis for the vertical deflection, −1 (up) … 1 (down), screen convention. */
  y?: string | number;
  /** An angle axis for the direction of deflection (radians, 0 = right, π/2 = down). */
  angle?: string | number;
  /** Digital directions, pressed while the deflection points that way past `deadZone`. */
  left?: string | number;
  right?: string | number;
  up?: string | number;
  down?: string | number;
  /** A button held while the stick is touched at all (e.g. fire while aiming). */
  active?: string | number;
}

/** Options of {@link attachStick}. */
export interface StickOptions {
  /** Deflection below this fraction of the radius counts as centred. Default 0.2. */
  deadZone?: number;
  /** The stick's radius in CSS pixels. Default: half the element's smaller side. */
  radius?: number;
}

/**
 * A virtual analog stick on an element: the first pointer that presses it drives the bound axes
 * (centred on the element, clamped to the radius) and digital directions; release recentres it.
 * Deflection is computed here, on the device side: the sampler quantises it, so the simulation
 * sees the same integer steps in a replay. Returns a function that detaches it.
 *
 * `timeOf` gives an event's time in ms on the loop's time line (default `event.timeStamp`; see
 * {@link attachKeyboard} for when to pass another).
 */
export function attachStick(
  element: PointerTarget,
  sampler: InputSampler<unknown>,
  binding: StickBinding,
  options: StickOptions = {},
  timeOf: (e: PointerEventLike) => number = (e) => e.timeStamp,
): () => void {
  const schema = sampler.schema;
  const axisIndex = (a: string | number): number => {
    const i = typeof a === 'number' ? a : schema.axis[a];
    if (i === undefined || !Number.isInteger(i) || i < 0 || i >= schema.axes.length) {
      throw new RangeError(`attachStick: unknown axis ${JSON.stringify(a)}`);
    }
    return i;
  };
  const ax = binding.x === undefined ? -1 : axisIndex(binding.x);
  const ay = binding.y === undefined ? -1 : axisIndex(binding.y);
  const aa = binding.angle === undefined ? -1 : axisIndex(binding.angle);
  const dirs = (['left', 'right', 'up', 'down', 'active'] as const).map((k) =>
    binding[k] === undefined ? -1 : buttonIndex(sampler, binding[k]),
  );
  const deadZone = options.deadZone ?? 0.2;
  if (!(deadZone >= 0 && deadZone < 1)) {
    throw new RangeError(`attachStick: deadZone must be from 0 to below 1, got ${deadZone}`);
  }
  const held = [false, false, false, false, false];
  let pointer: number | undefined;

  const setHeld = (k: number, on: boolean, t: number) => {
    const b = dirs[k]!;
    if (b < 0 || held[k] === on) return;
    held[k] = on;
    sampler.push(t, b, on);
  };
  const apply = (dx: number, dy: number, t: number, touching: boolean) => {
    const len = Math.sqrt(dx * dx + dy * dy);
    const live = len > deadZone;
    if (ax >= 0) sampler.setAxis(t, ax, live ? dx : 0);
    if (ay >= 0) sampler.setAxis(t, ay, live ? dy : 0);
    if (aa >= 0 && live) sampler.setAxis(t, aa, Math.atan2(dy, dx));
    // Within 67.5° of a direction counts as that direction: diagonals hold two (8 ways).
    const k = len * COS_67_5;
    setHeld(0, live && -dx > k, t);
    setHeld(1, live && dx > k, t);
    setHeld(2, live && -dy > k, t);
    setHeld(3, live && dy > k, t);
    setHeld(4, touching, t);
  };
  const deflection = (e: PointerEventLike): [number, number] => {
    const r = element.getBoundingClientRect();
    const radius = options.radius ?? Math.min(r.width, r.height) / 2;
    let dx = (e.clientX - (r.left + r.width / 2)) / radius;
    let dy = (e.clientY - (r.top + r.height / 2)) / radius;
    const len = Math.sqrt(dx * dx + dy * dy);
    if (len > 1) {
      dx /= len;
      dy /= len;
    }
    return [dx, dy];
  };
  const down = (e: PointerEventLike) => {
    e.preventDefault();
    if (pointer !== undefined) return;
    pointer = e.pointerId;
    element.setPointerCapture?.(e.pointerId);
    const [dx, dy] = deflection(e);
    apply(dx, dy, timeOf(e), true);
  };
  const move = (e: PointerEventLike) => {
    if (e.pointerId !== pointer) return;
    const [dx, dy] = deflection(e);
    apply(dx, dy, timeOf(e), true);
  };
  const up = (e: PointerEventLike) => {
    if (e.pointerId !== pointer) return;
    pointer = undefined;
    apply(0, 0, timeOf(e), false);
  };
  element.addEventListener('pointerdown', down);
  element.addEventListener('pointermove', move);
  for (const type of POINTER_EVENTS.slice(1)) element.addEventListener(type, up);
  return () => {
    element.removeEventListener('pointerdown', down);
    element.removeEventListener('pointermove', move);
    for (const type of POINTER_EVENTS.slice(1)) element.removeEventListener(type, up);
  };
}
