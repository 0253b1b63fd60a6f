/**
 * The hostile suite (issue 22): every attack found against the server, through real sockets
 * against `createServer` on 127.0.0.1, on each of its four surfaces where the attack applies —
 * the relay (`/ws`), state sync (`/state`), signalling (`/signal`) and quick match (`/match`).
 * Each client comes from a loopback address of its own (127.0.0.0/8 is all this machine's), so the
 * per-address caps see sixty addresses as sixty clients. Caps are small and time-outs short (the
 * server's options, never the environment); every wait is on state, never a fixed sleep.
 *
 * Findings held here, one test each (named after it):
 * - /signal: one address opened 1 000 host sockets, and every new host got SERVER_FULL for 60 s;
 *   1 100 more sockets, and every new connection was refused; anyone knowing a room's name joined
 *   it and received the host's offers.
 * - /state: one address made 500 rooms, kept by one ack a second, and an honest pair got
 *   SERVER_FULL; empty rooms kept stepping; anyone knowing a room's name watched the world; a
 *   dropped player's seat was taken by a stranger 300 ms later, and the owner's token was refused.
 * - /match: one client holding 4 tickets and re-queueing captured all 20 honest players; the
 *   matched attacker made the relay room first, with its own seed and 4 players; quick match never
 *   filled a room beyond 2.
 * - /ws: 63 addresses holding 500 running rooms, and a new honest room still got SERVER_FULL; an
 *   11.6 s stall of the server closed 19 live players.
 * - Origins: other sites' pages were let in at /state and /signal.
 * The goal they serve (issue 22, item 3): with 60 addresses each holding its maximum of rooms with
 * minimal keep-alive traffic, a new honest room starts within 5 s — on every surface.
 */
import net from 'node:net';
import { afterAll, beforeAll, describe, expect, it } from 'vitest';
import {
  IDLE_GRACE_MS,
  RELAY_PROTOCOL,
  Random,
  WAITING_GRACE_MS,
  SIGNAL_PROTOCOL,
  type MatchMessage,
  type NetMessage,
  type RoomHostOptions,
} from 'fixedstep';
import { createServer, type FixedstepServer, type ServerOptions } from '../src/index.js';
import { MatchTickets } from '../src/match/index.js';
import { GAMES } from './hostile-games.js';
import { freshAddress, Peer, WAIT_MS, type AnyMessage } from './hostile-peer.js';
import {
  MATCH,
  RELAY,
  GAMES_MODULE,
  ROOM_SURFACES,
  SURFACES,
  queueRequest,
  Refused,
  type JoinExtras,
  type Surface,
} from './hostile-surfaces.js';

/** The room core of every surface, small and quick (the defaults are in `net/room/options.ts`). */
const HOST = {
  maxRoomsPerAddress: 2,
  maxConnectionsPerAddress: 4,
  helloTimeoutMs: 800,
  silenceTimeoutMs: 1200,
  probeAfterMs: 300,
  // Above signalling's 250 ms between updates: a normal gap is no stall.
  stallToleranceMs: 500,
  waitingGraceMs: 800,
  idleGraceMs: 800,
  // Longer than the stall test's stall (a stalled server hears no one play).
  waitingRoomTtlMs: 2500,
  idleRoomTtlMs: 2500,
  emptyRoomTtlMs: 1000,
  seatHoldMs: 20_000,
  rate: { messagesPerSecond: 40, messageBurst: 80 },
} satisfies RoomHostOptions;
/** WebSockets one address may hold, every surface together (the server's `maxSocketsPerAddress`). */
const SOCKETS_PER_ADDRESS = 6;
/**
 * Quick match: a request must come this soon, a proposal be accepted this soon; a gap between its
 * sweeps (100 ms apart) longer than the tolerance is a stall of the server (ms).
 */
const MATCH_TIMEOUTS = { requestTimeoutMs: 800, acceptMs: 600, stallToleranceMs: 200 };
/** The ticket secret of every suite server (so the suite can sign tickets of its own). */
const SECRET = 'the hostile suite’s match secret';
/** The issue's goal: a new honest room starts within this, ms. */
const GOAL_MS = 5000;
/** An honest client refused with SERVER_FULL tries again after this, ms. */
const RETRY_MS = 100;

