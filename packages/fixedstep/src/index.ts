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
export { ButtonSampler, attachKeyboard, isDown, wasPressed, packButtons } from './sim/input.js';
export type { ButtonInput } from './sim/input.js';
export { Runner } from './sim/runner.js';
export type { RunnerOptions } from './sim/runner.js';
export { SimulatedDisplay } from './time/display.js';
export type { SimulatedDisplayOptions, DisplayEvent, DisplayFrame } from './time/display.js';
export type { Simulation } from './sim/simulation.js';
export { runForHash, snapshotRoundTrip, hashTrace, hex64 } from './testing/index.js';
export type { RoundTripResult } from './testing/index.js';
export * from './det/index.js';
export * from './physics/index.js';
export * from './replay/index.js';
export * from './net/index.js';
