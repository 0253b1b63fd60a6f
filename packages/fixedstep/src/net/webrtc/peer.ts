import { BaseTransport, type Transport } from '../transport.js';
import { dataChannelTransport, type DataChannelTransportOptions } from './data-channel.js';
import {
  DEFAULT_SIGNAL_LIMITS,
  decodeSignal,
  encodeSignal,
  type IceServerConfig,
  type SignalLimits,
  type SignalMessage,
} from './signal-messages.js';
import { ProtocolError } from '../wire/error.js';
import type {
  DataChannelInitLike,
  DataChannelLike,
  IceCandidateEventLike,
  IceCandidateLike,
  PeerConnectionConstructor,
  PeerConnectionLike,
} from './types.js';

/** Label of the unreliable, unordered channel (every message up to `maxUnreliableBytes`). */
export const UNRELIABLE_LABEL = 'fixedstep-u';
/** Label of the reliable, ordered channel (large messages, in chunks). */
export const RELIABLE_LABEL = 'fixedstep-r';
/**
 * The SCTP streams of the two channels. Both peers create both channels as `negotiated` on these
 * streams rather than the joiner announcing them (DCEP): each side then sends by its own
 * `ordered`/`maxRetransmits`. With DCEP, werift 0.24 announces `{ ordered: false, maxRetransmits:
 * n }` as *ordered* (its channel type byte drops the unordered bit), so a werift host sent the
 * game's datagrams ordered: one loss held every later message until it was retransmitted.
 */
export const UNRELIABLE_STREAM = 0;
export const RELIABLE_STREAM = 1;

/**
 * The signalling connection's client end: encodes and decodes {@link SignalMessage}s on a
 * transport (a WebSocket to the server's `/signal`). Undecodable messages are counted and dropped.
 */
export class SignalClient {
  /** Messages from the server that could not be decoded. */
  badMessages = 0;
  private readonly listeners = new Set<(m: SignalMessage) => void>();
  private readonly closeListeners = new Set<(reason: string) => void>();
  private closedReason: string | undefined;

  constructor(
    readonly transport: Transport,
    limits: Partial<SignalLimits> = {},
  ) {
    const all = { ...DEFAULT_SIGNAL_LIMITS, ...limits };
    transport.onMessage((bytes) => {
      let m: SignalMessage;
      try {
        m = decodeSignal(bytes, all);
      } catch (error) {
        if (!(error instanceof ProtocolError)) throw error;
        this.badMessages++;
        return;
      }
      // The server checks that a quiet connection is alive: answer at once.
      if (m.type === 'ping') {
        this.send({ type: 'pong', id: m.id, time: m.time, serverTime: m.time });
        return;
      }
      for (const l of [...this.listeners]) l(m);
    });
    transport.onClose((reason) => {
      this.closedReason = reason;
      for (const l of [...this.closeListeners]) l(reason);
    });
  }

  /** Whether the connection to the server is still open. */
  get isOpen(): boolean {
    return this.closedReason === undefined && this.transport.isOpen;
  }

  send(m: SignalMessage): void {
    if (this.transport.isOpen) this.transport.send(encodeSignal(m));
  }

  /** Listen to every message; returns a function that stops listening. */
  listen(handler: (m: SignalMessage) => void): () => void {
    this.listeners.add(handler);
    return () => this.listeners.delete(handler);
  }

  /** Be told when the connection closes (at once if it already has); returns a function that stops it. */
  onClose(handler: (reason: string) => void): () => void {
    if (this.closedReason !== undefined) {
      handler(this.closedReason);
      return () => undefined;
    }
    this.closeListeners.add(handler);
    return () => this.closeListeners.delete(handler);
  }

  close(reason = 'closed'): void {
    this.transport.close(reason);
  }
}

/**
 * A game connection tunnelled through the signalling server (`data` messages to and from one
 * peer): the fallback when no direct connection could be made. It is a WebSocket to the server on
 * each side, so it is reliable and ordered, with TCP's head-of-line blocking.
 */
class TunnelTransport extends BaseTransport {
  /** A WebSocket each way: every message arrives, in order (or the tunnel closes). */
  readonly reliable = true;
  constructor(
    private readonly signal: SignalClient,
    private readonly peer: number,
    private readonly onClosed: () => void,
  ) {
    super();
  }
  send(bytes: Uint8Array): void {
    if (this.isOpen) this.signal.send({ type: 'data', peer: this.peer, bytes });
  }
  receive(bytes: Uint8Array): void {
    this.deliver(bytes);
  }
  remoteClose(reason: string): void {
    this.closedRemotely(reason);
    this.onClosed();
  }
  protected doClose(): void {
    this.onClosed();
  }
}

