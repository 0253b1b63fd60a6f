/**
 * The loss harness, Node-peer version (the transport benchmark runs it): one capture-the-flag
 * match of two bot players in one Node process, the host's relay and its own player on one side,
 * the joiner on the other side of an impaired link — over WebRTC (werift data channels, forced
 * through coturn on 127.0.0.1 behind the impairing UDP proxy) or over a WebSocket (behind the TCP
 * proxy). The host is the room's creator running the relay, as in peer-to-peer play; over the
 * WebSocket the same relay takes the joiner's connection as a server would. Real time, real sockets.
 */
import http from 'node:http';
import { WebSocket, WebSocketServer } from 'ws';
import { RTCPeerConnection } from 'werift';
import {
  PeerHost,
  Relay,
  RollbackSession,
  SignalClient,
  SignallingHub,
  joinPeer,
  memoryPair,
  nodeWebSocketTransport,
  performanceClock,
  gameCatalog,
  type AnyGameDefinition,
  type Transport,
} from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { CLEAN, type Impairment } from './impair.js';
import {
  Probe,
  summarize,
  type ProbeReport,
  type TransportSummary,
  type WireCounts,
} from './probe.js';
import { startTcpProxy } from './tcp-proxy.js';
import type { TurnServer } from './turn.js';
import { startUdpProxy } from './udp-proxy.js';

export interface NodeMatchOptions {
  transport: 'webrtc' | 'websocket';
  /** Match length in ticks (60 Hz). */
  ticks: number;
  /** One-way conditions of the joiner's link (each direction). */
  link: Impairment;
  /** Needed for WebRTC. */
  turn?: TurnServer;
  game?: AnyGameDefinition;
  seed?: number;
  /** Bots re-decide every this many ticks. Default 6. */
  botEvery?: number;
  /** Give up after this long, ms. Default ticks × 17 × 3 + 30 s. */
  timeoutMs?: number;
}

export interface NodeMatchResult {
  summary: TransportSummary;
  reports: ProbeReport[];
}

const clock = performanceClock();

function bot(game: AnyGameDefinition, slot: number, every: number) {
  let held: unknown = game.input.neutral();
  return (tick: number, sim: unknown) => {
    if (game.bot && tick % every === 0) held = game.bot(sim as never, slot);
    return held;
  };
}

