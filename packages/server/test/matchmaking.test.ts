/**
 * Quick match: the queue on a manual clock (the ready check, rooms filled to the largest count all
 * accept, a no-show dropped while its partner keeps its place, one address never matched with
 * itself, a ticket-holding attacker held to its share, versions kept apart, timeouts, cancels,
 * caps), the tickets (signed, bound to their room and seat, expiring), and over real sockets on
 * 127.0.0.1 through `createServer`: two Node clients matched at `/match`, then playing a lockstep
 * match in the relay room their tickets seat them in — which nobody else can set up first.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import {
  LockstepSession,
  MATCH_PROTOCOL,
  ManualClock,
  decodeFrame,
  encodeMessage,
  hex64,
  performanceClock,
  quickMatch,
  type GameCatalog,
  type HostedGame,
  type MatchQueueRequest,
  type MatchServerMessage,
  type NetMessage,
  type QuickMatchResult,
} from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { createServer, type FixedstepServer } from '../src/index.js';
import {
  MatchQueue,
  isLoopbackKey,
  MatchTickets,
  type Match,
  type MatchQueueOptions,
} from '../src/match/index.js';
import { addressKey } from '../src/http/admission.js';
import { connectNodeWebSocket } from '../src/relay/index.js';
import { frameUntilFinished } from './session-frames.js';

const INPUT = '0123456789abcdef';
const duel = (version: number): HostedGame =>
  ({
    id: 'duel',
    version,
    tickRate: 60,
    minPlayers: 1,
    maxPlayers: 4,
    input: { id: INPUT },
  }) as unknown as HostedGame;
/** A catalog that plays versions 1 and 2 of "duel", to show the queue keeps them apart. */
const catalog: GameCatalog = (id, version) =>
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

function makeQueue(limits = {}, options: Partial<MatchQueueOptions> = {}) {
  const clock = new ManualClock(1000);
  let n = 0;
  const queue = new MatchQueue<string>({
    clock,
    catalog,
    limits,
    randomBytes: (k) => new Uint8Array(k).fill(++n),
    randomU32: () => 0xc0ffee,
    ...options,
  });
  /** Sweeps; every proposal is accepted by all but `refuse`; returns the matches made. */
  const sweep = (refuse: (data: string) => boolean = () => false): Match<string>[] => {
    const matches: Match<string>[] = [];
    for (const p of queue.sweep().proposed) {
      for (const m of p.members) {
        if (refuse(m.data)) continue;
        const match = queue.accept(m.ticket);
        if (match) matches.push(match);
      }
    }
    return matches;
  };
  return { clock, queue, sweep };
}

const teams = (matches: Match<string>[]) => matches.map((m) => m.members.map((x) => x.data));

