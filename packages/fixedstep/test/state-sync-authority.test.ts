/**
 * The server is the authority: a client that sends impossible inputs — outside the schema, too
 * many for a tick, for another player — is refused, and a client that lies about its state changes
 * nothing, because it sends none. And interest management: a member receives only what the game
 * lets it see.
 */
import { describe, expect, it } from 'vitest';
import {
  ByteWriter,
  STATE_SYNC_PROTOCOL,
  SimulatedLink,
  decodeStateSyncMessage,
  encodeMessage,
  encodeStateSyncMessage,
  fnv1a64,
  hex64,
  type ButtonInput,
  type StateSyncMessage,
} from 'fixedstep';
import { ARENA_INPUT, Arena, SPEED, World, arenaGame, scripted } from './state-sync-fixture.js';

/** A raw connection to the world's room: sends what it is told, keeps what it gets. */
function hostile(w: World, role: 'player' | 'spectator' = 'player') {
  const link = new SimulatedLink({ scheduler: w.scheduler, latencyMs: 10 });
  w.room.accept(link.b);
  const got: StateSyncMessage[] = [];
  let closed: string | undefined;
  link.a.onMessage((b) => got.push(decodeStateSyncMessage(b)));
  link.a.onClose((r) => {
    closed = r;
  });
  const send = (m: StateSyncMessage) => {
    link.a.send(encodeStateSyncMessage(m));
  };
  send({
    type: 'join',
    room: 'r',
    role,
    game: 'arena',
    gameVersion: 1,
    input: ARENA_INPUT.id,
    players: 2,
    name: 'mallory',
    ...(role === 'spectator' ? { token: w.room.invite } : {}),
  });
  w.run(50);
  const welcome = got.find((m) => m.type === 'welcome');
  if (welcome?.type !== 'welcome') throw new Error('no welcome');
  return {
    slot: welcome.slot,
    got,
    send,
    sendBytes: (b: Uint8Array) => {
      link.a.send(b);
    },
    get closed() {
      return closed;
    },
    errors: () =>
      got.flatMap((m) =>
        m.type === 'error' ? [`${m.code}${m.fatal ? '!' : ''}: ${m.message}`] : [],
      ),
  };
}

/** The server's state hash at tick `t` after `ms`, with an honest client in slot 0 and `other` in slot 1. */
function serverHash(ms: number, slotOne: (w: World) => void): { hash: string; w: World } {
  const w = new World(arenaGame(), { latencyMs: 10, jitterMs: 0, loss: 0 });
  w.client({ localInput: (tick) => scripted(tick, 0) });
  w.run(40); // the honest client joins first: slot 0
  slotOne(w);
  w.run(ms);
  return { hash: hex64(w.room.simulation.history!.get(240)!), w };
}

