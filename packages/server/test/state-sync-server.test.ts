/**
 * State-sync rooms on the HTTP server, over real WebSockets on 127.0.0.1: rooms run in worker
 * threads (many per worker), so a room that is busy — or broken — holds up neither the HTTP server
 * nor the rooms of other workers.
 */
import { mkdtemp, rm, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import { ServerMetrics } from '../src/http/metrics.js';
import WebSocket from 'ws';
import {
  StateSyncSession,
  decodeStateSyncMessage,
  encodeStateSyncMessage,
  fnv1a64,
  hex64,
  performanceClock,
  type ButtonInput,
  type GameDefinition,
  type Simulation,
  type StateSyncEvent,
  type StateSyncMessage,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { startServer, type RunningServer } from '@fixedstep/server';
import { connectNodeWebSocket } from '../src/relay/index.js';
import {
  attachStateSync,
  type StateSyncEndpoint,
  type StateSyncEndpointOptions,
} from '../src/state-sync/index.js';
import { GAMES as TEST_GAMES } from './state-sync-games.js';

let dir: string;

beforeAll(async () => {
  dir = await mkdtemp(path.join(os.tmpdir(), 'fixedstep-state-'));
  await writeFile(path.join(dir, 'index.html'), '<!doctype html><title>lab</title>');
});

afterAll(async () => {
  await rm(dir, { recursive: true, force: true });
});

/** A client session driven by a timer, as a Node client would run one. */
async function client<S extends Simulation>(
  url: string,
  room: string,
  game: GameDefinition<ButtonInput, S>,
  extra: {
    players?: number;
    events?: StateSyncEvent[];
    /** The client's own copy of the game (default: the game's own). */
    local?: GameDefinition<ButtonInput, S>;
    /** The address to connect from (127/8: each a client of its own). Default 127.0.0.1. */
    address?: string;
    /** Each snapshot's tick and base, as it arrives. */
    snapshots?: { tick: number; base: number }[];
  } = {},
): Promise<{ session: StateSyncSession<ButtonInput, S>; stop: () => void }> {
  const transport = await connectNodeWebSocket(`${url}/${room}`, {
    ...(extra.address !== undefined ? { localAddress: extra.address } : {}),
  });
  const local = extra.local ?? game;
  const seen = extra.snapshots;
  if (seen) {
    const onMessage = transport.onMessage.bind(transport);
    transport.onMessage = (handler) => {
      onMessage((bytes) => {
        const m = decodeStateSyncMessage(bytes);
        if (m.type === 'snapshot') seen.push({ tick: m.tick, base: m.base });
        handler(bytes);
      });
    };
  }
  const session: StateSyncSession<ButtonInput, S> = new StateSyncSession<ButtonInput, S>({
    transport,
    clock: performanceClock(),
    room,
    game,
    players: extra.players ?? 2,
    seed: 5,
    createSimulation: (setup) => local.create(setup),
    localInput: (tick, sim): ButtonInput =>
      game.bot ? game.bot(sim, session.welcome?.slot ?? 0) : tick & 1,
    onEvent: (e) => extra.events?.push(e),
  });
  const timer = setInterval(() => session.frame(), 8);
  return {
    session,
    stop: () => {
      clearInterval(timer);
      session.leave();
    },
  };
}

/** A server serving the test folder with state-sync rooms at `/state` (`options`), ready. */
async function startStateSync(
  options: StateSyncEndpointOptions,
): Promise<{ server: RunningServer; endpoint: StateSyncEndpoint; url: string }> {
  const server = await startServer({ port: 0, host: '127.0.0.1', root: dir });
  const endpoint = attachStateSync(server.server, options);
  await endpoint.ready;
  return { server, endpoint, url: `ws://127.0.0.1:${server.port}/state` };
}

async function stopStateSync(server: RunningServer, endpoint: StateSyncEndpoint): Promise<void> {
  await endpoint.close();
  await server.close();
}

describe('state-sync rooms of the talk’s games', () => {
  let server: RunningServer;
  let endpoint: StateSyncEndpoint;
  let url: string;
  beforeAll(async () => {
    ({ server, endpoint, url } = await startStateSync({ workers: 1 }));
  }, 60_000);
  afterAll(() => stopStateSync(server, endpoint));

  it('two clients play capture the flag through a worker and hold the same server world', async () => {
    const snapshots: { tick: number; base: number }[] = [];
    const a = await client<Game>(url, 'duel', ctfGame, { snapshots });
    const b = await client<Game>(url, 'duel', ctfGame);
    try {
      await expect
        .poll(() => Math.min(a.session.snapshotTick, b.session.snapshotTick), {
          timeout: 30_000,
          interval: 50,
        })
        .toBeGreaterThanOrEqual(180);
      // A tick both hold: the server sent both the same world.
      const every = a.session.welcome!.snapshotEvery;
      const t =
        Math.floor(Math.min(a.session.snapshotTick, b.session.snapshotTick) / every) * every;
      const ha = a.session.snapshotAt(t);
      const hb = b.session.snapshotAt(t);
      expect(ha && hex64(fnv1a64(ha))).toBe(hb && hex64(fnv1a64(hb)));
      expect(new Set([a.session.welcome?.slot, b.session.welcome?.slot])).toEqual(new Set([0, 1]));
      for (const s of [a.session, b.session]) {
        expect(s.errors).toEqual([]);
        expect(s.stats.badSnapshots).toBe(0);
        expect(s.stats.deltaSnapshots).toBeGreaterThan(30);
        expect(s.stats.rtt).toBeLessThan(100);
        // Predicting ahead of the newest snapshot, its own player at the server's clock.
        expect(s.tick).toBeGreaterThan(s.snapshotTick);
      }
      expect(endpoint.rooms()).toEqual([{ room: 'duel', worker: 0 }]);
      // A WebSocket delivers in order: after the whole one a join brings (and the first delta,
      // from it), each snapshot is coded against the one sent before it.
      expect(snapshots[0]!.base).toBe(-1);
      expect(snapshots.slice(2).map((m) => m.tick - m.base)).toEqual(
        snapshots.slice(2).map(() => every),
      );

      // What /metrics reads: the worker's report (every second) of its rooms and counters.
      const metrics = new ServerMetrics({ defaultMetrics: false });
      metrics.watchStateSync(endpoint);
      await expect
        .poll(() => endpoint.stats.ticks, { timeout: 30_000, interval: 50 })
        .toBeGreaterThanOrEqual(180);
      const stats = endpoint.stats;
      expect(stats).toMatchObject({ rooms: 1, players: 2 });
      expect(stats.snapshotBytes).toBeGreaterThan(30 * 20);
      const text = await metrics.registry.metrics();
      const value = (name: string) =>
        Number(
          text
            .split('\n')
            .find((l) => l.startsWith(`${name} `))
            ?.split(' ')[1],
        );
      expect(value('fixedstep_state_sync_rooms')).toBe(1);
      expect(value('fixedstep_state_sync_players')).toBe(2);
      expect(value('fixedstep_state_sync_ticks_total')).toBeGreaterThanOrEqual(stats.ticks);
      expect(value('fixedstep_state_sync_snapshot_bytes_total')).toBeGreaterThanOrEqual(
        stats.snapshotBytes,
      );
      expect(text).toContain('fixedstep_state_sync_late_inputs_total');
      expect(text).toContain('fixedstep_state_sync_filled_inputs_total');
    } finally {
      a.stop();
      b.stop();
    }
  });

  it('refuses other paths, bad room names, text frames, and a join for another room', async () => {
    const status = (p: string) =>
      new Promise<number>((resolve) => {
        const ws = new WebSocket(`ws://127.0.0.1:${server.port}${p}`);
        ws.on('unexpected-response', (_req, res) => {
          resolve(res.statusCode ?? 0);
        });
        ws.on('error', () => undefined);
      });
    expect(await status('/other')).toBe(404);
    expect(await status('/state/a%20b')).toBe(400);
    expect(await status('/state/')).toBe(400);
    const closed = await new Promise<number>((resolve) => {
      const ws = new WebSocket(`${url}/text-room`);
      ws.on('open', () => {
        ws.send('hello as text');
      });
      ws.on('close', (code) => {
        resolve(code);
      });
    });
    expect(closed).toBe(1003);
    // A join naming another room than the path's, and one for a game the server does not have.
    const answer = (room: string, join: Partial<Extract<StateSyncMessage, { type: 'join' }>>) =>
      new Promise<StateSyncMessage>((resolve) => {
        const ws = new WebSocket(`${url}/${room}`);
        ws.on('open', () => {
          ws.send(
            encodeStateSyncMessage({
              type: 'join',
              room,
              role: 'player',
              game: 'ctf',
              gameVersion: ctfGame.version,
              input: ctfGame.input.id,
              players: 2,
              name: 'x',
              ...join,
            }),
          );
        });
        ws.on('message', (data) => {
          resolve(decodeStateSyncMessage(new Uint8Array(data as Buffer)));
          ws.close();
        });
      });
    expect(await answer('room-a', { room: 'room-b' })).toMatchObject({
      type: 'error',
      code: 'WRONG_ROOM',
      fatal: true,
      message: 'this connection is for room room-a, not room-b',
    });
    expect(await answer('room-c', { game: 'chess' })).toMatchObject({
      type: 'error',
      code: 'UNKNOWN_GAME',
      message: 'no game "chess" on this server',
    });
  });
});

describe('state-sync rooms in a pool of workers', () => {
  let server: RunningServer;
  let endpoint: StateSyncEndpoint;
  let url: string;
  const logged: string[] = [];
  const [counter, stall, broken] = TEST_GAMES as unknown as [
    GameDefinition<ButtonInput, Simulation>,
    GameDefinition<ButtonInput, Simulation>,
    GameDefinition<ButtonInput, Simulation>,
  ];
  beforeAll(async () => {
    ({ server, endpoint, url } = await startStateSync({
      workers: 2,
      games: pathToFileURL(path.join(import.meta.dirname, 'state-sync-games.ts')).href,
      log: (m) => logged.push(m),
    }));
  }, 60_000);
  afterAll(() => stopStateSync(server, endpoint));

  it('a room that keeps its worker busy holds up neither the HTTP server nor a room on another worker', async () => {
    // The client runs a plain counter (a state-sync client need not run the server's code).
    const slow = await client(url, 'slow', stall, {
      players: 1,
      local: counter,
      address: '127.0.3.1',
    });
    const fast = await client(url, 'fast', counter, { players: 1, address: '127.0.3.2' });
    try {
      // New rooms of two addresses go to the worker with the fewest rooms: one each.
      await expect.poll(() => endpoint.rooms().length).toBe(2);
      expect(new Set(endpoint.rooms().map((r) => r.worker))).toEqual(new Set([0, 1]));
      // The slow room's step of tick 60 blocks its worker for 5 s: its snapshots stop at 60.
      await expect
        .poll(() => slow.session.snapshotTick, { timeout: 30_000, interval: 20 })
        .toBe(60);
      const from = fast.session.snapshotTick;
      // Meanwhile the HTTP server answers, and the other worker's room runs on.
      const page = await fetch(`http://127.0.0.1:${server.port}/`);
      expect(await page.text()).toContain('lab');
      await expect
        .poll(() => fast.session.snapshotTick, { timeout: 30_000, interval: 20 })
        .toBeGreaterThanOrEqual(from + 30);
      // …all while the busy worker still had not finished that one step.
      expect(slow.session.snapshotTick).toBe(60);
      // Then it catches up.
      await expect
        .poll(() => slow.session.snapshotTick, { timeout: 30_000, interval: 20 })
        .toBeGreaterThan(60);
    } finally {
      slow.stop();
      fast.stop();
    }
  });

  it("an address's rooms share a worker, so its per-address caps count them all", async () => {
    const workerOf = async (room: string) => {
      await expect.poll(() => endpoint.rooms().some((r) => r.room === room)).toBe(true);
      return endpoint.rooms().find((r) => r.room === room)!.worker;
    };
    const loads = () => {
      const n = [0, 0];
      for (const r of endpoint.rooms()) n[r.worker]!++;
      return n;
    };
    const rooms = [await client(url, 'home-1', counter, { players: 1, address: '127.0.4.1' })];
    try {
      const home = await workerOf('home-1');
      // Another address's new room goes where the fewest rooms are…
      const before = loads();
      rooms.push(await client(url, 'away-1', counter, { players: 1, address: '127.0.4.2' }));
      expect(await workerOf('away-1')).toBe(before.indexOf(Math.min(...before)));
      // …this address's next ones where its first one is, however loaded.
      for (const name of ['home-2', 'home-3']) {
        rooms.push(await client(url, name, counter, { players: 1, address: '127.0.4.1' }));
        expect(await workerOf(name)).toBe(home);
      }
    } finally {
      for (const r of rooms) r.stop();
    }
  });

  it('a game that throws closes its room (INTERNAL); the worker keeps serving', async () => {
    const events: StateSyncEvent[] = [];
    const bad = await client(url, 'bad', broken, { players: 1, events, local: counter });
    try {
      await expect.poll(() => bad.session.phase, { timeout: 30_000, interval: 20 }).toBe('closed');
      expect(bad.session.errors.map((e) => [e.code, e.fatal])).toEqual([['INTERNAL', true]]);
      expect(bad.session.errors[0]!.message).toBe('the room stopped: the counter broke at tick 30');
      expect(logged.some((m) => m.includes('room bad stopped'))).toBe(true);
      // The same worker takes a new room.
      const next = await client(url, 'after-bad', counter, { players: 1 });
      await expect
        .poll(() => next.session.snapshotTick, { timeout: 30_000, interval: 20 })
        .toBeGreaterThan(30);
      next.stop();
    } finally {
      bad.stop();
    }
  });

  it('closing says SHUTDOWN to every member', async () => {
    const events: StateSyncEvent[] = [];
    const c = await client(url, 'last', counter, { players: 1, events });
    await expect
      .poll(() => c.session.snapshotTick, { timeout: 30_000, interval: 20 })
      .toBeGreaterThan(3);
    await endpoint.close();
    await expect.poll(() => c.session.phase, { timeout: 10_000 }).toBe('closed');
    expect(c.session.errors.map((e) => e.code)).toEqual(['SHUTDOWN']);
    c.stop();
  });
});
