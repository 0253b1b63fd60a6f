/**
 * Driving a simulation from a simulated display: the fixed loop turns frame times (any rate,
 * jitter, hitches) into ticks, and a {@link ButtonSampler} per player turns timestamped button
 * events into per-tick inputs. With no time dropped, the ticks and their inputs — and so the
 * per-tick states — are the same at every display rate. The catalogue checks exactly that.
 */
import {
  ButtonSampler,
  FixedLoop,
  MAX_BUTTONS,
  downBit,
  downMask,
  pressedMask,
  SimulatedDisplay,
  Timestep,
  type DisplayEvent,
  type SimulatedDisplayOptions,
} from 'fixedstep';
import type { TraceRun } from './trace.js';

/** A button going down or up at a real time, ms from the start (the shape of `ScriptedInput`). */
export interface TraceButtonEvent {
  readonly timeMs: number;
  /** 0–15. */
  readonly button: number;
  readonly down: boolean;
}

/** The display rates every display-rate scene is traced at, Hz. */
export const TRACE_DISPLAY_RATES: readonly number[] = Object.freeze([30, 59.94, 60, 144, 240]);

/** Frame-to-frame jitter of the display-rate scenes: ±30 % of the period. */
export const TRACE_DISPLAY_JITTER = 0.3;

/**
 * Hitches of the display-rate scenes (no frame for a while). The longest is 400 ms: the loop's
 * accumulator is clamped at 1000 ms (the talk's MAX_ACCUM_TIME), so no time is dropped and the
 * catch-up (at most 8 steps a frame) spreads over the following frames.
 */
export const TRACE_DISPLAY_HITCHES: readonly DisplayEvent[] = Object.freeze([
  { kind: 'hitch', atMs: 2_050, durationMs: 120 },
  { kind: 'hitch', atMs: 7_310, durationMs: 400 },
  { kind: 'hitch', atMs: 31_000, durationMs: 250 },
]);

/** The accumulator clamp of the display-rate scenes' loop, ms. */
export const TRACE_MAX_ACCUMULATOR_MS = 1000;

/** The simulated display of one rate: jittered, with the hitches; the seed depends on the rate. */
export function traceDisplay(hz: number): SimulatedDisplayOptions {
  return {
    hz,
    jitter: TRACE_DISPLAY_JITTER,
    seed: 1000 + Math.round(hz * 100),
    events: [...TRACE_DISPLAY_HITCHES],
  };
}

/** A short label for a rate: `59.94hz`. */
export function rateLabel(hz: number): string {
  return `${String(hz)}hz`;
}

/** The fixed step of a game or scene from its seconds per step (integer rates kept exact). */
export function timestepOf(stepSeconds: number, tickRate?: number): Timestep {
  if (tickRate !== undefined && Number.isInteger(tickRate) && tickRate * stepSeconds === 1) {
    return Timestep.fromHz(tickRate);
  }
  const hz = 1 / stepSeconds;
  if (Math.abs(hz - Math.round(hz)) < 1e-9) return Timestep.fromHz(Math.round(hz));
  return Timestep.fromMs(stepSeconds * 1000);
}

/** Options of {@link displayRun}. */
export interface DisplayRunOptions {
  step: Timestep;
  display: SimulatedDisplayOptions;
  /** One script per player (sorted by time); none for a scene without inputs. */
  scripts: readonly (readonly TraceButtonEvent[])[];
  /** One fixed step with one input per player; returns the state bytes after it. */
  advance: (inputs: readonly number[]) => Uint8Array;
}

/**
 * A {@link TraceRun} whose ticks come from a fixed loop fed by a simulated display. Throws if the
 * loop ever drops time (the clamp or the overload policy): the display would then change which
 * tick an input lands in, and the scene would be testing its own set-up, not the library.
 */
