import http from 'node:http';
import { afterEach, describe, expect, it } from 'vitest';
import {
  ManualClock,
  SIGNAL_PROTOCOL,
  SignallingHub,
  decodeSignal,
  encodeSignal,
  memoryPair,
  type SignalMessage,
  type SignallingHubOptions,
  type Transport,
} from 'fixedstep';
import { attachSignalling, iceServersFromEnv } from '../src/signalling/endpoint.js';
import { connectNodeWebSocket } from '../src/relay/index.js';

/** Lets the memory pairs deliver (they deliver on later microtasks). */
const settle = () =>
  new Promise<void>((resolve) => {
    setImmediate(resolve);
  });

/** A client of the hub on a memory pair: what it received, decoded, and why it was closed. */
function client(hub: SignallingHub, address = 'unknown') {
  const [end, hubEnd] = memoryPair();
  hub.accept(hubEnd, { address });
  const got: SignalMessage[] = [];
  const closed: string[] = [];
  end.onMessage((b) => got.push(decodeSignal(b)));
  end.onClose((r) => closed.push(r));
  return {
    end,
    got,
    closed,
    send: (m: SignalMessage) => {
      end.send(encodeSignal(m));
    },
    raw: (b: Uint8Array) => {
      end.send(b);
    },
  };
}

function setup(options: Partial<SignallingHubOptions> = {}) {
  const clock = new ManualClock(0);
  const hub = new SignallingHub({ clock, ...options });
  return { clock, hub };
}

/** The invite a host got in its `joined`. */
function inviteOf(host: { got: SignalMessage[] }): Uint8Array {
  const joined = host.got.find((m) => m.type === 'joined');
  if (joined?.type !== 'joined') throw new Error('not hosting');
  return joined.invite;
}

