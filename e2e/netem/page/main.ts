/**
 * One player of the loss harness in a browser page: it hosts a peer-to-peer room (the relay runs
 * here, its own session on a memory pair), joins one over WebRTC through the signalling server,
 * or plays through a WebSocket to the server's relay — and measures itself with the probe the
 * Node version uses. The test drives it through `window.netem`.
 */
import {
  PeerHost,
  Relay,
  RollbackSession,
  SignalClient,
  connectWebSocket,
  joinPeer,
  memoryPair,
  performanceClock,
  gameCatalog,
  type IceServerConfig,
  type PeerConnectionConstructor,
  type Transport,
} from 'fixedstep';
import { ctfGame } from '@fixedstep/games';
import { Probe, type ProbeReport } from '../probe.js';

export interface PlayOptions {
  room: string;
  ticks: number;
  seed: number;
  slot: number;
}

export interface NetemPageApi {
  readonly ready: true;
  /**
   * Host a p2p room: run the relay here and wait for the joiner; resolves once hosting, with the
   * room's invite (hex) for the joiner.
   */
  host(signalUrl: string, room: string, iceServers: IceServerConfig[]): Promise<string>;
  /** Join a p2p room with its invite (hex); resolves with how it connected ('webrtc' or 'server'). */
  join(
    signalUrl: string,
    room: string,
    iceServers: IceServerConfig[],
    invite: string,
  ): Promise<string>;
  /** Connect to the server's relay over a WebSocket. */
  connectRelay(url: string): Promise<void>;
  /** Start this page's player on the connection made above. */
  play(options: PlayOptions): void;
  /** Whether the match reached its last tick with a confirmed state. */
  finished(): boolean;
  /** This page's measurements (JSON of a ProbeReport). */
  report(): string;
  status(): string;
}

declare global {
  interface Window {
    netem?: NetemPageApi;
  }
}

const clock = performanceClock();
const status = document.getElementById('status')!;
let transport: Transport | undefined;
let relay: Relay | undefined;
let session: RollbackSession<unknown> | undefined;
let probe: Probe | undefined;
const PC: PeerConnectionConstructor = RTCPeerConnection;

async function signal(url: string): Promise<SignalClient> {
  return new SignalClient(await connectWebSocket(url));
}

function say(text: string): void {
  status.textContent = text;
}

window.netem = {
  ready: true,
  async host(signalUrl, room, iceServers) {
    relay = new Relay({ clock, catalog: gameCatalog([ctfGame]) });
    const r = relay;
    setInterval(() => {
      r.update();
    }, 4);
    const [mine, theirs] = memoryPair();
    r.accept(theirs);
    transport = mine;
    const host = new PeerHost({
      signal: await signal(`${signalUrl}/${room}`),
      room,
      PeerConnection: PC,
      iceServers,
      iceTransportPolicy: 'relay',
      fallback: false,
      onPeer: (link) => {
        say(`peer ${link.peer} connected via ${link.via}`);
        r.accept(link.transport);
      },
    });
    const { invite } = await host.ready;
    say(`hosting ${room}`);
    return Array.from(invite, (b) => b.toString(16).padStart(2, '0')).join('');
  },
  async join(signalUrl, room, iceServers, invite) {
    const link = await joinPeer({
      signal: await signal(`${signalUrl}/${room}`),
      room,
      invite: Uint8Array.from({ length: 16 }, (_, i) =>
        parseInt(invite.slice(2 * i, 2 * i + 2), 16),
      ),
      PeerConnection: PC,
      iceServers,
      iceTransportPolicy: 'relay',
      fallback: false,
      connectTimeoutMs: 20_000,
    });
    transport = link.transport;
    say(`joined ${room} via ${link.via}`);
    return link.via;
  },
  async connectRelay(url) {
    transport = await connectWebSocket(url);
    say(`connected to ${url}`);
  },
  play({ room, ticks, seed, slot }) {
    if (!transport) throw new Error('play: not connected');
    const p = new Probe(slot, ticks);
    probe = p;
    let held: unknown = ctfGame.input.neutral();
    const s = new RollbackSession<unknown>({
      transport,
      clock,
      room,
      game: ctfGame,
      players: 2,
      seed,
      name: `page${slot + 1}`,
      stopAt: ticks,
      localInput: p.input((tick, sim) => {
        if (tick % 6 === 0) held = ctfGame.bot(sim as never, slot);
        return held;
      }),
      onCorrection: p.onCorrection,
    });
    session = s;
    // 60 Hz frames on timers (a page in the background of a headless browser gets no animation frames).
    let next = clock.now();
    const frame = () => {
      s.frame();
      p.afterFrame(s);
      if (s.isFinished) {
        say(`finished at tick ${s.tick}`);
        return;
      }
      next += 1000 / 60;
      setTimeout(frame, Math.max(0, next - clock.now()));
    };
    frame();
  },
  finished: () => session?.isFinished ?? false,
  report(): string {
    if (!session || !probe) throw new Error('report: no match');
    const r: ProbeReport = probe.report(session);
    return JSON.stringify(r);
  },
  status: () =>
    session
      ? `tick ${session.tick}, confirmed ${session.confirmedTick}, phase ${session.phase}`
      : status.textContent,
};
say('ready');