export function displayRun(options: DisplayRunOptions): TraceRun {
  const loop = new FixedLoop({
    step: options.step,
    maxAccumulatorMs: TRACE_MAX_ACCUMULATOR_MS,
  });
  const display = new SimulatedDisplay(options.display);
  const start = display.now;
  const scripts = options.scripts;
  const samplers = scripts.map(() => new ButtonSampler());
  const cursors = scripts.map(() => 0);
  const inputs = scripts.map(() => 0);
  const queue: Uint8Array[] = [];
  let head = 0;

  const frame = (): void => {
    const t = display.next().time - start;
    for (let p = 0; p < scripts.length; p++) {
      const script = scripts[p]!;
      let i = cursors[p]!;
      while (i < script.length && script[i]!.timeMs <= t) {
        const e = script[i++]!;
        samplers[p]!.push(e.timeMs, e.button, e.down);
      }
      cursors[p] = i;
    }
    const n = loop.frame(t);
    if (loop.droppedUnits() !== 0) {
      throw new Error(
        `display scene at ${String(options.display.hz)} Hz dropped ${String(loop.droppedMs())} ms by ${String(t)} ms: ` +
          'its hitches are too long for its accumulator clamp',
      );
    }
    for (let j = 0; j < n; j++) {
      for (let p = 0; p < samplers.length; p++) inputs[p] = samplers[p]!.sample(loop, j);
      queue.push(options.advance(inputs));
    }
  };

  return {
    next(): Uint8Array {
      while (head === queue.length) {
        queue.length = 0;
        head = 0;
        frame();
      }
      return queue[head++]!;
    },
  };
}

/**
 * Turns per-tick inputs (`ButtonInput`s) into timestamped button events that a {@link ButtonSampler}
 * turns back into them, tick by tick, at any display rate: a press lands at 40 % of its tick, a
 * release at 60 % (or at 20 %, before a new press of a button still held) — in the middle of
 * ticks, far from their boundaries. A button that is down without a press in a tick after one in
 * which it was up (a bot may say "held" from the start) goes down in that tick like a real key,
 * so its sampled input also says "pressed"; {@link sampledInputs} gives exactly what arrives.
 */
export function inputsToScript(inputs: ArrayLike<number>, stepMs: number): TraceButtonEvent[] {
  const out: TraceButtonEvent[] = [];
  let held = 0;
  for (let t = 0; t < inputs.length; t++) {
    const want = inputs[t]! >>> 0;
    const pressed = pressedMask(want);
    const goesDown = pressed | (downMask(want) & ~held);
    const next = t + 1 < inputs.length ? inputs[t + 1]! >>> 0 : 0;
    const keep = downMask(next) & ~pressedMask(next);
    const base = t * stepMs;
    for (let b = 0; b < MAX_BUTTONS; b++) {
      const bit = downBit(b);
      if (pressed & bit && held & bit) {
        out.push({ timeMs: base + 0.2 * stepMs, button: b, down: false });
        held &= ~bit;
      }
    }
    for (let b = 0; b < MAX_BUTTONS; b++) {
      const bit = downBit(b);
      if (goesDown & bit) {
        out.push({ timeMs: base + 0.4 * stepMs, button: b, down: true });
        held |= bit;
      }
    }
    for (let b = 0; b < MAX_BUTTONS; b++) {
      const bit = downBit(b);
      if (held & bit && !(keep & bit)) {
        out.push({ timeMs: base + 0.6 * stepMs, button: b, down: false });
        held &= ~bit;
      }
    }
  }
  return out;
}

/** The per-tick inputs a {@link ButtonSampler} makes of `script`, one tick per step of `stepMs`. */
export function sampledInputs(
  script: readonly TraceButtonEvent[],
  ticks: number,
  stepMs: number,
): Uint32Array {
  const sampler = new ButtonSampler();
  const out = new Uint32Array(ticks);
  let i = 0;
  let end = 0;
  const loop = { isBeforeUpdateEnd: (timeMs: number) => timeMs < end };
  for (let t = 0; t < ticks; t++) {
    end = (t + 1) * stepMs;
    while (i < script.length && script[i]!.timeMs < end) {
      const e = script[i++]!;
      sampler.push(e.timeMs, e.button, e.down);
    }
    out[t] = sampler.sample(loop, 0);
  }
  return out;
}
