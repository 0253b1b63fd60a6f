/**
 * A UDP proxy on 127.0.0.1 that delays, jitters and drops datagrams: put in front of the TURN
 * relay, it impairs every WebRTC packet of the peers that use it (each datagram from a peer to the
 * relay goes through `up`, each from the relay back to the peer through `down`). One upstream
 * socket per client address, so the relay sees each client as a distinct address.
 */
import dgram from 'node:dgram';
import {
  CLEAN,
  Dice,
  checkImpairment,
  newStats,
  realSchedule,
  type DirectionStats,
  type Impairment,
  type Schedule,
} from './impair.js';

export interface UdpProxyOptions {
  /** Where datagrams go (the TURN relay's port on 127.0.0.1). */
  targetPort: number;
  /** Client → target conditions. Default clean. */
  up?: Impairment;
  /** Target → client conditions. Default clean. */
  down?: Impairment;
  /** Seed of the delays and losses. Default 1. */
  seed?: number;
  /** Timer (default setTimeout). */
  schedule?: Schedule;
}

interface Client {
  key: string;
  address: string;
  port: number;
  socket: dgram.Socket;
  up: DirectionStats;
  down: DirectionStats;
}

/** The proxy; {@link startUdpProxy} binds it. */
export class UdpProxy {
  private up: Impairment;
  private down: Impairment;
  private readonly upDice: Dice;
  private readonly downDice: Dice;
  private readonly clients = new Map<string, Client>();
  private readonly schedule: Schedule;
  private closed = false;

  constructor(
    private readonly socket: dgram.Socket,
    private readonly options: UdpProxyOptions,
  ) {
    this.up = checkImpairment(options.up ?? CLEAN);
    this.down = checkImpairment(options.down ?? CLEAN);
    const seed = options.seed ?? 1;
    this.upDice = new Dice(seed);
    this.downDice = new Dice(seed ^ 0x9e3779b9);
    this.schedule = options.schedule ?? realSchedule;
    socket.on('message', (msg, rinfo) => {
      this.fromClient(msg, rinfo.address, rinfo.port);
    });
  }

  /** The proxy's port on 127.0.0.1 (what the peers use as the TURN server's port). */
  get port(): number {
    return this.socket.address().port;
  }

  /** Change the conditions (from now on). */
  setConditions(up: Impairment, down: Impairment = CLEAN): void {
    this.up = checkImpairment(up);
    this.down = checkImpairment(down);
  }

  /** Per client address: what went up and down, and what was dropped. */
  stats(): { client: string; up: DirectionStats; down: DirectionStats }[] {
    return [...this.clients.values()].map((c) => ({
      client: c.key,
      up: { ...c.up },
      down: { ...c.down },
    }));
  }

  /** @internal */
  fromClient(msg: Buffer, address: string, port: number): void {
    if (this.closed) return;
    const c = this.client(address, port);
    c.up.packets++;
    c.up.bytes += msg.length;
    if (this.upDice.lost(this.up)) {
      c.up.lost++;
      return;
    }
    this.schedule(() => {
      if (!this.closed) c.socket.send(msg, this.options.targetPort, '127.0.0.1');
    }, this.upDice.delay(this.up));
  }

  private client(address: string, port: number): Client {
    const key = `${address}:${port}`;
    let c = this.clients.get(key);
    if (c) return c;
    const socket = dgram.createSocket('udp4');
    socket.bind(0, '127.0.0.1');
    const client: Client = { key, address, port, socket, up: newStats(), down: newStats() };
    socket.on('message', (msg) => {
      this.fromTarget(client, msg);
    });
    socket.on('error', () => undefined);
    this.clients.set(key, client);
    c = client;
    return c;
  }

  private fromTarget(c: Client, msg: Buffer): void {
    if (this.closed) return;
    c.down.packets++;
    c.down.bytes += msg.length;
    if (this.downDice.lost(this.down)) {
      c.down.lost++;
      return;
    }
    this.schedule(() => {
      if (!this.closed) this.socket.send(msg, c.port, c.address);
    }, this.downDice.delay(this.down));
  }

  close(): Promise<void> {
    this.closed = true;
    for (const c of this.clients.values()) c.socket.close();
    return new Promise((resolve) => {
      this.socket.close(() => {
        resolve();
      });
    });
  }
}

/** Binds a {@link UdpProxy} to a free port on 127.0.0.1. */
export async function startUdpProxy(options: UdpProxyOptions): Promise<UdpProxy> {
  const socket = dgram.createSocket('udp4');
  await new Promise<void>((resolve, reject) => {
    socket.once('error', reject);
    socket.bind(0, '127.0.0.1', () => {
      socket.off('error', reject);
      resolve();
    });
  });
  return new UdpProxy(socket, options);
}