/** A server with `surface` alone; its room core `host`. */
async function start(
  surface: Surface,
  host: RoomHostOptions = HOST,
  extra: Partial<ServerOptions> = {},
): Promise<{ server: FixedstepServer; base: string }> {
  const options = surface.options(host, {
    maxSocketsPerAddress: SOCKETS_PER_ADDRESS,
    matchSecret: SECRET,
    ...extra,
  });
  if (options.matchmaking !== false) {
    options.matchmaking = {
      ...MATCH_TIMEOUTS,
      // Every address of the suite is loopback: let none be matched with itself.
      matchesItself: () => false,
      ...(typeof options.matchmaking === 'object' ? options.matchmaking : {}),
    };
  }
  const server = await createServer(options);
  await server.stateSync?.ready;
  return { server, base: `ws://127.0.0.1:${server.port}` };
}

/** Blocks this thread — the server's event loop — for `ms`: a long collection, a blocking call. */
function stall(ms: number): void {
  Atomics.wait(new Int32Array(new SharedArrayBuffer(4)), 0, 0, ms);
}

/** Resolves once `test()` holds (checked every 20 ms); fails naming `what` after `timeoutMs`. */
async function until(what: string, test: () => boolean, timeoutMs = WAIT_MS): Promise<void> {
  await expect.poll(test, { timeout: timeoutMs, interval: 20, message: what }).toBe(true);
}

/** Prints a measured time toward the goal (only its bound is asserted: the time is the machine's). */
function report(what: string, ms: number): void {
  console.log(`hostile: ${what}: ${Math.round(ms)} ms`);
}

