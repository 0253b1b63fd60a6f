/**
 * How a networked session ends: `finished` resolves at its end (relay sessions: the state at
 * `stopAt` confirmed, or `leave()`; state sync: `leave()`, or the server closing the room), and
 * rejects with a SessionError — announced first by an `error` event — when the server refuses or
 * drops it, its welcome cannot be built, or its transport closes first. Nobody has to await it.
 */
import { describe, expect, it } from 'vitest';
import {
  EventScheduler,
  LockstepSession,
  Random,
  Relay,
  RollbackSession,
  SessionError,
  SimulatedLink,
  SpectatorSession,
  gameCatalog,
  type ButtonInput,
  type ConnectionInfo,
  type NetEvent,
  type NetSession,
  type NetSessionOptions,
  type StateSyncEvent,
  type StateSyncSession,
} from 'fixedstep';
import { World, arenaGame, scripted, type Arena } from './state-sync-fixture.js';

type Kind = 'lockstep' | 'rollback' | 'spectator';

/** A relay and sessions joining it over 20 ms links that keep order (a WebSocket). */
function relayWorld() {
  const scheduler = new EventScheduler(0);
  const game = arenaGame();
  const random = new Random(3);
  const relay = new Relay({
    clock: scheduler.clock,
    catalog: gameCatalog([game]),
    randomU32: () => random.nextU32(),
  });
  scheduler.every(1000 / 120, () => {
    relay.update();
  });
  let seed = 1;
  const join = (
    kind: Kind,
    options: Partial<NetSessionOptions> = {},
    info: ConnectionInfo = {},
  ) => {
    const link = new SimulatedLink({ scheduler, seed: seed++, latencyMs: 20, ordered: true });
    relay.accept(link.b, info);
    const events: NetEvent[] = [];
    const o: NetSessionOptions = {
      transport: link.a,
      clock: scheduler.clock,
      room: 'r',
      game,
      players: 2,
      seed: 5,
      localInput: (tick) => scripted(tick, session.welcome?.slot ?? 0),
      onEvent: (e) => events.push(e),
      ...options,
    };
    const session: NetSession =
      kind === 'lockstep'
        ? new LockstepSession(o)
        : kind === 'rollback'
          ? new RollbackSession(o)
          : new SpectatorSession(o);
    const frames = scheduler.every(1000 / 60, () => {
      if (session.phase === 'closed') frames.cancel();
      else session.frame();
    });
    return { session, events, link };
  };
  return { scheduler, relay, game, join };
}

/** The one `error` event of `events`, which must be fatal and come right before `closed`. */
function fatalError(events: readonly { type: string }[]): SessionError {
  const types = events.map((e) => e.type);
  expect(types.slice(-2)).toEqual(['error', 'closed']);
  expect(types.filter((t) => t === 'error')).toHaveLength(1);
  const e = events.at(-2) as { type: 'error'; error: SessionError };
  expect(e.error).toBeInstanceOf(SessionError);
  expect(e.error.fatal).toBe(true);
  return e.error;
}

