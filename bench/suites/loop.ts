/**
 * The cost per display frame of the production loop, against the smallest loop that does the same
 * job: the talk's accumulator written by hand.
 *
 * Every candidate eats the same precomputed frames (144 Hz ± 30 % jitter, from a seeded Random)
 * with a 60 Hz tick, runs the due updates (empty: they only count) and reads alpha for the render.
 * So the difference is the loop's own bookkeeping: integer time, the clamp, the cap and policies,
 * the counters, input sampling.
 */
import { InputSampler, FixedLoop, Random, FrameStepper } from 'fixedstep';
import type { Candidate } from '../lib/suite.js';
import { formatBytes } from '../lib/format.js';
import { ALLOCATION_NOISE_BYTES } from '../lib/report.js';
import { defineSuite } from '../lib/suite.js';

const TICK_HZ = 60;
const DISPLAY_HZ = 144;
const JITTER = 0.3;
const SEED = 0x5eed;
/** Frames in the sequence (a power of two: candidates wrap around it with a mask). */
const FRAMES = 4096;
const MASK = FRAMES - 1;
/** On average one button event per this many frames, for the FrameStepper with a InputSampler. */
const FRAMES_PER_EVENT = 8;
const BUTTONS = 4;

const STEP_MS = 1000 / TICK_HZ;
/** The hand-written loop's clamp: FixedLoop's default `maxAccumulatorMs`. */
const MAX_ACC_MS = 250;

/** The frames every candidate eats, and the input events between them. */
interface Frames {
  /** Frame Δt, in ms. */
  readonly dt: Float64Array;
  /** Clock reading at the end of each frame, in ms: the running sum of `dt`. */
  readonly at: Float64Array;
  /** Clock reading after the whole sequence: the offset added on each wrap-around. */
  readonly total: number;
  /** An event before frame i (at a time inside it), or NaN for none. */
  readonly eventAt: Float64Array;
  readonly eventButton: Uint8Array;
  /** 1 for a press, 0 for a release. */
  readonly eventDown: Uint8Array;
}

function makeFrames(seed: number): Frames {
  const rng = new Random(seed);
  const period = 1000 / DISPLAY_HZ;
  const dt = new Float64Array(FRAMES);
  const at = new Float64Array(FRAMES);
  const eventAt = new Float64Array(FRAMES).fill(NaN);
  const eventButton = new Uint8Array(FRAMES);
  const eventDown = new Uint8Array(FRAMES);
  let held = 0;
  let t = 0;
  for (let i = 0; i < FRAMES; i++) {
    const d = period * (1 + JITTER * (2 * rng.next() - 1));
    dt[i] = d;
    if (rng.int(FRAMES_PER_EVENT) === 0) {
      const b = rng.int(BUTTONS);
      eventAt[i] = t + d * rng.next();
      eventButton[i] = b;
      eventDown[i] = (held >> b) & 1 ? 0 : 1;
      held ^= 1 << b;
    }
    t += d;
    at[i] = t;
  }
  return { dt, at, total: t, eventAt, eventButton, eventDown };
}

/** A candidate that also says how many updates it has run (to check all do the same work). */
interface LoopCandidate extends Candidate {
  ticks(): number;
}

/**
 * Where a candidate keeps what persists from frame to frame. An object's fields, not closure
 * variables: V8 boxes a float stored in a closure variable (an allocation per write), while an
 * object field holding floats is updated in place. A game keeps its loop state in one too.
 */
class State {
  /** The hand-written loop's accumulator, in ms. */
  acc = 0.5;
  /** Position in the frame sequence. */
  i = 0;
  /** Clock offset of the current pass over the sequence, in ms. */
  base = 0.5;
  /** Updates run. */
  ticks = 0;
  /** XOR of the inputs the updates received. */
  inputs = 0;
  /** Sum of the alphas rendered. */
  alphas = 0.5;
  /** What `run` returns: derived from all the work, so none of it can be discarded. */
  result(): number {
    return this.ticks + this.inputs + this.alphas;
  }
}

/** `acc += dt; clamp; while (acc >= STEP) { update(); acc -= STEP; }`, then alpha. */
function handWritten(f: Frames): LoopCandidate {
  const dt = f.dt;
  const s = new State();
  const update = () => {
    s.ticks++;
  };
  return {
    name: 'hand-written accumulator',
    ticks: () => s.ticks,
    run(ops) {
      for (let k = 0; k < ops; k++) {
        s.acc += dt[s.i]!;
        s.i = (s.i + 1) & MASK;
        if (s.acc > MAX_ACC_MS) s.acc = MAX_ACC_MS;
        while (s.acc >= STEP_MS) {
          update();
          s.acc -= STEP_MS;
        }
        s.alphas += s.acc / STEP_MS;
      }
      return s.result();
    },
  };
}

