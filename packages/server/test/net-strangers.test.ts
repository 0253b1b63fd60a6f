/**
 * Issue 12's findings against the relay, each reproduced here: idle WebSockets that blocked every
 * new game, 4 000 connections that locked everyone out, a frozen peer that held its room and
 * started a newcomer's match against it, spectators who could join any room and fake a desync.
 * Every test runs on simulated time (SimulatedMatch): the numbers are exact and repeat.
 */
import { describe, expect, it } from 'vitest';
import { LockstepSession, SimulatedMatch, type DesyncMessage, type Transport } from 'fixedstep';
import { ctfGame, type Game } from '@fixedstep/games';
import { registryCatalog } from '../src/relay/index.js';
import { RawClient } from './raw-client.js';

/** A client that speaks the protocol by hand: a "stranger" asking for two players. */
class Raw extends RawClient {
  constructor(t: Transport, answerPings = false) {
    super(t, { name: 'stranger', players: 2, answerPings });
  }
}

const quiet = { latencyMs: 10, jitterMs: 0, loss: 0 };
const honest = (address: string, joinAtMs = 0) =>
  ({ kind: 'lockstep', joinAtMs, connection: { address } }) as const;

/** A room "honest" of capture the flag for two, on simulated time, beside whatever a test adds. */
function match(
  ticks: number,
  clients: ConstructorParameters<typeof SimulatedMatch>[0]['clients'],
  relay: ConstructorParameters<typeof SimulatedMatch>[0]['relay'] = {},
): SimulatedMatch {
  return new SimulatedMatch({
    game: ctfGame,
    seed: 12,
    ticks,
    catalog: registryCatalog(),
    link: { latencyMs: 30, jitterMs: 5 },
    players: 2,
    room: 'honest',
    relay,
    clients,
  });
}

/** Runs `m` for up to `ms` of simulated time: the honest room finishes and its hashes agree. */
function finishHonestly(m: SimulatedMatch, ms: number): ReturnType<SimulatedMatch['run']> {
  const r = m.run(ms);
  expect(r.finished).toBe(true);
  expect(r.hashesAgree).toBe(true);
  return r;
}