describe('relay sessions: a refused join is an error event, then finished rejects with its code', () => {
  const cases: {
    code: string;
    kinds: Kind[];
    /** Says why, in the server's words. */
    says: RegExp;
    /** Joins the session under test (after whatever the case sets up). */
    join: (
      w: ReturnType<typeof relayWorld>,
      kind: Kind,
    ) => ReturnType<ReturnType<typeof relayWorld>['join']>;
  }[] = [
    {
      code: 'WRONG_ROOM',
      kinds: ['lockstep', 'rollback', 'spectator'],
      says: /for room lobby, not r/,
      // Its WebSocket's URL names another room than its hello.
      join: (w, kind) => w.join(kind, {}, { room: 'lobby' }),
    },
    {
      code: 'BAD_TOKEN',
      kinds: ['lockstep', 'rollback'],
      says: /no seat of this room has that token/,
      join: (w, kind) => {
        w.join('lockstep');
        w.scheduler.runFor(200);
        return w.join(kind, { token: new Uint8Array(16).fill(7) });
      },
    },
    {
      code: 'BAD_TOKEN',
      kinds: ['spectator'],
      says: /invite token/,
      join: (w, kind) => {
        w.join('lockstep');
        w.scheduler.runFor(200);
        return w.join(kind, { invite: new Uint8Array(16).fill(7) });
      },
    },
    {
      code: 'ROOM_FULL',
      kinds: ['lockstep', 'rollback'],
      says: /all 1 player seats are taken/,
      join: (w, kind) => {
        w.join('lockstep', { players: 1 });
        w.scheduler.runFor(200);
        return w.join(kind, { players: 1 });
      },
    },
    {
      code: 'GAME_MISMATCH',
      kinds: ['lockstep', 'rollback', 'spectator'],
      says: /plays arena version 1, not 2/,
      join: (w, kind) => w.join(kind, { game: { ...w.game, version: 2 } }),
    },
  ];
  for (const c of cases) {
    for (const kind of c.kinds) {
      it(`${c.code}: ${kind}`, async () => {
        const w = relayWorld();
        const { session, events } = c.join(w, kind);
        w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
        expect(session.phase).toBe('closed');
        const error = fatalError(events);
        expect(error.code).toBe(c.code);
        expect(error.message).toMatch(new RegExp(`^${c.code}: `));
        expect(error.message).toMatch(c.says);
        // The same error, by the promise and by the getter; never finished.
        await expect(session.finished).rejects.toBe(error);
        expect(session.failure).toBe(error);
        expect(session.isFinished).toBe(false);
        expect(session.welcome).toBeUndefined();
        expect(session.errors.map((m) => [m.code, m.fatal])).toEqual([[c.code, true]]);
      });
    }
  }
});