describe.each(SURFACES)('$path', (surface) => {
  let server: FixedstepServer;
  let base: string;
  beforeAll(async () => {
    ({ server, base } = await start(surface));
  }, 60_000);
  afterAll(async () => {
    await server.close();
  });

  /** A client of `room` from a fresh address. */
  const open = (room = 'lobby', address = freshAddress()) => surface.open(base, address, room);

  it('garbage frames — noise, another protocol, text, over a message’s limit, over the frame limit, random bytes — close that connection with the protocol’s error; the server serves on', async () => {
    const p = surface.protocol;
    const other = (surface.path === '/ws'
      ? SIGNAL_PROTOCOL
      : RELAY_PROTOCOL) as unknown as typeof p;
    const first = surface.hello('garbage').type;
    const overMessage = new Uint8Array(p.maxBytes(first) + 1);
    overMessage.set([p.header, p.code(first)]);
    const cases: [string, Uint8Array | string, string, RegExp][] = [
      ['noise', Uint8Array.of(0xde, 0xad, 0xbe, 0xef, 1, 2, 3), 'BAD_MESSAGE', /header 0xde/],
      [
        'another protocol',
        other.encode(
          surface.path === '/ws' ? ({ type: 'host', room: 'x' } as AnyMessage) : RELAY.hello('x'),
        ),
        'BAD_MESSAGE',
        new RegExp(`a ${other.name} message, not ${p.name}`),
      ],
      ['text', 'hello?', 'BAD_MESSAGE', /binary/],
    ];
    if (overMessage.length <= p.largest('client')) {
      cases.push(['over its limit', overMessage, 'TOO_LARGE', new RegExp(`a ${first} message`)]);
    }
    const seen = [];
    for (const [what, frame] of cases) {
      const peer = await open('garbage');
      peer.raw(frame);
      const code = await peer.outcome([]);
      const close = (await peer.ended()).code;
      seen.push({ what, code, message: peer.error?.message, close });
    }
    expect(seen).toEqual(
      cases.map(([what, , code, message]) => ({
        what,
        code,
        message: expect.stringMatching(message) as unknown,
        close: what === 'text' ? 1003 : 1000,
      })),
    );
    // Over the largest message a client sends: `ws` refuses the frame before buffering it.
    const big = await open('garbage');
    big.raw(new Uint8Array(p.largest('client') + 1));
    expect((await big.ended()).code).toBe(1009);
    // Random bytes, of the surface's own protocol and version: refused with a code, or harmless
    // until the join deadline — never a broken connection (1006) or a crash.
    const random = new Random(22);
    const peers: Peer[] = [];
    for (let i = 0; i < 16; i++) {
      const frame = new Uint8Array(2 + random.int(40));
      for (let k = 0; k < frame.length; k++) frame[k] = random.int(256);
      frame[0] = p.header;
      const peer = await open('garbage');
      peer.raw(frame);
      peers.push(peer);
    }
    for (const peer of peers) {
      const closed = await peer.ended();
      expect(closed.code).toBe(1000);
      expect(peer.error ?? peer.last('cancelled')).toBeDefined();
    }
    // The server serves on.
    const good = await open('after-garbage');
    good.send(surface.hello('after-garbage'));
    expect(await good.outcome([surface.welcome])).toBe(surface.welcome);
    good.close();
  });

  it('slow handshakes: connections that never send their first message are closed at the deadline and hold no place', async () => {
    const deadline =
      surface.path === '/match' ? MATCH_TIMEOUTS.requestTimeoutMs : HOST.helloTimeoutMs;
    const slow = freshAddress();
    const t0 = performance.now();
    // As many as the address may hold (the room core's share, or the server's): no more.
    const cap = surface.rooms ? HOST.maxConnectionsPerAddress : SOCKETS_PER_ADDRESS;
    const silent = await Promise.all(Array.from({ length: cap }, () => open('slow', slow)));
    expect(silent.map((s) => s.status)).toEqual(new Array(cap).fill(101));
    const more = await open('slow', slow);
    expect(more.status === 101 ? await more.outcome([]) : `HTTP ${more.status}`).toBe(
      surface.rooms ? 'ADDRESS_LIMIT' : 'HTTP 429',
    );
    // Meanwhile an honest client from elsewhere is served at once.
    const honest = await open('honest');
    honest.send(surface.hello('honest'));
    expect(await honest.outcome([surface.welcome])).toBe(surface.welcome);
    honest.close();
    for (const s of silent) {
      expect(await s.outcome([])).toBe('TIMEOUT');
      await s.ended();
    }
    const took = performance.now() - t0;
    expect(took).toBeGreaterThanOrEqual(deadline);
    // The address holds nothing: it may open as many again, and is served.
    const again = await Promise.all(Array.from({ length: cap }, () => open('slow', slow)));
    expect(again.map((s) => s.status)).toEqual(new Array(cap).fill(101));
    again[0]!.send(surface.hello('slow'));
    expect(await again[0]!.outcome([surface.welcome])).toBe(surface.welcome);
    for (const s of again) s.close();
  });

  it('floods: a connection sending faster than its rate is cut off (RATE_LIMIT); the others play on', async () => {
    const honest =
      surface.rooms !== undefined
        ? await surface.rooms.play(base, 'flood-honest', [freshAddress(), freshAddress()], true)
        : [];
    const flooder = await open('flood');
    flooder.send(surface.hello('flood'));
    await flooder.outcome([surface.welcome]);
    for (let i = 0; i < 200; i++) flooder.send(surface.chatter());
    expect(await flooder.outcome([])).toBe('RATE_LIMIT');
    await flooder.ended();
    // The honest room is untouched: its players hear on.
    const heard = honest.map((p) => p.got.length);
    for (const [i, p] of honest.entries()) {
      await p.until('more traffic', () => p.got.length > heard[i]! + 5);
      expect(p.error).toBeUndefined();
      expect(p.closed).toBeUndefined();
    }
    for (const p of honest) p.close();
    // Quick match: an honest pair is matched after the flood.
    const matchedAfter = async () => {
      const pair = await Promise.all([open(), open()]);
      for (const p of pair) {
        p.onMessage((m) => {
          if (m.type === 'found') p.send({ type: 'accept' });
        });
        p.send(queueRequest());
      }
      return Promise.all(pair.map((p) => p.outcome(['matched'])));
    };
    expect(surface.path === '/match' ? await matchedAfter() : ['matched', 'matched']).toEqual([
      'matched',
      'matched',
    ]);
  });

  it('foreign origins: another site’s page is refused (403); the server’s own page and programs are let in', async () => {
    const port = server.port;
    const origin = (o?: string) =>
      surface.open(base, freshAddress(), 'origin', o === undefined ? {} : { Origin: o });
    expect((await origin('http://evil.example')).status).toBe(403);
    expect((await origin('null')).status).toBe(403);
    expect((await origin(`http://127.0.0.1:${port + 1}`)).status).toBe(403);
    for (const ok of [await origin(`http://127.0.0.1:${port}`), await origin()]) {
      expect(ok.status).toBe(101);
      ok.close();
    }
  });

  const rooms = surface.rooms;
  if (rooms === undefined) return;

  it('one address opening many sockets for rooms gets its share (HTTP 429, ADDRESS_LIMIT), never SERVER_FULL for others; keep-alives alone do not hold its rooms', async () => {
    const squat = freshAddress();
    const outcomes = await Promise.all(
      Array.from({ length: 40 }, async (_, i) => {
        const peer = await open(`squat${i}`, squat);
        return {
          peer,
          outcome:
            peer.status === 101 ? await rooms.hold(peer, `squat${i}`) : `HTTP ${peer.status}`,
        };
      }),
    );
    const held = outcomes.filter((o) => o.outcome === 'held');
    expect(held).toHaveLength(HOST.maxRoomsPerAddress);
    for (const o of outcomes) expect(['held', 'HTTP 429', 'ADDRESS_LIMIT']).toContain(o.outcome);
    // Every new room from elsewhere starts at once.
    const t0 = performance.now();
    const pair = await rooms.play(base, 'beside-squat', [freshAddress(), freshAddress()], true);
    const took = performance.now() - t0;
    report(`${surface.path} honest room beside one squatting address started in`, took);
    expect(took).toBeLessThan(GOAL_MS);
    // Kept alive but never played in, the squatter's rooms are closed at the room TTL.
    for (const { peer } of held) {
      expect(await peer.outcome([], HOST.idleRoomTtlMs + WAIT_MS)).toBe(
        surface.path === '/signal' ? 'TIMEOUT' : 'IDLE',
      );
    }
    for (const p of pair) {
      expect(p.error).toBeUndefined();
      p.close();
    }
  });

  it('60 addresses each holding its maximum of rooms with keep-alives: a new honest room starts within 5 s', async () => {
    // By default a room nobody plays in — idle, or still waiting — makes way within the goal.
    expect(Math.max(IDLE_GRACE_MS, WAITING_GRACE_MS)).toBeLessThanOrEqual(GOAL_MS);
    const addresses = Array.from({ length: 60 }, (_, i) => `127.0.0.${i + 1}`);
    // The server is exactly full: no room to spare, only rooms that make way (and none closes of
    // itself meanwhile).
    const full = await start(surface, {
      ...HOST,
      maxRooms: 60 * HOST.maxRoomsPerAddress,
      idleRoomTtlMs: 60_000,
      waitingRoomTtlMs: 60_000,
    });
    try {
      const squatters = await Promise.all(
        addresses.flatMap((a, i) =>
          Array.from({ length: HOST.maxRoomsPerAddress }, async (_, k) => {
            const peer = await surface.open(full.base, a, `squat${i}-${k}`);
            expect(await rooms.hold(peer, `squat${i}-${k}`)).toBe('held');
            return peer;
          }),
        ),
      );
      expect(rooms.count(full.server)).toBe(60 * HOST.maxRoomsPerAddress);
      // An honest pair arrives at once, as a client would: refused (SERVER_FULL) while every
      // squatted room is younger than the grace, it tries again until one makes way.
      const t0 = performance.now();
      const refusals: string[] = [];
      let pair: Peer[] | undefined;
      while (pair === undefined && performance.now() - t0 < GOAL_MS) {
        pair = await rooms
          .play(full.base, 'honest', ['127.0.0.61', '127.0.0.62'], true)
          .catch(async (error: unknown) => {
            if (!(error instanceof Refused)) throw error;
            refusals.push(error.code);
            await new Promise((resolve) => setTimeout(resolve, RETRY_MS));
            return undefined;
          });
      }
      const took = performance.now() - t0;
      report(
        `${surface.path} honest room beside 60 full addresses started in (${refusals.length} refusals first)`,
        took,
      );
      expect(pair).toBeDefined();
      expect(took).toBeLessThan(GOAL_MS);
      expect(refusals.every((code) => code === 'SERVER_FULL')).toBe(true);
      // One squatted room made way for it; the others are held as before.
      await until('the evicted squatter told', () =>
        squatters.some((s) => s.error?.code === 'IDLE'),
      );
      expect(squatters.filter((s) => s.error !== undefined)).toHaveLength(1);
      expect(rooms.count(full.server)).toBe(60 * HOST.maxRoomsPerAddress);
      for (const p of [...pair!, ...squatters]) p.close();
    } finally {
      await full.server.close();
    }
  }, 60_000);

  it('knowing a room’s name is not enough: watching it (signalling: joining it) takes the invite', async () => {
    const [a, b] = await rooms.play(base, 'secret', [freshAddress(), freshAddress()]);
    const invite = rooms.invite(a);
    expect(invite).toHaveLength(16);
    const role = rooms.spectators ? 'spectator' : 'player';
    for (const token of [undefined, new Uint8Array(16), invite.map((x) => x ^ 1)]) {
      const stranger = await open('secret');
      rooms.join(stranger, 'secret', { role, ...(token ? { token } : {}) });
      expect(await stranger.outcome([rooms.joined])).toBe('BAD_TOKEN');
    }
    // With the invite a player handed over: in — and not handed it again to pass on.
    const invited = await open('secret');
    rooms.join(invited, 'secret', { role, token: invite });
    expect(await invited.outcome([rooms.joined])).toBe(rooms.joined);
    const got = invited.first(rooms.joined) as unknown as { invite: Uint8Array };
    expect(got.invite).toHaveLength(0);
    for (const p of [a, b, invited]) p.close();
  });

  it('empty rooms stop: a room its players left is removed within the empty-room TTL', async () => {
    const pair = await rooms.play(base, 'emptied', [freshAddress(), freshAddress()]);
    expect(rooms.has(server, 'emptied')).toBe(true);
    // They leave on purpose: no seat is held for them (a dropped player's is, see below).
    for (const p of pair) {
      const leave = rooms.leave(p);
      if (leave !== undefined) p.send(leave);
      p.close();
    }
    const t0 = performance.now();
    await until('the empty room removed', () => !rooms.has(server, 'emptied'));
    // Within the TTL and a housekeeping round (250 ms) or two.
    expect(performance.now() - t0).toBeLessThan(HOST.emptyRoomTtlMs + 1000);
  });

  it('a server stall longer than the silence timeout does not close live players', async () => {
    const pair = await rooms.play(base, 'stalled', [freshAddress(), freshAddress()], true);
    stall(HOST.silenceTimeoutMs + HOST.stallToleranceMs);
    // The server wakes to its players' messages and reads them before it judges anyone silent. A
    // ping sent now is answered after whatever the server did about the stall.
    for (const p of pair) p.send(rooms.ping(99));
    for (const p of pair) {
      await p.until('the pong after the stall', () =>
        p.got.some((m) => m.type === 'pong' && (m as unknown as { id: number }).id === 99),
      );
      expect(p.error).toBeUndefined();
      expect(p.closed).toBeUndefined();
    }
    // The host saw its stall (state sync's is in its worker, whose own loop never stalled).
    const stalled =
      surface.path === '/ws'
        ? server.relay!.relay.stats.stalledMs
        : surface.path === '/signal'
          ? server.signalling!.hub.stats.stalledMs
          : Infinity;
    expect(stalled).toBeGreaterThan(HOST.silenceTimeoutMs);
    for (const p of pair) p.close();
  });

  it('drain: a running room plays on until the timeout, then SHUTDOWN; a new room is refused (SHUTDOWN)', async () => {
    // A server of its own: draining it ends it.
    const own = await start(surface);
    try {
      const [a, b] = await rooms.play(own.base, 'draining', [freshAddress(), freshAddress()], true);
      const drained = own.server.drain(1500);
      const late = await surface.open(own.base, freshAddress(), 'after-drain');
      late.send(surface.hello('after-drain'));
      expect(await late.outcome([surface.welcome])).toBe('SHUTDOWN');
      // Still playing: a drain lets a running room end on its own, up to the timeout.
      expect(a.error).toBeUndefined();
      await drained;
      await until(
        `both players told SHUTDOWN: ${[a, b].map((p) => `${p.error?.code}/${p.closed?.code}`).join(' ')}`,
        () => [a, b].every((p) => p.error?.code === 'SHUTDOWN'),
      );
      expect(own.server.draining).toBe(true);
    } finally {
      await own.server.close();
    }
  });

  if (!rooms.holdsSeats) return;

  it('forged tokens — a random reconnect token, a forged, altered or expired match ticket, a ticket of another room — are refused (BAD_TOKEN)', async () => {
    const [a, b] = await rooms.play(base, 'forged', [freshAddress(), freshAddress()]);
    const refused = async (room: string, extras: Parameters<typeof rooms.join>[2]) => {
      const peer = await open(room);
      rooms.join(peer, room, extras);
      const outcome = await peer.outcome([rooms.joined]);
      peer.close();
      return [outcome, peer.error?.message ?? ''];
    };
    expect(await refused('forged', { token: new Uint8Array(16).fill(7) })).toEqual([
      'BAD_TOKEN',
      'no seat of this room has that token',
    ]);
    const seat = { room: 'qm-forged', game: 'slow', gameVersion: 1, players: 2, seed: 5, slot: 0 };
    const ours = new MatchTickets({ secret: SECRET });
    const valid = ours.issue(seat);
    const altered = valid.slice();
    altered[12] = altered[12]! ^ 1;
    const tickets: [string, Uint8Array, string, RegExp][] = [
      [
        'forged',
        new MatchTickets({ secret: 'another deployment' }).issue(seat),
        'qm-forged',
        /not signed/,
      ],
      ['altered', altered, 'qm-forged', /not signed/],
      [
        'expired',
        new MatchTickets({ secret: SECRET, now: () => Date.now() - 11 * 60_000 }).issue(seat),
        'qm-forged',
        /expired/,
      ],
      ['another room’s', valid, 'qm-other', /for room qm-forged/],
    ];
    const takesTickets = surface.path === '/ws';
    const answers = [];
    for (const [what, ticket, room] of tickets)
      answers.push([what, ...(await refused(room, { ticket }))]);
    expect(answers).toEqual(
      tickets.map(([what, , , why]) => [
        what,
        'BAD_TOKEN',
        // State sync's rooms take no tickets at all.
        expect.stringMatching(takesTickets ? why : /takes no match tickets/) as unknown,
      ]),
    );
    // A quick-match room is made by its ticket only: naming it is not enough.
    expect(await refused('qm-forged', { players: 4, seed: 1 })).toEqual([
      'BAD_TOKEN',
      expect.stringMatching(/made by quick match/),
    ]);
    a.close();
    b.close();
  });

  it('a stolen token cannot take a seat from its connected, playing owner (ROOM_FULL); the owner plays on', async () => {
    const [a, b] = await rooms.play(base, 'stolen', [freshAddress(), freshAddress()], true);
    const token = rooms.token(a);
    const thief = await open('stolen');
    rooms.join(thief, 'stolen', { token });
    expect(await thief.outcome([rooms.joined])).toBe('ROOM_FULL');
    expect(thief.error!.message).toMatch(/in use/);
    const heard = a.got.length;
    await a.until('more traffic', () => a.got.length > heard + 3);
    expect(a.error).toBeUndefined();
    expect(a.closed).toBeUndefined();
    b.close();
    a.close();
  });

  it('seat hijack on reconnect: a dropped player’s seat is held — a stranger 300 ms later gets ROOM_FULL — and its owner’s token takes it back', async () => {
    const [a, b] = await rooms.play(base, 'hijack', [freshAddress(), freshAddress()], true);
    const token = rooms.token(b);
    const slot = (b.first('welcome') as unknown as { slot: number }).slot;
    const open0 = server.admission.open;
    b.cut();
    await until('the drop seen by the server', () => server.admission.open === open0 - 1);
    const stranger = await open('hijack');
    rooms.join(stranger, 'hijack', {});
    expect(await stranger.outcome([rooms.joined])).toBe('ROOM_FULL');
    expect(stranger.error!.message).toMatch(/held for the player who left it/);
    const back = await open('hijack', b.address);
    rooms.join(back, 'hijack', { token });
    expect(await back.outcome([rooms.joined])).toBe(rooms.joined);
    expect((back.first('welcome') as unknown as { slot: number }).slot).toBe(slot);
    expect(a.error).toBeUndefined();
    a.close();
    back.close();
  });
});

