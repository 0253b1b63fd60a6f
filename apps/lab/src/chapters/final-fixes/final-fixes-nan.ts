/**
 * Chapter 8's note on a NaN frame: the talk's final loop, translated word for word to JavaScript,
 * stops for good after one frame whose time is NaN, because `Math.max(0, NaN)` is NaN — where the
 * slide's C++ `max(0, dt)` (`a < b ? b : a`) gives 0 and skips the frame. The numbers come from
 * {@link talkLoopTicks} (pure, tested).
 */
import { code, h } from '../../ui/dom.js';
import { textSection } from '../../ui/prose.js';

const TIME_STEP = 0.03;
const MAX_ACCUM_TIME = 1.0;

/** C++'s `std::max(a, b)`: `a < b ? b : a` — with a NaN it returns `a`. */
export function cppMax(a: number, b: number): number {
  return a < b ? b : a;
}

/**
 * The slide's final loop over display frames at `times` (s), with `max` as the language has it;
 * returns the updates run after each frame (cumulative).
 */
export function talkLoopTicks(times: readonly number[], max: (a: number, b: number) => number) {
  let lastUpdateTime = times[0] ?? 0;
  let accumulator = 0;
  let updates = 0;
  const out: number[] = [];
  for (const currentTime of times) {
    const dt = max(0, currentTime - lastUpdateTime);
    lastUpdateTime = currentTime;
    accumulator = Math.min(Math.max(accumulator + dt, 0), MAX_ACCUM_TIME); // clamp
    while (accumulator > TIME_STEP) {
      updates++;
      accumulator -= TIME_STEP;
    }
    out.push(updates);
  }
  return out;
}

/** One second of a 60 Hz display (61 readings, 0 to 1 s); the reading at 10/60 s is NaN. */
export function nanFrames(): number[] {
  return Array.from({ length: 61 }, (_, k) => (k === 10 ? Number.NaN : k / 60));
}

export function nanSection(): HTMLElement {
  const frames = nanFrames();
  const js = talkLoopTicks(frames, Math.max);
  const cpp = talkLoopTicks(frames, cppMax);
  const jsEnd = js[js.length - 1] ?? 0;
  const cppEnd = cpp[cpp.length - 1] ?? 0;
  return textSection(
    'nan',
    'nan-title',
    'One NaN frame: the talk’s loop in JavaScript',
    'Word for word, the final loop in JavaScript is:',
    code(
      'dt = Math.max(0, currentTime - lastUpdateTime);\nlastUpdateTime = currentTime;\naccumulator = Math.min(Math.max(accumulator + dt, 0), MAX_ACCUM_TIME);\nwhile (accumulator > TIME_STEP) { update(TIME_STEP); accumulator -= TIME_STEP; }',
    ),
    h(
      'p',
      { 'data-testid': 'nan-text', 'data-value': `${jsEnd} ${cppEnd}` },
      `Give it one second of a 60 Hz display whose reading at 10/60 s is NaN. Math.max(0, NaN) is NaN, so the accumulator becomes NaN; NaN > TIME_STEP is false and every sum with NaN is NaN: the loop runs ${jsEnd} updates, all before the bad frame, and never another. The slide’s C++ max(0, dt) is a < b ? b : a, and 0 < NaN is false, so it gives 0: that frame is skipped and the second ends at ${cppEnd} updates. FixedLoop counts a non-finite reading and treats it as no time (loop.invalidFrames), like the C++.`,
    ),
  );
}
