/**
 * A TCP proxy on 127.0.0.1 that delays what it forwards and models loss the way TCP feels it — a
 * model of TCP, not TCP itself. Each chunk read from one side is a "segment": it is delivered
 * after `latency ± jitter`; a "lost" one (probability `loss`) is held for a retransmission timeout
 * (RTO; doubled for each further loss of the same segment, as TCP backs off), and because a stream
 * delivers in order, everything behind it waits too — head-of-line blocking. The real TCP on
 * loopback underneath never loses anything.
 *
 * The default RTO is `2 × latency + 200 ms`: Linux's `srtt + max(4 × rttvar, 200 ms)` with the
 * round trip of this link and its minimum of 200 ms. Real TCP sometimes does better (fast
 * retransmit after three duplicate acks needs traffic behind the loss; tail loss probes) and
 * sometimes worse (a lost retransmission, a collapsed congestion window); the model leaves those
 * out.
 */
import net from 'node:net';
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

export interface TcpProxyOptions {
  targetPort: number;
  /** Conditions of both directions. Default clean. */
  conditions?: Impairment;
  /** Retransmission timeout, ms. Default `2 × latency + 200`. */
  rtoMs?: number;
  seed?: number;
  schedule?: Schedule;
  /** The clock `schedule` runs on (ms). Default performance.now. */
  now?: () => number;
}

/** One direction of one connection: in-order delivery times. */
export class SegmentTimeline {
  private last = -Infinity;
  /** Retransmissions modelled. */
  retransmissions = 0;
  constructor(private readonly dice: Dice) {}

  /** When a segment sent at `now` is delivered, in order after every earlier one. */
  deliveryTime(now: number, c: Impairment, rtoMs: number): number {
    let extra = 0;
    let rto = rtoMs;
    while (this.dice.lost(c)) {
      this.retransmissions++;
      extra += rto;
      rto *= 2;
    }
    const at = Math.max(now + this.dice.delay(c) + extra, this.last);
    this.last = at;
    return at;
  }
}

export class TcpProxy {
  private conditions: Impairment;
  private rtoMs: number | undefined;
  private readonly sockets = new Set<net.Socket>();
  private readonly schedule: Schedule;
  private readonly now: () => number;
  private seed: number;
  private closed = false;
  /** Per connection: client → target (`up`) and back (`down`). */
  readonly connections: { up: DirectionStats; down: DirectionStats }[] = [];

  constructor(
    private readonly server: net.Server,
    private readonly options: TcpProxyOptions,
  ) {
    this.conditions = checkImpairment(options.conditions ?? CLEAN);
    this.rtoMs = options.rtoMs;
    this.schedule = options.schedule ?? realSchedule;
    this.now = options.now ?? (() => performance.now());
    this.seed = options.seed ?? 1;
    server.on('connection', (client) => {
      this.connect(client);
    });
  }

  get port(): number {
    return (this.server.address() as net.AddressInfo).port;
  }

  setConditions(c: Impairment, rtoMs?: number): void {
    this.conditions = checkImpairment(c);
    this.rtoMs = rtoMs;
  }

  /** The retransmission timeout in force, ms. */
  get rto(): number {
    return this.rtoMs ?? 2 * this.conditions.latencyMs + 200;
  }

  private connect(client: net.Socket): void {
    if (this.closed) {
      client.destroy();
      return;
    }
    const target = net.connect(this.options.targetPort, '127.0.0.1');
    client.setNoDelay(true);
    target.setNoDelay(true);
    this.sockets.add(client);
    this.sockets.add(target);
    const stats = { up: newStats(), down: newStats() };
    this.connections.push(stats);
    const n = this.connections.length;
    this.pipe(client, target, stats.up, new SegmentTimeline(new Dice(this.seed + 2 * n)));
    this.pipe(target, client, stats.down, new SegmentTimeline(new Dice(this.seed + 2 * n + 1)));
    const end = () => {
      client.destroy();
      target.destroy();
      this.sockets.delete(client);
      this.sockets.delete(target);
    };
    client.on('close', end);
    target.on('close', end);
    client.on('error', end);
    target.on('error', end);
  }

  private pipe(
    from: net.Socket,
    to: net.Socket,
    stats: DirectionStats,
    timeline: SegmentTimeline,
  ): void {
    // One queue per direction, drained in order by one timer: timers alone could swap two segments
    // whose delivery times are equal (head-of-line) but were rounded differently.
    const queue: { at: number; chunk: Buffer }[] = [];
    let head = 0;
    let armed = false;
    const drain = (): void => {
      armed = false;
      const now = this.now();
      while (head < queue.length && queue[head]!.at <= now + 0.5) {
        const { chunk } = queue[head++]!;
        if (!to.destroyed) to.write(chunk);
      }
      if (head === queue.length) {
        queue.length = 0;
        head = 0;
      } else arm(queue[head]!.at - now);
    };
    const arm = (ms: number): void => {
      if (armed) return;
      armed = true;
      this.schedule(drain, Math.max(0, ms));
    };
    from.on('data', (chunk: Buffer) => {
      stats.packets++;
      stats.bytes += chunk.length;
      const now = this.now();
      const before = timeline.retransmissions;
      const at = timeline.deliveryTime(now, this.conditions, this.rto);
      stats.lost += timeline.retransmissions - before;
      queue.push({ at, chunk });
      arm(queue[head]!.at - now);
    });
  }

  close(): Promise<void> {
    this.closed = true;
    for (const s of this.sockets) s.destroy();
    return new Promise((resolve) => {
      this.server.close(() => {
        resolve();
      });
    });
  }
}

export async function startTcpProxy(options: TcpProxyOptions): Promise<TcpProxy> {
  const server = net.createServer();
  await new Promise<void>((resolve, reject) => {
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      server.off('error', reject);
      resolve();
    });
  });
  return new TcpProxy(server, options);
}
