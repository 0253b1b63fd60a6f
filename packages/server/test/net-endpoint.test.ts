/**
 * The relay's HTTP side over real WebSockets on 127.0.0.1: rooms in the URL, the origin
 * allow-list, the client address from a trusted proxy's header (and the per-address cap it
 * feeds), options from the environment, and 500 idle sockets beside a game that still plays.
 */
import http from 'node:http';
import type { AddressInfo } from 'node:net';
import { afterEach, describe, expect, it } from 'vitest';
import WebSocket from 'ws';
import { decodeFrame, encodeMessage, type ErrorMessage, type NetMessage } from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { attachRelay, type RelayEndpoint, type RelayEndpointOptions } from '../src/relay/index.js';
import {
  Admission,
  addressKey,
  admissionOptionsFromEnv,
  roomCapsFromEnv,
} from '../src/http/admission.js';
import { createServer } from '../src/index.js';
import { ctfBotsOnRelay } from './session-frames.js';

/** What the relay's endpoint reads from the environment. */
const relayEndpointOptionsFromEnv = (env: Record<string, string>) => ({
  ...admissionOptionsFromEnv(env),
  ...roomCapsFromEnv(env),
});

let server: http.Server | undefined;
let endpoint: RelayEndpoint | undefined;
const sockets: WebSocket[] = [];

afterEach(async () => {
  for (const ws of sockets.splice(0)) ws.terminate();
  await endpoint?.close();
  await new Promise<void>((resolve) => {
    if (server)
      server.close(() => {
        resolve();
      });
    else resolve();
  });
  server = undefined;
  endpoint = undefined;
});

async function start(options: RelayEndpointOptions = {}): Promise<number> {
  server = http.createServer((_req, res) => res.end('lab'));
  endpoint = attachRelay(server, { env: {}, ...options });
  await new Promise<void>((resolve) => server!.listen(0, '127.0.0.1', resolve));
  return (server.address() as AddressInfo).port;
}

/** The HTTP status of an upgrade, or 101 when it opened. */
function upgrade(url: string, headers: Record<string, string> = {}): Promise<number> {
  return new Promise((resolve) => {
    const ws = new WebSocket(url, { headers });
    sockets.push(ws);
    ws.on('open', () => {
      resolve(101);
    });
    ws.on('unexpected-response', (_req, res) => {
      resolve(res.statusCode ?? 0);
    });
    ws.on('error', () => undefined);
  });
}

/** Opens a socket, sends `hello`, and resolves with the first message back. */
function helloReply(
  url: string,
  hello: Partial<NetMessage>,
  headers: Record<string, string> = {},
): Promise<NetMessage> {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url, { headers });
    sockets.push(ws);
    ws.on('open', () => {
      ws.send(
        encodeMessage({
          type: 'hello',
          room: 'room',
          role: 'player',
          game: 'ctf',
          gameVersion: ctfGame.info.version,
          input: ctfGame.input.id,
          players: 2,
          name: 'p',
          ...hello,
        } as NetMessage),
      );
    });
    ws.on('message', (data: Buffer) => {
      resolve(decodeFrame(new Uint8Array(data))[0]!);
    });
    ws.on('error', reject);
  });
}

describe('rooms in the URL', () => {
  it('/ws/<room> and /ws?room= pin the hello to that room; a bad name is a 400', async () => {
    const port = await start();
    const base = `ws://127.0.0.1:${port}/ws`;
    expect((await helloReply(`${base}/alpha`, { room: 'alpha' })).type).toBe('welcome');
    expect((await helloReply(`${base}?room=beta`, { room: 'beta' })).type).toBe('welcome');
    const wrong = (await helloReply(`${base}/alpha`, { room: 'gamma' })) as ErrorMessage;
    expect(wrong.code).toBe('WRONG_ROOM');
    expect(wrong.message).toMatch(/for room alpha, not gamma/);
    expect(await upgrade(`${base}/no%20spaces`)).toBe(400);
    expect(await upgrade(`${base}/a/b`)).toBe(400);
    expect(await upgrade(`ws://127.0.0.1:${port}/wss`)).toBe(404);
  });
});