describe('the server is the authority', () => {
  it('refuses an input outside the schema (a button the game does not have), and drops that client', () => {
    const w = new World(arenaGame(), { latencyMs: 10 });
    const h = hostile(w);
    // Bit 4: a fifth button; the arena has four.
    h.send({
      type: 'input',
      player: h.slot,
      ack: -1,
      tick: w.room.tick + 2,
      words: 1,
      inputs: Uint32Array.of(1 << 4),
    });
    w.run(100);
    const errors = h.errors();
    expect(errors.length).toBe(1);
    expect(errors[0]).toMatch(
      /^BAD_INPUT!: input of tick \d+: button word 0x10 sets bits of buttons the game does not define$/,
    );
    expect(h.closed).toMatch(/^BAD_INPUT/);
    expect(w.room.stats.dropped).toEqual({ BAD_INPUT: 1 });
    expect(w.room.occupied()).toEqual([false, false]);
  });

  it('refuses inputs for another player (and from a spectator)', () => {
    const w = new World(arenaGame(), { latencyMs: 10 });
    const honest = w.client();
    w.run(100);
    const h = hostile(w);
    const other = honest.welcome!.slot;
    h.send({
      type: 'input',
      player: other,
      ack: -1,
      tick: w.room.tick + 1,
      words: 1,
      inputs: Uint32Array.of(1),
    });
    w.run(100);
    expect(h.errors()).toEqual([
      `SPOOFED_PLAYER!: inputs for player ${other} from player ${h.slot}`,
    ]);
    expect(h.closed).toMatch(/^SPOOFED_PLAYER/);
    // The honest player plays on.
    expect(honest.phase).toBe('running');
    expect(w.room.occupied()[other]).toBe(true);
    const watcher = hostile(w, 'spectator');
    expect(watcher.slot).toBe(-1);
    watcher.send({
      type: 'input',
      player: 0,
      ack: -1,
      tick: w.room.tick + 1,
      words: 1,
      inputs: Uint32Array.of(1),
    });
    w.run(100);
    expect(watcher.errors()).toEqual(['SPOOFED_PLAYER!: a spectator sent inputs']);
  });

  it('takes one input a tick — the first — however many a client sends', () => {
    // Reference: slot 1 holds "right" from tick 60 on.
    const right = 1 << 1;
    const reference = serverHash(4000, (w) => {
      w.client({ localInput: (tick) => (tick >= 60 ? right : 0) });
    });
    // A cheat in slot 1 sends, every frame, the right input for the next ticks *and* two more
    // messages with other inputs for the same ticks — trying to move more than once a tick.
    const cheat = serverHash(4000, (w) => {
      const h = hostile(w);
      w.scheduler.every(1000 / 60, () => {
        const t = w.room.tick;
        const honest = Uint32Array.from({ length: 8 }, (_, k) => (t + k >= 60 ? right : 0));
        h.send({ type: 'input', player: h.slot, ack: -1, tick: t, words: 1, inputs: honest });
        for (let k = 0; k < 2; k++) {
          const extra = new Uint32Array(8).fill(right | (1 << 3));
          h.send({ type: 'input', player: h.slot, ack: -1, tick: t, words: 1, inputs: extra });
        }
      });
    });
    const room = cheat.w.room;
    // Every second and third input for a tick was refused (the first is final)…
    expect(room.stats.conflictingInputs).toBeGreaterThan(400);
    expect(room.stats.dropped).toEqual({});
    // …so not one extra step went through: its disc is exactly where the honest right-walker's is,
    // and the whole world hashes the same.
    expect(cheat.hash).toBe(reference.hash);
    const cheatX = room.simulation.trail!.get(120)!;
    const refX = reference.w.room.simulation.trail!.get(120)!;
    expect(cheatX[2]).toBe(refX[2]);
    expect(cheatX[3]).toBe(refX[3]);
    // 60 ticks of walking at SPEED units a second, not eleven times that.
    expect(cheatX[2]! - 40).toBeCloseTo(SPEED, 0);
  });

  it('refuses inputs more than maxAheadTicks ahead: a strike, then the door', () => {
    const w = new World(arenaGame(), { latencyMs: 10 }, { maxAheadTicks: 30, maxStrikes: 3 });
    const h = hostile(w);
    for (let k = 0; k < 4; k++) {
      h.send({
        type: 'input',
        player: h.slot,
        ack: -1,
        tick: w.room.tick + 100,
        words: 1,
        inputs: Uint32Array.of(2),
      });
      w.run(20);
    }
    const errors = h.errors();
    expect(errors.length).toBe(2);
    expect(errors[0]).toMatch(/^TICK_WINDOW: inputs for tick \d+, the room is at \d+$/);
    expect(errors[1]).toMatch(/^TICK_WINDOW!: .*\(too many violations\)$/);
    expect(h.closed).toMatch(/^TICK_WINDOW/);
  });

  it('a client that lies about its state changes nothing: it sends none, and what it sends instead is refused', () => {
    // Honest slot 1: walks right. Liar in slot 1: its own game gives it triple speed, it walks
    // right too, and it sends the relay protocol's snapshot and hash messages and a state-sync
    // snapshot "from the client".
    const right = (tick: number): ButtonInput => (tick >= 60 ? 1 << 1 : 0);
    const honest = serverHash(4000, (w) => {
      w.client({ localInput: right });
    });
    let liarSession: ReturnType<World['client']> | undefined;
    const liar = serverHash(4000, (w) => {
      liarSession = w.client({
        localInput: right,
        createSimulation: (setup) => new Arena(setup.players, setup.seed, { speed: 3 }),
      });
    });
    expect(liar.hash).toBe(honest.hash);
    // Its own screen showed it fast (and the server corrected it every snapshot).
    expect(liarSession!.stats.maxCorrection).toBeGreaterThan(1);
    // The server took no state from it: it could not have, there is no message for it.
    const w = new World(arenaGame(), { latencyMs: 10 });
    const h = hostile(w);
    const fake = new Arena(2, 7);
    fake.x[h.slot] = 99;
    const state = fake.save();
    h.send({
      type: 'snapshot',
      tick: 1,
      base: -1,
      older: -1,
      sendDelayUs: 0,
      inputAck: 1,
      filled: 0,
      late: 0,
      slack: 0,
      codec: 'bytes',
      size: state.length,
      hash: fnv1a64(state),
      payload: state,
    });
    w.run(50);
    expect(h.errors()).toEqual([
      'BAD_MESSAGE!: BAD_TYPE: state sync snapshot: a snapshot is sent by the server, not the client (at byte 1)',
    ]);
    const h2 = hostile(w);
    h2.sendBytes(encodeMessage({ type: 'snapshot', room: 0, id: 0, tick: 1, bytes: state }));
    w.run(50);
    expect(h2.errors()).toEqual([
      'BAD_MESSAGE!: BAD_VERSION: state sync: a relay message, not state sync (at byte 0)',
    ]);
    expect(w.room.simulation.x[h.slot]).not.toBe(99);
  });

  it('drops bytes that are not a message, and a client over the rate limit', () => {
    const w = new World(arenaGame(), { latencyMs: 10 });
    const h = hostile(w);
    h.sendBytes(new ByteWriter().u8(STATE_SYNC_PROTOCOL.header).u8(0x02).u8(0xff).finish());
    w.run(50);
    expect(h.errors()).toEqual([
      'BAD_MESSAGE!: TRUNCATED: state sync input.player: player: varint runs past the end (at byte 2)',
    ]);
    expect(h.closed).toMatch(/^BAD_MESSAGE/);
    const flood = hostile(w);
    // 1000 pings in a second: the bucket holds 480 and refills at 240 a second.
    w.scheduler.every(1, () => {
      flood.send({ type: 'ping', id: 1, time: w.scheduler.now });
    });
    w.run(1000);
    expect(flood.errors()).toEqual([
      'RATE_LIMIT!: more than 240 messages (or 131072 bytes) a second',
    ]);
    expect(w.room.stats.dropped).toEqual({ BAD_MESSAGE: 1, RATE_LIMIT: 1 });
  });
});