describe('idle sockets and squatters no longer block every new game', () => {
  it('500 idle sockets from one address get 32 connections and 8 rooms; a new game starts beside them', () => {
    const m = match(600, [honest('198.51.100.1', 1000), honest('198.51.100.2', 1000)]);
    const idle: Raw[] = [];
    for (let i = 0; i < 500; i++) {
      const r = new Raw(m.connect(quiet, { address: '203.0.113.9' }).transport);
      r.hello(`idle${i}`, 'player');
      idle.push(r);
    }
    m.scheduler.runUntil(500);
    // 468 refused at once; of the 32 let in, 24 asked for a ninth room and more.
    const refused = idle.filter((r) => r.error?.code === 'ADDRESS_LIMIT');
    expect(refused).toHaveLength(468 + 24);
    expect(m.relay.stats.connections).toBe(8);
    expect(m.relay.stats.rooms).toBe(8);
    expect(idle[8]!.error!.message).toMatch(/at most 8 rooms from one address/);
    expect(idle[499]!.error!.message).toMatch(/at most 32 connections from one address/);
    finishHonestly(m, 60_000);
  });

  it('500 idle sockets from 500 addresses fill the server for 10 s, then are dropped as silent', () => {
    const m = match(600, [honest('198.51.100.1', 11_000), honest('198.51.100.2', 11_000)]);
    const idle: Raw[] = [];
    for (let i = 0; i < 500; i++) {
      const r = new Raw(m.connect(quiet, { address: `10.${i >> 8}.${i & 255}.1` }).transport);
      r.hello(`idle${i}`, 'player');
      idle.push(r);
    }
    m.scheduler.runUntil(500);
    expect(m.relay.stats.rooms).toBe(500);
    // While they hold every room, a newcomer is refused...
    const early = new Raw(m.connect(quiet, { address: '198.51.100.7' }).transport);
    early.hello('early', 'player');
    m.scheduler.runUntil(1000);
    expect(early.error?.code).toBe('SERVER_FULL');
    // ...each is pinged after 1 s of silence, and dropped after 10 s.
    m.scheduler.runUntil(10_500);
    expect(m.relay.stats.probes).toBeGreaterThanOrEqual(500 * 9);
    expect(m.relay.stats.rooms).toBe(0);
    expect(idle.every((r) => r.error?.code === 'TIMEOUT' && r.closed !== undefined)).toBe(true);
    finishHonestly(m, 60_000);
  });

  it('squatters that answer every ping lose their waiting rooms after 120 s', () => {
    const m = match(600, [honest('198.51.100.1', 121_000), honest('198.51.100.2', 121_000)]);
    const squatters: Raw[] = [];
    for (let i = 0; i < 500; i++) {
      const r = new Raw(m.connect(quiet, { address: `10.${i >> 8}.${i & 255}.2` }).transport, true);
      r.hello(`squat${i}`, 'player');
      squatters.push(r);
    }
    m.scheduler.runUntil(60_000);
    // Alive: they answer the probes, so the silence rule keeps them...
    expect(m.relay.stats.rooms).toBe(500);
    expect(m.relay.roomList().every((room) => room.state === 'waiting')).toBe(true);
    // ...until the waiting rooms expire.
    m.scheduler.runUntil(120_500);
    expect(m.relay.stats.rooms).toBe(0);
    expect(squatters.every((r) => r.error?.code === 'TIMEOUT')).toBe(true);
    expect(squatters[0]!.error!.message).toMatch(/waited 120 s/);
    finishHonestly(m, 200_000);
  });

  it('4 000 connections from one address do not lock everyone out', () => {
    const m = match(600, [honest('198.51.100.1', 100), honest('198.51.100.2', 100)]);
    const flood: Raw[] = [];
    for (let i = 0; i < 4000; i++) {
      flood.push(new Raw(m.connect(quiet, { address: '203.0.113.66' }).transport));
    }
    m.scheduler.runUntil(50);
    expect(m.relay.stats.connections).toBe(32);
    expect(flood.filter((r) => r.error?.code === 'ADDRESS_LIMIT')).toHaveLength(3968);
    expect(m.relay.stats.dropped.ADDRESS_LIMIT).toBe(3968);
    finishHonestly(m, 60_000);
    // The 32 that got in never said hello: gone after 5 s.
    expect(m.relay.stats.dropped.TIMEOUT).toBe(32);
  });
});

