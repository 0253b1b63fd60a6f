/**
 * coturn (Debian's `turnserver`) on 127.0.0.1, started for one test or benchmark run: UDP only, a
 * static user, loopback peers allowed (every peer is on this machine), its database and pid file
 * in a scratch directory. `findTurnServer()` says where it is or why it cannot run
 * (`scripts/coturn.mjs` installs it when `npm test` runs as root).
 */
import { spawn, type ChildProcess } from 'node:child_process';
import dgram from 'node:dgram';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import type { IceServerConfig } from 'fixedstep';

const repo = fileURLToPath(new URL('../..', import.meta.url));

/** Where coturn is, or why not (scripts/coturn.mjs's `findCoturn`). */
export async function findTurnServer(): Promise<
  { ok: true; path: string } | { ok: false; reason: string }
> {
  const mod = (await import(pathToFileURL(path.join(repo, 'scripts', 'coturn.mjs')).href)) as {
    findCoturn(): { ok: true; path: string } | { ok: false; reason: string };
  };
  return mod.findCoturn();
}

export interface TurnServer {
  port: number;
  username: string;
  credential: string;
  /** The ICE servers for a peer, through `port` (default the relay's own; pass a proxy's port). */
  iceServers(port?: number): IceServerConfig[];
  stop(): Promise<void>;
}

async function freeUdpPort(): Promise<number> {
  const s = dgram.createSocket('udp4');
  await new Promise<void>((resolve) => s.bind(0, '127.0.0.1', resolve));
  const port = s.address().port;
  await new Promise<void>((resolve) =>
    s.close(() => {
      resolve();
    }),
  );
  return port;
}

/** A STUN binding request: answered once coturn listens. */
function stunPing(port: number, timeoutMs: number): Promise<boolean> {
  return new Promise((resolve) => {
    const s = dgram.createSocket('udp4');
    const req = Buffer.alloc(20);
    req.writeUInt16BE(0x0001, 0);
    req.writeUInt32BE(0x2112a442, 4);
    for (let i = 8; i < 20; i++) req[i] = i;
    const done = (ok: boolean) => {
      clearTimeout(timer);
      s.close();
      resolve(ok);
    };
    const timer = setTimeout(() => {
      done(false);
    }, timeoutMs);
    s.on('message', () => {
      done(true);
    });
    s.on('error', () => {
      done(false);
    });
    s.send(req, port, '127.0.0.1');
  });
}

/** Starts coturn; resolves once it answers STUN on 127.0.0.1 (rejects after ~10 s). */
export async function startTurnServer(binary: string): Promise<TurnServer> {
  const dir = mkdtempSync(path.join(tmpdir(), 'fixedstep-turn-'));
  const port = await freeUdpPort();
  const minPort = 20000 + ((port * 7) % 30000);
  const username = 'fixedstep';
  const credential = 'loopback-only';
  const child: ChildProcess = spawn(
    binary,
    [
      '-n',
      '--listening-ip=127.0.0.1',
      '--relay-ip=127.0.0.1',
      `--listening-port=${port}`,
      `--min-port=${minPort}`,
      `--max-port=${minPort + 200}`,
      '--lt-cred-mech',
      `--user=${username}:${credential}`,
      '--realm=fixedstep.test',
      '--allow-loopback-peers',
      '--no-tcp',
      '--no-tls',
      '--no-dtls',
      '--no-cli',
      '--no-tcp-relay',
      '--fingerprint',
      `--userdb=${path.join(dir, 'turndb')}`,
      `--pidfile=${path.join(dir, 'turnserver.pid')}`,
      '--log-file=stdout',
      '--simple-log',
    ],
    { stdio: ['ignore', 'pipe', 'pipe'] },
  );
  let log = '';
  child.stdout?.on('data', (d: Buffer) => {
    log = (log + d.toString()).slice(-4000);
  });
  child.stderr?.on('data', (d: Buffer) => {
    log = (log + d.toString()).slice(-4000);
  });
  const exited = new Promise<void>((resolve) =>
    child.once('exit', () => {
      resolve();
    }),
  );
  const stop = async () => {
    if (child.exitCode === null && child.signalCode === null) child.kill('SIGTERM');
    await exited;
    rmSync(dir, { recursive: true, force: true });
  };
  for (let i = 0; i < 50; i++) {
    if (child.exitCode !== null) break;
    if (await stunPing(port, 200)) {
      return {
        port,
        username,
        credential,
        iceServers: (p = port) => [
          { urls: [`turn:127.0.0.1:${p}?transport=udp`], username, credential },
        ],
        stop,
      };
    }
  }
  await stop();
  throw new Error(`coturn did not start on 127.0.0.1:${port}:\n${log}`);
}