/** Options shared by {@link PeerHost} and {@link joinPeer}. */
export interface PeerToPeerOptions {
  /** The signalling connection (a {@link SignalClient} on a WebSocket to the server's `/signal/<room>`). */
  signal: SignalClient;
  /** The room: the host's name for it, which the joiners use. */
  room: string;
  /**
   * Joiners: the room's invite token, which the host got in its `joined` ({@link PeerHosting}) and
   * handed to the people it invites (a link, a chat message). The server lets no joiner in without
   * it: room names are often guessable.
   */
  invite?: Uint8Array;
  /**
   * The `RTCPeerConnection` constructor: `globalThis.RTCPeerConnection` in a browser, `werift`'s in
   * Node. Injected so the library has no runtime dependency.
   */
  PeerConnection: PeerConnectionConstructor;
  /**
   * STUN/TURN servers. Default: the ones the signalling server announces in `joined` (configured
   * where the server runs; none by default, which connects peers on one network only).
   */
  iceServers?: IceServerConfig[];
  /**
   * `'relay'` uses TURN relays only (hides each peer's addresses from the other; the loss
   * harness uses it to keep every packet on 127.0.0.1). Default `'all'`.
   */
  iceTransportPolicy?: 'all' | 'relay';
  /**
   * How long a direct connection may take to open before the joiner falls back to the tunnel
   * through the server, in ms. Default 10 000.
   */
  connectTimeoutMs?: number;
  /**
   * Fall back to tunnelling the game through the signalling server when no direct connection
   * opens in time (default true). When false, {@link joinPeer} rejects instead.
   */
  fallback?: boolean;
  /** Options of the data channel transport. */
  dataChannel?: DataChannelTransportOptions;
  /**
   * How this peer sends on the unreliable channel (both peers create both channels, negotiated on
   * streams {@link UNRELIABLE_STREAM} and {@link RELIABLE_STREAM}; `negotiated` and `id` are set
   * here). Default `{ ordered: false, maxRetransmits: 0 }`: never retransmitted. werift 0.24 treats
   * `maxRetransmits: 0` as unlimited and never expires `maxPacketLifeTime`, so a werift peer — host
   * or joiner — passes `{ ordered: false, maxRetransmits: 1 }` (at most one retransmission):
   * docs/webrtc.md.
   */
  unreliableChannel?: Omit<DataChannelInitLike, 'negotiated' | 'id'>;
}

/** A connection to or from one peer. */
export interface PeerLink {
  /** The peer id the signalling server gave (the host is 0, joiners 1 … 15). */
  peer: number;
  /** The game's transport to that peer. */
  transport: Transport;
  /** `'webrtc'`: direct data channels; `'server'`: tunnelled through the signalling server. */
  via: 'webrtc' | 'server';
}

function candidateText(c: { toJSON?(): IceCandidateLike } | IceCandidateLike): string {
  const json: IceCandidateLike =
    'toJSON' in c && typeof c.toJSON === 'function' ? c.toJSON() : (c as IceCandidateLike);
  return JSON.stringify({
    candidate: json.candidate ?? '',
    sdpMid: json.sdpMid ?? null,
    sdpMLineIndex: json.sdpMLineIndex ?? null,
  });
}

/** A candidate from the other side, checked: undefined when it is not one. */
function parseCandidate(text: string): IceCandidateLike | undefined {
  let v: unknown;
  try {
    v = JSON.parse(text);
  } catch {
    return undefined;
  }
  if (typeof v !== 'object' || v === null) return undefined;
  const o = v as Record<string, unknown>;
  if (typeof o.candidate !== 'string') return undefined;
  const out: IceCandidateLike = { candidate: o.candidate };
  if (typeof o.sdpMid === 'string' || o.sdpMid === null) out.sdpMid = o.sdpMid;
  if (typeof o.sdpMLineIndex === 'number' || o.sdpMLineIndex === null) {
    out.sdpMLineIndex = o.sdpMLineIndex;
  }
  return out;
}

/**
 * One side of one peer connection: trickles candidates through the signalling server, queues
 * remote candidates until the remote description is set, and resolves once both channels are open.
 */
