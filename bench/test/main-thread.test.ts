import { describe, expect, it } from 'vitest';
import { mainThreadWork, type TraceEvent } from '../lib/main-thread.js';

/** A complete event on the renderer's main thread (pid 1, tid 7), times in ms. */
const x = (name: string, fromMs: number, toMs: number, tid = 7): TraceEvent => ({
  name,
  ph: 'X',
  pid: 1,
  tid,
  ts: fromMs * 1000,
  dur: (toMs - fromMs) * 1000,
});

const META: TraceEvent[] = [
  { name: 'thread_name', ph: 'M', pid: 1, tid: 7, ts: 0, args: { name: 'CrRendererMain' } },
  { name: 'thread_name', ph: 'M', pid: 1, tid: 9, ts: 0, args: { name: 'Compositor' } },
];

describe('mainThreadWork', () => {
  it('counts style and layout inside script as forced, and the browser’s own as not', () => {
    const events = [
      ...META,
      // A frame whose script reads a size after writing: forced style (1 ms) and layout (2 ms).
      x('RunTask', 0, 10),
      x('FireAnimationFrame', 1, 6),
      x('UpdateLayoutTree', 2, 3),
      x('Layout', 3, 5),
      // The browser's rendering step after the script: not forced.
      x('RunTask', 20, 30),
      x('UpdateLayoutTree', 21, 22),
      x('Layout', 22, 25),
      // Another thread's layout-looking work is not the page's.
      x('Layout', 40, 50, 9),
    ];
    expect(mainThreadWork(events)).toEqual({
      windowMs: 30,
      busyMs: 20,
      forcedMs: 3,
      forcedLayouts: 1,
      layouts: 2,
    });
  });

  it('reads nothing from a trace without the renderer’s main thread', () => {
    expect(mainThreadWork([x('RunTask', 0, 10)]).busyMs).toBe(0);
  });
});