describe('signalling hub', () => {
  it('introduces invited joiners to the host and stamps every forwarded message with its sender', async () => {
    const iceServers = [{ urls: ['stun:127.0.0.1:3478'] }];
    const { hub } = setup({ iceServers });
    const host = client(hub);
    const a = client(hub);
    const b = client(hub);
    host.send({ type: 'host', room: 'room1' });
    await settle();
    const invite = inviteOf(host);
    expect(invite).toHaveLength(16);
    a.send({ type: 'join', room: 'room1', invite });
    await settle();
    b.send({ type: 'join', room: 'room1', invite });
    await settle();
    expect(host.got).toEqual([
      { type: 'joined', room: 'room1', peer: 0, invite, iceServers },
      { type: 'peer', peer: 1 },
      { type: 'peer', peer: 2 },
    ]);
    // A joiner is not given the invite again (it has it).
    expect(a.got).toEqual([
      { type: 'joined', room: 'room1', peer: 1, invite: new Uint8Array(0), iceServers },
    ]);
    expect(hub.roomList()).toEqual([{ room: 'room1', peers: [0, 1, 2] }]);

    // Peer 2 claims to be peer 1 when it offers: the host sees peer 2.
    b.send({ type: 'signal', peer: 0, kind: 'offer', text: 'sdp' });
    await settle();
    expect(host.got.at(-1)).toEqual({ type: 'signal', peer: 2, kind: 'offer', text: 'sdp' });
    // The host answers peer 2 only; peer 1 sees nothing of it.
    host.send({ type: 'signal', peer: 2, kind: 'answer', text: 'sdp2' });
    host.send({ type: 'data', peer: 2, bytes: Uint8Array.from([9, 8]) });
    await settle();
    expect(b.got.slice(1)).toEqual([
      { type: 'signal', peer: 0, kind: 'answer', text: 'sdp2' },
      { type: 'data', peer: 0, bytes: Uint8Array.from([9, 8]) },
    ]);
    expect(a.got).toHaveLength(1);
    // A joiner cannot address another joiner: only the host. A signal to nobody is an error.
    a.send({ type: 'signal', peer: 2, kind: 'offer', text: 'x' });
    await settle();
    expect(a.got.at(-1)).toMatchObject({ type: 'error', code: 'NO_PEER', fatal: false });
    expect(b.got).toHaveLength(3);
    expect(hub.stats.tunnelled).toBe(1);

    // The host leaves: the joiners are told, the room is gone.
    host.end.close('bye');
    await settle();
    expect(a.got.at(-2)).toEqual({ type: 'leave', peer: 0 });
    expect(a.got.at(-1)).toMatchObject({ type: 'error', code: 'NO_ROOM', fatal: true });
    expect(hub.roomList()).toEqual([]);
  });

  it('lets nobody in without the invite, and refuses a taken, missing or full room', async () => {
    const { hub } = setup();
    const host = client(hub);
    host.send({ type: 'host', room: 'r' });
    await settle();
    const invite = inviteOf(host);
    // Someone who knows (or guessed) the name, without the invite: never sees the host's offers.
    const stranger = client(hub);
    stranger.send({ type: 'join', room: 'r', invite: new Uint8Array(16) });
    const again = client(hub);
    again.send({ type: 'host', room: 'r' });
    const lost = client(hub);
    lost.send({ type: 'join', room: 'nope', invite });
    const joiners = Array.from({ length: 16 }, () => client(hub));
    await settle();
    for (const j of joiners) {
      j.send({ type: 'join', room: 'r', invite });
      await settle();
    }
    expect(stranger.got).toEqual([
      {
        type: 'error',
        code: 'BAD_TOKEN',
        fatal: true,
        message: 'joining room r takes its invite token',
      },
    ]);
    expect(host.got.filter((m) => m.type === 'peer')).toHaveLength(15);
    expect(again.got).toEqual([
      { type: 'error', code: 'ROOM_TAKEN', fatal: true, message: 'room r already has a host' },
    ]);
    expect(lost.got[0]).toMatchObject({ type: 'error', code: 'NO_ROOM' });
    expect(joiners[14]!.got[0]).toMatchObject({ type: 'joined', peer: 15 });
    expect(joiners[15]!.got).toEqual([
      { type: 'error', code: 'ROOM_FULL', fatal: true, message: 'room r has 15 peers' },
    ]);
  });

  it('holds one address to its share: 1 000 hosts from one address get 8 rooms', async () => {
    const { hub } = setup();
    const hosts = Array.from({ length: 1000 }, (_, i) => {
      const c = client(hub, '203.0.113.9');
      c.send({ type: 'host', room: `squat${i}` });
      return c;
    });
    await settle();
    expect(hub.stats.rooms).toBe(8);
    expect(hub.stats.connections).toBe(8);
    const codes = hosts.map((h) => h.got[0]?.type === 'error' && h.got[0].code);
    expect(codes.filter((c) => c === 'ADDRESS_LIMIT')).toHaveLength(1000 - 8);
    // Someone else hosts at once.
    const honest = client(hub, '198.51.100.1');
    honest.send({ type: 'host', room: 'honest' });
    await settle();
    expect(honest.got[0]).toMatchObject({ type: 'joined', peer: 0 });
  });

  it('drops bad bytes, server-only messages, floods and silent connections; keeps quiet hosts that answer', async () => {
    const { clock, hub } = setup({
      rate: { messagesPerSecond: 10, messageBurst: 20 },
      helloTimeoutMs: 5000,
    });
    const bad = client(hub);
    bad.raw(Uint8Array.from([SIGNAL_PROTOCOL.header, 77]));
    const cheeky = client(hub);
    cheeky.raw(encodeSignal({ type: 'leave', peer: 3 }));
    const early = client(hub);
    early.send({ type: 'data', peer: 0, bytes: new Uint8Array(1) });
    const flood = client(hub);
    flood.send({ type: 'host', room: 'f' });
    for (let k = 0; k < 40; k++) flood.send({ type: 'data', peer: 1, bytes: new Uint8Array(1) });
    const silent = client(hub);
    // A host that waits for its joiners and answers the hub's pings (a SignalClient does).
    const [quietEnd, quietHub] = memoryPair();
    hub.accept(quietHub);
    quietEnd.onMessage((b) => {
      const m = decodeSignal(b);
      if (m.type === 'ping')
        quietEnd.send(encodeSignal({ type: 'pong', id: m.id, time: m.time, serverTime: 0 }));
    });
    quietEnd.send(encodeSignal({ type: 'host', room: 'quiet' }));
    await settle();
    expect(bad.got[0]).toMatchObject({ type: 'error', code: 'BAD_MESSAGE' });
    expect(bad.closed[0]).toMatch(/BAD_MESSAGE: .*unknown message type 0x4d/);
    expect(cheeky.closed[0]).toMatch(
      /BAD_MESSAGE: .*a leave is sent by the server, not the client/,
    );
    // A message before host or join is ignored; the connection then misses its join deadline.
    expect(early.closed).toEqual([]);
    // The burst: the 21st message in the same instant is refused.
    expect(flood.closed[0]).toMatch(/^RATE_LIMIT: more than 10 messages/);
    expect(hub.roomList()).toEqual([{ room: 'quiet', peers: [0] }]);
    for (let t = 0; t < 24; t++) {
      clock.advance(250);
      hub.update();
      await settle();
    }
    expect(silent.closed).toEqual(['TIMEOUT: no join in time']);
    expect(early.closed).toEqual(['TIMEOUT: no join in time']);
    expect(hub.stats.dropped).toEqual({ BAD_MESSAGE: 2, RATE_LIMIT: 1, TIMEOUT: 2 });
    // 6 s of silence from the quiet host, answered pings all along: it is kept.
    expect(hub.stats.probes).toBeGreaterThan(3);
    expect(hub.roomList()).toEqual([{ room: 'quiet', peers: [0] }]);
    expect(hub.stats.connections).toBe(1);
  });

  it('refuses an ICE server configuration it could not send', () => {
    expect(() => setup({ iceServers: [{ urls: [] }] })).toThrow(
      /iceServers: \[0\]: urls: 0 items, not 1 to 8/,
    );
  });
});

