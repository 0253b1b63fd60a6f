/**
 * The cross-engine part of `fixedstep check`: the user's module and ./page.ts bundled into one
 * page with esbuild, served on 127.0.0.1, opened in Chromium (V8), Firefox ESR (SpiderMonkey) and
 * WebKitGTK (JavaScriptCore) where installed; each page runs the input script and posts its hashes
 * back, and they are compared with Node's tick by tick.
 *
 * The browsers are started directly with the page's URL — no driver library: the page answers
 * over HTTP, so the command needs nothing beyond the browsers themselves (found as
 * scripts/engines.mjs finds them for the determinism suite). WebKitGTK has no headless mode, so
 * it runs under its own Xvfb. Every process started here is stopped (its whole process group)
 * when its run ends, also on a timeout or an error.
 * @module
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { accessSync, constants, mkdtempSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { createServer, type IncomingMessage, type ServerResponse } from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import type { AnyGameDefinition } from 'fixedstep';
import { describeDifference, type CheckResult } from './checks.js';
import { fromHex, stateAt, traceGame, type CheckPlan, type TraceResult } from './script.js';

export const BROWSER_IDS = ['chromium', 'firefox', 'webkit'] as const;
export type BrowserId = (typeof BROWSER_IDS)[number];

const NAMES: Record<BrowserId, string> = {
  chromium: 'Chromium',
  firefox: 'Firefox',
  webkit: 'WebKitGTK',
};

/**
 * How long one browser may take from start to its answer (start-up ~0.3–4 s, then the script):
 * `FIXEDSTEP_CHECK_BROWSER_TIMEOUT_MS`, default 120 s.
 */
export const BROWSER_TIMEOUT_MS = 120_000;
/** The largest answer a page may post (a state's hex, or the hashes of a million ticks). */
const MAX_POST_BYTES = 64 * 1024 * 1024;

/** Chromium's flags: headless, no sandbox (root in containers), nothing fetched from the network. */
const CHROMIUM_FLAGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
];

/** Firefox's prefs: no first-run pages, updates or telemetry; no slow-script dialog. */
const FIREFOX_PREFS = `user_pref("app.update.enabled", false);
user_pref("browser.shell.checkDefaultBrowser", false);
user_pref("browser.startup.homepage_override.mstone", "ignore");
user_pref("datareporting.policy.dataSubmissionEnabled", false);
user_pref("toolkit.telemetry.enabled", false);
user_pref("dom.max_script_run_time", 0);
`;

