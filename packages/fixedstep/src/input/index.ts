/**
 * Device adapters: keyboard, on-screen touch buttons, a virtual stick and gamepads, each feeding
 * timestamped events into an {@link InputSampler}. This is device code, not simulation code: it
 * may use any math (a stick's angle comes from `Math.atan2`) because what reaches a simulation is
 * the sampler's quantised steps, which replays and the network carry exactly.
 * @module
 */
export { attachKeyboard, buttonIndex } from './keyboard.js';
export type { KeyboardEventLike, KeyboardHost } from './keyboard.js';
export { attachButtons, attachStick } from './pointer.js';
export type {
  OnScreenButton,
  PointerEventLike,
  PointerTarget,
  StickBinding,
  StickOptions,
} from './pointer.js';
export { gamepadPoller } from './gamepad.js';
export type { GamepadBinding, GamepadHost, GamepadLike, GamepadOptions } from './gamepad.js';