describe('the quick-match queue (no sockets, a manual clock)', () => {
  it('proposes a match, makes it once every player has accepted, in the order they queued', () => {
    const { queue } = makeQueue();
    expect(queue.join(req(), '10.0.0.1', 'a')).toEqual({ ok: true, ticket: 1, timeoutMs: 10_000 });
    expect(queue.join(req(), '10.0.0.2', 'b')).toMatchObject({ ok: true, ticket: 2 });
    const { proposed } = queue.sweep();
    expect(proposed).toHaveLength(1);
    expect(proposed[0]!.members.map((m) => m.data)).toEqual(['a', 'b']);
    expect(queue.accept(1)).toBeUndefined(); // b has not accepted yet
    const match = queue.accept(2)!;
    expect(match.players).toBe(2);
    expect(match.seed).toBe(0xc0ffee);
    expect(match.members.map((m) => [m.data, m.order])).toEqual([
      ['a', 0],
      ['b', 1],
    ]);
    // qm- and 18 bytes in base64url: within the relay's room names, made by tickets only.
    expect(match.room).toBe(`qm-${Buffer.alloc(18, 1).toString('base64url')}`);
    expect(match.room).toMatch(/^[A-Za-z0-9_.-]{1,32}$/);
    expect(queue.size).toBe(0);
    expect(queue.waitingFrom('10.0.0.1')).toBe(0);
  });

  it('fills rooms to the largest count every player accepts: ten of 2–4 make 4, 4 and 2', () => {
    const { clock, queue, sweep } = makeQueue();
    for (let i = 0; i < 10; i++) queue.join(req({ maxPlayers: 4 }), `10.0.0.${i}`, `p${i}`);
    // Two rooms of four at once; the two left wait the fill window for more before playing as two.
    expect(teams(sweep())).toEqual([
      ['p0', 'p1', 'p2', 'p3'],
      ['p4', 'p5', 'p6', 'p7'],
    ]);
    clock.advance(999);
    expect(sweep()).toEqual([]);
    clock.advance(1);
    expect(teams(sweep())).toEqual([['p8', 'p9']]);
    // A player who needs three waits for a third; one who wants a duel is not put in a room of three.
    queue.join(req({ minPlayers: 3, maxPlayers: 3 }), 'a', 'trio');
    queue.join(req(), 'b', 'duellist');
    clock.advance(5000);
    expect(sweep()).toEqual([]);
    queue.join(req({ minPlayers: 2, maxPlayers: 4 }), 'c', 'flexible');
    queue.join(req({ minPlayers: 3, maxPlayers: 4 }), 'd', 'third');
    expect(teams(sweep())).toEqual([['trio', 'flexible', 'third']]);
    expect(queue.size).toBe(1); // the duellist still waits for another
  });

  it('drops a player who does not accept; its partner keeps its place in the queue', () => {
    const { clock, queue, sweep } = makeQueue();
    queue.join(req(), '10.0.0.1', 'honest');
    queue.join(req(), '10.0.0.2', 'no-show');
    expect(sweep((d) => d === 'no-show')).toEqual([]);
    clock.advance(2999);
    expect(queue.sweep()).toEqual({ proposed: [], requeued: [], noShows: [], expired: [] });
    queue.join(req(), '10.0.0.3', 'newcomer');
    clock.advance(1);
    const s = queue.sweep();
    expect(s.noShows.map((m) => m.data)).toEqual(['no-show']);
    expect(s.requeued.map((m) => m.data)).toEqual(['honest']);
    // Back in its old place, the first in the queue: matched with the newcomer at once.
    expect(s.proposed.map((p) => p.members.map((m) => m.data))).toEqual([['honest', 'newcomer']]);
    expect(queue.waitingFrom('10.0.0.2')).toBe(0);
  });

  it('never matches an address with itself, and holds one address to two tickets', () => {
    const { queue, sweep } = makeQueue();
    expect(queue.join(req(), 'home', 'a')).toMatchObject({ ok: true });
    expect(queue.join(req(), 'home', 'b')).toMatchObject({ ok: true });
    expect(queue.join(req(), 'home', 'c')).toEqual({
      ok: false,
      code: 'ADDRESS_LIMIT',
      message: 'at most 2 players wait from one address',
    });
    expect(sweep()).toEqual([]);
    queue.join(req(), 'away', 'd');
    expect(teams(sweep())).toEqual([['a', 'd']]);
  });

  it("pairs this machine's own tabs (loopback), and only those, with each other", () => {
    expect([isLoopbackKey('127.0.0.1'), isLoopbackKey('127.4.5.6')]).toEqual([true, true]);
    expect(isLoopbackKey(addressKey('::1'))).toBe(true);
    expect([isLoopbackKey('10.0.0.1'), isLoopbackKey(addressKey('2001:db8::1'))]).toEqual([
      false,
      false,
    ]);
    const { queue, sweep } = makeQueue();
    queue.join(req(), '127.0.0.1', 'tab1');
    queue.join(req(), '127.0.0.1', 'tab2');
    expect(teams(sweep())).toEqual([['tab1', 'tab2']]);
    const strict = makeQueue({}, { matchesItself: () => false });
    strict.queue.join(req(), '127.0.0.1', 'tab1');
    strict.queue.join(req(), '127.0.0.1', 'tab2');
    expect(strict.sweep()).toEqual([]);
  });

  it('an attacker holding its tickets and re-queueing after every match captures only its share', () => {
    const { queue, sweep } = makeQueue();
    let n = 0;
    const attack = () => queue.join(req(), '203.0.113.66', `attacker${n++}`);
    attack();
    attack();
    // Twenty honest players arrive together, each from an address of its own.
    for (let i = 0; i < 20; i++) queue.join(req(), `198.51.100.${i}`, `honest${i}`);
    const withAttacker: string[][] = [];
    const honestPairs: string[][] = [];
    for (let round = 0; round < 5; round++) {
      for (const t of teams(sweep())) {
        if (t.some((d) => d.startsWith('attacker'))) {
          withAttacker.push(t);
          attack(); // straight back into the queue
        } else honestPairs.push(t);
      }
    }
    // Its two tickets were the oldest: it met two honest players, then queued behind the rest.
    expect(withAttacker).toHaveLength(2);
    expect(honestPairs).toHaveLength(9);
    expect(honestPairs.flat().every((d) => d.startsWith('honest'))).toBe(true);
  });

  it('times a waiting player out on its deadline, capped by maxTimeoutMs; cancels', () => {
    const { clock, queue, sweep } = makeQueue({ maxTimeoutMs: 5000 });
    expect(queue.join(req({ timeoutMs: 3000 }), 'x', 'short')).toMatchObject({ timeoutMs: 3000 });
    expect(queue.join(req({ timeoutMs: 60_000, gameVersion: 2 }), 'y', 'long')).toMatchObject({
      timeoutMs: 5000,
    });
    clock.advance(2999);
    expect(queue.sweep().expired).toEqual([]);
    clock.advance(1);
    expect(queue.sweep().expired.map((m) => m.data)).toEqual(['short']);
    clock.advance(2000);
    expect(queue.sweep().expired.map((m) => m.data)).toEqual(['long']);
    expect(queue.size).toBe(0);
    // A cancelled player is never matched; cancelling inside a proposal puts the other back.
    const a = queue.join(req(), 'x', 'a');
    if (!a.ok) throw new Error('refused');
    expect(queue.cancel(a.ticket)).toEqual([]);
    queue.join(req(), 'y', 'b');
    const c = queue.join(req(), 'z', 'c');
    if (!c.ok) throw new Error('refused');
    expect(queue.sweep().proposed).toHaveLength(1);
    expect(queue.cancel(c.ticket).map((m) => m.data)).toEqual(['b']);
    expect(queue.size).toBe(1);
    expect(sweep()).toEqual([]);
  });

  it('caps waiting players in total', () => {
    const { queue } = makeQueue({ maxWaiting: 3 });
    const four = req({ minPlayers: 4, maxPlayers: 4 });
    for (const a of ['x', 'y', 'z']) expect(queue.join(four, a, a)).toMatchObject({ ok: true });
    expect(queue.join(four, 'w', 'w')).toEqual({
      ok: false,
      code: 'QUEUE_FULL',
      message: 'the queue is full (3 waiting)',
    });
    expect(queue.clear()).toEqual(['x', 'y', 'z']);
    expect(
      () => new MatchQueue({ clock: new ManualClock(), catalog, limits: { maxWaiting: 0 } }),
    ).toThrow('matchmaking limit maxWaiting must be a positive integer, got 0');
  });

  it('never matches other versions or input schemas, and refuses what cannot be played', () => {
    const { queue, sweep } = makeQueue();
    queue.join(req({ gameVersion: 1 }), 'x', 'v1');
    queue.join(req({ gameVersion: 2 }), 'y', 'v2');
    expect(sweep()).toEqual([]);
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
    expect(queue.join(req({ maxPlayers: 5 }), 'z', 'c')).toMatchObject({
      code: 'BAD_PLAYERS',
      message: 'duel is played by 1 to 4 players, not 2 to 5',
    });
    queue.join(req({ gameVersion: 2 }), 'z', 'v2b');
    expect(teams(sweep())).toEqual([['v2', 'v2b']]);
  });
});