describe('the origin allow-list', () => {
  it('same-origin by default: the lab’s own pages in, other sites’ pages out, programs in', async () => {
    const port = await start();
    const url = `ws://127.0.0.1:${port}/ws`;
    expect(await upgrade(url, { Origin: `http://127.0.0.1:${port}` })).toBe(101);
    expect(await upgrade(url, { Origin: 'http://evil.example' })).toBe(403);
    expect(await upgrade(url, { Origin: `http://127.0.0.1:${port + 1}` })).toBe(403);
    expect(await upgrade(url, { Origin: 'null' })).toBe(403);
    expect(await upgrade(url)).toBe(101);
  });

  it('a configured list is exactly those origins; any lets everyone in', async () => {
    let port = await start({ allowedOrigins: ['https://play.example.com'] });
    let url = `ws://127.0.0.1:${port}/ws`;
    expect(await upgrade(url, { Origin: 'https://play.example.com' })).toBe(101);
    expect(await upgrade(url, { Origin: `http://127.0.0.1:${port}` })).toBe(403);
    await endpoint!.close();
    await new Promise<void>((resolve) =>
      server!.close(() => {
        resolve();
      }),
    );
    port = await start({ allowedOrigins: 'any' });
    url = `ws://127.0.0.1:${port}/ws`;
    expect(await upgrade(url, { Origin: 'http://evil.example' })).toBe(101);
  });
});

describe('the client address', () => {
  it('comes from a trusted proxy’s header, and the per-address cap counts by it', async () => {
    const port = await start({
      trustProxy: { header: 'x-forwarded-for' },
      maxConnectionsPerAddress: 3,
    });
    const url = `ws://127.0.0.1:${port}/ws`;
    const from = (ip: string) => ({ 'X-Forwarded-For': `1.2.3.4, ${ip}` });
    // The proxy appends the address it saw: the last entry counts, not what the client wrote.
    for (let i = 0; i < 3; i++) expect(await upgrade(url, from('198.51.100.7'))).toBe(101);
    const fourth = (await helloReply(url, {}, from('198.51.100.7'))) as ErrorMessage;
    expect(fourth.code).toBe('ADDRESS_LIMIT');
    expect(fourth.message).toMatch(/at most 3 connections from one address/);
    expect((await helloReply(url, { room: 'other' }, from('198.51.100.8'))).type).toBe('welcome');
    expect(endpoint!.relay.stats.addresses).toBe(2);
    // From a trusted proxy, a malformed header is refused; none at all is the proxy's own client.
    expect(await upgrade(url, { 'X-Forwarded-For': 'not an address' })).toBe(400);
    expect(await upgrade(url)).toBe(101);
    expect(endpoint!.relay.stats.addresses).toBe(3);
  });

  it('is the socket’s own when the peer is not a trusted proxy (the header is ignored)', async () => {
    const port = await start({
      trustProxy: { header: 'x-forwarded-for', proxies: ['10.0.0.0/8'] },
      maxConnectionsPerAddress: 2,
    });
    const url = `ws://127.0.0.1:${port}/ws`;
    expect(await upgrade(url, { 'X-Forwarded-For': '198.51.100.1' })).toBe(101);
    expect(await upgrade(url, { 'X-Forwarded-For': '198.51.100.2' })).toBe(101);
    const third = (await helloReply(
      url,
      {},
      { 'X-Forwarded-For': '198.51.100.3' },
    )) as ErrorMessage;
    expect(third.code).toBe('ADDRESS_LIMIT');
  });

  it('is keyed by IPv4 address and by IPv6 /64', () => {
    expect(addressKey('198.51.100.7')).toBe('198.51.100.7');
    expect(addressKey('::ffff:198.51.100.7')).toBe('198.51.100.7');
    expect(addressKey('2001:db8:1:2:3:4:5:6')).toBe('2001:db8:1:2::/64');
    expect(addressKey('2001:db8:1:2::9')).toBe(addressKey('2001:db8:1:2:ffff::1'));
    expect(addressKey('2001:db8::1')).toBe('2001:db8:0:0::/64');
    expect(addressKey('::1')).toBe('0:0:0:0::/64');
  });
});