describe('relay sessions: how they end', () => {
  it('finished resolves when the state at stopAt is confirmed, and a later close changes nothing', async () => {
    const w = relayWorld();
    const stopAt = 120;
    const a = w.join('lockstep', { stopAt });
    const b = w.join('rollback', { stopAt });
    // When isFinished turns true, the state at stopAt is final here.
    let hashWhenDone: bigint | undefined;
    w.scheduler.runUntilDone(() => {
      if (a.session.isFinished && hashWhenDone === undefined)
        hashWhenDone = a.session.hashAt(stopAt);
      return a.session.isFinished && b.session.isFinished;
    }, 60_000);
    await expect(a.session.finished).resolves.toBeUndefined();
    await expect(b.session.finished).resolves.toBeUndefined();
    expect(a.session.tick).toBe(stopAt);
    expect(hashWhenDone).toBeDefined();
    expect(b.session.hashAt(stopAt)).toBe(hashWhenDone);
    for (const s of [a, b]) {
      expect(s.events.map((e) => e.type)).toEqual(['welcome', 'running']);
      expect(s.session.failure).toBeUndefined();
    }
    // The server going away after the end is reported, and is no failure.
    w.relay.close();
    w.scheduler.runUntilDone(() => a.session.phase === 'closed', 10_000);
    const error = fatalError(a.events);
    expect(error.code).toBe('SHUTDOWN');
    await expect(a.session.finished).resolves.toBeUndefined();
    expect(a.session.isFinished).toBe(true);
    expect(a.session.failure).toBeUndefined();
  });

  it('the running event says the tick the session starts from', () => {
    const w = relayWorld();
    const a = w.join('lockstep');
    const b = w.join('lockstep');
    w.scheduler.runUntilDone(() => a.session.tick > 60 && b.session.tick > 60, 10_000);
    const late = w.join('spectator', { invite: w.relay.invite('r')! });
    w.scheduler.runUntilDone(() => late.session.phase === 'running', 10_000);
    expect(a.events).toContainEqual({ type: 'running', tick: 0 });
    const running = late.events.find((e) => e.type === 'running');
    // A late spectator starts from a member's snapshot, past tick 60.
    expect(running).toEqual({ type: 'running', tick: late.session.welcome!.startTick });
    expect(late.session.welcome!.startTick).toBeGreaterThan(30);
  });

  it('a transport that closes before the end: an error event, then finished rejects with CLOSED', async () => {
    const w = relayWorld();
    const a = w.join('rollback', { stopAt: 600 });
    w.join('rollback', { stopAt: 600 });
    w.scheduler.runUntilDone(() => a.session.tick >= 30, 10_000);
    // The server's end of the link goes away without a word (a network failure, a crash).
    a.link.b.close('connection reset');
    w.scheduler.runUntilDone(() => a.session.phase === 'closed', 10_000);
    const error = fatalError(a.events);
    expect(error.code).toBe('CLOSED');
    expect(error.message).toContain('connection reset');
    await expect(a.session.finished).rejects.toBe(error);
    expect(a.session.isFinished).toBe(false);
    expect(a.events.at(-1)).toEqual({ type: 'closed', reason: 'connection reset' });
  });

  it('leave() before stopAt is the owner’s end: finished resolves, no error', async () => {
    const w = relayWorld();
    const a = w.join('lockstep', { stopAt: 600 });
    w.join('lockstep', { stopAt: 600 });
    w.scheduler.runUntilDone(() => a.session.tick >= 30, 10_000);
    a.session.leave();
    await expect(a.session.finished).resolves.toBeUndefined();
    expect(a.session.isFinished).toBe(true);
    expect(a.session.phase).toBe('closed');
    expect(a.events.map((e) => e.type)).toEqual(['welcome', 'running', 'closed']);
  });

  it('a welcome whose game cannot be built: an error event, then finished rejects with BAD_WELCOME', async () => {
    const w = relayWorld();
    const { session, events } = w.join('lockstep', {
      createSimulation: () => {
        throw new RangeError('no arena of that size');
      },
    });
    w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
    // The welcome came; the game it describes could not be made.
    expect(events[0]).toMatchObject({ type: 'error' });
    const error = fatalError(events);
    expect(error.code).toBe('BAD_WELCOME');
    expect(error.message).toContain('no arena of that size');
    await expect(session.finished).rejects.toBe(error);
    expect(session.simulation).toBeUndefined();
    // The session closed its connection: the relay let the seat go.
    w.scheduler.runFor(100);
    expect(w.relay.stats.connections).toBe(0);
  });
});

