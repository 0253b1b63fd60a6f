import { describe, expect, it } from 'vitest';
import {
  RELAY_PROTOCOL,
  SimulatedMatch,
  decodeFrame,
  encodeMessage,
  type ErrorMessage,
  type NetErrorCode,
  type NetMessage,
  type Transport,
  type WelcomeMessage,
} from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { registryCatalog } from '../src/relay/index.js';

/** A client that speaks the protocol by hand, to misbehave. */
class Raw {
  readonly got: NetMessage[] = [];
  closed: string | undefined;
  constructor(
    readonly t: Transport,
    /** A room's invite token, which a spectator's hello carries unless told otherwise. */
    private readonly inviteOf: (room: string) => Uint8Array | undefined = () => undefined,
  ) {
    t.onMessage((b) => this.got.push(...decodeFrame(b)));
    t.onClose((r) => (this.closed = r));
  }
  send(m: NetMessage): void {
    this.t.send(encodeMessage(m));
  }
  bytes(b: Uint8Array): void {
    this.t.send(b);
  }
  hello(
    room: string,
    role: 'player' | 'spectator' = 'spectator',
    extra: Partial<NetMessage> = {},
  ): void {
    const invite = role === 'spectator' ? this.inviteOf(room) : undefined;
    this.send({
      type: 'hello',
      room,
      role,
      ...(invite ? { token: invite } : {}),
      game: 'ctf',
      gameVersion: ctfGame.info.version,
      input: ctfGame.input.id,
      players: 0,
      name: 'mallory',
      ...extra,
    } as NetMessage);
  }
  get welcome(): WelcomeMessage | undefined {
    return this.got.find((m): m is WelcomeMessage => m.type === 'welcome');
  }
  get error(): ErrorMessage | undefined {
    return this.got.find((m): m is ErrorMessage => m.type === 'error' && m.fatal);
  }
}