describe('a frozen peer', () => {
  it('does not start a newcomer’s match against it, and is dropped after 10 s of silence', () => {
    // The frozen one created the room, then stopped: no ping, no ack, no pong.
    const m = match(600, [honest('198.51.100.1', 4000), honest('198.51.100.2', 12_000)]);
    const frozen = new Raw(m.connect(quiet, { address: '203.0.113.1' }).transport);
    frozen.hello('honest', 'player');
    m.scheduler.runUntil(6000);
    // The newcomer filled the room at ~4 s, but the frozen one has been silent for 6 s.
    const room = m.relay.room('honest')!;
    expect(room.members).toHaveLength(2);
    expect(room.state).toBe('waiting');
    m.scheduler.runUntil(10_300);
    expect(frozen.error?.code).toBe('TIMEOUT');
    expect(frozen.error?.message).toMatch(/silent for 10 s/);
    expect(m.relay.room('honest')!.members).toHaveLength(1);
    // The second honest player takes the freed slot and the match is played.
    const r = finishHonestly(m, 60_000);
    expect(r.room!.startAt).toBeGreaterThan(12_000);
  });

  /**
   * The honest room's second player, a capture-the-flag bot from `address` on a 30 ± 5 ms link,
   * playing to tick 3000 when framed.
   */
  function secondPlayer(m: ReturnType<typeof match>, address: string) {
    const { transport } = m.connect({ latencyMs: 30, jitterMs: 5 }, { address });
    let slot = 0;
    const session = new LockstepSession({
      transport,
      clock: m.scheduler.clock,
      room: 'honest',
      game: ctfGame,
      players: 2,
      seed: 12,
      stopAt: 3000,
      createSimulation: (w) => {
        slot = w.slot;
        return ctfGame.create(ctfGame.decodeConfig(w.config));
      },
      localInput: (_t, sim) => ctfGame.bot(sim as Game, slot),
    });
    return { transport, session };
  }

  it('in a running match is dropped after 10 s; its room plays on, not held', () => {
    const m = match(3000, [honest('198.51.100.1')]);
    // A real session that freezes at 5 s: no frames, and its message handler stops too.
    const { transport, session } = secondPlayer(m, '203.0.113.2');
    const frames = m.scheduler.every(1000 / 60, () => session.frame(m.scheduler.now), 3);
    m.scheduler.at(5000, () => {
      frames.cancel();
      transport.onMessage(() => undefined);
    });
    m.scheduler.runUntil(14_000);
    expect(m.relay.room('honest')!.members).toHaveLength(2);
    m.scheduler.runUntil(15_300);
    expect(m.relay.room('honest')!.members).toHaveLength(1);
    expect(m.relay.stats.dropped.TIMEOUT).toBe(1);
    const r = m.run(120_000);
    expect(r.finished).toBe(true);
    expect(r.clients[0]!.closed).toBe(false);
  });

  it('a background tab (no frames, its message handler alive) answers the probes and is kept', () => {
    const m = match(3000, [honest('198.51.100.1')]);
    const { session } = secondPlayer(m, '198.51.100.3');
    // Hidden from 5 s to 35 s: not a single frame.
    const hidden = (t: number) => t >= 5000 && t < 35_000;
    m.scheduler.every(
      1000 / 60,
      () => {
        if (!hidden(m.scheduler.now)) session.frame(m.scheduler.now);
      },
      3,
    );
    m.scheduler.runUntil(35_000);
    expect(m.relay.room('honest')!.members).toHaveLength(2);
    expect(m.relay.stats.dropped).toEqual({});
    expect(
      m.scheduler.runUntilDone(() => session.isFinished && m.sessions[0]!.isFinished, 120_000),
    ).toBe(true);
    expect(session.hashAt(3000)).toBe(m.sessions[0]!.hashAt(3000));
    // Its frames came back at 35 s, 30 s of ticks behind: it caught up, 32 ticks a frame.
    expect(session.stats.maxTicksInFrame).toBe(32);
  });
});

