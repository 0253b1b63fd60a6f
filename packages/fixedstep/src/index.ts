/**
 * fixedstep — fixed-step, deterministic simulation.
 * @packageDocumentation
 */
export { Timestep } from './time/timestep.js';
export type { Loop, LoopKind } from './time/loop.js';
export { FixedLoop } from './time/fixed-loop.js';
export type { FixedLoopOptions, OverloadPolicy, HiddenPolicy, DropReason } from './time/fixed-loop.js';
export { FrameLockedLoop, VariableLoop, NaiveFixedLoop, FinalFixedLoop } from './time/talk-loops.js';
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
export { Fnv1a64, fnv1a64, fnv1a64Hex } from './det/hash.js';
export { Random } from './det/random.js';
export { SimulatedDisplay } from './time/display.js';
export type { SimulatedDisplayOptions, DisplayEvent, DisplayFrame } from './time/display.js';
