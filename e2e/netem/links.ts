/**
 * Player 2's impaired link for the model comparison (model-match.ts), made fresh for each match:
 * WebRTC data channels between two werift peers through coturn behind the impairing UDP proxy, or
 * a WebSocket over the kernel's TCP through the TUN link (tun-link.py; this process must run in
 * the network namespace that link is in: tun.ts starts it there).
 */
import { spawn } from 'node:child_process';
import http from 'node:http';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { RTCPeerConnection } from 'werift';
import { WebSocket, WebSocketServer } from 'ws';
import {
  PeerHost,
  SignalClient,
  SignallingHub,
  joinPeer,
  memoryPair,
  nodeWebSocketTransport,
  performanceClock,
  type Transport,
} from 'fixedstep';
import { CLEAN, type Impairment } from './impair.js';
import type { ImpairedLink } from './model-match.js';
import type { TurnServer } from './turn.js';
import { startUdpProxy } from './udp-proxy.js';

const clock = performanceClock();

/** WebRTC between two werift peers, forced through `turn` behind a UDP proxy with `link`'s conditions. */
export async function webrtcLink(
  turn: TurnServer,
  link: Impairment,
  seed: number,
  accept: (t: Transport) => void,
): Promise<ImpairedLink> {
  const proxy = await startUdpProxy({ targetPort: turn.port, seed });
  const hub = new SignallingHub({ clock });
  const [hostEnd, hostHub] = memoryPair();
  const [joinEnd, joinHub] = memoryPair();
  hub.accept(hostHub);
  hub.accept(joinHub);
  const rtc = {
    PeerConnection: RTCPeerConnection,
    iceServers: turn.iceServers(proxy.port),
    iceTransportPolicy: 'relay' as const,
    room: 'netem',
    connectTimeoutMs: 20_000,
    fallback: false,
    // werift 0.24 never gives up on a chunk with maxRetransmits 0 (docs/webrtc.md).
    unreliableChannel: { ordered: false, maxRetransmits: 1 },
  };
  const host = new PeerHost({
    ...rtc,
    signal: new SignalClient(hostEnd),
    onPeer: (l) => {
      accept(l.transport);
    },
  });
  try {
    const { invite } = await host.ready;
    const joined = await joinPeer({ ...rtc, invite, signal: new SignalClient(joinEnd) });
    return {
      joiner: joined.transport,
      impair: () => {
        proxy.setConditions(link, CLEAN);
      },
      wire: () => {
        // The joiner's peer connection allocates on the relay first: the proxy's first client.
        const [j, h] = proxy.stats();
        return {
          up: j?.up.bytes ?? 0,
          down: h?.up.bytes ?? 0,
          lostUp: j?.up.lost ?? 0,
          lostDown: h?.up.lost ?? 0,
          packetsUp: j?.up.packets ?? 0,
          packetsDown: h?.up.packets ?? 0,
        };
      },
      close: async () => {
        joined.transport.close('done');
        host.close();
        await proxy.close();
      },
    };
  } catch (error) {
    host.close();
    await proxy.close();
    throw error;
  }
}

interface TunStats {
  up: { packets: number; bytes: number; lost: number };
  down: { packets: number; bytes: number; lost: number };
}

const tunScript = fileURLToPath(new URL('./tun-link.py', import.meta.url));

/** Local and peer address of the TUN link (a private /32 pair inside the namespace). */
export const TUN_LOCAL = '10.77.0.1';
export const TUN_PEER = '10.77.0.2';

/**
 * A WebSocket over the kernel's TCP through a TUN link with `link`'s conditions each way: the room
 * listens on this namespace's addresses, player 2 connects to {@link TUN_PEER}, whose packets the
 * link delays, drops and reflects back. Needs root inside a network namespace of its own.
 */
export async function tunLink(
  link: Impairment,
  seed: number,
  accept: (t: Transport) => void,
): Promise<ImpairedLink> {
  const server = http.createServer();
  const wss = new WebSocketServer({ server, perMessageDeflate: false });
  wss.on('connection', (ws) => {
    ws.binaryType = 'nodebuffer';
    accept(nodeWebSocketTransport(ws));
  });
  await new Promise<void>((resolve) => server.listen(0, '0.0.0.0', resolve));
  const port = (server.address() as { port: number }).port;
  const tun = spawn('python3', [tunScript, '--server-port', String(port), '--seed', String(seed)], {
    stdio: ['pipe', 'pipe', 'inherit'],
  });
  const exited = new Promise<void>((resolve) =>
    tun.once('exit', () => {
      resolve();
    }),
  );
  const lines = createInterface({ input: tun.stdout });
  const waiting: ((line: string) => void)[] = [];
  lines.on('line', (line) => waiting.shift()?.(line));
  const nextLine = () => new Promise<string>((resolve) => waiting.push(resolve));
  const stop = async () => {
    if (tun.exitCode === null) tun.stdin.write('quit\n');
    const killer = setTimeout(() => tun.kill('SIGKILL'), 2000);
    await exited;
    clearTimeout(killer);
    for (const c of wss.clients) c.terminate();
    wss.close();
    await new Promise<void>((resolve) =>
      server.close(() => {
        resolve();
      }),
    );
  };
  try {
    const ready = await Promise.race([nextLine(), exited.then(() => 'exited')]);
    if (ready !== 'ready') throw new Error(`tun-link.py did not start (${ready})`);
    const ws = new WebSocket(`ws://${TUN_PEER}:${port}/`, { perMessageDeflate: false });
    ws.binaryType = 'nodebuffer';
    await new Promise<void>((resolve, reject) => {
      ws.once('open', () => {
        resolve();
      });
      ws.once('error', reject);
    });
    (ws as unknown as { _socket?: { setNoDelay(b: boolean): void } })._socket?.setNoDelay(true);
    const joiner = nodeWebSocketTransport(ws);
    return {
      joiner,
      impair: () => {
        tun.stdin.write(`set ${link.latencyMs} ${link.jitterMs} ${link.loss}\n`);
      },
      wire: async () => {
        tun.stdin.write('stats\n');
        const stats = JSON.parse(await nextLine()) as TunStats;
        return {
          up: stats.up.bytes,
          down: stats.down.bytes,
          lostUp: stats.up.lost,
          lostDown: stats.down.lost,
          packetsUp: stats.up.packets,
          packetsDown: stats.down.packets,
        };
      },
      close: async () => {
        joiner.close('done');
        await stop();
      },
    };
  } catch (error) {
    await stop();
    throw error;
  }
}