function isExecutable(file: string | undefined): file is string {
  if (file === undefined || file === '') return false;
  try {
    accessSync(file, constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

function which(
  name: string,
  env: Readonly<Record<string, string | undefined>>,
): string | undefined {
  for (const dir of (env.PATH ?? '/usr/local/bin:/usr/bin:/bin').split(path.delimiter)) {
    if (dir && isExecutable(path.join(dir, name))) return path.join(dir, name);
  }
  return undefined;
}

function findMiniBrowser(): string | undefined {
  const apis = ['webkit2gtk-4.1', 'webkit2gtk-4.0', 'webkitgtk-6.0'];
  const candidates: string[] = [];
  for (const lib of ['/usr/lib', '/usr/lib64']) {
    let entries: string[];
    try {
      entries = readdirSync(lib).sort((a, b) => a.localeCompare(b));
    } catch {
      continue;
    }
    for (const e of entries)
      for (const api of apis) candidates.push(path.join(lib, e, api, 'MiniBrowser'));
    for (const api of apis) candidates.push(path.join(lib, api, 'MiniBrowser'));
  }
  return candidates.find(isExecutable);
}

/** Where a browser is, or why it cannot run: the determinism suite's rules (scripts/engines.mjs). */
export function findBrowser(
  id: BrowserId,
  env: Readonly<Record<string, string | undefined>>,
): { ok: true; path: string; xvfb?: string } | { ok: false; reason: string } {
  if (id === 'chromium') {
    const p = [env.CHROMIUM_PATH, '/usr/bin/chromium', '/usr/bin/chromium-browser'].find(
      isExecutable,
    );
    return p
      ? { ok: true, path: p }
      : { ok: false, reason: 'no Chromium (CHROMIUM_PATH, /usr/bin/chromium)' };
  }
  if (id === 'firefox') {
    const p = [env.FIREFOX_PATH, '/usr/bin/firefox-esr', '/usr/bin/firefox'].find(isExecutable);
    return p
      ? { ok: true, path: p }
      : { ok: false, reason: 'no Firefox (FIREFOX_PATH, /usr/bin/firefox-esr)' };
  }
  const browser = isExecutable(env.MINIBROWSER_PATH) ? env.MINIBROWSER_PATH : findMiniBrowser();
  const xvfb = which('Xvfb', env);
  if (!browser)
    return { ok: false, reason: 'no WebKitGTK MiniBrowser (Debian: libwebkit2gtk-4.1-0)' };
  if (!xvfb) return { ok: false, reason: 'no Xvfb (Debian: xvfb): WebKitGTK has no headless mode' };
  return { ok: true, path: browser, xvfb };
}

/** The page's bundle: the user's module and ./page.ts, for the browser. */
export async function bundleCheckPage(moduleFile: string): Promise<string> {
  // esbuild is an optional peer dependency: a plain install of the CLI does not bring it (nor its
  // install script, which npm asks users to approve), and only the browser checks need it.
  let esbuild: typeof import('esbuild');
  try {
    esbuild = await import('esbuild');
  } catch {
    throw new Error(
      'the browser checks bundle your module with esbuild, which is not installed: npm install --save-dev esbuild',
    );
  }
  const here = import.meta.url;
  const pageFile = fileURLToPath(new URL(`./page${here.endsWith('.ts') ? '.ts' : '.js'}`, here));
  try {
    const result = await esbuild.build({
      stdin: {
        contents: `import * as games from ${JSON.stringify(moduleFile)};\nimport { checkPage } from ${JSON.stringify(pageFile)};\nawait checkPage(games);\n`,
        resolveDir: path.dirname(moduleFile),
        sourcefile: 'fixedstep-check-entry.js',
        loader: 'js',
      },
      bundle: true,
      write: false,
      format: 'esm',
      platform: 'browser',
      target: 'es2022',
      logLevel: 'silent',
    });
    return result.outputFiles[0]!.text;
  } finally {
    // esbuild answers from a service process it keeps for the next build: none will come.
    await esbuild.stop();
  }
}

const PAGE_HTML = `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>fixedstep check</title>
<script>
  // An error before the check starts (the module throws on import): say so instead of hanging.
  addEventListener('error', (e) => {
    fetch('error', { method: 'POST', body: JSON.stringify({ message: String(e.message) }) });
  });
</script>
<script type="module" src="bundle.js"></script></head><body>fixedstep check</body></html>
`;

/** What the page reported as failing: the user's module threw on import, or has no such game. */
class PageError extends Error {
  override readonly name = 'PageError';
}

/** What one browser answered. */
interface BrowserAnswer {
  trace: TraceResult & { userAgent: string; ms: number };
  state?: { tick: number; hex: string };
}

/** One browser's run: its answers arrive over HTTP, keyed by a path of its own. */
interface Pending {
  plan: CheckPlan;
  /** The tick whose state to ask for once the trace is in (set by the comparison). */
  wantState: (trace: TraceResult) => number | undefined;
  trace?: BrowserAnswer['trace'];
  resolve(answer: BrowserAnswer): void;
  reject(error: Error): void;
}

function readBody(req: IncomingMessage): Promise<string> {
  return new Promise((resolve, reject) => {
    let size = 0;
    const chunks: Buffer[] = [];
    req.on('data', (d: Buffer) => {
      size += d.length;
      if (size > MAX_POST_BYTES) {
        reject(new Error('the page posted too much'));
        req.destroy();
        return;
      }
      chunks.push(d);
    });
    req.on('end', () => {
      resolve(Buffer.concat(chunks).toString('utf8'));
    });
    req.on('error', reject);
  });
}

/**
 * Every browser and Xvfb started here and still running. Should this process exit or be
 * interrupted (Ctrl-C, SIGTERM) while they run, their process groups are killed first: they run
 * detached (so that a group can be stopped whole) and would not get the terminal's signal.
 */
const live = new Set<ChildProcess>();
/** Their profile folders, removed with them. */
const profiles = new Set<string>();

function killGroup(child: ChildProcess): void {
  if (!child.pid) return;
  try {
    process.kill(-child.pid, 'SIGKILL');
  } catch {
    child.kill('SIGKILL');
  }
}

function killAll(): void {
  for (const child of live) killGroup(child);
  for (const dir of profiles) rmSync(dir, { recursive: true, force: true, maxRetries: 3 });
}

function onSignal(signal: NodeJS.Signals): void {
  killAll();
  release();
  process.kill(process.pid, signal); // as if we had never listened
}

function release(): void {
  process.off('exit', killAll);
  process.off('SIGINT', onSignal);
  process.off('SIGTERM', onSignal);
}

/** Registers a started process until it exits. */
function track(child: ChildProcess): ChildProcess {
  if (live.size === 0) {
    process.on('exit', killAll);
    process.on('SIGINT', onSignal);
    process.on('SIGTERM', onSignal);
  }
  live.add(child);
  child.once('exit', () => {
    live.delete(child);
    if (live.size === 0) release();
  });
  return child;
}

/** Stops a process group we started and waits for it to go (at most 5 s). */
async function stop(child: ChildProcess | undefined): Promise<void> {
  if (!child?.pid || child.exitCode !== null || child.signalCode !== null) return;
  const gone = new Promise<void>((resolve) => {
    child.once('exit', () => {
      resolve();
    });
  });
  killGroup(child);
  let timer: ReturnType<typeof setTimeout> | undefined;
  await Promise.race([gone, new Promise<void>((r) => (timer = setTimeout(r, 5000)))]);
  clearTimeout(timer);
}

/** Starts Xvfb on a free display (`-displayfd`); resolves with it and the display. */
function startXvfb(xvfb: string): Promise<{ child: ChildProcess; display: string }> {
  const child = track(
    spawn(
      xvfb,
      ['-displayfd', '3', '-nolisten', 'tcp', '-screen', '0', '1024x768x24', '-nocursor'],
      { stdio: ['ignore', 'ignore', 'ignore', 'pipe'], detached: true },
    ),
  );
  const fd3 = child.stdio[3] as NodeJS.ReadableStream | null;
  return new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => {
      void stop(child);
      reject(new Error('Xvfb did not report a display within 10 s'));
    }, 10_000);
    child.once('error', (e) => {
      clearTimeout(timer);
      reject(e);
    });
    child.once('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`Xvfb exited (${String(code)})`));
    });
    fd3?.on('data', (d: Buffer) => {
      out += d.toString();
      const m = /^(\d+)\n/.exec(out);
      if (m) {
        clearTimeout(timer);
        child.removeAllListeners('exit');
        resolve({ child, display: `:${m[1]!}` });
      }
    });
  });
}