describe('/match', () => {
  let server: FixedstepServer;
  let base: string;
  beforeAll(async () => {
    ({ server, base } = await start(MATCH));
  }, 60_000);
  afterAll(async () => {
    await server.close();
  });

  /** A quick-match client from `address` that accepts what it is offered. */
  async function player(address = freshAddress(), accepts = true): Promise<Peer> {
    const p = await MATCH.open(base, address);
    if (accepts) {
      p.onMessage((m) => {
        if (m.type === 'found') p.send({ type: 'accept' } satisfies MatchMessage);
      });
    }
    return p;
  }
  const matched = (p: Peer) =>
    p.first('matched') as unknown as Extract<MatchMessage, { type: 'matched' }> | undefined;

  it('one client holding 4 tickets and re-queueing captures only its share of 20 honest players', async () => {
    const attacker = freshAddress();
    const rooms = new Set<string>();
    const tickets: Peer[] = [];
    let stop = false;
    let opening = 0;
    /** One of the attacker's tickets: accept, note the room, queue again at once. */
    const ticket = async (): Promise<string> => {
      opening++;
      const p = await player(attacker);
      opening--;
      tickets.push(p);
      p.onMessage((m) => {
        if (m.type !== 'matched') return;
        rooms.add((m as Extract<MatchMessage, { type: 'matched' }>).room);
        if (!stop) void ticket();
      });
      p.send(queueRequest());
      return p.outcome(['queued']);
    };
    const four = await Promise.all([ticket(), ticket(), ticket(), ticket()]);
    expect(four.sort()).toEqual(['ADDRESS_LIMIT', 'ADDRESS_LIMIT', 'queued', 'queued']);
    // Twenty honest players, from twenty addresses, queue together.
    const honest = await Promise.all(Array.from({ length: 20 }, () => player()));
    for (const p of honest) p.send(queueRequest());
    for (const p of honest) expect(await p.outcome(['matched'])).toBe('matched');
    stop = true;
    const captured = honest.filter((p) => rooms.has(matched(p)!.room)).length;
    // Its two tickets were the oldest: it met two players, then queued behind the rest.
    expect(captured).toBeLessThanOrEqual(4);
    await until('the attacker’s last tickets open', () => opening === 0);
    for (const p of tickets) p.close();
    await until('the queue empty', () => server.matchmaking!.queue.size === 0);
  });

  it('the matched attacker cannot make the relay room first with its own seed and players: a qm- room takes the signed ticket that fixes its setup', async () => {
    const [mallory, alice] = await Promise.all([player(), player()]);
    mallory.send(queueRequest());
    await mallory.outcome(['queued']);
    alice.send(queueRequest());
    for (const p of [mallory, alice]) expect(await p.outcome(['matched'])).toBe('matched');
    const m = matched(mallory)!;
    const a = matched(alice)!;
    expect(a.room).toBe(m.room);
    const hello = async (extras: JoinExtras) => {
      const p = await RELAY.open(base, mallory.address, m.room);
      RELAY.rooms!.join(p, m.room, extras);
      await p.outcome(['welcome']);
      return p;
    };
    // Its own setup, no ticket: refused.
    const setup = await hello({ players: 4, seed: 1 });
    expect(setup.error?.code).toBe('BAD_TOKEN');
    // An altered ticket, an expired one: refused.
    const altered = m.ticket.slice();
    altered[20] = altered[20]! ^ 0x40;
    expect((await hello({ ticket: altered })).error?.message).toMatch(/not signed/);
    const stale = new MatchTickets({ secret: SECRET, now: () => Date.now() - 11 * 60_000 });
    const expired = stale.issue({
      room: m.room,
      game: 'slow',
      gameVersion: 1,
      players: 4,
      seed: 1,
      slot: 0,
    });
    expect((await hello({ ticket: expired })).error?.message).toMatch(/expired/);
    // Its own ticket, asking for 4 players and seed 1: the matchmaker's setup it is.
    const first = await hello({ ticket: m.ticket, players: 4, seed: 1 });
    const w = first.first('welcome') as unknown as Extract<NetMessage, { type: 'welcome' }>;
    expect([w.players, w.seed, w.slot]).toEqual([2, m.seed, m.order]);
    // Its ticket again, from a second connection: the seat is taken.
    const again = await hello({ ticket: m.ticket });
    expect(again.error?.code).toBe('ROOM_FULL');
    // The honest player takes its own seat with its ticket.
    const own = await RELAY.open(base, alice.address, a.room);
    RELAY.rooms!.join(own, a.room, { ticket: a.ticket });
    expect(await own.outcome(['start'])).toBe('start');
    for (const p of [first, own]) p.close();
  });

  it('a server stall longer than the ready check does not drop players who accepted at once', async () => {
    const pair = [await player(undefined, false), await player(undefined, false)];
    for (const p of pair) {
      p.onMessage((m) => {
        if (m.type !== 'found') return;
        // The server stalls between its proposal and the answers: they wait, unread, in its sockets.
        if (p === pair[0]) stall(MATCH_TIMEOUTS.acceptMs + 500);
        p.send({ type: 'accept' } satisfies MatchMessage);
      });
      p.send(queueRequest());
    }
    for (const p of pair) expect(await p.outcome(['matched'])).toBe('matched');
  });

  it('quick match fills rooms beyond 2: four players who accept 2 to 4 play as four', async () => {
    const four = await Promise.all(Array.from({ length: 4 }, () => player()));
    for (const p of four) p.send(queueRequest(2, 4));
    for (const p of four) expect(await p.outcome(['matched'])).toBe('matched');
    const got = four.map((p) => matched(p)!);
    expect(new Set(got.map((g) => g.room)).size).toBe(1);
    expect(got.map((g) => g.players)).toEqual([4, 4, 4, 4]);
    expect(got.map((g) => g.order).sort((x, y) => x - y)).toEqual([0, 1, 2, 3]);
  });

  it('60 addresses each holding its two tickets without accepting: an honest pair is matched within 5 s', async () => {
    const squatters = await Promise.all(
      Array.from({ length: 60 }, (_, i) => `127.0.0.${i + 1}`).flatMap((a) =>
        [0, 1].map(async () => {
          const p = await player(a, false);
          p.send(queueRequest());
          expect(await p.outcome(['queued'])).toBe('queued');
          return p;
        }),
      ),
    );
    const t0 = performance.now();
    const pair = await Promise.all([player('127.0.0.61'), player('127.0.0.62')]);
    for (const p of pair) p.send(queueRequest());
    for (const p of pair) expect(await p.outcome(['matched'])).toBe('matched');
    const took = performance.now() - t0;
    report('/match honest pair beside 60 full addresses matched in', took);
    expect(took).toBeLessThan(GOAL_MS);
    // Squatters who never accept lose their place at the ready check.
    await until('squatters dropped as no-shows', () =>
      squatters.some((s) => s.error?.code === 'NO_SHOW'),
    );
    for (const s of squatters) s.close();
    await until('the queue empty', () => server.matchmaking!.queue.size === 0);
  }, 30_000);

  // The last test of the block: it drains the server.
  it('drain: a new request is refused (SHUTDOWN); the drain ends when nobody waits', async () => {
    const drained = server.drain(10_000);
    const late = await MATCH.open(base, freshAddress());
    late.send(queueRequest());
    expect(await late.outcome(['queued'])).toBe('SHUTDOWN');
    await drained;
    expect(server.matchmaking!.queue.size).toBe(0);
  });
});