describe('attachSignalling', () => {
  const servers: http.Server[] = [];
  afterEach(async () => {
    for (const s of servers.splice(0)) {
      await new Promise<void>((resolve) => {
        s.close(() => {
          resolve();
        });
      });
    }
  });

  it('serves /signal over WebSocket, refuses other paths and other origins', async () => {
    const server = http.createServer();
    servers.push(server);
    const endpoint = attachSignalling(server, { allowedOrigins: ['http://good.example'] });
    await new Promise<void>((resolve) => server.listen(0, '127.0.0.1', resolve));
    const port = (server.address() as { port: number }).port;
    const t: Transport = await connectNodeWebSocket(`ws://127.0.0.1:${port}/signal/live`);
    const got: SignalMessage[] = [];
    t.onMessage((b) => got.push(decodeSignal(b)));
    t.send(encodeSignal({ type: 'host', room: 'live' }));
    for (let k = 0; k < 200 && got.length === 0; k++) await settle();
    expect(got).toMatchObject([{ type: 'joined', room: 'live', peer: 0, iceServers: [] }]);
    expect(endpoint.hub.roomList()).toEqual([{ room: 'live', peers: [0] }]);
    // The room is in the URL (a balancer routes by it): a join for another room is refused.
    const other: Transport = await connectNodeWebSocket(`ws://127.0.0.1:${port}/signal/live`);
    const refused: SignalMessage[] = [];
    other.onMessage((b) => refused.push(decodeSignal(b)));
    other.send(encodeSignal({ type: 'host', room: 'elsewhere' }));
    for (let k = 0; k < 200 && refused.length === 0; k++) await settle();
    expect(refused[0]).toMatchObject({ type: 'error', code: 'WRONG_ROOM' });
    await expect(connectNodeWebSocket(`ws://127.0.0.1:${port}/signal`)).rejects.toThrow(/404/);
    await expect(connectNodeWebSocket(`ws://127.0.0.1:${port}/other`)).rejects.toThrow(/404/);
    const status = await new Promise<number | undefined>((resolve) => {
      const req = http.get({
        host: '127.0.0.1',
        port,
        path: '/signal/live',
        headers: {
          Connection: 'Upgrade',
          Upgrade: 'websocket',
          Origin: 'http://evil.example',
          'Sec-WebSocket-Version': '13',
          'Sec-WebSocket-Key': 'dGhlIHNhbXBsZSBub25jZQ==',
        },
      });
      req.on('response', (res) => {
        resolve(res.statusCode);
      });
      req.on('upgrade', () => {
        resolve(101);
      });
    });
    expect(status).toBe(403);
    t.close('done');
    await endpoint.close();
  });

  it('announces the STUN/TURN servers of FIXEDSTEP_ICE_SERVERS; a bad value is refused, naming it', async () => {
    const server = http.createServer();
    servers.push(server);
    const turn = { urls: ['turn:turn.example:3478?transport=udp'], username: 'u', credential: 'c' };
    const endpoint = attachSignalling(server, {
      env: { FIXEDSTEP_ICE_SERVERS: JSON.stringify([{ urls: 'stun:stun.example:3478' }, turn]) },
    });
    await new Promise<void>((resolve) => server.listen(0, '127.0.0.1', resolve));
    const port = (server.address() as { port: number }).port;
    const t: Transport = await connectNodeWebSocket(`ws://127.0.0.1:${port}/signal/ice`);
    const got: SignalMessage[] = [];
    t.onMessage((b) => got.push(decodeSignal(b)));
    t.send(encodeSignal({ type: 'host', room: 'ice' }));
    for (let k = 0; k < 200 && got.length === 0; k++) await settle();
    expect(got[0]).toMatchObject({
      type: 'joined',
      iceServers: [{ urls: ['stun:stun.example:3478'] }, turn],
    });
    t.close('done');
    await endpoint.close();
    for (const [value, why] of [
      ['stun:x', 'not JSON'],
      ['{"urls":["stun:x"]}', 'not an array'],
      ['[{"urls":[]}]', 'entry 0 has no urls'],
      ['[{"urls":["stun:x"],"credential":5}]', "entry 0's credential is not a string"],
    ]) {
      expect(() => iceServersFromEnv({ FIXEDSTEP_ICE_SERVERS: value })).toThrow(
        `FIXEDSTEP_ICE_SERVERS: ${why}`,
      );
    }
    expect(iceServersFromEnv({})).toEqual({});
  });
});
