/**
 * What the tests that run deploy/haproxy/haproxy.cfg for real share (net-deploy.test.ts with stub
 * servers, net-balancer.test.ts with `fixedstep serve` processes): where Debian's haproxy is, free
 * ports, waiting on a condition, and HAProxy started on the deployed configuration plus a test-only
 * statistics frontend.
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { existsSync } from 'node:fs';
import { writeFile } from 'node:fs/promises';
import net from 'node:net';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

/** The repository's root. */
export const root = fileURLToPath(new URL('../../../', import.meta.url));
/** The deployed configuration. */
export const HAPROXY_CFG = path.join(root, 'deploy/haproxy/haproxy.cfg');
/** Debian's haproxy (`npm test` installs it as root), or undefined: then these tests are skipped. */
export const haproxy = ['/usr/sbin/haproxy', '/usr/local/sbin/haproxy'].find((p) => existsSync(p));

/** A free TCP port on 127.0.0.1 (bound and released). */
export function freePort(): Promise<number> {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const port = (s.address() as net.AddressInfo).port;
      s.close(() => {
        resolve(port);
      });
    });
  });
}

/** Resolves with what `f` returns once it is truthy; polls every 50 ms, rejects after `ms`. */
export async function until<T>(
  what: string,
  f: () => T | Promise<T>,
  ms = 30_000,
  detail: () => string = () => '',
): Promise<T> {
  const end = performance.now() + ms;
  for (;;) {
    const v = await f();
    if (v) return v;
    if (performance.now() > end) throw new Error(`timed out waiting for ${what} ${detail()}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** One server line of HAProxy's CSV statistics. */
export interface ServerStats {
  /** The backend, e.g. `relays_match`. */
  backend: string;
  /** The server, e.g. `relay1`. */
  server: string;
  /** `UP`, `DOWN`, `UP 1/2` (going down), `DOWN 1/2` (coming up) … */
  status: string;
  /** Connections it has taken since HAProxy started. */
  sessions: number;
}

/** A running HAProxy on the deployed configuration. */
export interface RunningHaproxy {
  /** Where the configuration's frontend listens (127.0.0.1). */
  port: number;
  child: ChildProcess;
  /** The end of its log (servers going down and up), for failure messages. */
  log(): string;
  /** Every server of every backend, from the test-only statistics frontend. */
  stats(): Promise<ServerStats[]>;
  /** Servers of `backend` HAProxy would send a connection to now (status UP, also `UP 1/2`). */
  usable(backend: string): Promise<number>;
}

/**
 * Starts `haproxy -db` on the deployed configuration, with the three servers at `servers`
 * (127.0.0.1 ports) and a second configuration file adding only a statistics frontend (CSV) for the
 * test. `dir` receives that file. Kill `child` when done.
 */
export async function startHaproxy(
  dir: string,
  servers: readonly number[],
): Promise<RunningHaproxy> {
  if (!haproxy) throw new Error('no haproxy');
  const port = await freePort();
  const statsPort = await freePort();
  const extra = path.join(dir, 'stats.cfg');
  await writeFile(
    extra,
    `listen test_stats\n  bind 127.0.0.1:${statsPort}\n  stats enable\n  stats uri /\n`,
  );
  let log = '';
  const child = spawn(haproxy, ['-db', '-f', HAPROXY_CFG, '-f', extra], {
    env: {
      PATH: process.env.PATH ?? '',
      FIXEDSTEP_BIND: `127.0.0.1:${port}`,
      FIXEDSTEP_RELAY1: `127.0.0.1:${servers[0]!}`,
      FIXEDSTEP_RELAY2: `127.0.0.1:${servers[1]!}`,
      FIXEDSTEP_RELAY3: `127.0.0.1:${servers[2]!}`,
      // The deployed check: /readyz answers 200 once the store is open (PGlite's start-up holds
      // the event loop for seconds; a process taking rooms then would drop them as silent).
      FIXEDSTEP_CHECK_PATH: '/readyz',
    },
    stdio: ['ignore', 'ignore', 'pipe'],
  });
  child.stderr.on('data', (b: Buffer) => (log = (log + b.toString()).slice(-4000)));
  const stats = async (): Promise<ServerStats[]> => {
    const res = await fetch(`http://127.0.0.1:${statsPort}/;csv`);
    const [head, ...rows] = (await res.text()).trim().split('\n');
    const columns = head!.replace(/^# /, '').split(',');
    const at = (name: string) => columns.indexOf(name);
    return rows
      .map((r) => r.split(','))
      .filter((f) => f[at('svname')] !== 'FRONTEND' && f[at('svname')] !== 'BACKEND')
      .map((f) => ({
        backend: f[at('pxname')]!,
        server: f[at('svname')]!,
        status: f[at('status')]!,
        sessions: Number(f[at('stot')]),
      }));
  };
  const running: RunningHaproxy = {
    port,
    child,
    log: () => log,
    stats,
    async usable(backend) {
      try {
        return (await stats()).filter((s) => s.backend === backend && s.status.startsWith('UP'))
          .length;
      } catch {
        return -1;
      }
    },
  };
  try {
    await until(
      'HAProxy to answer its statistics',
      async () => (await running.usable('relays_by_room')) >= 0,
      30_000,
      () => log,
    );
  } catch (error) {
    await stopProcess(child);
    throw error;
  }
  return running;
}

/** Kills `child` (SIGKILL) unless it has ended, and resolves once it has. */
export async function stopProcess(child: ChildProcess): Promise<void> {
  if (child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise((resolve) => child.once('exit', resolve));
  child.kill('SIGKILL');
  await exited;
}