export async function runNodeMatch(o: NodeMatchOptions): Promise<NodeMatchResult> {
  const game = o.game ?? ctfGame;
  const seed = o.seed ?? 7;
  const relay = new Relay({ clock, catalog: gameCatalog([game]), randomU32: () => 0x12345678 });
  const cleanup: (() => Promise<void> | void)[] = [];
  const timer = setInterval(() => {
    relay.update();
  }, 4);
  cleanup.push(() => {
    clearInterval(timer);
    relay.close();
  });
  let wire: () => WireCounts;
  let joinerTransport: Transport;
  let impair: () => void;
  try {
    if (o.transport === 'webrtc') {
      const turn = o.turn;
      if (!turn) throw new Error('runNodeMatch: WebRTC needs a TURN server');
      const proxy = await startUdpProxy({ targetPort: turn.port, seed });
      cleanup.push(() => proxy.close());
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
        unreliableChannel: { ordered: false, maxRetransmits: Number(process.env.MAXRTX ?? 1) },
      };
      const host = new PeerHost({
        ...rtc,
        signal: new SignalClient(hostEnd),
        onPeer: (link) => relay.accept(link.transport),
      });
      cleanup.push(() => {
        host.close();
      });
      const { invite } = await host.ready;
      const link = await joinPeer({ ...rtc, invite, signal: new SignalClient(joinEnd) });
      joinerTransport = link.transport;
      // The link is impaired from the datagrams' side: each peer's packets to the TURN relay get
      // the one-way conditions (so A → B and B → A each cross one impaired hop).
      impair = () => {
        proxy.setConditions(o.link, CLEAN);
      };
      wire = () => {
        // The joiner's pc allocates on the relay first (the host makes its own on the offer), so
        // the proxy's first client is the joiner: its packets up are joiner → host, the other's
        // host → joiner.
        const [j, h] = proxy.stats();
        return {
          up: j?.up.bytes ?? 0,
          down: h?.up.bytes ?? 0,
          lostUp: j?.up.lost ?? 0,
          lostDown: h?.up.lost ?? 0,
          packetsUp: j?.up.packets ?? 0,
          packetsDown: h?.up.packets ?? 0,
        };
      };
    } else {
      const server = http.createServer();
      const wss = new WebSocketServer({ server, perMessageDeflate: false });
      wss.on('connection', (ws) => relay.accept(nodeWebSocketTransport(ws)));
      await new Promise<void>((resolve) => server.listen(0, '127.0.0.1', resolve));
      cleanup.push(
        () =>
          new Promise<void>((resolve) => {
            for (const c of wss.clients) c.terminate();
            wss.close();
            server.close(() => {
              resolve();
            });
          }),
      );
      const port = (server.address() as { port: number }).port;
      const proxy = await startTcpProxy({ targetPort: port, seed });
      cleanup.push(() => proxy.close());
      const ws = new WebSocket(`ws://127.0.0.1:${proxy.port}/`, { perMessageDeflate: false });
      ws.binaryType = 'nodebuffer';
      await new Promise<void>((resolve, reject) => {
        ws.once('open', () => {
          resolve();
        });
        ws.once('error', reject);
      });
      ws.on('open', () => undefined);
      (ws as unknown as { _socket?: { setNoDelay(b: boolean): void } })._socket?.setNoDelay(true);
      joinerTransport = nodeWebSocketTransport(ws);
      impair = () => {
        proxy.setConditions(o.link);
      };
      wire = () => {
        const c = proxy.connections;
        const sum = (f: (x: (typeof c)[number]) => number) => c.reduce((n, x) => n + f(x), 0);
        return {
          up: sum((x) => x.up.bytes),
          down: sum((x) => x.down.bytes),
          lostUp: sum((x) => x.up.lost),
          lostDown: sum((x) => x.down.lost),
          packetsUp: sum((x) => x.up.packets),
          packetsDown: sum((x) => x.down.packets),
        };
      };
    }
    impair();
    const wireBefore = wire();

    const [hostSide, relaySide] = memoryPair();
    relay.accept(relaySide);
    const every = o.botEvery ?? 6;
    const probes = [new Probe(0, o.ticks), new Probe(1, o.ticks)];
    const sessions = ([hostSide, joinerTransport] as const).map(
      (transport, slot) =>
        new RollbackSession<unknown>({
          transport,
          clock,
          room: 'netem',
          game,
          players: 2,
          seed,
          name: `p${slot + 1}`,
          stopAt: o.ticks,
          localInput: probes[slot]!.input(bot(game, slot, every)),
          onCorrection: probes[slot]!.onCorrection,
        }),
    );
    const frameMs = 1000 / 60;
    const deadline = clock.now() + (o.timeoutMs ?? o.ticks * 17 * 3 + 30_000);
    await new Promise<void>((resolve, reject) => {
      let next = clock.now();
      const frame = () => {
        for (const [i, s] of sessions.entries()) {
          s.frame();
          probes[i]!.afterFrame(s);
        }
        if (sessions.every((s) => s.isFinished)) {
          resolve();
          return;
        }
        if (clock.now() > deadline) {
          reject(
            new Error(
              `runNodeMatch(${o.transport}): not finished in time: ticks ${sessions.map((s) => s.tick).join(', ')}, confirmed ${sessions.map((s) => s.confirmedTick).join(', ')}`,
            ),
          );
          return;
        }
        next += frameMs;
        setTimeout(frame, Math.max(0, next - clock.now()));
      };
      frame();
    });
    // Let the last hash reports through, then stop.
    const reports = sessions.map((s, i) => probes[i]!.report(s as never));
    const w = wire();
    for (const s of sessions) s.leave();
    const sum = summarize(o.transport, 'Node peers', o.ticks, reports, {
      up: w.up - wireBefore.up,
      down: w.down - wireBefore.down,
      lostUp: w.lostUp - wireBefore.lostUp,
      lostDown: w.lostDown - wireBefore.lostDown,
      packetsUp: w.packetsUp - wireBefore.packetsUp,
      packetsDown: w.packetsDown - wireBefore.packetsDown,
    });
    return { summary: sum, reports, probes } as NodeMatchResult;
  } finally {
    for (const f of cleanup.reverse()) await f();
  }
}