class PeerConnectionSide {
  readonly pc: PeerConnectionLike;
  private remoteSet = false;
  private readonly pendingCandidates: IceCandidateLike[] = [];
  private unreliable: DataChannelLike | undefined;
  private reliable: DataChannelLike | undefined;
  private opened = false;
  closed = false;

  constructor(
    private readonly options: PeerToPeerOptions,
    iceServers: IceServerConfig[],
    private readonly peer: number,
    private readonly onOpen: (transport: Transport) => void,
  ) {
    const config: { iceServers: IceServerConfig[]; iceTransportPolicy?: 'all' | 'relay' } = {
      iceServers: options.iceServers ?? iceServers,
    };
    if (options.iceTransportPolicy) config.iceTransportPolicy = options.iceTransportPolicy;
    this.pc = new options.PeerConnection(config);
    this.pc.onicecandidate = (event: IceCandidateEventLike) => {
      if (this.closed) return;
      const c = event.candidate;
      if (!c) {
        options.signal.send({ type: 'signal', peer, kind: 'end-of-candidates', text: '' });
        return;
      }
      const text = candidateText(c);
      // An empty candidate marks the end of a generation: nothing to send.
      if (parseCandidate(text)?.candidate) {
        options.signal.send({ type: 'signal', peer, kind: 'candidate', text });
      }
    };
  }

  /** Create both channels, negotiated (both sides do, before the offer or the answer). */
  createChannels(): void {
    const unreliable = this.options.unreliableChannel ?? { ordered: false, maxRetransmits: 0 };
    this.adopt(
      this.pc.createDataChannel(UNRELIABLE_LABEL, {
        ...unreliable,
        negotiated: true,
        id: UNRELIABLE_STREAM,
      }),
    );
    this.adopt(
      this.pc.createDataChannel(RELIABLE_LABEL, {
        ordered: true,
        negotiated: true,
        id: RELIABLE_STREAM,
      }),
    );
  }

  private adopt(ch: DataChannelLike): void {
    if (ch.label === UNRELIABLE_LABEL) this.unreliable = ch;
    else if (ch.label === RELIABLE_LABEL) this.reliable = ch;
    else return;
    ch.binaryType = 'arraybuffer';
    ch.onopen = () => {
      this.checkOpen();
    };
    this.checkOpen();
  }

  private checkOpen(): void {
    const u = this.unreliable;
    const r = this.reliable;
    if (this.opened || this.closed || !u || !r) return;
    if (u.readyState !== 'open' || r.readyState !== 'open') return;
    this.opened = true;
    const transport = dataChannelTransport(u, r, {
      ...this.options.dataChannel,
      onClose: () => {
        this.close();
      },
    });
    this.onOpen(transport);
  }

  async remoteDescription(type: 'offer' | 'answer', sdp: string): Promise<void> {
    await this.pc.setRemoteDescription({ type, sdp });
    this.remoteSet = true;
    for (const c of this.pendingCandidates.splice(0)) await this.addCandidate(c);
  }

  async remoteCandidate(text: string): Promise<void> {
    const c = parseCandidate(text);
    if (!c) return;
    if (!this.remoteSet) this.pendingCandidates.push(c);
    else await this.addCandidate(c);
  }

  private async addCandidate(c: IceCandidateLike): Promise<void> {
    try {
      await this.pc.addIceCandidate(c);
    } catch {
      // A candidate this side cannot use (another address family, an mDNS name): skip it.
    }
  }

  close(): void {
    if (this.closed) return;
    this.closed = true;
    this.pc.onicecandidate = null;
    try {
      this.pc.close();
    } catch {
      // already closed
    }
  }
}

/** A room the signalling server confirmed to its host. */
export interface PeerHosting {
  room: string;
  /** The invite token joiners must bring (see {@link PeerToPeerOptions.invite}): a secret. */
  invite: Uint8Array;
  /** The STUN/TURN servers the server announced. */
  iceServers: IceServerConfig[];
}

/** What a {@link PeerHost} reports. */
export type PeerHostEvent =
  | ({ type: 'hosting' } & PeerHosting)
  | { type: 'peer'; peer: number }
  | { type: 'connected'; link: PeerLink }
  | { type: 'left'; peer: number }
  | { type: 'error'; message: string };

/** Options of a {@link PeerHost}. */
export interface PeerHostOptions extends PeerToPeerOptions {
  /** A peer is connected (directly or through the server): hand its transport to the relay. */
  onPeer: (link: PeerLink) => void;
  /** Hosting started, peers came and went, errors. */
  onEvent?: (event: PeerHostEvent) => void;
}

