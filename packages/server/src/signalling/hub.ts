import {
  DEFAULT_SIGNAL_LIMITS,
  MAX_SIGNAL_PEERS,
  SignalError,
  decodeSignal,
  encodeSignal,
  type Clock,
  type IceServerConfig,
  type SignalErrorCode,
  type SignalLimits,
  type SignalMessage,
  type Transport,
} from 'fixedstep';

/** Options of a {@link SignallingHub}. */
export interface SignallingHubOptions {
  /** The clock of rate limits and timeouts (ms). */
  clock: Clock;
  /**
   * STUN/TURN servers announced to every host and joiner in `joined` (clients may override them).
   * Default none: peers then connect only where their host addresses reach each other.
   */
  iceServers?: IceServerConfig[];
  /** Connections at once. Default 2000. */
  maxConnections?: number;
  /** Rooms at once. Default 1000. */
  maxRooms?: number;
  /** A connection must send `host` or `join` within this time. Default 10 000 ms. */
  helloTimeoutMs?: number;
  /**
   * Sustained messages per second per connection (a host tunnelling for 15 peers at 60 Hz sends
   * ~900). Default 1200, burst twice that.
   */
  messagesPerSecond?: number;
  /** Sustained bytes per second per connection. Default 512 KiB, burst 4 MiB (a snapshot fits). */
  bytesPerSecond?: number;
  limits?: Partial<SignalLimits>;
}

/** Counters of a hub. */
export interface SignallingStats {
  connections: number;
  rooms: number;
  messagesIn: number;
  messagesOut: number;
  bytesIn: number;
  bytesOut: number;
  /** Tunnelled messages forwarded (the fallback path). */
  tunnelled: number;
  /** Connections dropped for a bad message, a rate limit or a timeout. */
  dropped: number;
}

interface Conn {
  id: number;
  transport: Transport;
  room: Room | undefined;
  /** 0 for a host, 1 … 15 for a joiner, -1 before hello. */
  peer: number;
  openedAt: number;
  tokens: number;
  bytes: number;
  at: number;
  closed: boolean;
}

interface Room {
  name: string;
  host: Conn;
  peers: Map<number, Conn>;
}

/**
 * The server side of signalling, transport-agnostic (`attachSignalling` puts it on a WebSocket
 * path): rooms of one host and up to 15 joiners; offers, answers and candidates are forwarded
 * between a joiner and its host with the sender's peer id stamped by the server (a client cannot
 * speak for another), and so are tunnelled game messages when a direct connection failed. The hub
 * never reads SDP or game bytes beyond their size.
 */
export class SignallingHub {
  readonly stats: SignallingStats = {
    connections: 0,
    rooms: 0,
    messagesIn: 0,
    messagesOut: 0,
    bytesIn: 0,
    bytesOut: 0,
    tunnelled: 0,
    dropped: 0,
  };
  private readonly conns = new Map<number, Conn>();
  private readonly rooms = new Map<string, Room>();
  private nextId = 1;
  private readonly o: Required<Omit<SignallingHubOptions, 'limits' | 'clock'>>;
  private readonly limits: SignalLimits;
  private readonly clock: Clock;

  constructor(options: SignallingHubOptions) {
    this.clock = options.clock;
    this.o = {
      iceServers: options.iceServers ?? [],
      maxConnections: options.maxConnections ?? 2000,
      maxRooms: options.maxRooms ?? 1000,
      helloTimeoutMs: options.helloTimeoutMs ?? 10_000,
      messagesPerSecond: options.messagesPerSecond ?? 1200,
      bytesPerSecond: options.bytesPerSecond ?? 512 * 1024,
    };
    this.limits = { ...DEFAULT_SIGNAL_LIMITS, ...options.limits };
    // Refuse a bad configuration here, not at the first client.
    encodeSignal(
      { type: 'joined', room: 'x', peer: 0, iceServers: this.o.iceServers },
      this.limits,
    );
  }

  /** The ICE servers announced to clients. */
  get iceServers(): readonly IceServerConfig[] {
    return this.o.iceServers;
  }

  /** Take a connection. Returns its id, or -1 when refused (`SERVER_FULL`). */
  accept(transport: Transport): number {
    const now = this.clock.now();
    if (this.conns.size >= this.o.maxConnections) {
      transport.send(encodeSignal({ type: 'error', code: 'SERVER_FULL', message: 'server full' }));
      transport.close('server full');
      return -1;
    }
    const conn: Conn = {
      id: this.nextId++,
      transport,
      room: undefined,
      peer: -1,
      openedAt: now,
      tokens: this.o.messagesPerSecond * 2,
      bytes: this.o.bytesPerSecond * 8,
      at: now,
      closed: false,
    };
    this.conns.set(conn.id, conn);
    this.stats.connections = this.conns.size;
    transport.onMessage((bytes) => {
      this.onBytes(conn, bytes);
    });
    transport.onClose(() => {
      this.remove(conn);
    });
    return conn.id;
  }

  /** Time out connections that never said `host` or `join`. Call now and then (every second). */
  update(now = this.clock.now()): void {
    for (const c of [...this.conns.values()]) {
      if (c.peer < 0 && now - c.openedAt > this.o.helloTimeoutMs) {
        this.drop(c, 'TIMEOUT', 'no host or join in time');
      }
    }
  }

  /** The rooms: name, and the peer ids present (0 is the host). */
  roomList(): { room: string; peers: number[] }[] {
    return [...this.rooms.values()].map((r) => ({
      room: r.name,
      peers: [0, ...[...r.peers.keys()].sort((a, b) => a - b)],
    }));
  }

