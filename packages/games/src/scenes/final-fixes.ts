import type { DisplayEvent, Loop, OverloadPolicy } from 'fixedstep';
import { BallScene } from './ball.js';
import { defaultBallScript } from './loop-rig.js';
import { makeLoop, type LoopSpec, type ScriptedInput } from './loops.js';
import { SceneRig } from './movement-rig.js';

/** The talk's TIME_STEP, ms. */
export const FINAL_STEP_MS = 30;

/**
 * A frame with more work than this is one the page could not run: the browser would offer to
 * kill it. The rigs here run at most this much work per frame and count the rest as owed.
 */
export const STALL_WORK_MS = 5000;

/** The three loops of the spiral-of-death comparison. */
export type SpiralLoop = 'noclamp' | 'clamp' | 'fixed';
/** The four loops of the backwards-clock comparison. */
export type BackwardsLoop = 'variable' | 'naive' | 'final' | 'fixed';

/** How to build each loop: the slides' accumulator, with the final fixes, and FixedLoop. */
export function spiralLoopSpec(loop: SpiralLoop, overload: OverloadPolicy = 'drop'): LoopSpec {
  switch (loop) {
    case 'noclamp':
      return { kind: 'fixed-naive', stepMs: FINAL_STEP_MS };
    case 'clamp':
      return { kind: 'fixed-final', stepMs: FINAL_STEP_MS };
    case 'fixed':
      return { kind: 'fixed', stepMs: FINAL_STEP_MS, fixed: { overload } };
  }
}

export function backwardsLoopSpec(loop: BackwardsLoop): LoopSpec {
  switch (loop) {
    case 'variable':
      return { kind: 'variable' };
    case 'naive':
      return { kind: 'fixed-naive', stepMs: FINAL_STEP_MS };
    case 'final':
      return { kind: 'fixed-final', stepMs: FINAL_STEP_MS };
    case 'fixed':
      return { kind: 'fixed', stepMs: FINAL_STEP_MS };
  }
}

/** The ball script of chapter 1 repeated every `periodMs` up to `untilMs`. */
export function repeatedBallScript(periodMs: number, untilMs: number): ScriptedInput[] {
  const base = defaultBallScript();
  const out: ScriptedInput[] = [];
  for (let t0 = 0; t0 < untilMs; t0 += periodMs) {
    for (const e of base) out.push({ ...e, timeMs: t0 + e.timeMs });
  }
  return out;
}

/**
 * A wall clock that jumps back by `backMs` at each of `atMs` (display times): what a loop sees
 * when it reads `Date.now()` and the system clock is corrected, or a buggy timer source.
 */
export function jumpingClock(atMs: readonly number[], backMs: number): (t: number) => number {
  const at = [...atMs].sort((a, b) => a - b);
  return (t) => {
    let back = 0;
    for (const a of at) if (t >= a) back += backMs;
    return t - back;
  };
}

export interface SpiralOptions {
  loop: SpiralLoop;
  /** What one update costs on this machine, ms. */
  updateCostMs: number;
  /** FixedLoop's overload policy. Default 'drop'. */
  overload?: OverloadPolicy;
  /** Display rate. Default 60. */
  hz?: number;
  /** Hitches (no frames for a while). */
  events?: readonly DisplayEvent[];
  script?: readonly ScriptedInput[];
}

/**
 * The spiral-of-death scene builder: the chapter 1 ball on a slow machine under one of the three
 * loops. The display waits for every update the loop asks for — as a real page would — but the
 * rig runs at most {@link STALL_WORK_MS} of them per frame and counts the rest as owed, so even a
 * loop in a spiral is cheap to simulate.
 */
export function spiralRig(options: SpiralOptions): SceneRig<BallScene> {
  const loop: Loop = makeLoop(spiralLoopSpec(options.loop, options.overload));
  return new SceneRig({
    loop,
    display: { hz: options.hz ?? 60, events: options.events ?? [] },
    scene: new BallScene(),
    script: options.script ?? repeatedBallScript(8000, 120_000),
    updateCostMs: options.updateCostMs,
    stallGuard: Math.max(1, Math.floor(STALL_WORK_MS / Math.max(options.updateCostMs, 1e-9))),
  });
}

export interface BackwardsOptions {
  loop: BackwardsLoop;
  /** Display times at which the clock jumps back. */
  jumpsAtMs: readonly number[];
  /** How far it jumps back each time, ms. */
  backMs: number;
  /** Display rate. Default 60. */
  hz?: number;
  script?: readonly ScriptedInput[];
}

/** The backwards-clock scene builder: the ball under one loop, reading a clock that jumps back. */
export function backwardsRig(options: BackwardsOptions): SceneRig<BallScene> {
  return new SceneRig({
    loop: backwardsLoopSpec(options.loop),
    display: { hz: options.hz ?? 60 },
    scene: new BallScene(),
    script: options.script ?? repeatedBallScript(8000, 120_000),
    clock: jumpingClock(options.jumpsAtMs, options.backMs),
  });
}
