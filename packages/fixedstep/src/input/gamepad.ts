import type { InputSampler } from '../sim/input.js';
import { buttonIndex } from './keyboard.js';

/** The part of a `Gamepad` the gamepad adapter reads. */
export interface GamepadLike {
  readonly connected: boolean;
  readonly buttons: readonly { readonly pressed: boolean }[];
  readonly axes: readonly number[];
}

/** Where gamepads come from: `navigator`. */
export interface GamepadHost {
  getGamepads(): readonly (GamepadLike | null)[];
}

/** How a gamepad's controls map to a schema. Buttons and axes by schema name or index. */
export interface GamepadBinding {
  /** Gamepad button index (standard mapping: 0 = A, 12–15 = d-pad) → schema button. */
  buttons?: Readonly<Record<number, string | number>>;
  /** Gamepad axis index (standard mapping: 0/1 left stick x/y, 2/3 right stick) → schema linear axis. */
  axes?: Readonly<Record<number, string | number>>;
  /** A stick (two gamepad axes) as an angle axis, e.g. `{ x: 2, y: 3, axis: 'aim' }` for the right stick. */
  angle?: { readonly x: number; readonly y: number; readonly axis: string | number };
  /** Stick directions as buttons (left stick, past the dead zone). */
  stickButtons?: {
    readonly x: number;
    readonly y: number;
    readonly left?: string | number;
    readonly right?: string | number;
    readonly up?: string | number;
    readonly down?: string | number;
  };
}

/** Options of {@link gamepadPoller}. */
export interface GamepadOptions {
  /** Which gamepad (index into `getGamepads()`). Default: the first connected one. */
  pad?: number;
  /** Stick deflection below this counts as centred. Default 0.25. */
  deadZone?: number;
}

/**
 * Gamepads have no events: this returns a `poll(timeMs)` to call once per display frame, before
 * the loop runs the frame's ticks, with the frame's timestamp. Each change since the last poll
 * becomes a sampler event at that time, so a press is seen by exactly one tick like a key (but it
 * is only as precise as the frame rate: that is the device, not the loop).
 */
export function gamepadPoller(
  host: GamepadHost,
  sampler: InputSampler<unknown>,
  binding: GamepadBinding,
  options: GamepadOptions = {},
): (timeMs: number) => void {
  const schema = sampler.schema;
  const axisIndex = (a: string | number): number => {
    const i = typeof a === 'number' ? a : schema.axis[a];
    if (i === undefined || !Number.isInteger(i) || i < 0 || i >= schema.axes.length) {
      throw new RangeError(`gamepadPoller: unknown axis ${JSON.stringify(a)}`);
    }
    return i;
  };
  const buttons = Object.entries(binding.buttons ?? {}).map(
    ([pad, b]) => [Number(pad), buttonIndex(sampler, b)] as const,
  );
  const axes = Object.entries(binding.axes ?? {}).map(
    ([pad, a]) => [Number(pad), axisIndex(a)] as const,
  );
  const angle = binding.angle && { ...binding.angle, index: axisIndex(binding.angle.axis) };
  const sb = binding.stickButtons;
  const dirs = sb
    ? ([sb.left, sb.right, sb.up, sb.down] as const).map((b) =>
        b === undefined ? -1 : buttonIndex(sampler, b),
      )
    : [];
  const deadZone = options.deadZone ?? 0.25;
  const down = new Map<number, boolean>();
  const steps = new Map<number, number>();

  const setButton = (b: number, on: boolean, t: number) => {
    if ((down.get(b) ?? false) === on) return;
    down.set(b, on);
    sampler.push(t, b, on);
  };
  const setAxis = (a: number, value: number, t: number) => {
    const q = schema.quantise(a, value);
    if (steps.get(a) === q) return;
    steps.set(a, q);
    sampler.setAxis(t, a, value);
  };
  const centred = (v: number | undefined) =>
    v === undefined || !Number.isFinite(v) || Math.abs(v) < deadZone ? 0 : v;

  return (timeMs: number) => {
    const pads = host.getGamepads();
    const pad =
      options.pad !== undefined ? pads[options.pad] : pads.find((p) => p?.connected === true);
    const live = pad?.connected === true ? pad : undefined;
    // A pad that disconnects releases everything it held.
    const pressed = (pb: number) => live?.buttons[pb]?.pressed === true;
    for (const [pb, b] of buttons) setButton(b, pressed(pb), timeMs);
    for (const [pa, a] of axes) setAxis(a, centred(live?.axes[pa]), timeMs);
    if (angle && live) {
      const x = centred(live.axes[angle.x]);
      const y = centred(live.axes[angle.y]);
      if (x !== 0 || y !== 0) setAxis(angle.index, Math.atan2(y, x), timeMs);
    }
    if (sb) {
      const x = centred(live?.axes[sb.x]);
      const y = centred(live?.axes[sb.y]);
      const on = [x < 0, x > 0, y < 0, y > 0];
      dirs.forEach((b, k) => {
        if (b >= 0) setButton(b, on[k]!, timeMs);
      });
    }
  };
}
