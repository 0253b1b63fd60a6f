import {
  FinalFixedLoop,
  FixedLoop,
  FrameLockedLoop,
  NaiveFixedLoop,
  Timestep,
  VariableLoop,
  type FixedLoopOptions,
  type Loop,
  type LoopKind,
} from 'fixedstep';

/** A scripted button event, at a real time in ms from the start. */
export interface ScriptedInput {
  timeMs: number;
  button: number;
  down: boolean;
}

export interface LoopSpec {
  kind: LoopKind;
  /** Step in ms for the fixed loops (default 1000/60 for 'fixed', 30 — the talk's — otherwise). */
  stepMs?: number;
  /** Options for the production loop. */
  fixed?: Partial<Omit<FixedLoopOptions, 'step'>>;
}

/** Builds one of the five loops. The talk's loops use its TIME_STEP = 0.03 s by default. */
export function makeLoop(spec: LoopSpec): Loop {
  switch (spec.kind) {
    case 'frame-locked':
      return new FrameLockedLoop(60);
    case 'variable':
      return new VariableLoop();
    case 'fixed-naive':
      return new NaiveFixedLoop(spec.stepMs ?? 30);
    case 'fixed-final':
      return new FinalFixedLoop(spec.stepMs ?? 30);
    case 'fixed':
      return new FixedLoop({
        ...spec.fixed,
        step: spec.stepMs === undefined ? 60 : stepFromMs(spec.stepMs),
      });
  }
}

/** 1000/60-style steps become a tick rate, so they stay exact; others a whole number of ns. */
function stepFromMs(ms: number): Timestep {
  const hz = 1000 / ms;
  return Math.abs(hz - Math.round(hz)) < 1e-9
    ? Timestep.fromHz(Math.round(hz))
    : Timestep.fromMs(ms);
}