  /** Close every connection. */
  close(): void {
    for (const c of [...this.conns.values()]) c.transport.close('server shutting down');
  }

  private onBytes(c: Conn, bytes: Uint8Array): void {
    if (c.closed) return;
    this.stats.messagesIn++;
    this.stats.bytesIn += bytes.length;
    if (!this.takeTokens(c, bytes.length)) {
      this.drop(c, 'RATE_LIMIT', 'too many messages');
      return;
    }
    let m: SignalMessage;
    try {
      m = decodeSignal(bytes, this.limits);
    } catch (error) {
      if (!(error instanceof SignalError)) throw error;
      this.drop(c, error.problem === 'too-large' ? 'TOO_LARGE' : 'BAD_MESSAGE', error.message);
      return;
    }
    switch (m.type) {
      case 'host':
        this.onHost(c, m.room);
        break;
      case 'join':
        this.onJoin(c, m.room);
        break;
      case 'signal':
      case 'data':
        this.forward(c, m);
        break;
      default:
        this.drop(c, 'UNEXPECTED', `a client does not send ${m.type}`);
    }
  }

  private onHost(c: Conn, name: string): void {
    if (c.peer >= 0) {
      this.drop(c, 'UNEXPECTED', 'already in a room');
      return;
    }
    if (this.rooms.has(name)) {
      this.error(c, 'ROOM_TAKEN', `room ${name} already has a host`);
      return;
    }
    if (this.rooms.size >= this.o.maxRooms) {
      this.error(c, 'SERVER_FULL', 'too many rooms');
      return;
    }
    const room: Room = { name, host: c, peers: new Map() };
    this.rooms.set(name, room);
    this.stats.rooms = this.rooms.size;
    c.room = room;
    c.peer = 0;
    this.send(c, { type: 'joined', room: name, peer: 0, iceServers: this.o.iceServers });
  }

  private onJoin(c: Conn, name: string): void {
    if (c.peer >= 0) {
      this.drop(c, 'UNEXPECTED', 'already in a room');
      return;
    }
    const room = this.rooms.get(name);
    if (!room) {
      this.error(c, 'NO_ROOM', `no room ${name} (its host has not arrived or has left)`);
      return;
    }
    let peer = 1;
    while (peer <= MAX_SIGNAL_PEERS && room.peers.has(peer)) peer++;
    if (peer > MAX_SIGNAL_PEERS) {
      this.error(c, 'ROOM_FULL', `room ${name} has ${MAX_SIGNAL_PEERS} peers`);
      return;
    }
    room.peers.set(peer, c);
    c.room = room;
    c.peer = peer;
    this.send(c, { type: 'joined', room: name, peer, iceServers: this.o.iceServers });
    this.send(room.host, { type: 'peer', peer });
  }

  /** Route a signal or tunnelled message to its target, stamping the sender's peer id. */
  private forward(c: Conn, m: Extract<SignalMessage, { type: 'signal' | 'data' }>): void {
    const room = c.room;
    if (!room) {
      this.drop(c, 'UNEXPECTED', `${m.type} before host or join`);
      return;
    }
    let target: Conn | undefined;
    if (c.peer === 0) target = room.peers.get(m.peer);
    else if (m.peer === 0) target = room.host;
    if (!target) {
      if (m.type === 'signal') this.error(c, 'NO_PEER', `no peer ${m.peer} in room ${room.name}`);
      return;
    }
    if (m.type === 'data') this.stats.tunnelled++;
    this.send(target, { ...m, peer: c.peer });
  }

  private remove(c: Conn): void {
    if (c.closed) return;
    c.closed = true;
    this.conns.delete(c.id);
    this.stats.connections = this.conns.size;
    const room = c.room;
    c.room = undefined;
    if (!room) return;
    if (room.host === c) {
      this.rooms.delete(room.name);
      this.stats.rooms = this.rooms.size;
      for (const p of room.peers.values()) {
        p.room = undefined;
        this.send(p, { type: 'leave', peer: 0 });
      }
    } else if (room.peers.get(c.peer) === c) {
      room.peers.delete(c.peer);
      this.send(room.host, { type: 'leave', peer: c.peer });
    }
  }

  private takeTokens(c: Conn, bytes: number): boolean {
    const now = this.clock.now();
    const dt = Math.max(0, now - c.at) / 1000;
    c.at = now;
    c.tokens = Math.min(this.o.messagesPerSecond * 2, c.tokens + dt * this.o.messagesPerSecond);
    c.bytes = Math.min(this.o.bytesPerSecond * 8, c.bytes + dt * this.o.bytesPerSecond);
    if (c.tokens < 1 || c.bytes < bytes) return false;
    c.tokens -= 1;
    c.bytes -= bytes;
    return true;
  }

  private error(c: Conn, code: SignalErrorCode, message: string): void {
    this.send(c, { type: 'error', code, message });
  }

  private drop(c: Conn, code: SignalErrorCode, message: string): void {
    this.stats.dropped++;
    this.error(c, code, message);
    c.transport.close(`${code}: ${message}`);
    this.remove(c);
  }

  private send(c: Conn, m: SignalMessage): void {
    if (c.closed || !c.transport.isOpen) return;
    const bytes = encodeSignal(m, this.limits);
    this.stats.messagesOut++;
    this.stats.bytesOut += bytes.length;
    c.transport.send(bytes);
  }
}