describe('the HTTP handshake', () => {
  it('slow handshakes over TCP: one address’s half-sent upgrade requests hold its share of connections only, and are closed at the headers timeout', async () => {
    const perAddress = 10;
    const { server, base } = await start(RELAY, HOST, {
      limits: {
        headersTimeoutMs: 1000,
        requestTimeoutMs: 1500,
        maxConnections: 40,
        maxConnectionsPerAddress: perAddress,
      },
    });
    try {
      const attacker = freshAddress();
      const closed = new Set<net.Socket>();
      const t0 = performance.now();
      const sockets = Array.from({ length: 60 }, () => {
        const s = net.connect({ port: server.port, host: '127.0.0.1', localAddress: attacker });
        // Headers that never end.
        s.write('GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\n');
        s.on('error', () => undefined);
        s.on('close', () => closed.add(s));
        s.resume();
        return s;
      });
      // Past its share, the address's connections are closed at once...
      await until('all but its share closed', () => closed.size >= sockets.length - perAddress);
      expect(server.admission.refusedConnections).toBe(sockets.length - perAddress);
      // ...so another address is served while they dribble.
      const honest = await RELAY.open(base, freshAddress(), 'honest');
      expect(honest.status).toBe(101);
      honest.close();
      // Its share is closed at the headers timeout.
      await until('every half-sent request closed', () => closed.size === sockets.length);
      const took = performance.now() - t0;
      expect(took).toBeGreaterThanOrEqual(1000);
    } finally {
      await server.close();
    }
  });
});