/**
 * The room creator's end of peer-to-peer play: registers `room` with the signalling server, answers
 * each joiner's offer, and hands every connected peer's transport to `onPeer` — typically
 * `relay.accept(link.transport)` on a {@link Relay} this page runs, with the host's own session on a
 * `memoryPair()` to the same relay. Lockstep, rollback, desync detection and forensics then work
 * unchanged between peers. A joiner that cannot connect directly falls back to a tunnel through
 * the server; `onPeer` gets that transport the same way.
 */
export class PeerHost {
  /**
   * Resolves when the server confirmed the room, with its invite token for the joiners (rejects on
   * an error such as `ROOM_TAKEN`).
   */
  readonly ready: Promise<PeerHosting>;
  private readonly sides = new Map<number, PeerConnectionSide>();
  private readonly links = new Map<number, Transport>();
  private readonly tunnels = new Map<number, TunnelTransport>();
  private iceServers: IceServerConfig[] = [];
  private readonly stopListening: () => void;
  private closed = false;

  constructor(private readonly options: PeerHostOptions) {
    const signal = options.signal;
    let resolveReady!: (h: PeerHosting) => void;
    let rejectReady!: (e: Error) => void;
    this.ready = new Promise((resolve, reject) => {
      resolveReady = resolve;
      rejectReady = reject;
    });
    let hosting = false;
    this.stopListening = signal.listen((m) => {
      if (m.type === 'joined' && !hosting) {
        hosting = true;
        this.iceServers = m.iceServers;
        const info: PeerHosting = { room: m.room, invite: m.invite, iceServers: m.iceServers };
        this.emit({ type: 'hosting', ...info });
        resolveReady(info);
      } else if (m.type === 'error') {
        this.emit({ type: 'error', message: `${m.code}: ${m.message}` });
        if (!hosting) rejectReady(new Error(`PeerHost: ${m.code}: ${m.message}`));
      } else if (m.type === 'peer') {
        this.emit({ type: 'peer', peer: m.peer });
      } else if (m.type === 'signal') {
        void this.onSignal(m.peer, m.kind, m.text).catch((error: unknown) => {
          this.emit({ type: 'error', message: `peer ${m.peer}: ${String(error)}` });
          this.drop(m.peer);
        });
      } else if (m.type === 'data') {
        this.tunnels.get(m.peer)?.receive(m.bytes);
      } else if (m.type === 'leave') {
        this.drop(m.peer);
        this.emit({ type: 'left', peer: m.peer });
      }
    });
    signal.onClose((reason) => {
      if (!hosting) rejectReady(new Error(`PeerHost: signalling closed: ${reason}`));
      for (const t of [...this.tunnels.values()]) t.remoteClose('signalling closed');
    });
    signal.send({ type: 'host', room: options.room });
  }

  private async onSignal(peer: number, kind: string, text: string): Promise<void> {
    if (this.closed) return;
    if (kind === 'offer') {
      this.drop(peer);
      const side = new PeerConnectionSide(this.options, this.iceServers, peer, (transport) => {
        this.connected({ peer, transport, via: 'webrtc' });
      });
      this.sides.set(peer, side);
      side.createChannels();
      await side.remoteDescription('offer', text);
      const answer = await side.pc.createAnswer();
      await side.pc.setLocalDescription(answer);
      const sdp = side.pc.localDescription?.sdp ?? answer.sdp ?? '';
      this.options.signal.send({ type: 'signal', peer, kind: 'answer', text: sdp });
    } else if (kind === 'candidate') {
      await this.sides.get(peer)?.remoteCandidate(text);
    } else if (kind === 'fallback') {
      this.drop(peer);
      if (this.options.fallback === false) return;
      const tunnel = new TunnelTransport(this.options.signal, peer, () => {
        this.tunnels.delete(peer);
      });
      this.tunnels.set(peer, tunnel);
      this.connected({ peer, transport: tunnel, via: 'server' });
    }
  }

  private connected(link: PeerLink): void {
    this.links.set(link.peer, link.transport);
    this.emit({ type: 'connected', link });
    this.options.onPeer(link);
  }

  /** Close everything of `peer` (its connection is replaced or gone). */
  private drop(peer: number): void {
    this.sides.get(peer)?.close();
    this.sides.delete(peer);
    this.links.get(peer)?.close('peer left');
    this.links.delete(peer);
    this.tunnels.get(peer)?.close('peer left');
    this.tunnels.delete(peer);
  }