describe('match tickets', () => {
  const seat = { room: 'qm-abc', game: 'ctf', gameVersion: 3, players: 2, seed: 77, slot: 1 };

  it('carry their room, setup and seat, signed: any process with the secret checks them', () => {
    let now = 1_000_000;
    const issuer = new MatchTickets({ secret: 'a secret of this deployment', now: () => now });
    const relay = new MatchTickets({ secret: 'a secret of this deployment', now: () => now });
    const ticket = issuer.issue(seat);
    expect(relay.verify(ticket)).toEqual(seat);
    // Another deployment's secret, a flipped bit, a cut ticket: refused, saying why.
    expect(new MatchTickets({ secret: 'another deployment!!' }).verify(ticket)).toBe(
      'not signed by this deployment',
    );
    for (const at of [0, 5, ticket.length - 40, ticket.length - 1]) {
      const forged = ticket.slice();
      forged[at] = forged[at]! ^ 1;
      expect(relay.verify(forged)).toBe('not signed by this deployment');
    }
    expect(relay.verify(ticket.subarray(0, 20))).toBe('too short to be a ticket');
    now += 10 * 60_000;
    expect(relay.verify(ticket)).toBe('expired');
  });

  it('take their secret from FIXEDSTEP_MATCH_SECRET, refusing a short one', () => {
    const env = { FIXEDSTEP_MATCH_SECRET: 'sixteen chars ok' };
    const t = new MatchTickets({ env }).issue(seat);
    expect(new MatchTickets({ env }).verify(t)).toEqual(seat);
    expect(() => new MatchTickets({ env: { FIXEDSTEP_MATCH_SECRET: 'short' } })).toThrow(
      'FIXEDSTEP_MATCH_SECRET: at least 16 characters',
    );
    // Without one, each process signs with its own random secret.
    expect(new MatchTickets({ env: {} }).verify(new MatchTickets({ env: {} }).issue(seat))).toBe(
      'not signed by this deployment',
    );
  });
});

