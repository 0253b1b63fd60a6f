import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import {
  LockstepSession,
  RollbackSession,
  SpectatorSession,
  decodeFrame,
  encodeMessage,
  hex64,
  performanceClock,
  type NetSession,
  type NetSessionOptions,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { run } from '@fixedstep/cli';
import { startServer, type RunningServer } from '@fixedstep/server';
import { attachRelay, connectNodeWebSocket, type RelayEndpoint } from '../src/relay/index.js';

let dir: string;
let server: RunningServer;
let endpoint: RelayEndpoint;

beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-net-'));
  await writeFile(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
  server = await startServer({ port: 0, host: '127.0.0.1', root: dir });
  endpoint = attachRelay(server.server, { startDelayMs: 300 });
});

afterAll(async () => {
  await endpoint.close();
  await server.close();
  await rm(dir, { recursive: true, force: true });
});

const wsUrl = () => `ws://127.0.0.1:${server.port}/ws`;

describe('the relay over real WebSockets on 127.0.0.1', () => {
  it('plays a short match: lockstep, rollback and a spectator end on the same hash', async () => {
    const ticks = 240;
    const clock = performanceClock();
    const sessions: NetSession[] = [];
    // Frames from a timer, as a Node client (or a throttled tab) would run them.
    const timer = setInterval(() => {
      for (const s of sessions) s.frame();
    }, 8);
    const welcomed = async () => {
      while (sessions[0]!.welcome === undefined) await new Promise((r) => setTimeout(r, 10));
    };
    for (const kind of ['lockstep', 'rollback', 'spectator'] as const) {
      // The spectator brings the invite token a player got in its welcome.
      if (kind === 'spectator') await welcomed();
      const transport = await connectNodeWebSocket(
        // The room in the URL, as a load balancer routes it.
        kind === 'rollback' ? `${wsUrl()}/ws-match` : wsUrl(),
      );
      let slot = 0;
      const options: NetSessionOptions = {
        transport,
        clock,
        room: 'ws-match',
        game: 'ctf',
        gameVersion: ctfGame.info.version,
        input: ctfGame.input,
        players: 2,
        seed: 77,
        stopAt: ticks,
        createSimulation: (w) => {
          slot = w.slot;
          return ctfGame.create(ctfGame.decodeConfig(w.config));
        },
        localInput: (_tick, sim) => ctfGame.bot(sim as Game, slot),
        ...(kind === 'spectator' ? { invite: sessions[0]!.welcome!.invite } : {}),
      };
      sessions.push(
        kind === 'lockstep'
          ? new LockstepSession(options)
          : kind === 'rollback'
            ? new RollbackSession(options)
            : new SpectatorSession(options),
      );
    }
    try {
      await expect
        .poll(() => sessions.every((s) => s.isFinished), { timeout: 20_000, interval: 50 })
        .toBe(true);
    } finally {
      clearInterval(timer);
    }
    const hashes = sessions.map((s) => hex64(s.hashAt(ticks)!));
    expect(new Set(hashes).size).toBe(1);
    const room = endpoint.relay.room('ws-match')!;
    expect(room.closedTick).toBeGreaterThanOrEqual(ticks);
    expect(room.hashChecks).toBeGreaterThanOrEqual(7);
    expect(room.desyncs).toHaveLength(0);
    for (const s of sessions) {
      expect(s.errors).toEqual([]);
      expect(s.stats.rtt).toBeLessThan(50);
    }
    for (const s of sessions) s.leave();
    await expect.poll(() => endpoint.relay.room('ws-match')?.members.length ?? 0).toBe(0);
  });

  it('shares the port with the lab, refuses other upgrade paths and text frames', async () => {
    expect(await (await fetch(server.url.replace('localhost', '127.0.0.1'))).text()).toContain(
      'lab',
    );
    const status = await new Promise<number>((resolve) => {
      const ws = new WebSocket(`ws://127.0.0.1:${server.port}/other`);
      ws.on('unexpected-response', (_req, res) => {
        resolve(res.statusCode ?? 0);
      });
      ws.on('error', () => undefined);
    });
    expect(status).toBe(404);
    // A text frame: refused as on every surface (binary protocols only), close code 1003.
    const closed = await new Promise<{ code: number }>((resolve) => {
      const ws = new WebSocket(wsUrl());
      ws.on('open', () => {
        ws.send('hello as text');
      });
      ws.on('close', (code) => {
        resolve({ code });
      });
    });
    expect(closed.code).toBe(1003);
    // A binary message over the frame limit never reaches the relay: ws closes with 1009.
    const tooBig = await new Promise<number>((resolve) => {
      const ws = new WebSocket(wsUrl());
      ws.on('open', () => {
        ws.send(new Uint8Array((1 << 20) + 2048));
      });
      ws.on('close', (code) => {
        resolve(code);
      });
      ws.on('error', () => undefined);
    });
    expect(tooBig).toBe(1009);
  });

  it('`fixedstep serve` attaches the relay at /ws', async () => {
    let stop!: () => void;
    const stopped = new Promise<void>((resolve) => (stop = resolve));
    let out = '';
    const done = run(
      ['serve', '--root', dir, '--data', dir, '--port', '0'],
      {},
      {
        out: (t) => (out += t),
        err: () => undefined,
        stopSignal: stopped,
      },
    );
    await expect.poll(() => out).toMatch(/http:\/\/localhost:\d+\//);
    const port = /localhost:(\d+)/.exec(out)![1]!;
    const reply = await new Promise<string>((resolve, reject) => {
      const ws = new WebSocket(`ws://127.0.0.1:${port}/ws`);
      ws.on('open', () => {
        ws.send(encodeMessage({ type: 'ping', id: 7, time: 1 }));
      });
      ws.on('message', (data: Buffer) => {
        resolve(decodeFrame(new Uint8Array(data))[0]!.type);
        ws.close();
      });
      ws.on('error', reject);
    });
    expect(reply).toBe('pong');
    stop();
    expect(await done).toBe(0);
  });
});
