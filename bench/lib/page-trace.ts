/**
 * Driving a page's frames and tracing them (Chrome DevTools Protocol), for the lab bench and the
 * lab's frame tests alike; `main-thread.ts` reads the events.
 * @module
 */
import type { CDPSession, Page } from 'playwright-core';
import type { TraceEvent } from './main-thread.js';

/**
 * `n` animation frames of the page, awaited in the page. (A string: tsx would wrap a function's
 * inner functions in a helper the page does not have.)
 */
export function animationFrames(page: Page, n: number): Promise<void> {
  return page.evaluate(`new Promise((resolve) => {
    let left = ${n};
    const step = () => (--left <= 0 ? resolve() : requestAnimationFrame(step));
    requestAnimationFrame(step);
  })`);
}

/** Runs `n` frames of the page under a DevTools trace on `cdp` and returns the trace's events. */
export async function traceFrames(page: Page, cdp: CDPSession, n: number): Promise<TraceEvent[]> {
  const events: TraceEvent[] = [];
  cdp.on('Tracing.dataCollected', (e) => {
    events.push(...(e.value as unknown as TraceEvent[]));
  });
  const done = new Promise<void>((resolve) => {
    cdp.once('Tracing.tracingComplete', () => {
      resolve();
    });
  });
  await cdp.send('Tracing.start', {
    categories: 'devtools.timeline,disabled-by-default-devtools.timeline',
    transferMode: 'ReportEvents',
  });
  await animationFrames(page, n);
  await cdp.send('Tracing.end');
  await done;
  return events;
}
