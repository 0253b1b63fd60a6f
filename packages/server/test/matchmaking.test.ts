/**
 * Quick match: the queue core on a manual clock (pairing, waiting for a third, versions and
 * schemas kept apart, timeouts, cancels, caps, garbage), the JSON codec's refusals, and over real
 * sockets on 127.0.0.1: two Node clients matched through `createServer`'s `/match`, then playing
 * a lockstep match in the relay room they were given, ending on the same hash.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import {
  LockstepSession,
  ManualClock,
  MatchmakingError,
  decodeMatchClientMessage,
  decodeMatchServerMessage,
  hex64,
  performanceClock,
  quickMatch,
  type MatchQueueRequest,
  type MatchServerMessage,
  type QuickMatchResult,
  type RelayCatalog,
  type RelayGame,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { createServer, type FixedstepServer } from '../src/index.js';
import { MatchQueue } from '../src/match/index.js';

const INPUT = '0123456789abcdef';
const duel = (version: number): RelayGame =>
  ({
    id: 'duel',
    version,
    tickRate: 60,
    minPlayers: 1,
    maxPlayers: 4,
    input: { id: INPUT },
  }) as unknown as RelayGame;
/** A catalog that plays versions 1 and 2 of "duel", to show the queue keeps them apart. */
const catalog: RelayCatalog = (id, version) =>
  id === 'duel' && (version === 1 || version === 2)
    ? duel(version)
    : id === 'duel'
      ? { code: 'GAME_MISMATCH', message: `no duel version ${version}` }
      : { code: 'UNKNOWN_GAME', message: `no game "${id}" on this server` };

const req = (over: Partial<MatchQueueRequest> = {}): MatchQueueRequest => ({
  type: 'queue',
  game: 'duel',
  gameVersion: 1,
  input: INPUT,
  minPlayers: 2,
  maxPlayers: 2,
  timeoutMs: 10_000,
  ...over,
});

function makeQueue(limits = {}) {
  const clock = new ManualClock(1000);
  let n = 0;
  const queue = new MatchQueue<string>({
    clock,
    catalog,
    limits,
    randomBytes: (k) => new Uint8Array(k).fill(++n),
  });
  return { clock, queue };
}

