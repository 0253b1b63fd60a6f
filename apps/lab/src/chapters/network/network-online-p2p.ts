/**
 * Chapter 6, "Play online" peer to peer: the same lockstep match over WebRTC data channels instead
 * of the server's relay. The first page in a room hosts it — the relay runs in that page, its own
 * session on a memory pair to it — and the second joins it directly, the server's `/signal` only
 * introducing them (offer, answer, ICE candidates). When no direct connection opens in time the
 * library falls back to a tunnel through the signalling server; {@link P2pConnection.via} says
 * which.
 */
import {
  PeerHost,
  Relay,
  SignalClient,
  connectWebSocket,
  joinPeer,
  memoryPair,
  performanceClock,
  relayCatalog,
  type PeerConnectionConstructor,
  type Transport,
} from 'fixedstep';
import type { GameDefinition } from '@fixedstep/games';

/** A page's way into a peer-to-peer room. */
export interface P2pConnection {
  /** The transport the session plays over (to the relay in the host's page). */
  transport: Transport;
  /** `host`: the relay runs in this page; `webrtc`: joined directly; `server`: joined through the server's tunnel. */
  via: 'host' | 'webrtc' | 'server';
  /** Stop hosting (or joining): the relay, the peer connections, the signalling. */
  close(): void;
}

/** How often the hosting page's relay closes ticks and pings, ms (a quarter of a 60 Hz tick). */
const RELAY_EVERY_MS = 4;

/**
 * Host `room` if nobody does yet, else join its host. `signalUrl` is the server's `/signal`
 * WebSocket address. Rejects when the signalling server cannot be reached or refuses the room.
 */
export async function connectPeerToPeer(
  signalUrl: string,
  room: string,
  def: GameDefinition,
): Promise<P2pConnection> {
  const PeerConnection = (
    globalThis as unknown as { RTCPeerConnection?: PeerConnectionConstructor }
  ).RTCPeerConnection;
  if (PeerConnection === undefined) throw new Error('this browser has no WebRTC');
  const hostSignal = new SignalClient(await connectWebSocket(signalUrl));
  const relay = new Relay({ clock: performanceClock(), catalog: relayCatalog([def]) });
  const host = new PeerHost({
    signal: hostSignal,
    room,
    PeerConnection,
    onPeer: (link) => {
      relay.accept(link.transport);
    },
  });
  try {
    await host.ready;
  } catch (e) {
    host.close();
    hostSignal.close();
    if (!(e instanceof Error && e.message.includes('ROOM_TAKEN'))) throw e;
    // Someone hosts this room: join them.
    const signal = new SignalClient(await connectWebSocket(signalUrl));
    const link = await joinPeer({ signal, room, PeerConnection });
    return {
      transport: link.transport,
      via: link.via,
      close: () => {
        link.transport.close();
        signal.close();
      },
    };
  }
  const timer = setInterval(() => {
    relay.update();
  }, RELAY_EVERY_MS);
  const [mine, theirs] = memoryPair();
  relay.accept(theirs);
  return {
    transport: mine,
    via: 'host',
    close: () => {
      clearInterval(timer);
      host.close();
      hostSignal.close();
    },
  };
}