/** Starts browser `id` on `url`; returns the processes to stop (the browser last). */
async function launch(
  id: BrowserId,
  found: { path: string; xvfb?: string },
  url: string,
  profile: string,
): Promise<ChildProcess[]> {
  const opts = { detached: true, stdio: 'ignore' as const };
  if (id === 'chromium') {
    return [track(spawn(found.path, [...CHROMIUM_FLAGS, `--user-data-dir=${profile}`, url], opts))];
  }
  if (id === 'firefox') {
    writeFileSync(path.join(profile, 'user.js'), FIREFOX_PREFS);
    return [
      track(
        spawn(found.path, ['--headless', '--no-remote', '--profile', profile, url], {
          ...opts,
          env: { ...process.env, MOZ_HEADLESS: '1' },
        }),
      ),
    ];
  }
  const x = await startXvfb(found.xvfb!);
  const browser = track(
    spawn(found.path, [url], {
      ...opts,
      env: {
        ...process.env,
        DISPLAY: x.display,
        HOME: profile,
        XDG_CACHE_HOME: profile,
        XDG_DATA_HOME: profile,
      },
    }),
  );
  return [x.child, browser];
}

/** A short name of the engine from its user agent: `Chrome/156.0.0.0`, `Firefox/153.0` … */
function engineVersion(id: BrowserId, userAgent: string): string {
  const re =
    id === 'chromium'
      ? /(?:Headless)?Chrome\/[\d.]+/
      : id === 'firefox'
        ? /Firefox\/[\d.]+/
        : /AppleWebKit\/[\d.]+/;
  return re.exec(userAgent)?.[0] ?? NAMES[id];
}

