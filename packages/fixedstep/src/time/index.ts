/**
 * Time: the fixed-step loop ({@link FixedLoop}: the accumulator, render interpolation's alpha,
 * overload and hidden-tab policies, pause, single step and time scale) and the talk's loops that
 * lead to it, the timestep in integer ticks, clocks and frame schedulers (real and manual), and a
 * simulated display for tests and the lab.
 * @module
 */
export { Timestep } from './timestep.js';
export type { Loop, LoopKind } from './loop.js';
export { FixedLoop } from './fixed-loop.js';
export type {
  FixedLoopOptions,
  OverloadPolicy,
  HiddenPolicy,
  DropReason,
  LoopWarning,
} from './fixed-loop.js';
export { FrameLockedLoop, VariableLoop, NaiveFixedLoop, FinalFixedLoop } from './talk-loops.js';
export {
  ManualClock,
  performanceClock,
  animationFrameScheduler,
  timerScheduler,
  ManualScheduler,
  FrameDriver,
  trackVisibility,
} from './drivers.js';
export type { Clock, FrameCallback, FrameScheduler } from './drivers.js';
export { SimulatedDisplay } from './display.js';
export type { SimulatedDisplayOptions, DisplayEvent, DisplayFrame } from './display.js';