  /** Stop hosting: close every peer connection and stop listening (the signalling stays open). */
  close(): void {
    if (this.closed) return;
    this.closed = true;
    for (const peer of [...this.sides.keys(), ...this.tunnels.keys()]) this.drop(peer);
    this.stopListening();
  }

  private emit(e: PeerHostEvent): void {
    this.options.onEvent?.(e);
  }
}

/**
 * Joins the peer-to-peer room `room`: asks the signalling server to introduce us to its host,
 * offers an unreliable and a reliable data channel, trickles ICE candidates, and resolves with the
 * transport once both channels are open — give it to a session as its transport to the relay the
 * host runs. If no direct connection opens within `connectTimeoutMs`, it falls back to a tunnel
 * through the server (`via: 'server'`), unless `fallback` is false. Rejects on a signalling error
 * (`NO_ROOM`, `ROOM_FULL` …) or when the signalling connection closes first.
 */
export function joinPeer(options: PeerToPeerOptions): Promise<PeerLink> {
  const signal = options.signal;
  const timeoutMs = options.connectTimeoutMs ?? 10_000;
  if (!(timeoutMs > 0)) throw new RangeError(`connectTimeoutMs must be > 0, got ${timeoutMs}`);
  const invite = options.invite;
  if (invite === undefined) {
    throw new RangeError(
      "joinPeer: give the room's invite token (the host's PeerHost.ready has it)",
    );
  }
  return new Promise<PeerLink>((resolve, reject) => {
    let side: PeerConnectionSide | undefined;
    let tunnel: TunnelTransport | undefined;
    let done = false;
    let timer: ReturnType<typeof setTimeout> | undefined;
    const finish = (result: PeerLink | Error): void => {
      if (done) return;
      done = true;
      if (timer !== undefined) clearTimeout(timer);
      if (result instanceof Error) {
        side?.close();
        stop();
        stopClose();
        reject(result);
      } else {
        resolve(result);
      }
    };
    const stop = signal.listen((m) => {
      if (m.type === 'joined' && side === undefined && !done) {
        side = new PeerConnectionSide(options, m.iceServers, 0, (transport) => {
          finish({ peer: m.peer, transport, via: 'webrtc' });
        });
        side.createChannels();
        timer = setTimeout(() => {
          if (options.fallback === false) {
            finish(
              new Error(
                `joinPeer: no direct connection to room ${options.room} within ${timeoutMs} ms`,
              ),
            );
            return;
          }
          side?.close();
          signal.send({ type: 'signal', peer: 0, kind: 'fallback', text: '' });
          tunnel = new TunnelTransport(signal, 0, () => undefined);
          finish({ peer: m.peer, transport: tunnel, via: 'server' });
        }, timeoutMs);
        void (async () => {
          const offer = await side.pc.createOffer();
          await side.pc.setLocalDescription(offer);
          const sdp = side.pc.localDescription?.sdp ?? offer.sdp ?? '';
          signal.send({ type: 'signal', peer: 0, kind: 'offer', text: sdp });
        })().catch((error: unknown) => {
          finish(new Error(`joinPeer: cannot make an offer: ${String(error)}`));
        });
      } else if (m.type === 'signal' && m.peer === 0 && side && !side.closed) {
        const s = side;
        const work =
          m.kind === 'answer'
            ? s.remoteDescription('answer', m.text)
            : m.kind === 'candidate'
              ? s.remoteCandidate(m.text)
              : Promise.resolve();
        work.catch((error: unknown) => {
          finish(new Error(`joinPeer: ${m.kind} from the host: ${String(error)}`));
        });
      } else if (m.type === 'data' && m.peer === 0) {
        tunnel?.receive(m.bytes);
      } else if (m.type === 'leave' && m.peer === 0) {
        tunnel?.remoteClose('the host left');
        finish(new Error(`joinPeer: the host of ${options.room} left`));
      } else if (m.type === 'error' && !done) {
        finish(new Error(`joinPeer: ${m.code}: ${m.message}`));
      }
    });
    const stopClose = signal.onClose((reason) => {
      tunnel?.remoteClose(`signalling closed: ${reason}`);
      finish(new Error(`joinPeer: signalling closed: ${reason}`));
    });
    signal.send({ type: 'join', room: options.room, invite });
  });
}
