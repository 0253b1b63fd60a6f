/**
 * InterpolationBuffer: blending 10,000 bodies per display frame, against the plain loop a user
 * would write over two Float64Arrays, and what it allocates (nothing).
 */
import { InterpolationBuffer, Random } from 'fixedstep';
import type { Candidate } from '../lib/measure.js';
import { defineSuite } from '../lib/suite.js';

const SEED = 5;

/** The positions of `bodies` bodies after two ticks, and an alpha per frame. */
function makeWorld(bodies: number) {
  const rng = new Random(SEED);
  const prev = new Float64Array(bodies * 2);
  const curr = new Float64Array(bodies * 2);
  for (let i = 0; i < bodies * 2; i++) {
    prev[i] = rng.range(-100, 100);
    curr[i] = prev[i]! + rng.range(-1, 1);
  }
  const alphas = new Float64Array(1024);
  for (let i = 0; i < alphas.length; i++) alphas[i] = rng.next();
  return { prev, curr, alphas };
}

/** The baseline: `out[i] = prev[i] + (curr[i] − prev[i]) × alpha` over plain arrays. */
function handWritten(bodies: number): Candidate {
  const { prev, curr, alphas } = makeWorld(bodies);
  const out = new Float64Array(bodies * 2);
  let f = 0;
  return {
    name: 'hand-written lerp',
    run(ops) {
      let sink = 0;
      for (let k = 0; k < ops; k++) {
        const a = alphas[f++ & 1023]!;
        for (let i = 0; i < out.length; i++) out[i] = prev[i]! + (curr[i]! - prev[i]!) * a;
        sink += out[k % out.length]!;
      }
      return sink;
    },
  };
}

function buffer(bodies: number): Candidate {
  const { prev, curr, alphas } = makeWorld(bodies);
  const view = new InterpolationBuffer({ fields: 2, capacity: bodies });
  view.beginTick();
  for (let i = 0; i < bodies; i++) view.store(i, prev[2 * i]!, prev[2 * i + 1]);
  view.beginTick();
  for (let i = 0; i < bodies; i++) view.store(i, curr[2 * i]!, curr[2 * i + 1]);
  let f = 0;
  return {
    name: 'InterpolationBuffer.interpolate',
    run(ops) {
      let sink = 0;
      for (let k = 0; k < ops; k++) {
        const out = view.interpolate(alphas[f++ & 1023]!);
        sink += out[k % out.length]!;
      }
      return sink;
    },
  };
}

/** A tick's bookkeeping: beginTick, then a store per body. */
function tick(bodies: number): Candidate {
  const { curr } = makeWorld(bodies);
  const view = new InterpolationBuffer({ fields: 2, capacity: bodies });
  return {
    name: 'beginTick + store × N',
    run(ops) {
      for (let k = 0; k < ops; k++) {
        view.beginTick();
        for (let i = 0; i < bodies; i++) view.store(i, curr[2 * i]!, curr[2 * i + 1]);
      }
      return view.out.length;
    },
  };
}

export default defineSuite({
  name: 'interpolation',
  description:
    'InterpolationBuffer: 10,000 bodies blended per frame vs a hand-written lerp; bytes allocated',
  run(ctx) {
    const bodies = ctx.quick ? 2000 : 10_000;
    // Same work: the buffer's output equals the hand-written lerp, bit for bit.
    const { prev, curr } = makeWorld(bodies);
    const view = new InterpolationBuffer({ fields: 2, capacity: bodies });
    view.beginTick();
    for (let i = 0; i < bodies; i++) view.store(i, prev[2 * i]!, prev[2 * i + 1]);
    view.beginTick();
    for (let i = 0; i < bodies; i++) view.store(i, curr[2 * i]!, curr[2 * i + 1]);
    const got = view.interpolate(0.375);
    for (let i = 0; i < bodies * 2; i++) {
      if (got[i] !== prev[i]! + (curr[i]! - prev[i]!) * 0.375) {
        throw new Error(`interpolation differs from the plain lerp at ${i}`);
      }
    }
    ctx.note(`${bodies} bodies × 2 fields (x, y); one op = one display frame`);
    const frame = ctx.compare('Time per frame', [handWritten(bodies), buffer(bodies)], {
      unit: 'frame',
    });
    const perBody = frame.candidates.map((c) => [c.name, (c.ns.median / bodies).toFixed(2)]);
    ctx.table('Nanoseconds per body per frame', ['candidate', 'ns/body'], perBody);
    ctx.compare('Time per tick (bookkeeping)', [tick(bodies)], { unit: 'tick' });
    ctx.allocation('Heap allocated per frame', [buffer(bodies)], { unit: 'frame' });
  },
});
