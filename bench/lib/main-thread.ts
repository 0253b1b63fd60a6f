/**
 * What a page's main thread did, from a Chrome trace (DevTools' `devtools.timeline` events): how
 * busy it was, and how much of that was forced layout — style and layout computed synchronously
 * because script read a size (`getBoundingClientRect`, `offsetWidth`) after writing to the page,
 * instead of by the browser's own rendering step after the frame's script.
 *
 * Pure: it reads trace events and returns numbers, so its tests feed it hand-made traces.
 * @module
 */

/** One event of a Chrome trace (the fields this file reads). */
export interface TraceEvent {
  readonly name: string;
  /** `X`: complete (with `dur`), `B`/`E`: begin/end, `M`: metadata. */
  readonly ph: string;
  readonly pid: number;
  readonly tid: number;
  /** Start, µs. */
  readonly ts: number;
  /** Duration, µs (complete events). */
  readonly dur?: number;
  readonly args?: { readonly name?: string };
}

/** The main thread's work over a window of a trace. */
export interface MainThreadWork {
  /** The window, ms (from the first to the last event counted). */
  readonly windowMs: number;
  /** Time in top-level tasks, ms. */
  readonly busyMs: number;
  /** Style and layout run inside script (forced), ms. */
  readonly forcedMs: number;
  /** How many forced layouts (`Layout` inside script). */
  readonly forcedLayouts: number;
  /** Layouts in all. */
  readonly layouts: number;
}

/** The events in which page script runs: a style or layout inside one of them was forced. */
const SCRIPT = new Set([
  'FireAnimationFrame',
  'FunctionCall',
  'EventDispatch',
  'TimerFire',
  'EvaluateScript',
  'v8.callFunction',
  'FireIdleCallback',
]);
/** Style and layout work. */
const LAYOUT = new Set(['Layout', 'UpdateLayoutTree', 'RecalculateStyles']);

/** The renderer's main thread: the thread named `CrRendererMain` with the most events. */
function mainThread(events: readonly TraceEvent[]): { pid: number; tid: number } | undefined {
  const named = events.filter(
    (e) => e.ph === 'M' && e.name === 'thread_name' && e.args?.name === 'CrRendererMain',
  );
  let best: { pid: number; tid: number } | undefined;
  let most = -1;
  for (const t of named) {
    const n = events.filter((e) => e.pid === t.pid && e.tid === t.tid && e.ph === 'X').length;
    if (n > most) {
      most = n;
      best = { pid: t.pid, tid: t.tid };
    }
  }
  return best;
}

/**
 * The main thread's busy time and forced style/layout time in `events` (complete events only:
 * Chrome writes the timeline's tasks, script and layout as `X` events). A read in a
 * `ResizeObserver` callback forces nothing unless script wrote to the page before it in that
 * callback: the browser has just laid the page out.
 */
export function mainThreadWork(events: readonly TraceEvent[]): MainThreadWork {
  const main = mainThread(events);
  const none = { windowMs: 0, busyMs: 0, forcedMs: 0, forcedLayouts: 0, layouts: 0 };
  if (!main) return none;
  const mine = events
    .filter((e) => e.pid === main.pid && e.tid === main.tid && e.ph === 'X' && e.dur !== undefined)
    .sort((a, b) => a.ts - b.ts || b.dur! - a.dur!);
  if (mine.length === 0) return none;
  let busy = 0;
  let taskEnd = -Infinity;
  let forced = 0;
  let forcedLayouts = 0;
  let layouts = 0;
  // Events nest: a stack of the open ones, closed as time passes their end.
  const open: TraceEvent[] = [];
  let from = Infinity;
  let to = -Infinity;
  for (const e of mine) {
    const end = e.ts + e.dur!;
    from = Math.min(from, e.ts);
    to = Math.max(to, end);
    while (open.length > 0 && open[open.length - 1]!.ts + open[open.length - 1]!.dur! <= e.ts) {
      open.pop();
    }
    if (e.name === 'RunTask' && e.ts >= taskEnd) {
      busy += e.dur!;
      taskEnd = end;
    }
    if (LAYOUT.has(e.name)) {
      if (e.name === 'Layout') layouts++;
      const inLayout = open.some((o) => LAYOUT.has(o.name));
      if (!inLayout && open.some((o) => SCRIPT.has(o.name))) {
        forced += e.dur!;
        if (e.name === 'Layout') forcedLayouts++;
      }
    }
    open.push(e);
  }
  return {
    windowMs: (to - from) / 1000,
    busyMs: busy / 1000,
    forcedMs: forced / 1000,
    forcedLayouts,
    layouts,
  };
}