describe('state-sync sessions: how they end', () => {
  const join = (
    w: World,
    options: Parameters<World['client']>[0] = {},
  ): { session: StateSyncSession<ButtonInput, Arena>; events: StateSyncEvent[] } => {
    const events: StateSyncEvent[] = [];
    const session = w.client({ ...options, onEvent: (e) => events.push(e) });
    return { session, events };
  };
  const quiet = { latencyMs: 20, jitterMs: 0, loss: 0 };

  const refusals: {
    code: string;
    says: RegExp;
    options: (w: World) => Parameters<World['client']>[0];
  }[] = [
    {
      code: 'WRONG_ROOM',
      says: /for room r, not elsewhere/,
      options: () => ({ room: 'elsewhere' }),
    },
    {
      code: 'GAME_MISMATCH',
      says: /plays arena version 1, not 2/,
      options: (w) => ({
        game: { ...w.game, version: 2 },
      }),
    },
    {
      code: 'BAD_TOKEN',
      says: /invite token/,
      options: () => ({ role: 'spectator', invite: new Uint8Array(16).fill(7) }),
    },
  ];
  for (const c of refusals) {
    it(`a refused join (${c.code}): an error event, then finished rejects with its code`, async () => {
      const w = new World(arenaGame(), quiet);
      const { session, events } = join(w, c.options(w));
      w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
      const error = fatalError(events);
      expect(error.code).toBe(c.code);
      expect(error.message).toMatch(c.says);
      await expect(session.finished).rejects.toBe(error);
      expect(session.failure).toBe(error);
      expect(session.isFinished).toBe(false);
    });
  }

  it('a welcome whose game cannot be built: finished rejects with BAD_WELCOME', async () => {
    const w = new World(arenaGame(), quiet);
    const { session, events } = join(w, {
      createSimulation: () => {
        throw new RangeError('no arena of that size');
      },
    });
    w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
    const error = fatalError(events);
    expect(error.code).toBe('BAD_WELCOME');
    expect(error.message).toContain('no arena of that size');
    await expect(session.finished).rejects.toBe(error);
  });

  it('leave() resolves finished', async () => {
    const w = new World(arenaGame(), quiet);
    const { session, events } = join(w);
    w.scheduler.runUntilDone(() => session.snapshotTick > 30, 10_000);
    expect(session.isFinished).toBe(false);
    session.leave();
    await expect(session.finished).resolves.toBeUndefined();
    expect(session.isFinished).toBe(true);
    expect(events.map((e) => e.type)).toEqual(['welcome', 'running', 'closed']);
  });

  it('the server closing the room after the welcome is its end: finished resolves, SHUTDOWN is reported', async () => {
    const w = new World(arenaGame(), quiet);
    const { session, events } = join(w);
    w.scheduler.runUntilDone(() => session.snapshotTick > 30, 10_000);
    w.room.close();
    w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
    expect(fatalError(events).code).toBe('SHUTDOWN');
    await expect(session.finished).resolves.toBeUndefined();
    expect(session.isFinished).toBe(true);
    expect(session.failure).toBeUndefined();
  });

  it('a SHUTDOWN before the welcome is a refusal: finished rejects with SHUTDOWN', async () => {
    const w = new World(arenaGame(), quiet);
    const first = join(w);
    w.scheduler.runUntilDone(() => first.session.phase === 'running', 10_000);
    w.room.close();
    const late = join(w);
    w.scheduler.runUntilDone(() => late.session.phase === 'closed', 10_000);
    const error = fatalError(late.events);
    expect(error.code).toBe('SHUTDOWN');
    await expect(late.session.finished).rejects.toBe(error);
  });

  it('a transport that closes first: finished rejects with CLOSED', async () => {
    const w = new World(arenaGame(), quiet);
    const { session, events } = join(w);
    w.scheduler.runUntilDone(() => session.snapshotTick > 30, 10_000);
    w.links[0]!.b.close('connection reset');
    w.scheduler.runUntilDone(() => session.phase === 'closed', 10_000);
    const error = fatalError(events);
    expect(error.code).toBe('CLOSED');
    expect(error.message).toContain('connection reset');
    await expect(session.finished).rejects.toBe(error);
  });
});

describe('nobody has to await finished', () => {
  it('sessions that fail unobserved raise no unhandled rejection', async () => {
    const unhandled: unknown[] = [];
    const onUnhandled = (reason: unknown) => {
      unhandled.push(reason);
    };
    process.on('unhandledRejection', onUnhandled);
    try {
      const w = relayWorld();
      const relayed = w.join('lockstep', {}, { room: 'lobby' }).session;
      const world = new World(arenaGame(), { latencyMs: 20 });
      const synced = world.client({ room: 'elsewhere' });
      w.scheduler.runUntilDone(() => relayed.phase === 'closed', 10_000);
      world.scheduler.runUntilDone(() => synced.phase === 'closed', 10_000);
      // Node reports a rejection nobody handled once the microtasks after it have run: let a
      // turn of the event loop pass (no timer).
      await new Promise((resolve) => setImmediate(resolve));
      await new Promise((resolve) => setImmediate(resolve));
      expect(unhandled).toEqual([]);
      // They did fail: the promises are rejected, for whoever asks.
      expect(relayed.failure?.code).toBe('WRONG_ROOM');
      expect(synced.failure?.code).toBe('WRONG_ROOM');
      await expect(relayed.finished).rejects.toBeInstanceOf(SessionError);
      await expect(synced.finished).rejects.toBeInstanceOf(SessionError);
    } finally {
      process.off('unhandledRejection', onUnhandled);
    }
  });
});