describe('spectators', () => {
  it('join only with the room’s invite token', () => {
    const m = match(600, [honest('198.51.100.1'), honest('198.51.100.2')]);
    const none = new Raw(m.connect(quiet).transport);
    const wrong = new Raw(m.connect(quiet).transport);
    const nowhere = new Raw(m.connect(quiet).transport);
    const invited = new Raw(m.connect(quiet).transport);
    m.scheduler.at(1000, () => {
      none.hello('honest', 'spectator');
      wrong.hello('honest', 'spectator', { token: new Uint8Array(16).fill(1) });
      nowhere.hello('no-such-room', 'spectator', { token: new Uint8Array(16).fill(1) });
      // A player hands the invite over (here: its welcome's).
      invited.hello('honest', 'spectator', { token: m.sessions[0]!.welcome!.invite });
    });
    m.scheduler.runUntil(1500);
    expect(none.error?.code).toBe('BAD_TOKEN');
    expect(wrong.error?.code).toBe('BAD_TOKEN');
    expect(nowhere.error?.code).toBe('BAD_HELLO');
    expect(invited.welcome?.slot).toBe(-1);
    // Players get the invite; spectators do not pass it on.
    expect(m.sessions[0]!.welcome!.invite).toEqual(m.relay.invite('honest'));
    expect(invited.welcome!.invite).toHaveLength(0);
  });

  it('with the token, cannot fake a desync: only the spectator is told its state differs', () => {
    const m = match(1800, [honest('198.51.100.1'), honest('198.51.100.2')]);
    const liar = new Raw(m.connect(quiet).transport, true);
    m.scheduler.at(1000, () => {
      liar.hello('honest', 'spectator', { token: m.relay.invite('honest')! });
    });
    // Every report tick, a wrong hash.
    m.scheduler.every(
      500,
      () => {
        const room = m.relay.room('honest');
        const w = liar.welcome;
        if (!room || !w || room.closedTick < 30) return;
        const tick = Math.floor(room.closedTick / 30) * 30;
        liar.send({ type: 'hash', room: w.room, tick, hash: 0xbadn });
        liar.send({ type: 'ack', room: w.room, ack: room.closedTick });
      },
      1500,
    );
    const r = finishHonestly(m, 120_000);
    expect(r.room!.desyncs).toHaveLength(0);
    expect(r.relay.desyncs).toBe(0);
    for (const s of m.sessions) expect(s!.desyncs).toEqual([]);
    expect(r.relay.spectatorDesyncs).toBeGreaterThan(5);
    const told = liar.got.filter((x): x is DesyncMessage => x.type === 'desync');
    expect(told.length).toBe(r.relay.spectatorDesyncs);
    expect(told[0]!.groups[1]!.peers).toEqual([liar.welcome!.peer]);
  });
});

describe('drain: graceful shutdown', () => {
  it('closes waiting rooms, refuses new ones, lets the running match end, then resolves', async () => {
    const m = match(1200, [honest('198.51.100.1'), honest('198.51.100.2')]);
    const lonely = new Raw(m.connect(quiet, { address: '198.51.100.3' }).transport, true);
    lonely.hello('lonely', 'player');
    let drained: Promise<void> | undefined;
    let resolved = false;
    m.scheduler.at(5000, () => {
      drained = m.relay.drain({ timeoutMs: 60_000 });
      void drained.then(() => (resolved = true));
    });
    let late!: Raw;
    m.scheduler.at(6000, () => {
      late = new Raw(m.connect(quiet, { address: '198.51.100.4' }).transport);
      late.hello('late', 'player');
    });
    m.scheduler.runUntil(7000);
    expect(m.relay.draining).toBe(true);
    expect(lonely.error?.code).toBe('SHUTDOWN');
    expect(late.error?.code).toBe('SHUTDOWN');
    expect(late.error?.message).toMatch(/no new rooms here/);
    expect(m.relay.roomList().map((r) => r.name)).toEqual(['honest']);
    // The match plays to its end; then its players leave.
    finishHonestly(m, 60_000);
    await Promise.resolve();
    expect(resolved).toBe(false);
    for (const s of m.sessions) s!.leave();
    m.scheduler.runFor(200);
    await drained;
    expect(m.relay.stats.rooms).toBe(0);
    // Shutdowns are not counted as drops.
    expect(m.relay.stats.dropped.SHUTDOWN).toBeUndefined();
  });

  it('tells a match still running at the timeout SHUTDOWN, and resolves', async () => {
    const m = match(6000, [honest('198.51.100.1'), honest('198.51.100.2')]);
    let drained: Promise<void> | undefined;
    m.scheduler.at(5000, () => {
      drained = m.relay.drain({ timeoutMs: 3000 });
    });
    m.scheduler.runUntil(7900);
    expect(m.relay.stats.rooms).toBe(1);
    m.scheduler.runUntil(8100);
    await drained;
    expect(m.relay.stats.rooms).toBe(0);
    for (const s of m.sessions) {
      expect(s!.phase).toBe('closed');
      expect(s!.errors.at(-1)?.code).toBe('SHUTDOWN');
    }
  });
});