describe('interest management', () => {
  it('a member gets only what the view lets it see', () => {
    // Each member sees its own disc and any disc within 30 units; the others are sent at (-1, -1).
    const hidden = -1;
    const seenBy: number[] = [];
    const w = new World(
      arenaGame(),
      { latencyMs: 20 },
      {
        view: (sim: Arena, slot: number) => {
          seenBy.push(slot);
          const v = new Arena(sim.players, 0);
          v.load(sim.save());
          for (let p = 0; p < sim.players; p++) {
            if (p === slot) continue;
            const near =
              slot >= 0 && Math.hypot(sim.x[p]! - sim.x[slot]!, sim.y[p]! - sim.y[slot]!) < 30;
            if (!near) {
              v.x[p] = hidden;
              v.y[p] = hidden;
            }
          }
          return v.save();
        },
      },
    );
    const a = w.client();
    const b = w.client({ role: 'spectator' });
    const c = w.client();
    const seen: number[] = [];
    w.onFrame = (s, i) => {
      s.frame(w.scheduler.now);
      const state = s.snapshotState;
      if (!state || i !== 0) return;
      const v = new Arena(2, 0);
      v.load(state);
      const other = 1 - s.welcome!.slot;
      const server = w.room.simulation.trail!.get(s.snapshotTick)!;
      const far = Math.hypot(server[0]! - server[2]!, server[1]! - server[3]!) >= 30;
      // A far disc is never in what it received; a near one is exactly the server's.
      expect([v.x[other], v.y[other]]).toEqual(
        far ? [hidden, hidden] : [server[2 * other], server[2 * other + 1]],
      );
      seen.push(far ? 0 : 1);
    };
    w.run(20_000);
    // Both cases happened (the scripted squares bring the discs together now and then).
    expect(seen.filter((x) => x === 1).length).toBeGreaterThan(20);
    expect(seen.filter((x) => x === 0).length).toBeGreaterThan(20);
    expect(new Set(seenBy)).toEqual(new Set([0, 1, -1]));
    expect(a.stats.badSnapshots + b.stats.badSnapshots + c.stats.badSnapshots).toBe(0);
  });
});