describe('hostile traffic is refused; the other rooms play on', () => {
  it('drops every misbehaving connection and nobody else', () => {
    const ticks = 1800;
    // Room A: 4 slots, two honest lockstep players, two hostile players. Room B: two honest
    // rollback players and a spectator.
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 5,
      ticks,
      // The server's own catalog: every registered game.
      catalog: registryCatalog(),
      link: { latencyMs: 30, jitterMs: 8, loss: 0.02 },
      clients: [
        { kind: 'lockstep', room: 'A', players: 4 },
        { kind: 'lockstep', room: 'A', players: 4 },
        { kind: 'rollback', room: 'B', players: 2 },
        { kind: 'rollback', room: 'B', players: 2 },
        { kind: 'spectator', room: 'B', players: 2 },
      ],
    });
    const s = match.scheduler;
    const raw = (link = { latencyMs: 10, jitterMs: 0, loss: 0 }) =>
      new Raw(match.connect(link).transport, (room) => match.relay.invite(room));

    // Two hostile players fill room A so it starts.
    const spoofer = raw();
    const flooder = raw();
    spoofer.hello('A', 'player', { players: 4 });
    flooder.hello('A', 'player', { players: 4 });
    s.runUntil(3000);
    expect(match.relay.room('A')!.state).toBe('running');
    const roomA = spoofer.welcome!.room;
    const roomB = match.relay.room('B')!.number;
    const mySlot = spoofer.welcome!.slot;
    const otherSlot = (mySlot + 1) % 4;
    const expected: [Raw, NetErrorCode][] = [];
    const at = (ms: number, fn: () => void) => s.at(ms, fn);

    // 1. A player sends inputs as another player.
    at(4000, () => {
      spoofer.send({
        type: 'input',
        room: roomA,
        player: otherSlot,
        ack: 0,
        tick: 250,
        words: 1,
        inputs: Uint32Array.of(0xffff),
      });
    });
    expected.push([spoofer, 'SPOOFED_PLAYER']);
    // 2. A player sends inputs for ticks far in the future, again and again.
    at(4000, () => {
      for (let i = 0; i < 12; i++) {
        flooder.send({
          type: 'input',
          room: roomA,
          player: flooder.welcome!.slot,
          ack: 0,
          tick: 100_000 + i,
          words: 1,
          inputs: Uint32Array.of(1),
        });
      }
    });
    expected.push([flooder, 'TICK_WINDOW']);
    // 3. Garbage as the first message.
    const garbage = raw();
    at(4100, () => {
      garbage.bytes(Uint8Array.of(0xde, 0xad, 0xbe, 0xef, 1, 2, 3));
    });
    expected.push([garbage, 'BAD_MESSAGE']);
    // 4. A message before any hello: ignored (messages may overtake the hello on an unordered
    // link), and without a hello the connection times out.
    const early = raw();
    at(4100, () => {
      early.send({ type: 'ack', room: roomA, ack: 10 });
    });
    expected.push([early, 'TIMEOUT']);
    // 5. A spectator of room B uses room A's number.
    const wrongRoom = raw();
    at(4100, () => {
      wrongRoom.hello('B');
    });
    at(4500, () => {
      wrongRoom.send({ type: 'ack', room: roomA, ack: 1 });
    });
    expected.push([wrongRoom, 'WRONG_ROOM']);
    // 6. A spectator sends inputs.
    const spectatorInput = raw();
    at(4100, () => {
      spectatorInput.hello('B');
    });
    at(4500, () => {
      spectatorInput.send({
        type: 'input',
        room: roomB,
        player: 0,
        ack: 0,
        tick: 300,
        words: 1,
        inputs: Uint32Array.of(1),
      });
    });
    expected.push([spectatorInput, 'SPOOFED_PLAYER']);
    // 7. A flood of pings.
    const flood = raw();
    at(4100, () => {
      flood.hello('B');
      for (let i = 0; i < 2000; i++) flood.send({ type: 'ping', id: i, time: 0 });
    });
    expected.push([flood, 'RATE_LIMIT']);
    // 8. An oversized message, and an unrequested 1 MiB snapshot.
    const big = raw();
    at(4100, () => {
      big.hello('B');
      // Larger than an input can ever be (64 ticks of 16 words): refused before it is read.
      const b = new Uint8Array(RELAY_PROTOCOL.maxBytes('input') + 1);
      b.set([RELAY_PROTOCOL.header, RELAY_PROTOCOL.code('input')]);
      big.bytes(b);
    });
    expected.push([big, 'TOO_LARGE']);
    const snap = raw();
    at(4100, () => {
      snap.hello('B');
    });
    at(4500, () => {
      snap.send({ type: 'snapshot', room: roomB, id: 1, tick: 0, bytes: new Uint8Array(1 << 20) });
    });
    expected.push([snap, 'UNEXPECTED']);
    // 9. Unknown game, wrong version, a full room, a forged token.
    const unknown = raw();
    at(4100, () => {
      unknown.hello('C', 'player', { game: 'tetris' });
    });
    expected.push([unknown, 'UNKNOWN_GAME']);
    const version = raw();
    at(4100, () => {
      version.hello('B', 'player', { gameVersion: 999 });
    });
    expected.push([version, 'GAME_MISMATCH']);
    const full = raw();
    at(4100, () => {
      full.hello('B', 'player');
    });
    expected.push([full, 'ROOM_FULL']);
    const forged = raw();
    at(4100, () => {
      forged.hello('B', 'player', { token: new Uint8Array(16).fill(7) });
    });
    expected.push([forged, 'BAD_TOKEN']);
    // 10. A server-to-client message from a client; a hash of a tick not yet played.
    const confused = raw();
    at(4100, () => {
      confused.hello('B');
    });
    at(4500, () => {
      confused.send({ type: 'start', room: roomB, startAt: 0 });
    });
    // Refused as it is read: the protocol declares who sends a start.
    expected.push([confused, 'BAD_MESSAGE']);
    const liar = raw();
    at(4100, () => {
      liar.hello('B');
    });
    at(4500, () => {
      for (let i = 1; i <= 10; i++)
        liar.send({ type: 'hash', room: roomB, tick: 1_000_000 * i, hash: 1n });
    });
    expected.push([liar, 'TICK_WINDOW']);
    // 11. A connection that never says hello.
    const silent = raw();
    expected.push([silent, 'TIMEOUT']);

    const r = match.run(120_000);

    for (const [client, code] of expected) {
      expect(client.error?.code, `expected ${code}`).toBe(code);
      expect(client.closed).toBeDefined();
    }
    // The version check names the mismatch.
    expect(version.error!.message).toMatch(/version/);
    // The honest clients never saw an error, finished, and agree within each room.
    expect(r.finished).toBe(true);
    expect(r.hashesAgree).toBe(true);
    for (const c of r.clients) {
      expect(c.closed).toBe(false);
      expect(c.tick).toBe(ticks);
    }
    for (const session of match.sessions) expect(session!.errors).toEqual([]);
    const hashA = r.clients.filter((c) => c.room === 'A').map((c) => c.finalHash);
    const hashB = r.clients.filter((c) => c.room === 'B').map((c) => c.finalHash);
    expect(new Set(hashA).size).toBe(1);
    expect(new Set(hashB).size).toBe(1);
    expect(match.relay.room('A')!.closedTick).toBeGreaterThanOrEqual(ticks);
    expect(match.relay.room('B')!.closedTick).toBeGreaterThanOrEqual(ticks);
    expect(match.relay.room('A')!.desyncs).toHaveLength(0);
    expect(match.relay.room('B')!.desyncs).toHaveLength(0);
    // Room A lost its two hostile players; its honest ones are the only members left.
    expect(match.relay.room('A')!.members).toHaveLength(2);
    const dropped = r.relay.dropped;
    expect(Object.values(dropped).reduce((a, b) => a + b, 0)).toBe(expected.length);
  });

  it('a peer that stops acknowledging is streamed to, then dropped when it falls out of the history', () => {
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 6,
      ticks: 1200,
      // Silent members are dropped after 10 s by default: this one is heard from, but never acks.
      relay: { historyTicks: 600, silenceTimeoutMs: 60_000 },
      clients: [{ kind: 'lockstep', players: 1 }],
    });
    const mute = new Raw(match.connect({ latencyMs: 5 }).transport, (room) =>
      match.relay.invite(room),
    );
    match.scheduler.at(100, () => {
      mute.hello('match');
    });
    const r = match.run(60_000);
    expect(r.finished).toBe(true);
    expect(mute.error?.code).toBe('NO_SNAPSHOT');
    expect(r.clients[0]!.closed).toBe(false);
  });
});

