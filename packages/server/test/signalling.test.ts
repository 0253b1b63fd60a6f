import http from 'node:http';
import { afterEach, describe, expect, it } from 'vitest';
import {
  ManualClock,
  decodeSignal,
  encodeSignal,
  memoryPair,
  type SignalMessage,
  type Transport,
} from 'fixedstep';
import { SignallingHub, type SignallingHubOptions } from '../src/signalling/hub.js';
import { attachSignalling } from '../src/signalling/endpoint.js';
import { connectNodeWebSocket } from '../src/relay/index.js';

/** Lets the memory pairs deliver (they deliver on later microtasks). */
const settle = () =>
  new Promise<void>((resolve) => {
    setImmediate(resolve);
  });

/** A client of the hub on a memory pair: what it received, decoded, and why it was closed. */
function client(hub: SignallingHub) {
  const [end, hubEnd] = memoryPair();
  hub.accept(hubEnd);
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

describe('signalling hub', () => {
  it('introduces joiners to the host and stamps every forwarded message with its sender', async () => {
    const iceServers = [{ urls: ['stun:127.0.0.1:3478'] }];
    const { hub } = setup({ iceServers });
    const host = client(hub);
    const a = client(hub);
    const b = client(hub);
    host.send({ type: 'host', room: 'room1' });
    await settle();
    a.send({ type: 'join', room: 'room1' });
    await settle();
    b.send({ type: 'join', room: 'room1' });
    await settle();
    expect(host.got).toEqual([
      { type: 'joined', room: 'room1', peer: 0, iceServers },
      { type: 'peer', peer: 1 },
      { type: 'peer', peer: 2 },
    ]);
    expect(a.got).toEqual([{ type: 'joined', room: 'room1', peer: 1, iceServers }]);
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
    expect(a.got.at(-1)).toMatchObject({ type: 'error', code: 'NO_PEER' });
    expect(b.got).toHaveLength(3);
    expect(hub.stats.tunnelled).toBe(1);

    // The host leaves: the joiners are told, the room is gone.
    host.end.close('bye');
    await settle();
    expect(a.got.at(-1)).toEqual({ type: 'leave', peer: 0 });
    expect(hub.roomList()).toEqual([]);
  });

  it('refuses a taken room, a missing room, a full room, with their codes', async () => {
    const { hub } = setup();
    const host = client(hub);
    host.send({ type: 'host', room: 'r' });
    const again = client(hub);
    again.send({ type: 'host', room: 'r' });
    const lost = client(hub);
    lost.send({ type: 'join', room: 'nope' });
    const joiners = Array.from({ length: 16 }, () => client(hub));
    await settle();
    for (const j of joiners) {
      j.send({ type: 'join', room: 'r' });
      await settle();
    }
    expect(again.got).toEqual([
      { type: 'error', code: 'ROOM_TAKEN', message: 'room r already has a host' },
    ]);
    expect(lost.got[0]).toMatchObject({ type: 'error', code: 'NO_ROOM' });
    expect(joiners[14]!.got[0]).toMatchObject({ type: 'joined', peer: 15 });
    expect(joiners[15]!.got).toEqual([
      { type: 'error', code: 'ROOM_FULL', message: 'room r has 15 peers' },
    ]);
  });

  it('drops bad bytes, server-only messages, floods and silent connections', async () => {
    const { clock, hub } = setup({ messagesPerSecond: 10, helloTimeoutMs: 5000 });
    const bad = client(hub);
    bad.raw(Uint8Array.from([1, 77]));
    const cheeky = client(hub);
    cheeky.send({ type: 'leave', peer: 3 });
    const early = client(hub);
    early.send({ type: 'data', peer: 0, bytes: new Uint8Array(1) });
    const flood = client(hub);
    flood.send({ type: 'host', room: 'f' });
    for (let k = 0; k < 40; k++) flood.send({ type: 'data', peer: 1, bytes: new Uint8Array(1) });
    const silent = client(hub);
    await settle();
    expect(bad.got[0]).toMatchObject({ type: 'error', code: 'BAD_MESSAGE' });
    expect(bad.closed[0]).toMatch(/BAD_MESSAGE: .*unknown message type 77/);
    expect(cheeky.closed[0]).toBe('UNEXPECTED: a client does not send leave');
    expect(early.closed[0]).toBe('UNEXPECTED: data before host or join');
    // The burst is twice the sustained rate: the 21st message in the same instant is refused.
    expect(flood.closed[0]).toBe('RATE_LIMIT: too many messages');
    expect(hub.roomList()).toEqual([]);
    clock.advance(4999);
    hub.update();
    await settle();
    expect(silent.closed).toEqual([]);
    clock.advance(2);
    hub.update();
    await settle();
    expect(silent.closed).toEqual(['TIMEOUT: no host or join in time']);
    expect(hub.stats.dropped).toBe(5);
    expect(hub.stats.connections).toBe(0);
  });

  it('refuses an ICE server configuration it could not send', () => {
    expect(() => setup({ iceServers: [{ urls: [] }] })).toThrow(/needs 1 to 8 urls, got 0/);
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
    const t: Transport = await connectNodeWebSocket(`ws://127.0.0.1:${port}/signal`);
    const got: SignalMessage[] = [];
    t.onMessage((b) => got.push(decodeSignal(b)));
    t.send(encodeSignal({ type: 'host', room: 'live' }));
    for (let k = 0; k < 200 && got.length === 0; k++) await settle();
    expect(got).toEqual([{ type: 'joined', room: 'live', peer: 0, iceServers: [] }]);
    expect(endpoint.hub.roomList()).toEqual([{ room: 'live', peers: [0] }]);
    await expect(connectNodeWebSocket(`ws://127.0.0.1:${port}/other`)).rejects.toThrow(/404/);
    const status = await new Promise<number | undefined>((resolve) => {
      const req = http.get({
        host: '127.0.0.1',
        port,
        path: '/signal',
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
});