describe('one policy everywhere', () => {
  it('the environment’s origins and caps apply to every surface alike', async () => {
    const server = await createServer({
      port: 0,
      host: '127.0.0.1',
      games: GAMES,
      // Caps not given in code: the environment's.
      stateSync: { games: GAMES_MODULE, workers: 1 },
      env: {
        FIXEDSTEP_ALLOWED_ORIGINS: 'https://play.example',
        FIXEDSTEP_MAX_ROOMS_PER_ADDRESS: '1',
      },
    });
    try {
      await server.stateSync?.ready;
      const base = `ws://127.0.0.1:${server.port}`;
      const statuses = [];
      for (const s of SURFACES) {
        const origin = async (o: string) =>
          (await s.open(base, freshAddress(), 'o', { Origin: o })).status;
        statuses.push([
          s.path,
          await origin('http://evil.example'),
          await origin(`http://127.0.0.1:${server.port}`),
          await origin('https://play.example'),
        ]);
      }
      // Only the listed origin, on every surface.
      expect(statuses).toEqual(SURFACES.map((s) => [s.path, 403, 403, 101]));
      const holds = [];
      for (const s of ROOM_SURFACES) {
        const address = freshAddress();
        const first = await s.open(base, address, 'env-a');
        const second = await s.open(base, address, 'env-b');
        holds.push([
          s.path,
          await s.rooms.hold(first, 'env-a'),
          await s.rooms.hold(second, 'env-b'),
        ]);
        first.close();
      }
      // One room an address, on every surface.
      expect(holds).toEqual(ROOM_SURFACES.map((s) => [s.path, 'held', 'ADDRESS_LIMIT']));
    } finally {
      await server.close();
    }
  });
});
