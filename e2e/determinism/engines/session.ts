/**
 * One JavaScript engine, driven from Node: it loads the determinism page (or, for Node, imports the
 * same modules) and answers with the traces. Each browser driver implements this interface.
 */
import type { EngineRun } from '../run.js';

export type EngineId = 'node' | 'chromium' | 'firefox' | 'webkit';

/** What each engine is, for reports. */
export const ENGINE_NAMES: Readonly<Record<EngineId, string>> = {
  node: 'Node (V8)',
  chromium: 'Chromium (V8)',
  firefox: 'Firefox ESR (SpiderMonkey)',
  webkit: 'WebKitGTK (JavaScriptCore)',
};

export interface EngineSession {
  readonly id: EngineId;
  /** Browser (or Node) version, e.g. `Chromium 156.0.8078.79`. */
  readonly version: string;
  /** The JavaScript engine's version where the driver can tell (V8 via CDP, Node), else ''. */
  readonly jsVersion: string;
  readonly userAgent: string;
  /** Time to start and load the page, ms. */
  readonly startMs: number;
  /** Traces every scene (the page's `run()`). */
  run(): Promise<EngineRun>;
  /** The hex state of scene `id` after `tick` (the page's `state()`). */
  state(id: string, tick: number): Promise<string>;
  close(): Promise<void>;
}

/** Page expressions: the page defines `window.fixedstepDeterminism` (see page/main.ts). */
export const PAGE = {
  ready: '!!(window.fixedstepDeterminism && window.fixedstepDeterminism.ready)',
  run: 'window.fixedstepDeterminism.run()',
  state: (id: string, tick: number) =>
    `window.fixedstepDeterminism.state(${JSON.stringify(id)}, ${String(tick)})`,
  userAgent: 'navigator.userAgent',
} as const;

/** Parses the page's `run()` answer, with a clear message if it is not what the page returns. */
export function parseRun(json: unknown, engine: EngineId): EngineRun {
  if (typeof json !== 'string')
    throw new Error(`${engine}: run() returned ${typeof json}, not JSON`);
  const run = JSON.parse(json) as EngineRun;
  if (!Array.isArray(run.scenes)) throw new Error(`${engine}: run() returned no scenes`);
  return run;
}

/** Rejects after `ms` with a message naming `what`. */
export async function withTimeout<T>(what: string, ms: number, p: Promise<T>): Promise<T> {
  let timer: ReturnType<typeof setTimeout> | undefined;
  const timeout = new Promise<never>((_, reject) => {
    timer = setTimeout(() => {
      reject(new Error(`${what}: no answer within ${String(ms / 1000)} s`));
    }, ms);
  });
  try {
    return await Promise.race([p, timeout]);
  } finally {
    clearTimeout(timer);
  }
}