export interface BrowserRunOptions {
  game: AnyGameDefinition;
  /** The games module's file (what esbuild bundles). */
  moduleFile: string;
  plan: CheckPlan;
  /** Browsers named on the command line (each required); default every one, where installed. */
  only?: readonly BrowserId[];
  env: Readonly<Record<string, string | undefined>>;
  /** Called as each browser starts (for progress: a browser's run takes seconds). */
  onStart?(browser: string): void;
}

/**
 * Runs the plan in each browser and compares with Node. `infrastructureError`: a browser that
 * was named or is installed could not run (not the game's fault).
 */
export async function runBrowsers(
  options: BrowserRunOptions,
): Promise<{ results: CheckResult[]; infrastructureError: boolean }> {
  const { game, plan, env } = options;
  const ids = options.only ?? BROWSER_IDS;
  const results: CheckResult[] = [];
  let infrastructureError = false;
  const runnable: { id: BrowserId; found: { path: string; xvfb?: string } }[] = [];
  for (const id of ids) {
    const found = findBrowser(id, env);
    if (found.ok) runnable.push({ id, found });
    else {
      if (options.only !== undefined) infrastructureError = true;
      results.push({
        check: id,
        status: 'skipped',
        summary: `${options.only !== undefined ? 'asked for, but ' : ''}not installed: ${found.reason}`,
        details: [],
      });
    }
  }
  if (runnable.length === 0) return { results, infrastructureError };

  const node = traceGame(game, plan);
  let bundle: string;
  try {
    bundle = await bundleCheckPage(options.moduleFile);
  } catch (e) {
    const message = e instanceof Error ? e.message : String(e);
    for (const { id } of runnable) {
      results.push({
        check: id,
        status: 'skipped',
        summary: `the module could not be bundled for the browser: ${message.split('\n')[0] ?? ''}`,
        details: message.split('\n').slice(1, 6),
      });
    }
    return { results, infrastructureError: true };
  }

  const timeoutMs = timeoutFromEnv(env);
  const pending = new Map<string, Pending>();
  const server = createServer((req, res) => {
    void handle(req, res);
  });
  async function handle(req: IncomingMessage, res: ServerResponse): Promise<void> {
    const m = /^\/run\/([a-z]+)\/([a-z.]*)$/.exec(req.url ?? '');
    const run = m ? pending.get(m[1]!) : undefined;
    const what = m?.[2] ?? '';
    const send = (type: string, body: string) => {
      res.writeHead(200, { 'content-type': type, 'cache-control': 'no-store' });
      res.end(body);
    };
    if (!run) {
      res.writeHead(404).end();
      return;
    }
    try {
      const page: Record<string, [string, string]> = {
        '': ['text/html; charset=utf-8', PAGE_HTML],
        'bundle.js': ['text/javascript', bundle],
        plan: ['application/json', JSON.stringify(plan)],
      };
      const served = req.method === 'GET' ? page[what] : undefined;
      if (served !== undefined) {
        send(...served);
        return;
      }
      if (req.method !== 'POST') {
        res.writeHead(404).end();
        return;
      }
      const body = JSON.parse(await readBody(req)) as Record<string, unknown>;
      if (what === 'error') {
        send('application/json', '{}');
        run.reject(new PageError(String(body.message)));
      } else if (what === 'trace') {
        run.trace = body as unknown as BrowserAnswer['trace'];
        const tick = run.wantState(run.trace);
        send('application/json', JSON.stringify(tick === undefined ? {} : { stateAt: tick }));
        if (tick === undefined) run.resolve({ trace: run.trace });
      } else if (what === 'state' && run.trace) {
        send('application/json', '{}');
        run.resolve({ trace: run.trace, state: body as unknown as { tick: number; hex: string } });
      } else {
        res.writeHead(404).end();
      }
    } catch (e) {
      res.writeHead(400).end();
      run.reject(e instanceof Error ? e : new Error(String(e)));
    }
  }
  await new Promise<void>((resolve, reject) => {
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      resolve();
    });
  });
  const address = server.address();
  const port = typeof address === 'object' && address ? address.port : 0;
  try {
    for (const { id, found } of runnable) {
      const started = performance.now();
      options.onStart?.(NAMES[id]);
      const profile = mkdtempSync(path.join(os.tmpdir(), `fixedstep-check-${id}-`));
      profiles.add(profile);
      let launching: Promise<ChildProcess[]> = Promise.resolve([]);
      let timer: ReturnType<typeof setTimeout> | undefined;
      try {
        const answer = await new Promise<BrowserAnswer>((resolve, reject) => {
          pending.set(id, {
            plan,
            wantState: (trace) => firstDifference(node, trace),
            resolve,
            reject,
          });
          timer = setTimeout(() => {
            reject(
              new Error(
                `no answer within ${timeoutMs / 1000} s (FIXEDSTEP_CHECK_BROWSER_TIMEOUT_MS)`,
              ),
            );
          }, timeoutMs);
          launching = launch(id, found, `http://127.0.0.1:${port}/run/${id}/`, profile);
          launching.then((started) => {
            const browser = started[started.length - 1]!;
            browser.once('error', reject);
            browser.once('exit', (code, signal) => {
              reject(
                new Error(`${NAMES[id]} exited (${signal ?? String(code)}) before it answered`),
              );
            });
          }, reject);
        });
        results.push(compare(id, game, plan, node, answer, performance.now() - started));
      } catch (e) {
        if (e instanceof PageError) {
          // The module or the game failed in the page: the game's problem, not the checker's.
          results.push({
            check: id,
            status: 'error',
            summary: `the module failed in ${NAMES[id]} (not in Node): ${e.message}`,
            details: [],
          });
          continue;
        }
        infrastructureError = true;
        results.push({
          check: id,
          status: 'skipped',
          summary: `could not run in ${NAMES[id]}: ${e instanceof Error ? e.message : String(e)}`,
          details: [],
        });
      } finally {
        clearTimeout(timer);
        pending.delete(id);
        // Also what is still starting when a timeout ends the run: wait for it, then stop it.
        const children = await launching.catch(() => []);
        for (const child of children.reverse()) await stop(child);
        rmSync(profile, { recursive: true, force: true, maxRetries: 3 });
        profiles.delete(profile);
      }
    }
  } finally {
    server.closeAllConnections();
    await new Promise<void>((resolve) =>
      server.close(() => {
        resolve();
      }),
    );
  }
  return { results, infrastructureError };
}

