/**
 * Simulation: the contract a game implements ({@link Simulation}, {@link defineGame}), its input
 * (button words, input schemas with axes, samplers that quantise device events into steps), the
 * frame stepper, render-side interpolation and correction smoothing, and the guards that catch
 * a step reading a clock or `Math.random`.
 * @module
 */
export {
  MAX_BUTTONS,
  PRESSED_SHIFT,
  DOWN_MASK,
  downBit,
  pressedBit,
  anyBit,
  isDown,
  wasPressed,
  packButtons,
  downMask,
  pressedMask,
  heldOnly,
  interleave,
  deinterleave,
} from './buttons.js';
export type { ButtonInput } from './buttons.js';
export {
  defineInput,
  inputSchemaFromDescriptor,
  BUTTON_WORD,
  MAX_AXES,
  PlayerInput,
} from './input-schema.js';
export type {
  InputSchema,
  InputDefinition,
  AxisDefinition,
  AxisSpec,
  LinearAxisSpec,
  CentredAxisSpec,
  AxisDeadZone,
  AngleAxisSpec,
} from './input-schema.js';
export { InputSampler, ButtonSampler } from './input.js';
export { FrameStepper } from './stepper.js';
export type { FrameStepperOptions } from './stepper.js';
export { InterpolationBuffer } from './interpolation.js';
export { CorrectionSmoother } from './smoothing.js';
export type { CorrectionSmootherOptions } from './smoothing.js';
export { defineGame, gameOptions, gameSetup, findGameById } from './game.js';
export type { GameDefinition, GameSetup, AnyGameDefinition } from './game.js';
export type { Simulation } from './simulation.js';
export { defineStateSchema, readStateValue, StateSchema } from './state-schema.js';
export type {
  StateSchemaDefinition,
  StateColumn,
  StateColumnType,
  StateColumnCount,
  StateGroup,
  SentColumn,
  QuantiseReport,
  StateLocation,
} from './state-schema.js';
export { guardStep, guardSimulation } from './guard.js';
