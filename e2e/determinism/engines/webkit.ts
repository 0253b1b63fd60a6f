/**
 * WebKitGTK (JavaScriptCore) through plain W3C WebDriver over HTTP: `WebKitWebDriver` on a free
 * port drives webkit2gtk's MiniBrowser in automation mode. WebKitGTK has no headless mode (without
 * a display the session request hangs for ever), so it runs under its own Xvfb, and every
 * WebDriver call has a timeout.
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { createServer } from 'node:net';
import { PAGE, parseRun, type EngineSession } from './session.js';

export interface WebKitPaths {
  driver: string;
  browser: string;
  xvfb: string;
}

/** A free TCP port on 127.0.0.1 (asked of the kernel, then released). */
async function freePort(): Promise<number> {
  return new Promise((resolve, reject) => {
    const srv = createServer();
    srv.once('error', reject);
    srv.listen(0, '127.0.0.1', () => {
      const address = srv.address();
      const port = typeof address === 'object' && address ? address.port : 0;
      srv.close(() => {
        resolve(port);
      });
    });
  });
}

/** Stops a process we started (its whole group: WebKitWebDriver starts MiniBrowser). */
function stop(child: ChildProcess | undefined): void {
  if (!child?.pid || child.exitCode !== null || child.signalCode !== null) return;
  try {
    process.kill(-child.pid, 'SIGTERM');
  } catch {
    child.kill('SIGTERM');
  }
}

/** Starts Xvfb on the first free display (`-displayfd`); resolves with the display number. */
async function startXvfb(xvfb: string): Promise<{ child: ChildProcess; display: string }> {
  const child = spawn(
    xvfb,
    ['-displayfd', '3', '-nolisten', 'tcp', '-screen', '0', '1280x800x24', '-nocursor'],
    { stdio: ['ignore', 'ignore', 'pipe', 'pipe'], detached: true },
  );
  let stderr = '';
  child.stderr?.on('data', (d: Buffer) => {
    stderr += d.toString();
  });
  const fd3 = child.stdio[3] as NodeJS.ReadableStream | null;
  return new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => {
      stop(child);
      reject(new Error(`Xvfb did not report a display within 10 s: ${stderr.trim()}`));
    }, 10_000);
    child.once('error', (e) => {
      clearTimeout(timer);
      reject(e);
    });
    child.once('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`Xvfb exited (${String(code)}): ${stderr.trim()}`));
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

interface WdResponse {
  value: unknown;
}

/** One WebDriver command, with a timeout; throws with WebDriver's error and message. */
async function wd(
  base: string,
  method: 'GET' | 'POST' | 'DELETE',
  path: string,
  body: unknown,
  timeoutMs: number,
): Promise<unknown> {
  const init: RequestInit = { method, signal: AbortSignal.timeout(timeoutMs) };
  if (body !== undefined) {
    init.body = JSON.stringify(body);
    init.headers = { 'content-type': 'application/json; charset=utf-8' };
  }
  let res: Response;
  try {
    res = await fetch(`${base}${path}`, init);
  } catch (e) {
    const why =
      e instanceof Error && e.name === 'TimeoutError'
        ? `no answer within ${String(timeoutMs / 1000)} s`
        : String(e);
    throw new Error(`WebDriver ${method} ${path}: ${why}`, { cause: e });
  }
  const json = (await res.json().catch(() => ({ value: null }))) as WdResponse;
  if (!res.ok) {
    const v = json.value as { error?: string; message?: string } | null;
    throw new Error(
      `WebDriver ${method} ${path}: HTTP ${String(res.status)} ${v?.error ?? ''} ${v?.message ?? ''}`.trim(),
    );
  }
  return json.value;
}

export async function openWebKit(paths: WebKitPaths, url: string): Promise<EngineSession> {
  const t0 = performance.now();
  let xvfb: ChildProcess | undefined;
  let driver: ChildProcess | undefined;
  let base = '';
  let sessionId = '';
  const cleanup = async () => {
    if (sessionId) {
      await wd(base, 'DELETE', `/session/${sessionId}`, undefined, 10_000).catch(() => undefined);
      sessionId = '';
    }
    stop(driver);
    stop(xvfb);
  };
  try {
    const x = await startXvfb(paths.xvfb);
    xvfb = x.child;
    const port = await freePort();
    base = `http://127.0.0.1:${String(port)}`;
    let driverLog = '';
    driver = spawn(paths.driver, [`--port=${String(port)}`, '--host=local'], {
      env: { ...process.env, DISPLAY: x.display },
      stdio: ['ignore', 'pipe', 'pipe'],
      detached: true,
    });
    driver.stdout?.on('data', (d: Buffer) => (driverLog += d.toString()));
    driver.stderr?.on('data', (d: Buffer) => (driverLog += d.toString()));
    const driverExit = new Promise<never>((_, reject) => {
      driver?.once('exit', (code) => {
        reject(new Error(`WebKitWebDriver exited (${String(code)}): ${driverLog.trim()}`));
      });
    });
    driverExit.catch(() => undefined);

    // Wait for the driver to listen.
    const deadline = performance.now() + 10_000;
    for (;;) {
      try {
        const status = (await Promise.race([
          wd(base, 'GET', '/status', undefined, 1000),
          driverExit,
        ])) as { ready?: boolean } | null;
        if (status?.ready !== false) break;
      } catch (e) {
        if (performance.now() > deadline) throw e;
      }
      await new Promise((r) => setTimeout(r, 50));
    }

    const created = (await Promise.race([
      wd(
        base,
        'POST',
        '/session',
        {
          capabilities: {
            alwaysMatch: {
              'webkitgtk:browserOptions': { binary: paths.browser, args: ['--automation'] },
            },
          },
        },
        30_000,
      ),
      driverExit,
    ])) as { sessionId: string; capabilities?: { browserName?: string; browserVersion?: string } };
    sessionId = created.sessionId;
    const s = `/session/${sessionId}`;
    await wd(base, 'POST', `${s}/timeouts`, { script: 240_000, pageLoad: 30_000 }, 10_000);
    await wd(base, 'POST', `${s}/url`, { url }, 40_000);
    const exec = (expression: string, timeoutMs: number) =>
      wd(
        base,
        'POST',
        `${s}/execute/sync`,
        { script: `return ${expression};`, args: [] },
        timeoutMs,
      );
    const readyBy = performance.now() + 30_000;
    while (!(await exec(PAGE.ready, 10_000))) {
      if (performance.now() > readyBy) throw new Error('the page did not get ready within 30 s');
      await new Promise((r) => setTimeout(r, 50));
    }
    const userAgent = String(await exec(PAGE.userAgent, 10_000));
    const caps = created.capabilities ?? {};
    return {
      id: 'webkit',
      version: `WebKitGTK ${caps.browserVersion ?? '?'} (${caps.browserName ?? 'MiniBrowser'})`,
      jsVersion: '',
      userAgent,
      startMs: performance.now() - t0,
      run: async () => parseRun(await exec(PAGE.run, 240_000), 'webkit'),
      state: async (id, tick) => String(await exec(PAGE.state(id, tick), 60_000)),
      close: cleanup,
    };
  } catch (e) {
    await cleanup();
    throw e;
  }
}