describe('options from the environment', () => {
  it('reads origins, the proxy and the caps, and names a bad value', () => {
    expect(
      relayEndpointOptionsFromEnv({
        FIXEDSTEP_ALLOWED_ORIGINS: 'https://a.example, https://b.example:8443',
        FIXEDSTEP_PROXY_HEADER: 'x-forwarded-for',
        FIXEDSTEP_TRUSTED_PROXIES: '10.0.0.0/8, fd00::/8',
        FIXEDSTEP_PROXY_HOPS: '2',
        FIXEDSTEP_MAX_CONNECTIONS_PER_ADDRESS: '64',
        FIXEDSTEP_MAX_ROOMS: '2000',
      }),
    ).toEqual({
      allowedOrigins: ['https://a.example', 'https://b.example:8443'],
      trustProxy: { header: 'x-forwarded-for', proxies: ['10.0.0.0/8', 'fd00::/8'], hops: 2 },
      maxConnectionsPerAddress: 64,
      maxRooms: 2000,
    });
    expect(relayEndpointOptionsFromEnv({ FIXEDSTEP_ALLOWED_ORIGINS: '*' })).toEqual({
      allowedOrigins: 'any',
    });
    expect(relayEndpointOptionsFromEnv({})).toEqual({});
    expect(() =>
      relayEndpointOptionsFromEnv({ FIXEDSTEP_ALLOWED_ORIGINS: 'evil.example' }),
    ).toThrow(/FIXEDSTEP_ALLOWED_ORIGINS: "evil.example"/);
    expect(() => relayEndpointOptionsFromEnv({ FIXEDSTEP_MAX_ROOMS_PER_ADDRESS: '-1' })).toThrow(
      /FIXEDSTEP_MAX_ROOMS_PER_ADDRESS: "-1" is not an integer/,
    );
    expect(() =>
      relayEndpointOptionsFromEnv({
        FIXEDSTEP_PROXY_HEADER: 'x-forwarded-for',
        FIXEDSTEP_TRUSTED_PROXIES: '10.0.0.0/99',
      }),
    ).toThrow(/10.0.0.0\/99/);
    expect(() => relayEndpointOptionsFromEnv({ FIXEDSTEP_TRUSTED_PROXIES: '10.0.0.1' })).toThrow(
      /need FIXEDSTEP_PROXY_HEADER/,
    );
  });

  it('are used by attachRelay unless given in code', async () => {
    const port = await start({
      env: { FIXEDSTEP_ALLOWED_ORIGINS: 'https://play.example.com' },
    });
    const url = `ws://127.0.0.1:${port}/ws`;
    expect(await upgrade(url, { Origin: `http://127.0.0.1:${port}` })).toBe(403);
    expect(await upgrade(url, { Origin: 'https://play.example.com' })).toBe(101);
  });
});

