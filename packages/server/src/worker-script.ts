/**
 * Where a worker thread's script is. Built, it is the `.js` file next to the module that starts it.
 * From TypeScript sources (the tests, `npm run bench` under tsx) it is the `.ts` file, loaded
 * through tsx's loader, which a small bootstrap registers in the worker (a worker's `execArgv`
 * cannot carry `--import`), with the packages' `source` export condition.
 * @module
 */
import os from 'node:os';

/**
 * The script of a worker thread: `script` is the built file's URL relative to `from` (the starting
 * module's `import.meta.url`), e.g. `workerScript('./worker.js', import.meta.url)`.
 */
export function workerScript(script: string, from: string): { url: URL; execArgv?: string[] } {
  if (!from.endsWith('.ts')) return { url: new URL(script, from) };
  const tsx = import.meta.resolve('tsx/esm/api');
  const source = new URL(script.replace(/\.js$/, '.ts'), from).href;
  const bootstrap = `const { register } = await import(${JSON.stringify(tsx)}); register(); await import(${JSON.stringify(source)});`;
  return {
    url: new URL(`data:text/javascript,${encodeURIComponent(bootstrap)}`),
    execArgv: ['--conditions=source'],
  };
}

/**
 * How much lower than the event loop's a worker thread's scheduling priority is (a nice value;
 * 19 is the lowest). On Linux a thread has its own nice value, so a worker that calls
 * {@link lowerThreadPriority} gives way to the server's event loop when the cores are short —
 * the event loop's work is small and latency-bound (a relay's tick, a health check), a
 * verification worker's (a re-simulation) large and throughput-bound. The embedded database's
 * thread keeps the event loop's priority: its opening decides when the server is ready, and its
 * statements are short.
 */
export const WORKER_NICENESS = 10;

/** Lowers the calling thread's priority by {@link WORKER_NICENESS} (Linux; elsewhere a no-op). */
export function lowerThreadPriority(): void {
  if (process.platform !== 'linux') return;
  try {
    // On Linux, setpriority(PRIO_PROCESS, 0) changes the calling thread only.
    os.setPriority(0, Math.min(19, os.getPriority(0) + WORKER_NICENESS));
  } catch {
    // Not permitted (a sandbox): the thread keeps the event loop's priority.
  }
}