describe('the quick-match queue (no sockets, a manual clock)', () => {
  it('pairs two players of the same game at once, in the order they queued', () => {
    const { queue } = makeQueue();
    const a = queue.join(req(), '10.0.0.1', 'a');
    expect(a).toEqual({ ok: true, ticket: 1, timeoutMs: 10_000 });
    expect(queue.size).toBe(1);
    const b = queue.join(req(), '10.0.0.2', 'b');
    if (!b.ok || !b.match) throw new Error(`no match: ${JSON.stringify(b)}`);
    expect(b.match.players).toBe(2);
    expect(b.match.members.map((m) => [m.data, m.order])).toEqual([
      ['a', 0],
      ['b', 1],
    ]);
    // qm- and 18 bytes in base64url: within the relay's room names.
    expect(b.match.room).toBe(`qm-${Buffer.alloc(18, 1).toString('base64url')}`);
    expect(b.match.room).toMatch(/^[A-Za-z0-9_.-]{1,32}$/);
    expect(queue.size).toBe(0);
    expect(queue.waitingFrom('10.0.0.1')).toBe(0);
  });

  it('waits for a third when min is 3, and takes the largest count the waiting accept', () => {
    const { queue } = makeQueue();
    expect(queue.join(req({ minPlayers: 3, maxPlayers: 3 }), 'x', 'a')).not.toHaveProperty('match');
    expect(queue.join(req({ minPlayers: 3, maxPlayers: 4 }), 'x', 'b')).not.toHaveProperty('match');
    // A player who only wants a duel does not fit a room of 3: it waits too.
    expect(queue.join(req({ minPlayers: 2, maxPlayers: 2 }), 'y', 'c')).not.toHaveProperty('match');
    expect(queue.size).toBe(3);
    const d = queue.join(req({ minPlayers: 2, maxPlayers: 4 }), 'z', 'd');
    if (!d.ok || !d.match) throw new Error('no match');
    expect(d.match.players).toBe(3);
    expect(d.match.members.map((m) => m.data)).toEqual(['a', 'b', 'd']);
    expect(queue.size).toBe(1); // c still waits for another duellist
  });

  it('never matches other versions or input schemas', () => {
    const { queue } = makeQueue();
    expect(queue.join(req({ gameVersion: 1 }), 'x', 'v1')).not.toHaveProperty('match');
    expect(queue.join(req({ gameVersion: 2 }), 'y', 'v2')).not.toHaveProperty('match');
    expect(queue.size).toBe(2);
    expect(queue.join(req({ gameVersion: 3 }), 'z', 'v3')).toEqual({
      ok: false,
      code: 'GAME_MISMATCH',
      message: 'no duel version 3',
    });
    expect(queue.join(req({ input: 'ffffffffffffffff' }), 'z', 's')).toMatchObject({
      ok: false,
      code: 'GAME_MISMATCH',
    });
    expect(queue.join(req({ game: 'chess' }), 'z', 'c')).toMatchObject({
      ok: false,
      code: 'UNKNOWN_GAME',
    });
    const v2 = queue.join(req({ gameVersion: 2 }), 'z', 'v2b');
    expect(v2.ok && v2.match?.members.map((m) => m.data)).toEqual(['v2', 'v2b']);
  });

  it('times a waiting player out on its deadline, capped by maxTimeoutMs', () => {
    const { clock, queue } = makeQueue({ maxTimeoutMs: 5000 });
    expect(queue.join(req({ timeoutMs: 3000 }), 'x', 'short')).toMatchObject({ timeoutMs: 3000 });
    expect(queue.join(req({ timeoutMs: 60_000, gameVersion: 2 }), 'y', 'long')).toMatchObject({
      timeoutMs: 5000,
    });
    clock.advance(2999);
    expect(queue.expire()).toEqual([]);
    clock.advance(1);
    expect(queue.expire().map((m) => m.data)).toEqual(['short']);
    clock.advance(2000);
    expect(queue.expire().map((m) => m.data)).toEqual(['long']);
    expect(queue.size).toBe(0);
    // An expired player is not matched with a newcomer.
    expect(queue.join(req(), 'z', 'late')).not.toHaveProperty('match');
  });

  it('cancels: a cancelled player is never matched', () => {
    const { queue } = makeQueue();
    const a = queue.join(req(), 'x', 'a');
    if (!a.ok) throw new Error('refused');
    expect(queue.cancel(a.ticket)).toBe(true);
    expect(queue.cancel(a.ticket)).toBe(false);
    expect(queue.size).toBe(0);
    expect(queue.join(req(), 'y', 'b')).not.toHaveProperty('match');
  });

  it('caps waiting players in total and per address', () => {
    const { queue } = makeQueue({ maxWaiting: 3, maxWaitingPerAddress: 2 });
    const three = req({ minPlayers: 4, maxPlayers: 4 });
    expect(queue.join(three, 'x', '1')).toMatchObject({ ok: true });
    expect(queue.join(three, 'x', '2')).toMatchObject({ ok: true });
    expect(queue.join(three, 'x', '3')).toEqual({
      ok: false,
      code: 'TOO_MANY_FROM_ADDRESS',
      message: 'at most 2 players wait from one address',
    });
    expect(queue.join(three, 'y', '3')).toMatchObject({ ok: true });
    expect(queue.join(three, 'z', '4')).toEqual({
      ok: false,
      code: 'QUEUE_FULL',
      message: 'the queue is full (3 waiting)',
    });
    expect(queue.clear()).toEqual(['1', '2', '3']);
    expect(queue.waitingFrom('x')).toBe(0);
  });

  it('refuses garbage with a clear reason', () => {
    const { queue } = makeQueue();
    expect(queue.join(req({ minPlayers: 3, maxPlayers: 2 }), 'x', 'a')).toMatchObject({
      code: 'BAD_PLAYERS',
      message: 'minPlayers 3 and maxPlayers 2 are not a range of player counts',
    });
    expect(queue.join(req({ minPlayers: Number.NaN }), 'x', 'a')).toMatchObject({
      code: 'BAD_PLAYERS',
    });
    expect(queue.join(req({ maxPlayers: 5 }), 'x', 'a')).toMatchObject({
      code: 'BAD_PLAYERS',
      message: 'duel is played by 1 to 4 players, not 2 to 5',
    });
    expect(queue.join(req({ timeoutMs: 0 }), 'x', 'a')).toMatchObject({ code: 'BAD_MESSAGE' });
    expect(
      queue.join({ ...req(), game: 7 } as unknown as MatchQueueRequest, 'x', 'a'),
    ).toMatchObject({ code: 'BAD_MESSAGE' });
    expect(queue.size).toBe(0);
    expect(
      () => new MatchQueue({ clock: new ManualClock(), catalog, limits: { maxWaiting: 0 } }),
    ).toThrow('matchmaking limit maxWaiting must be a positive integer, got 0');
  });

  it('decodes only well-formed messages, naming what is wrong', () => {
    const bad = (text: string) => () => decodeMatchClientMessage(text);
    expect(decodeMatchClientMessage(JSON.stringify(req()))).toEqual(req());
    expect(decodeMatchClientMessage('{"type":"cancel"}')).toEqual({ type: 'cancel' });
    expect(bad('not json')).toThrow('a matchmaking message is JSON; this frame is not');
    expect(bad('[1]')).toThrow('a matchmaking message is a JSON object');
    expect(bad('{"type":"dance"}')).toThrow('unknown message type "dance"');
    expect(bad(JSON.stringify({ ...req(), extra: 1 }))).toThrow(
      'a "queue" message has no field "extra"',
    );
    expect(bad(JSON.stringify({ ...req(), minPlayers: 1.5 }))).toThrow(
      '"minPlayers" must be an integer from 1 to 16, got 1.5',
    );
    expect(bad(JSON.stringify({ ...req(), game: 'no spaces' }))).toThrow('"game" must be');
    expect(bad(JSON.stringify({ ...req(), input: 'XYZ' }))).toThrow('"input" must be 16');
    expect(bad(JSON.stringify({ ...req(), minPlayers: 4, maxPlayers: 2 }))).toThrow(
      'minPlayers (4) is above maxPlayers (2)',
    );
    expect(bad(`{"type":"cancel","pad":"${'x'.repeat(600)}"}`)).toThrow('at most 512 bytes');
    expect(bad('{"type":"cancel","__proto__":{"x":1}}')).toThrow('has no field "__proto__"');
    const e = (() => {
      try {
        decodeMatchClientMessage('{');
      } catch (error) {
        return error;
      }
      return undefined;
    })();
    expect(e).toBeInstanceOf(MatchmakingError);
    expect((e as MatchmakingError).code).toBe('BAD_MESSAGE');
    expect(
      decodeMatchServerMessage('{"type":"matched","room":"qm-x","players":2,"order":1}'),
    ).toEqual({ type: 'matched', room: 'qm-x', players: 2, order: 1 });
    expect(() =>
      decodeMatchServerMessage('{"type":"matched","room":"qm-x","players":2,"order":2}'),
    ).toThrow('"order" must be an integer from 0 to 1, got 2');
  });
});

