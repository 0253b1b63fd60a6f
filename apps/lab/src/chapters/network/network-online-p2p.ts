/**
 * Chapter 6, "Play online" peer to peer: the same lockstep match over WebRTC data channels instead
 * of the server's relay. The first page in a room hosts it — the relay runs in that page, its own
 * session on a memory pair to it — and the second, opened from the host's link with the room's
 * invite, joins it directly, the server's `/signal/<room>` only introducing them (offer, answer,
 * ICE candidates). When no direct connection opens in time the
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
  gameCatalog,
  type PeerConnectionConstructor,
  type PeerHosting,
  type Transport,
} from 'fixedstep';
import type { RegisteredGame } from '@fixedstep/games';

/** A page's way into a peer-to-peer room. */
export interface P2pConnection {
  /** The transport the session plays over (to the relay in the host's page). */
  transport: Transport;
  /** `host`: the relay runs in this page; `webrtc`: joined directly; `server`: joined through the server's tunnel. */
  via: 'host' | 'webrtc' | 'server';
  /** The room's invite token: the host hands it to the joiner (the second tab's link). */
  invite: Uint8Array;
  /** Stop hosting (or joining): the relay, the peer connections, the signalling. */
  close(): void;
}

/** How often the hosting page's relay closes ticks and pings, ms (a quarter of a 60 Hz tick). */
const RELAY_EVERY_MS = 4;

/**
 * Joins the host of `room` with its `invite` (from the host's link), or without one hosts `room`.
 * `signalUrl` is the server's `/signal` WebSocket address (the room is added to it). Rejects when
 * the signalling server cannot be reached or refuses: a taken room without the invite, a wrong
 * invite.
 */
export async function connectPeerToPeer(
  signalUrl: string,
  room: string,
  def: RegisteredGame,
  invite?: Uint8Array,
): Promise<P2pConnection> {
  if (typeof RTCPeerConnection !== 'function') throw new Error('this browser has no WebRTC');
  const PeerConnection: PeerConnectionConstructor = RTCPeerConnection;
  const url = `${signalUrl}/${room}`;
  if (invite !== undefined) {
    const signal = new SignalClient(await connectWebSocket(url));
    const link = await joinPeer({ signal, room, invite, PeerConnection });
    return {
      transport: link.transport,
      via: link.via,
      invite,
      close: () => {
        link.transport.close();
        signal.close();
      },
    };
  }
  const hostSignal = new SignalClient(await connectWebSocket(url));
  const relay = new Relay({ clock: performanceClock(), catalog: gameCatalog([def]) });
  const host = new PeerHost({
    signal: hostSignal,
    room,
    PeerConnection,
    onPeer: (link) => {
      relay.accept(link.transport);
    },
  });
  let hosting: PeerHosting;
  try {
    hosting = await host.ready;
  } catch (e) {
    host.close();
    hostSignal.close();
    if (e instanceof Error && e.message.includes('ROOM_TAKEN')) {
      throw new Error(
        `room ${room} has a host already: open its invite link from the host's page`,
        {
          cause: e,
        },
      );
    }
    throw e;
  }
  const timer = setInterval(() => {
    relay.update();
  }, RELAY_EVERY_MS);
  const [mine, theirs] = memoryPair();
  relay.accept(theirs);
  return {
    transport: mine,
    via: 'host',
    invite: hosting.invite,
    close: () => {
      clearInterval(timer);
      host.close();
      hostSignal.close();
    },
  };
}