/** `FixedLoop.advance(dt)`, the due updates, then `loop.alpha`. */
function fixedAdvance(f: Frames): LoopCandidate {
  const dt = f.dt;
  const loop = new FixedLoop({ step: TICK_HZ });
  const s = new State();
  const update = () => {
    s.ticks++;
  };
  return {
    name: 'FixedLoop.advance',
    ticks: () => s.ticks,
    run(ops) {
      for (let k = 0; k < ops; k++) {
        const n = loop.advance(dt[s.i]!);
        s.i = (s.i + 1) & MASK;
        for (let j = 0; j < n; j++) update();
        s.alphas += loop.alpha;
      }
      return s.result();
    },
  };
}

/** `FixedLoop.frame(now)` from clock readings, the due updates, then `loop.alpha`. */
function fixedFrame(f: Frames): LoopCandidate {
  const at = f.at;
  const loop = new FixedLoop({ step: TICK_HZ });
  const s = new State();
  const update = () => {
    s.ticks++;
  };
  return {
    name: 'FixedLoop.frame',
    ticks: () => s.ticks,
    run(ops) {
      for (let k = 0; k < ops; k++) {
        const n = loop.frame(s.base + at[s.i]!);
        s.i = (s.i + 1) & MASK;
        if (s.i === 0) s.base += f.total;
        for (let j = 0; j < n; j++) update();
        s.alphas += loop.alpha;
      }
      return s.result();
    },
  };
}

/**
 * The whole per-frame path of a game: button events pushed into a InputSampler as they happen,
 * then `FrameStepper.frame(now)`: the loop, one sampled input per update, the render callback.
 */
function runnerWithInput(f: Frames): LoopCandidate {
  const { at, eventAt, eventButton, eventDown } = f;
  const sampler = new InputSampler();
  const s = new State();
  const runner = new FrameStepper({
    loop: new FixedLoop({ step: TICK_HZ }),
    update: (_dt, input) => {
      s.ticks++;
      s.inputs ^= input;
    },
    render: (alpha) => {
      s.alphas += alpha;
    },
    input: sampler,
  });
  return {
    name: 'FrameStepper + InputSampler',
    ticks: () => s.ticks,
    run(ops) {
      for (let k = 0; k < ops; k++) {
        const e = eventAt[s.i]!;
        if (e === e) sampler.push(s.base + e, eventButton[s.i]!, eventDown[s.i] === 1);
        runner.frame(s.base + at[s.i]!);
        s.i = (s.i + 1) & MASK;
        if (s.i === 0) s.base += f.total;
      }
      return s.result();
    },
  };
}

/** Allocates one small object per frame, kept alive for a while: proves the check can see it. */
function allocatingControl(f: Frames): Candidate {
  const base = handWritten(f);
  const ring = new Array<{ k: number }>(256);
  let n = 0;
  return {
    name: 'control: + 1 object/frame',
    run(ops) {
      for (let k = 0; k < ops; k++) ring[n++ & 255] = { k };
      return base.run(ops) + ring.length;
    },
  };
}

const FACTORIES = [handWritten, fixedAdvance, fixedFrame, runnerWithInput];

export default defineSuite({
  name: 'loop',
  description: 'FixedLoop overhead per frame vs a hand-written accumulator (empty update)',
  run(ctx) {
    const frames = makeFrames(SEED);

    // Same work: from scratch, over the same frames, every candidate runs the same updates (the
    // hand-written loop sums floats, FixedLoop integers: allow one tick of rounding difference).
    const checkFrames = 4 * FRAMES;
    const counts = FACTORIES.map((make) => {
      const c = make(frames);
      c.run(checkFrames);
      return { name: c.name, ticks: c.ticks() };
    });
    const expected = counts[0]!.ticks;
    const off = counts.filter((c) => Math.abs(c.ticks - expected) > 1);
    if (off.length > 0) {
      throw new Error(
        `candidates disagree on the work: ${counts.map((c) => `${c.name} ${c.ticks}`).join(', ')}`,
      );
    }
    const eventCount = frames.eventAt.filter((t) => t === t).length;
    ctx.note(
      `${FRAMES} frames at ${DISPLAY_HZ} Hz ± ${JITTER * 100} % (seed ${SEED}), tick ${TICK_HZ} Hz, ` +
        `${eventCount} button events for the FrameStepper; all candidates run ${expected} ` +
        `updates per ${checkFrames} frames (±1)`,
    );

    const candidates = FACTORIES.map((make) => make(frames));
    ctx.compare('Time per display frame', candidates, { unit: 'frame' });
    const alloc = ctx.allocation(
      'Heap allocated per display frame',
      [...candidates, allocatingControl(frames)],
      { unit: 'frame' },
    );
    const allocating = alloc.candidates
      .slice(1, candidates.length)
      .filter((c) => c.bytes.median * alloc.opsPerChunk >= ALLOCATION_NOISE_BYTES);
    if (allocating.length > 0) {
      ctx.note(
        `${allocating.map((c) => `${c.name} ${formatBytes(c.bytes.median)}`).join(', ')} B/frame: ` +
          `16 B is one boxed float. V8 passes a float argument (a clock reading, alpha) to a call ` +
          `it does not inline as a new heap number, and what it inlines depends on its budget. ` +
          `If the row drops to 0 with node --expose-gc --max-inlined-bytecode-size-cumulative=3000 ` +
          `--import tsx bench/run.ts loop, the library itself allocates nothing.`,
      );
    }
  },
});