describe('strangers all at once, beside a well-behaved room', () => {
  it('idle sockets, squatters, fake hashes and floods: the honest room finishes and agrees', () => {
    const ticks = 3600;
    const match = new SimulatedMatch({
      game: ctfGame,
      seed: 31,
      ticks,
      catalog: registryCatalog(),
      link: { latencyMs: 40, jitterMs: 10, loss: 0.02 },
      room: 'honest',
      players: 3,
      clients: [
        { kind: 'rollback', connection: { address: '198.51.100.1' } },
        { kind: 'lockstep', connection: { address: '198.51.100.2' } },
        { kind: 'rollback', connection: { address: '198.51.100.3' } },
        { kind: 'spectator', connection: { address: '198.51.100.4' } },
      ],
    });
    const s = match.scheduler;
    const quiet = { latencyMs: 10, jitterMs: 0, loss: 0 };
    const raw = (address: string) =>
      new Raw(match.connect(quiet, { address }).transport, (room) => match.relay.invite(room));
    const strangers: Raw[] = [];
    // 300 idle sockets from 10 addresses: hello, then nothing.
    for (let i = 0; i < 300; i++) {
      const r = raw(`203.0.113.${i % 10}`);
      r.hello(`idle${i}`, 'player', { players: 2 });
      strangers.push(r);
    }
    // 100 squatters from 100 addresses that keep their waiting rooms alive with pings.
    const squatters: Raw[] = [];
    for (let i = 0; i < 100; i++) {
      const r = raw(`10.1.${i}.1`);
      r.hello(`squat${i}`, 'player', { players: 4 });
      squatters.push(r);
      s.every(
        800,
        () => {
          r.send({ type: 'ping', id: i, time: s.now });
        },
        800,
      );
    }
    // Fake hashes: an invited spectator reports nonsense for every report tick.
    let liar: Raw | undefined;
    s.at(3000, () => {
      liar = raw('203.0.113.50');
      liar.hello('honest', 'spectator');
    });
    s.every(
      400,
      () => {
        const w = liar?.welcome;
        const room = match.relay.room('honest');
        if (!w || !room || room.closedTick < 30) return;
        liar!.send({
          type: 'hash',
          room: w.room,
          tick: Math.floor(room.closedTick / 30) * 30,
          hash: 1n,
        });
      },
      3500,
    );
    // A stranger without the invite tries to watch; floods of pings from a few more.
    const peeker = raw('203.0.113.51');
    s.at(3000, () => {
      peeker.hello('honest', 'spectator', { token: new Uint8Array(16) });
    });
    const flooders = [0, 1, 2].map((i) => raw(`203.0.113.${60 + i}`));
    s.at(4000, () => {
      for (const f of flooders)
        for (let i = 0; i < 1000; i++) f.send({ type: 'ping', id: i, time: 0 });
    });

    const r = match.run(300_000);
    expect(r.finished).toBe(true);
    expect(r.hashesAgree).toBe(true);
    for (const c of r.clients) {
      expect(c.closed).toBe(false);
      expect(c.tick).toBe(ticks);
    }
    for (const session of match.sessions) {
      expect(session!.errors).toEqual([]);
      expect(session!.desyncs).toEqual([]);
    }
    expect(r.room!.desyncs).toHaveLength(0);
    expect(r.relay.spectatorDesyncs).toBeGreaterThan(0);
    // Every idle socket timed out; each of the 10 addresses was capped at 8 rooms first.
    const idle = strangers.map((x) => x.error?.code);
    expect(idle.filter((c) => c === 'TIMEOUT')).toHaveLength(80);
    expect(idle.filter((c) => c === 'ADDRESS_LIMIT')).toHaveLength(220);
    // The squatters outlived the silence rule, not the waiting-room limit (the match ran 60 s).
    expect(squatters.every((x) => x.error === undefined)).toBe(true);
    match.scheduler.runUntil(121_000);
    expect(squatters.every((x) => x.error?.code === 'TIMEOUT')).toBe(true);
    expect(peeker.error?.code).toBe('BAD_TOKEN');
    for (const f of flooders) expect(f.error?.code).toBe('RATE_LIMIT');
  });
});