/** The first tick (state after it) where `trace` differs from Node's, or undefined. */
function firstDifference(node: TraceResult, trace: TraceResult): number | undefined {
  const n = Math.min(node.trace.length, trace.trace.length) / 16;
  for (let i = 0; i < n; i++) {
    if (node.trace.slice(16 * i, 16 * i + 16) !== trace.trace.slice(16 * i, 16 * i + 16))
      return i + 1;
  }
  return undefined;
}

function compare(
  id: BrowserId,
  game: AnyGameDefinition,
  plan: CheckPlan,
  node: TraceResult,
  answer: BrowserAnswer,
  ms: number,
): CheckResult {
  const t = answer.trace;
  const engine = engineVersion(id, t.userAgent);
  const took = `${engine}, ${(ms / 1000).toFixed(1)} s`;
  if (answer.state !== undefined) {
    const tick = answer.state.tick;
    const d = describeDifference(game, stateAt(game, plan, tick), fromHex(answer.state.hex), [
      'Node',
      NAMES[id],
    ]);
    return {
      check: id,
      status: 'fail',
      summary: `${NAMES[id]} differs from Node after tick ${tick}, at ${d.field} (${took})`,
      tick,
      field: d.field,
      details: [
        ...d.details,
        'likely: engine math (Math.sin, cos, exp, pow … differ in the last bit between engines), or code that runs differently in a browser',
      ],
    };
  }
  if (t.error !== undefined && node.error === undefined) {
    return {
      check: id,
      status: 'error',
      summary: `the game threw in ${NAMES[id]} at tick ${t.errorTick ?? '?'} (not in Node): ${t.error}`,
      ...(t.errorTick !== undefined ? { tick: t.errorTick } : {}),
      details: [],
    };
  }
  const ticks = t.trace.length / 16;
  return {
    check: id,
    status: 'pass',
    summary: `${ticks} hashes equal to Node's (${took})`,
    details: [],
  };
}

function timeoutFromEnv(env: Readonly<Record<string, string | undefined>>): number {
  const ms = Number(env.FIXEDSTEP_CHECK_BROWSER_TIMEOUT_MS);
  return Number.isInteger(ms) && ms >= 1 ? ms : BROWSER_TIMEOUT_MS;
}