describe('new connections a minute', () => {
  it('one address opens at most its share a minute (429, saying when to try again); others are not held up', () => {
    let now = 0;
    const admission = new Admission({ maxSocketsPerMinute: 3, now: () => now });
    const from = (ip: string) =>
      ({ headers: {}, socket: { remoteAddress: ip } }) as unknown as http.IncomingMessage;
    const opened = [1, 2, 3].map(() => admission.admit(from('10.0.0.1')));
    for (const a of opened) expect(a).toHaveProperty('address', '10.0.0.1');
    // Closing them gives back their places at once, not the minute's count.
    for (const a of opened) if ('release' in a) a.release();
    expect(admission.admit(from('10.0.0.1'))).toEqual({
      status: '429 Too Many Requests',
      reason: '3 new connections a minute from one address: try again in 60 s',
    });
    expect(admission.admit(from('10.0.0.2'))).toHaveProperty('address', '10.0.0.2');
    now += 120_000;
    expect(admission.admit(from('10.0.0.1'))).toHaveProperty('address', '10.0.0.1');
    expect(admissionOptionsFromEnv({ FIXEDSTEP_MAX_SOCKETS_PER_MINUTE: '600' })).toEqual({
      maxSocketsPerMinute: 600,
    });
  });
});

describe('createServer’s one admission', () => {
  it('refuses an origin or proxy setting given to one surface alone, naming where it goes', async () => {
    await expect(
      createServer({
        port: 0,
        host: '127.0.0.1',
        stateSync: false,
        relay: { allowedOrigins: 'any' },
      }),
    ).rejects.toThrow(
      'createServer: set allowedOrigins on createServer itself, not on relay: every WebSocket surface shares one admission',
    );
    await expect(
      createServer({
        port: 0,
        host: '127.0.0.1',
        stateSync: false,
        matchmaking: { trustProxy: { header: 'x-forwarded-for' } },
      }),
    ).rejects.toThrow(/set trustProxy on createServer itself, not on matchmaking/);
  });
});

describe('500 idle WebSockets beside a game', () => {
  it('take their address’s share of sockets, connections and rooms; two players from elsewhere play', async () => {
    const port = await start({ trustProxy: { header: 'x-forwarded-for' }, startDelayMs: 200 });
    const url = `ws://127.0.0.1:${port}/ws`;
    const outcome = (i: number) =>
      new Promise<string>((resolve) => {
        const ws = new WebSocket(url, { headers: { 'X-Forwarded-For': '203.0.113.9' } });
        sockets.push(ws);
        ws.on('unexpected-response', (_req, res) => {
          resolve(`HTTP ${res.statusCode ?? 0}`);
        });
        ws.on('error', () => undefined);
        ws.on('open', () => {
          ws.send(
            encodeMessage({
              type: 'hello',
              room: `idle${i}`,
              role: 'player',
              game: 'ctf',
              gameVersion: ctfGame.info.version,
              input: ctfGame.input.id,
              players: 2,
              name: 'p',
            }),
          );
        });
        ws.on('message', (data: Buffer) => {
          const m = decodeFrame(new Uint8Array(data))[0]!;
          resolve(m.type === 'error' ? `${m.code}: ${m.message}` : m.type);
        });
      });
    const idle = await Promise.all(Array.from({ length: 500 }, (_, i) => outcome(i)));
    const count = (s: string) => idle.filter((o) => o === s).length;
    // Refused by the server's admission (64 sockets an address: HTTP 429) or the relay's caps
    // (32 connections, 8 rooms an address); how many of each depends on how fast the refused
    // sockets close and give their places back.
    expect(count('welcome')).toBe(8);
    expect(
      count('HTTP 429') +
        count('ADDRESS_LIMIT: at most 32 connections from one address') +
        count('ADDRESS_LIMIT: at most 8 rooms from one address'),
    ).toBe(492);
    expect(count('ADDRESS_LIMIT: at most 8 rooms from one address')).toBeGreaterThan(0);
    expect(endpoint!.relay.stats.connections).toBe(8);

    const [ha, hb] = await ctfBotsOnRelay({
      url: `${url}/play`,
      room: 'play',
      ticks: 180,
      seed: 3,
      headers: [{ 'X-Forwarded-For': '198.51.100.1' }, { 'X-Forwarded-For': '198.51.100.2' }],
      timeoutMs: 20_000,
    });
    expect(ha).toBe(hb);
    expect(endpoint!.relay.stats.addresses).toBe(3);
  });
});
