/**
 * Past one process: three `fixedstep serve` processes behind HAProxy with deploy/haproxy's own
 * configuration (rooms by consistent hash of the room in the URL), on 127.0.0.1. Every room lands
 * on exactly one process and plays to agreeing hashes; when one process is killed, its clients
 * get a clean close (no hang) and start again in a new room that lands on a live process, while
 * the other rooms play on. Needs Debian's haproxy (npm test installs it as root); skipped without.
 */
import { spawn, spawnSync, type ChildProcess } from 'node:child_process';
import { existsSync } from 'node:fs';
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import {
  LockstepSession,
  decodeMessage,
  encodeMessage,
  hex64,
  nodeWebSocketTransport,
  performanceClock,
  type ErrorMessage,
  type NetMessage,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';

const root = fileURLToPath(new URL('../../../', import.meta.url));
const haproxy = ['/usr/sbin/haproxy', '/usr/local/sbin/haproxy'].find((p) => existsSync(p));

/** A free TCP port on 127.0.0.1 (bound and released). */
function freePort(): Promise<number> {
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
async function until<T>(
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

interface Relay {
  port: number;
  child: ChildProcess;
  out: string;
}

const procs: ChildProcess[] = [];
let dir: string;
let relays: Relay[] = [];
let lbPort = 0;
let statsPort = 0;
/** The end of HAProxy's log (servers going down and up), shown when an upgrade is refused. */
let lbLog = '';

let started = 0;

async function startRelay(): Promise<Relay> {
  // Each process its own data folder: a data folder belongs to one process (it locks it); several
  // processes share scores through one PostgreSQL (DATABASE_URL), as deploy/ does.
  const data = path.join(dir, `data-${started++}`);
  const child = spawn(
    process.execPath,
    [
      '--conditions=source',
      '--import',
      'tsx',
      'packages/cli/src/cli.ts',
      'serve',
      '--port',
      '0',
      '--root',
      dir,
      '--data',
      data,
    ],
    {
      cwd: root,
      // The relays believe HAProxy's X-Forwarded-For (HAProxy is on loopback, trusted by default).
      env: { ...process.env, FIXEDSTEP_PROXY_HEADER: 'x-forwarded-for' },
      stdio: ['ignore', 'pipe', 'pipe'],
    },
  );
  procs.push(child);
  const r: Relay = { port: 0, child, out: '' };
  child.stdout.on('data', (b: Buffer) => (r.out += b.toString()));
  child.stderr.on('data', (b: Buffer) => (r.out += b.toString()));
  r.port = Number(
    await until(
      'a relay to listen',
      () => /localhost:(\d+)\//.exec(r.out)?.[1],
      60_000,
      () => r.out,
    ),
  );
  return r;
}

/** Usable servers of the room backend, as HAProxy sees them (a test-only stats frontend). */
async function usableRelays(): Promise<number> {
  try {
    const res = await fetch(`http://127.0.0.1:${statsPort}/`);
    return Number(await res.text());
  } catch {
    return -1;
  }
}

beforeAll(async () => {
  if (!haproxy) return;
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-balancer-'));
  await writeFile(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
  relays = await Promise.all([startRelay(), startRelay(), startRelay()]);
  // Ready (store open) before HAProxy starts: it counts a server as up until its checks fail, so
  // "three up" is only true once each /readyz answers 200.
  for (const r of relays) {
    await until(
      `relay ${r.port} to be ready`,
      async () => (await fetch(`http://127.0.0.1:${r.port}/readyz`).catch(() => undefined))?.ok,
      60_000,
      () => r.out,
    );
  }
  lbPort = await freePort();
  statsPort = await freePort();
  // The test's window into HAProxy: how many relays it counts as up.
  const extra = path.join(dir, 'stats.cfg');
  await writeFile(
    extra,
    `frontend test_stats\n  bind 127.0.0.1:${statsPort}\n` +
      `  http-request return status 200 content-type text/plain lf-string "%[nbsrv(relays_by_room)]"\n`,
  );
  const lb = spawn(
    haproxy,
    ['-db', '-f', path.join(root, 'deploy/haproxy/haproxy.cfg'), '-f', extra],
    {
      env: {
        PATH: process.env.PATH ?? '',
        FIXEDSTEP_BIND: `127.0.0.1:${lbPort}`,
        FIXEDSTEP_RELAY1: `127.0.0.1:${relays[0]!.port}`,
        FIXEDSTEP_RELAY2: `127.0.0.1:${relays[1]!.port}`,
        FIXEDSTEP_RELAY3: `127.0.0.1:${relays[2]!.port}`,
        // The deployed check: /readyz answers 200 once the store is open (PGlite's start-up holds
        // the event loop for seconds; a relay taking rooms then would drop them as silent).
        FIXEDSTEP_CHECK_PATH: '/readyz',
      },
      stdio: ['ignore', 'ignore', 'pipe'],
    },
  );
  procs.push(lb);
  lb.stderr.on('data', (b: Buffer) => (lbLog = (lbLog + b.toString()).slice(-4000)));
  await until('HAProxy to see three relays up', async () => (await usableRelays()) === 3);
}, 120_000);

afterAll(async () => {
  for (const p of procs) if (p.exitCode === null && p.signalCode === null) p.kill('SIGKILL');
  if (dir) await rm(dir, { recursive: true, force: true });
});

const hello = (room: string, role: 'player' | 'spectator'): NetMessage => ({
  type: 'hello',
  room,
  role,
  game: 'ctf',
  gameVersion: ctfGame.info.version,
  input: ctfGame.input.id,
  players: 2,
  name: 'probe',
});

/**
 * Whether `room` exists on the relay at `port`, asked directly: a spectator without the invite
 * gets BAD_TOKEN where the room is, BAD_HELLO ("no room to watch") where it is not.
 */
function roomOn(port: number, room: string): Promise<boolean> {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`ws://127.0.0.1:${port}/ws/${room}`);
    ws.on('open', () => {
      ws.send(encodeMessage(hello(room, 'spectator')));
    });
    ws.on('message', (data: Buffer) => {
      const m = decodeMessage(new Uint8Array(data)) as ErrorMessage;
      ws.terminate();
      resolve(m.code === 'BAD_TOKEN');
    });
    ws.on('error', reject);
  });
}

interface Player {
  session: LockstepSession;
  closedAt: number | undefined;
  closeReason: string | undefined;
}

/** Two lockstep players of `room` through the balancer (the room in the URL). */
async function playRoom(room: string, ticks: number): Promise<Player[]> {
  const clock = performanceClock();
  return Promise.all(
    [0, 1].map(
      () =>
        new Promise<Player>((resolve, reject) => {
          const ws = new WebSocket(`ws://127.0.0.1:${lbPort}/ws/${room}`);
          ws.on('error', reject);
          ws.on('unexpected-response', (_req, res) => {
            let body = '';
            res.on('data', (b: Buffer) => (body += b.toString()));
            res.on('end', () => {
              reject(
                new Error(`${room}: the upgrade got ${res.statusCode} ${body.trim()}\n${lbLog}`),
              );
            });
          });
          ws.on('open', () => {
            let slot = 0;
            const p: Player = { session: undefined!, closedAt: undefined, closeReason: undefined };
            p.session = new LockstepSession({
              transport: nodeWebSocketTransport(ws),
              clock,
              room,
              game: ctfGame,
              players: 2,
              seed: 9,
              stopAt: ticks,
              createSimulation: (w) => {
                slot = w.slot;
                return ctfGame.create(ctfGame.decodeConfig(w.config));
              },
              localInput: (_t, sim) => ctfGame.bot(sim as Game, slot),
              onEvent: (e) => {
                if (e.type === 'closed') {
                  p.closedAt = performance.now();
                  p.closeReason = e.reason;
                }
              },
            });
            resolve(p);
          });
        }),
    ),
  );
}

describe.skipIf(haproxy === undefined)('three relays behind HAProxy', () => {
  it('every room on exactly one process, no desync; a killed process’s rooms close cleanly and start again elsewhere', async () => {
    const ticks = 600;
    const names = Array.from({ length: 12 }, (_, i) => `room-${i}`);
    const rooms = new Map<string, Player[]>();
    const all = () => [...rooms.values()].flat();
    // Frames from the start: a member that does not answer the relay's pings is dropped as silent,
    // so the first rooms must be served while the later ones connect.
    const timer = setInterval(() => {
      for (const p of all()) p.session.frame();
    }, 8);
    try {
      for (const name of names) rooms.set(name, await playRoom(name, ticks));
      await until(
        'every room to start',
        () => all().every((p) => p.session.phase === 'running'),
        30_000,
        () =>
          all()
            .map((p) => `${p.session.phase}:${p.closeReason ?? ''}`)
            .join(' '),
      );
      // Where each room is: on exactly one of the three processes.
      const home = new Map<string, number>();
      for (const name of names) {
        const on = await Promise.all(relays.map((r) => roomOn(r.port, name)));
        expect(on.filter(Boolean), `${name} on ${on.join(',')}`).toHaveLength(1);
        home.set(name, on.indexOf(true));
      }
      const used = new Set(home.values());
      expect(used.size).toBeGreaterThanOrEqual(2);

      // Kill the process holding room-0's room, mid-match.
      const victim = home.get('room-0')!;
      const killedAt = performance.now();
      relays[victim]!.child.kill('SIGKILL');
      const orphans = names.filter((n) => home.get(n) === victim);
      const survivors = names.filter((n) => home.get(n) !== victim);
      // Its clients are closed at once: no hang.
      await until('the orphaned clients to be closed', () =>
        orphans.every((n) => rooms.get(n)!.every((p) => p.session.phase === 'closed')),
      );
      for (const n of orphans) {
        for (const p of rooms.get(n)!) expect(p.closedAt! - killedAt).toBeLessThan(5000);
      }
      // They start again under the same name: HAProxy sends the room to a live process.
      for (const n of orphans) rooms.set(n, await playRoom(n, ticks));
      await until('every room to finish', () => all().every((p) => p.session.isFinished), 120_000);
      for (const n of orphans) {
        const on = await Promise.all(
          relays.map((r, i) => (i === victim ? Promise.resolve(false) : roomOn(r.port, n))),
        );
        expect(on.filter(Boolean)).toHaveLength(1);
      }
      // Every room: both players on one final hash, no desync reported.
      for (const [name, players] of rooms) {
        const hashes = players.map((p) => hex64(p.session.hashAt(ticks)!));
        expect(new Set(hashes).size, `${name}: final hashes`).toBe(1);
        for (const p of players) expect(p.session.desyncs).toEqual([]);
      }
      expect(survivors.length + orphans.length).toBe(names.length);
      expect(await usableRelays()).toBe(2);
    } finally {
      clearInterval(timer);
      for (const p of all()) p.session.leave();
    }
  }, 240_000);
});

// The checked configuration is the one deployed: no test-only edits but the stats frontend.
describe.skipIf(haproxy === undefined)('the deployed HAProxy configuration', () => {
  it('is what this test runs (haproxy -c on both files)', () => {
    const r = spawnSync(
      haproxy!,
      [
        '-c',
        '-f',
        path.join(root, 'deploy/haproxy/haproxy.cfg'),
        '-f',
        path.join(dir, 'stats.cfg'),
      ],
      {
        env: {
          PATH: process.env.PATH ?? '',
          FIXEDSTEP_RELAY1: '127.0.0.1:1',
          FIXEDSTEP_RELAY2: '127.0.0.1:2',
          FIXEDSTEP_RELAY3: '127.0.0.1:3',
        },
        encoding: 'utf8',
      },
    );
    expect(r.status).toBe(0);
  });
});