describe('quick match over real sockets through createServer', () => {
  let server: FixedstepServer;
  let base: string;
  const clock = new ManualClock(0);
  /**
   * A WebSocket class whose sockets come from loopback address `ip` (127.0.0.0/8 is all this
   * machine's): each player its own client address, as across the internet.
   */
  const from = (ip: string) =>
    class extends WebSocket {
      constructor(url: string) {
        super(url, { localAddress: ip });
      }
    } as unknown as new (url: string) => globalThis.WebSocket;
  let nextIp = 2;
  /** A fresh loopback address. */
  const ip = () => `127.0.0.${nextIp++}`;
  const ctf = { game: ctfGame.id, gameVersion: ctfGame.version, input: ctfGame.input };
  const ctfRequest = (over: Partial<MatchQueueRequest> = {}) =>
    req({ game: 'ctf', gameVersion: ctfGame.version, input: ctfGame.input.id, ...over });

  beforeAll(async () => {
    server = await createServer({
      port: 0,
      stateSync: false,
      signalling: false,
      games: [ctfGame],
      env: {},
      // The manual clock's jumps are the test's, not stalls of the server.
      matchmaking: { clock, stallToleranceMs: Infinity },
    });
    base = `ws://127.0.0.1:${server.port}`;
  }, 60_000);
  afterAll(async () => {
    await server.close();
  });

  /** Opens a raw client, sends `frames`, and collects what the server says until it closes. */
  function raw(
    frames: (string | Uint8Array)[],
    onMessage?: (m: MatchServerMessage, ws: WebSocket) => void,
    address = ip(),
  ) {
    const ws = new WebSocket(`${base}/match`, { localAddress: address });
    const got: MatchServerMessage[] = [];
    const closed = new Promise<number>((resolve) => ws.on('close', resolve));
    ws.on('open', () => {
      for (const f of frames) ws.send(f);
    });
    ws.on('message', (data: Buffer) => {
      const m = MATCH_PROTOCOL.decode(new Uint8Array(data), {
        from: 'server',
      }) as MatchServerMessage;
      got.push(m);
      onMessage?.(m, ws);
    });
    ws.on('error', () => undefined);
    return { ws, got, closed };
  }

  /** The first message the relay answers a hello with, on a fresh socket to `/ws/<room>`. */
  async function hello(room: string, extra: Partial<NetMessage> = {}): Promise<NetMessage> {
    const t = await connectNodeWebSocket(`${base}/ws/${room}`);
    return new Promise((resolve) => {
      t.onMessage((b) => {
        resolve(decodeFrame(b)[0]!);
        t.close('done');
      });
      t.send(
        encodeMessage({
          type: 'hello',
          room,
          role: 'player',
          game: ctfGame.id,
          gameVersion: ctfGame.version,
          input: ctfGame.input.id,
          players: 4,
          seed: 1,
          name: 'mallory',
          ...extra,
        } as NetMessage),
      );
    });
  }

  it('matches two Node clients, whose tickets seat them in a room nobody else could set up', async () => {
    const options = { url: `${base}/match`, ...ctf, minPlayers: 2 };
    let queued = 0;
    let found = 0;
    const first = quickMatch({
      ...options,
      WebSocketClass: from(ip()),
      onQueued: () => queued++,
      onFound: () => found++,
    });
    await expect.poll(() => queued).toBe(1);
    expect(server.matchmaking?.queue.size).toBe(1);
    const second = quickMatch({ ...options, WebSocketClass: from(ip()) });
    const results: QuickMatchResult[] = await Promise.all([first, second]);
    expect(found).toBe(1);
    expect(results[0]!.room).toBe(results[1]!.room);
    expect(results.map((r) => [r.players, r.order, r.seed])).toEqual([
      [2, 0, results[0]!.seed],
      [2, 1, results[0]!.seed],
    ]);
    expect(results[0]!.room).toMatch(/^qm-[A-Za-z0-9_-]{24}$/);
    expect(server.matchmaking?.queue.size).toBe(0);
    const room = results[0]!.room;

    // Someone who learned the room's name cannot make it first, with a setup of its own...
    expect(await hello(room)).toMatchObject({ type: 'error', code: 'BAD_TOKEN' });
    // ...nor with a forged ticket, nor with another room's.
    const forged = results[0]!.ticket.slice();
    forged[10] = forged[10]! ^ 1;
    expect(await hello(room, { ticket: forged })).toMatchObject({
      type: 'error',
      code: 'BAD_TOKEN',
      message: 'match ticket refused: not signed by this deployment',
    });
    expect(await hello('qm-elsewhere', { ticket: results[0]!.ticket })).toMatchObject({
      type: 'error',
      code: 'BAD_TOKEN',
    });

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
          ticket: match.ticket,
          stopAt: ticks,
          createSimulation: (w) => {
            slot = w.slot;
            return ctfGame.create(ctfGame.decodeConfig(w.config));
          },
          localInput: (_tick, sim) => ctfGame.bot(sim as Game, slot),
        }),
      );
    }
    await frameUntilFinished(sessions);
    // The matchmaker's setup: two players, its seed, each in the seat its ticket names.
    expect(sessions.map((s) => [s.welcome!.players, s.welcome!.seed, s.welcome!.slot])).toEqual([
      [2, results[0]!.seed, 0],
      [2, results[0]!.seed, 1],
    ]);
    const hashes = sessions.map((s) => hex64(s.hashAt(ticks)!));
    expect(hashes[0]).toBe(hashes[1]);
    const info = server.relay!.relay.room(room)!;
    expect(info.desyncs).toHaveLength(0);
    // A third ticket-less player cannot take a seat of a ticketed room.
    expect(await hello(room)).toMatchObject({ type: 'error', code: 'BAD_TOKEN' });
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
      WebSocketClass: from(ip()),
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
      WebSocketClass: from(ip()),
    });
    await expect.poll(() => server.matchmaking?.queue.size).toBe(1);
    abort.abort(new Error('the player left'));
    await expect(aborted).rejects.toThrow('the player left');
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);

    const c = raw([MATCH_PROTOCOL.encode(ctfRequest())]);
    await expect.poll(() => c.got.length).toBe(1);
    expect(c.got[0]).toEqual({ type: 'queued', timeoutMs: 10_000 });
    c.ws.terminate();
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);
  });

  it('drops a player who does not accept; its partner is back in the queue and told so', async () => {
    const honest = raw([MATCH_PROTOCOL.encode(ctfRequest())], (m, ws) => {
      if (m.type === 'found') ws.send(MATCH_PROTOCOL.encode({ type: 'accept' }));
    });
    await expect.poll(() => server.matchmaking?.queue.size).toBe(1);
    const squatter = raw([MATCH_PROTOCOL.encode(ctfRequest())]);
    await expect.poll(() => squatter.got.map((m) => m.type)).toEqual(['queued', 'found']);
    clock.advance(3000);
    expect(await squatter.closed).toBe(1000);
    expect(squatter.got.at(-1)).toMatchObject({ type: 'error', code: 'NO_SHOW' });
    await expect.poll(() => honest.got.map((m) => m.type)).toEqual(['queued', 'found', 'queued']);
    // Told the wait it has left: its own, less the 3 s the proposal took.
    const [first, , again] = honest.got as { timeoutMs: number }[];
    expect(again!.timeoutMs).toBe(first!.timeoutMs - 3000);
    expect(server.matchmaking?.queue.size).toBe(1);
    honest.ws.terminate();
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);
  });

  it('holds one address to two tickets, with a message', async () => {
    const four = MATCH_PROTOCOL.encode(ctfRequest({ minPlayers: 4, maxPlayers: 4 }));
    const home = ip();
    const waiting = [raw([four], undefined, home), raw([four], undefined, home)];
    await expect.poll(() => server.matchmaking?.queue.size).toBe(2);
    const third = raw([four], undefined, home);
    expect(await third.closed).toBe(1000);
    expect(third.got).toEqual([
      {
        type: 'error',
        code: 'ADDRESS_LIMIT',
        fatal: true,
        message: 'at most 2 players wait from one address',
      },
    ]);
    for (const c of waiting) c.ws.terminate();
    await Promise.all(waiting.map((c) => c.closed));
    await expect.poll(() => server.matchmaking?.queue.size).toBe(0);
  });

  it('refuses garbage, unknown games and a second request with a clear error', async () => {
    // A text frame is refused as on every surface: the error, then close code 1003.
    const text = raw(['hello?']);
    expect(await text.closed).toBe(1003);
    expect(text.got).toEqual([
      {
        type: 'error',
        code: 'BAD_MESSAGE',
        fatal: true,
        message: 'quick match messages are binary frames, not text',
      },
    ]);
    const cases: [(string | Uint8Array)[], string, string][] = [
      [[new Uint8Array([1, 2, 3])], 'BAD_MESSAGE', 'a relay message, not quick match'],
      [
        [Uint8Array.of(MATCH_PROTOCOL.header, 0x13)],
        'BAD_MESSAGE',
        'a matched is sent by the server',
      ],
      [[MATCH_PROTOCOL.encode(req())], 'UNKNOWN_GAME', 'no game "duel" on this server'],
      [
        [MATCH_PROTOCOL.encode(ctfRequest({ gameVersion: ctfGame.version + 1 }))],
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
    const ok = MATCH_PROTOCOL.encode(ctfRequest());
    const twice = raw([ok, ok]);
    expect(await twice.closed).toBe(1000);
    expect(twice.got.map((m) => m.type)).toEqual(['queued', 'error']);
    expect(server.matchmaking?.queue.size).toBe(0);
    // A frame over the largest message a client sends never reaches the decoder: ws closes with 1009.
    const big = raw([new Uint8Array(MATCH_PROTOCOL.largest('client') + 1)]);
    expect(await big.closed).toBe(1009);
    // Unknown paths still get 404.
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
