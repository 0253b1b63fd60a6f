/**
 * fixedstep — fixed-step, deterministic simulation.
 * @packageDocumentation
 * @module fixedstep
 */
export { Timestep } from './time/timestep.js';
export type { Loop, LoopKind } from './time/loop.js';
export { FixedLoop } from './time/fixed-loop.js';
export type {
  FixedLoopOptions,
  OverloadPolicy,
  HiddenPolicy,
  DropReason,
  LoopWarning,
} from './time/fixed-loop.js';
export {
  FrameLockedLoop,
  VariableLoop,
  NaiveFixedLoop,
  FinalFixedLoop,
} from './time/talk-loops.js';
export {
  ManualClock,
  performanceClock,
  animationFrameScheduler,
  timerScheduler,
  ManualScheduler,
  FrameDriver,
  trackVisibility,
} from './time/drivers.js';
export type { Clock, FrameCallback, FrameScheduler } from './time/drivers.js';
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
} from './sim/buttons.js';
export type { ButtonInput } from './sim/buttons.js';
export {
  defineInput,
  inputSchemaFromDescriptor,
  BUTTON_WORD,
  MAX_AXES,
  PlayerInput,
} from './sim/input-schema.js';
export type {
  InputSchema,
  InputDefinition,
  AxisDefinition,
  AxisSpec,
  LinearAxisSpec,
  AngleAxisSpec,
} from './sim/input-schema.js';
export { InputSampler, ButtonSampler } from './sim/input.js';
export { FrameStepper } from './sim/stepper.js';
export type { FrameStepperOptions } from './sim/stepper.js';
export { InterpolationBuffer } from './sim/interpolation.js';
export { CorrectionSmoother } from './sim/smoothing.js';
export type { CorrectionSmootherOptions } from './sim/smoothing.js';
export { defineGame, gameOptions, gameSetup, findGameById } from './sim/game.js';
export type { GameDefinition, GameSetup, AnyGameDefinition } from './sim/game.js';
export * from './input/index.js';
export { SimulatedDisplay } from './time/display.js';
export type { SimulatedDisplayOptions, DisplayEvent, DisplayFrame } from './time/display.js';
export type { Simulation } from './sim/simulation.js';
export { guardStep, guardSimulation } from './sim/guard.js';
export { runForHash, snapshotRoundTrip, hashTrace } from './testing/index.js';
export type { RoundTripResult } from './testing/index.js';
export * from './det/index.js';
export * from './physics/index.js';
export * from './replay/index.js';
export * from './net/index.js';