describe('quick match over real sockets through createServer', () => {
  let server: FixedstepServer;
  let base: string;
  const clock = new ManualClock(0);
  const WS = WebSocket as unknown as new (url: string) => globalThis.WebSocket;
  const ctf = {
    game: ctfGame.id,
    gameVersion: ctfGame.version,
    input: ctfGame.input,
  };

  beforeAll(async () => {
    server = await createServer({
      port: 0,
      stateSync: false,
      signalling: false,
      games: [ctfGame],
      matchmaking: { clock, limits: { maxWaitingPerAddress: 3 } },
    });
    base = `ws://127.0.0.1:${server.port}`;
  }, 60_000);
  afterAll(async () => {
    await server.close();
  });

  /** Opens a raw client, sends `frames`, and collects what the server says until it closes. */
  function raw(frames: (string | Uint8Array)[]) {
    const ws = new WebSocket(`${base}/match`);
    const got: MatchServerMessage[] = [];
    const closed = new Promise<number>((resolve) => ws.on('close', resolve));
    ws.on('open', () => {
      for (const f of frames) ws.send(f);
    });
    ws.on('message', (data: Buffer) => got.push(decodeMatchServerMessage(data.toString())));
    return { ws, got, closed };
  }

  it('matches two Node clients, who then play a lockstep match in their room', async () => {
    const options = { url: `${base}/match`, ...ctf, minPlayers: 2, WebSocketClass: WS };
    let queued = 0;
    const first = quickMatch({ ...options, onQueued: () => queued++ });
    await expect.poll(() => queued).toBe(1);
    expect(server.matchmaking?.queue.size).toBe(1);
    const second = quickMatch(options);
    const results: QuickMatchResult[] = await Promise.all([first, second]);
    expect(results[0]!.room).toBe(results[1]!.room);
    expect(results.map((r) => [r.players, r.order])).toEqual([
      [2, 0],
      [2, 1],
    ]);
    expect(results[0]!.room).toMatch(/^qm-[A-Za-z0-9_-]{24}$/);
    expect(server.matchmaking?.queue.size).toBe(0);

    const { connectNodeWebSocket } = await import('../src/relay/index.js');
    const ticks = 180;
    const sessions: LockstepSession[] = [];
    for (const match of results) {
      const transport = await connectNodeWebSocket(`${base}/ws/${match.room}`);
      let slot = 0;
      sessions.push(
        new LockstepSession({
          transport,
          clock: performanceClock(),
          room: match.room,
          game: ctfGame.id,
          gameVersion: ctfGame.version,
          input: ctfGame.input,
          players: match.players,
          stopAt: ticks,
          createSimulation: (w) => {
            slot = w.slot;
            return ctfGame.create(ctfGame.decodeConfig(w.config));
          },
          localInput: (_tick, sim) => ctfGame.bot(sim as Game, slot),
        }),
      );
    }
    const timer = setInterval(() => {
      for (const s of sessions) s.frame();
    }, 8);
    try {
      await expect
        .poll(() => sessions.every((s) => s.finished), { timeout: 30_000, interval: 50 })
        .toBe(true);
    } finally {
      clearInterval(timer);
    }
    const hashes = sessions.map((s) => hex64(s.hashAt(ticks)!));
    expect(hashes[0]).toBe(hashes[1]);
    const room = server.relay!.relay.room(results[0]!.room)!;
    expect(room.desyncs).toHaveLength(0);
    expect(room.hashChecks).toBeGreaterThanOrEqual(1);
    for (const s of sessions) {
      expect(s.errors).toEqual([]);
      s.leave();
    }
  });

  it('answers no-match on the deadline, and cancels on abort and on close', async () => {
    const none = quickMatch({
      url: `${base}/match`,
      ...ctf,
      minPlayers: 2,
      timeoutMs: 5000,
      WebSocketClass: WS,
    });
    await expect.poll(() => server.matchmaking?.queue.size).toBe(1);
    clock.advance(5000);
    await expect(none).rejects.toMatchObject({ code: 'NO_MATCH' });
    expect(server.matchmaking?.queue.size).toBe(0);

    const abort = new AbortController();
    const aborted = quickMatch({
      url: `${base}/match`,
      ...ctf,
      minPlayers: 2,
      signal: abort.signal,
      WebSocketClass: WS,
    });
    await expect.poll(() => server.matchmaking?.queue.size).toBe(1);
    abort.abort(new Error('the player left'));
    await expect(aborted).rejects.toThrow('the player left');
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);

    const c = raw([
      JSON.stringify({
        ...req(),
        game: 'ctf',
        gameVersion: ctfGame.version,
        input: ctfGame.input.id,
      }),
    ]);
    await expect.poll(() => c.got.length).toBe(1);
    expect(c.got[0]).toEqual({ type: 'queued', timeoutMs: 10_000 });
    c.ws.terminate();
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);
  });

  it('caps waiting players per address with a message, and connections with HTTP 429', async () => {
    const four = JSON.stringify(
      req({
        game: 'ctf',
        gameVersion: ctfGame.version,
        input: ctfGame.input.id,
        minPlayers: 4,
        maxPlayers: 4,
      }),
    );
    // maxWaitingPerAddress is 3 on this server: three wait, the fourth hears why.
    const waiting = [raw([four]), raw([four]), raw([four])];
    await expect.poll(() => server.matchmaking?.queue.size).toBe(3);
    const fourth = raw([four]);
    expect(await fourth.closed).toBe(1000);
    expect(fourth.got).toEqual([
      {
        type: 'error',
        code: 'TOO_MANY_FROM_ADDRESS',
        message: 'at most 3 players wait from one address',
      },
    ]);
    await expect.poll(() => server.matchmaking?.connections).toBe(3);
    // Connections are capped at twice that: 3 more idle ones fit, the next upgrade gets 429.
    const idle = [raw([]), raw([]), raw([])];
    await Promise.all(idle.map((c) => new Promise((resolve) => c.ws.once('open', resolve))));
    const status = await new Promise<number>((resolve) => {
      const ws = new WebSocket(`${base}/match`);
      ws.on('unexpected-response', (_req, res) => {
        resolve(res.statusCode ?? 0);
      });
      ws.on('error', () => undefined);
    });
    expect(status).toBe(429);
    for (const c of [...waiting, ...idle]) c.ws.terminate();
    await Promise.all([...waiting, ...idle].map((c) => c.closed));
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);
  });

  it('refuses garbage, unknown games and a second request with a clear error', async () => {
    const cases: [(string | Uint8Array)[], string, string][] = [
      [['hello?'], 'BAD_MESSAGE', 'a matchmaking message is JSON; this frame is not'],
      [[new Uint8Array([1, 2, 3])], 'BAD_MESSAGE', 'JSON text frames, not binary'],
      [[JSON.stringify(req())], 'UNKNOWN_GAME', 'no game "duel" on this server'],
      [
        [JSON.stringify({ ...req({ game: 'ctf', gameVersion: ctfGame.version + 1 }) })],
        'GAME_MISMATCH',
        `this server plays ctf version ${ctfGame.version}`,
      ],
    ];
    for (const [frames, code, message] of cases) {
      const c = raw(frames);
      expect(await c.closed).toBe(1000);
      expect(c.got).toHaveLength(1);
      expect(c.got[0]).toMatchObject({ type: 'error', code });
      expect((c.got[0] as { message: string }).message).toContain(message);
    }
    const ok = JSON.stringify(
      req({
        game: 'ctf',
        gameVersion: ctfGame.version,
        input: ctfGame.input.id,
        minPlayers: 2,
        maxPlayers: 2,
      }),
    );
    const twice = raw([ok, ok]);
    expect(await twice.closed).toBe(1000);
    expect(twice.got.map((m) => m.type)).toEqual(['queued', 'error']);
    expect(server.matchmaking?.queue.size).toBe(0);
    // A frame over the byte limit never reaches the decoder: ws closes with 1009.
    const big = raw([`{"type":"cancel","x":"${'y'.repeat(1000)}"}`]);
    expect(await big.closed).toBe(1009);
    // The relay still answers beside it, and unknown paths still get 404.
    const status = await new Promise<number>((resolve) => {
      const ws = new WebSocket(`${base}/matchmaking`);
      ws.on('unexpected-response', (_req, res) => {
        resolve(res.statusCode ?? 0);
      });
      ws.on('error', () => undefined);
    });
    expect(status).toBe(404);
  });
});
