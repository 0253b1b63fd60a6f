/**
 * Peer-to-peer rollback as docs/webrtc.md describes it: the room's creator runs the relay in its
 * own process, its own session on a `memoryPair()`, and the joiner connects to it over WebRTC data
 * channels (werift, the Node implementation, on this machine's host candidates) introduced by the
 * signalling hub — or, when no direct connection opens, through the hub's tunnel. Real sockets and
 * real time (WebRTC has no simulated clock); every assertion is on deterministic outcomes (ticks,
 * hashes), never on durations.
 */
import { afterEach, describe, expect, it } from 'vitest';
import { RTCPeerConnection } from 'werift';
import {
  BUTTON_WORD,
  PeerHost,
  Relay,
  RollbackSession,
  SignalClient,
  joinPeer,
  memoryPair,
  performanceClock,
  gameCatalog,
  SignallingHub,
  type DataChannelInitLike,
  type PeerConnectionConstructor,
  type PeerLink,
} from 'fixedstep';
// The net tests' toy game: each player's counter moves by its input and a seeded draw.
import { Toy } from '../../fixedstep/test/toy-game.js';
import { UnreachablePeerConnection } from './unreachable-peer.js';

const clock = performanceClock();
const catalog = gameCatalog([
  { id: 'toy', version: 1, tickRate: 60, minPlayers: 2, maxPlayers: 4, input: BUTTON_WORD },
]);
const cleanup: (() => void)[] = [];
afterEach(() => {
  for (const f of cleanup.splice(0).reverse()) f();
});

/** Resolves when `done()` holds, checking every 10 ms; rejects after `limitMs` naming `what`. */
function until(done: () => boolean, what: string, limitMs = 30_000): Promise<void> {
  return new Promise((resolve, reject) => {
    const started = clock.now();
    const timer = setInterval(() => {
      if (done()) {
        clearInterval(timer);
        resolve();
      } else if (clock.now() - started > limitMs) {
        clearInterval(timer);
        reject(new Error(`timed out waiting for ${what}`));
      }
    }, 10);
  });
}

/**
 * A host (relay + its own session) and one joiner, introduced by a signalling hub. Returns the
 * relay, both sessions and the joiner's link once both sessions run their frames.
 */
async function peerToPeer(o: {
  PeerConnection: PeerConnectionConstructor;
  connectTimeoutMs: number;
  ticks: number;
  joinerGlitchFrom?: number;
  unreliableChannel?: DataChannelInitLike;
}) {
  const relay = new Relay({ clock, catalog, randomU32: () => 0x9e3779b9 });
  const relayTimer = setInterval(() => {
    relay.update();
  }, 4);
  cleanup.push(() => {
    clearInterval(relayTimer);
    relay.close();
  });
  const hub = new SignallingHub({ clock });
  cleanup.push(() => {
    hub.close();
  });
  const [hostSignal, hostHub] = memoryPair();
  const [joinSignal, joinHub] = memoryPair();
  hub.accept(hostHub);
  hub.accept(joinHub);
  const rtc = {
    PeerConnection: o.PeerConnection,
    room: 'p2p',
    connectTimeoutMs: o.connectTimeoutMs,
    ...(o.unreliableChannel ? { unreliableChannel: o.unreliableChannel } : {}),
  };
  const host = new PeerHost({
    ...rtc,
    signal: new SignalClient(hostSignal),
    onPeer: (link) => relay.accept(link.transport),
  });
  cleanup.push(() => {
    host.close();
  });
  const { invite } = await host.ready;
  const link: PeerLink = await joinPeer({ ...rtc, invite, signal: new SignalClient(joinSignal) });
  cleanup.push(() => {
    link.transport.close('test over');
  });

  // The host's own player: a session on a memory pair to the relay in its own process.
  const [hostEnd, relayEnd] = memoryPair();
  relay.accept(relayEnd);
  const session = (transport: typeof hostEnd, glitchFrom?: number) =>
    new RollbackSession({
      transport,
      clock,
      room: 'r',
      game: 'toy',
      gameVersion: 1,
      players: 2,
      seed: 11,
      stopAt: o.ticks,
      // From `glitchFrom` on, something only this machine does: player 0's counter, one more.
      createSimulation: () => new Toy(2, 11, { from: glitchFrom ?? Infinity, extra: () => 1 }),
      localInput: (tick) => (tick >> 3) & 3,
    });
  const sessions = [session(hostEnd), session(link.transport, o.joinerGlitchFrom)];
  const frames = setInterval(() => {
    for (const s of sessions) s.frame();
  }, 1000 / 60);
  cleanup.push(() => {
    clearInterval(frames);
  });
  return { relay, hub, sessions, link };
}

describe('peer-to-peer rollback: the host runs the relay, the joiner connects over WebRTC', () => {
  it('a deliberately diverging joiner: the host names the first differing tick', async () => {
    const { relay, sessions, link } = await peerToPeer({
      PeerConnection: RTCPeerConnection,
      connectTimeoutMs: 20_000,
      ticks: 600,
      joinerGlitchFrom: 200,
    });
    expect(link.via).toBe('webrtc');
    await until(() => relay.room('r')?.desyncs[0]?.complete ?? false, 'the desync report');
    const d = relay.room('r')!.desyncs[0]!;
    // The step of tick 200 diverged: the state of tick 201 is the first that differs.
    expect(d.reportTick).toBe(210);
    expect(d.tick).toBe(201);
    expect(d.exact).toBe(true);
    // Player 0's counter: bytes 20–23 of the snapshot (tick u32, rng 4 × u32).
    expect(d.diffs[0]!.diff.firstOffset).toBe(20);
    // Both players are told, the joiner across the data channel.
    await until(() => sessions.every((s) => s.desyncs.length > 0), 'both sessions told');
    for (const s of sessions) expect(s.desyncs[0]!.tick).toBe(201);
  }, 60_000);
});

describe('peer-to-peer fallback: no direct route, the game goes through the server', () => {
  it('the joiner tunnels through the signalling hub and the match ends on equal hashes', async () => {
    const ticks = 240;
    const { relay, hub, sessions, link } = await peerToPeer({
      PeerConnection: UnreachablePeerConnection,
      connectTimeoutMs: 200,
      ticks,
      unreliableChannel: { ordered: false, maxRetransmits: 1 },
    });
    expect(link.via).toBe('server');
    // The joiner, then the host on its offer, made both channels themselves (negotiated on streams
    // 0 and 1), the unreliable one as they were told to (werift needs this, see docs).
    const both = [
      ['fixedstep-u', { ordered: false, maxRetransmits: 1, negotiated: true, id: 0 }],
      ['fixedstep-r', { ordered: true, negotiated: true, id: 1 }],
    ];
    expect(UnreachablePeerConnection.created).toEqual([...both, ...both]);
    await until(() => sessions.every((s) => s.isFinished), 'the end of the match');
    const hashes = sessions.map((s) => s.hashAt(ticks));
    expect(hashes[0]).toBeDefined();
    expect(hashes[1]).toBe(hashes[0]);
    expect(relay.room('r')!.desyncs).toHaveLength(0);
    // Every message of the joiner crossed the hub: at least one input message a tick or so.
    expect(hub.stats.tunnelled).toBeGreaterThan(ticks / 2);
  }, 60_000);
});
