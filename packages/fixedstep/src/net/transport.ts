import { Random } from '../det/random.js';
import type { EventScheduler } from './scheduler.js';

/**
 * A message pipe between a client and the server: whole binary messages, in both directions.
 *
 * Implementations: {@link memoryPair} (in one process), {@link SimulatedLink} (seeded latency,
 * jitter and loss on an {@link EventScheduler}), and the WebSocket adapters
 * ({@link webSocketTransport} for the browser's WebSocket, {@link nodeWebSocketTransport} for the
 * Node `ws` package). The protocol above survives loss, duplication and reordering; a WebSocket
 * has none of them, a simulated link has all three.
 */
export interface Transport {
  /** Send one message. Ignored once closed. The bytes may be reused by the caller afterwards. */
  send(bytes: Uint8Array): void;
  /** Set the one handler of incoming messages (messages that came before it are queued, up to 1024). */
  onMessage(handler: (bytes: Uint8Array) => void): void;
  /** Set the one handler called once when the pipe closes, from either end. */
  onClose(handler: (reason: string) => void): void;
  /** Close the pipe (idempotent). */
  close(reason?: string): void;
  /** Whether messages can still be sent. */
  readonly isOpen: boolean;
  /**
   * Whether every message sent arrives, in order, unless the pipe closes (a WebSocket, TCP). The
   * relay and the sessions then send each tick once instead of repeating unacknowledged ones; it
   * is read once, when the connection starts. Default: false (the protocol's redundancy on).
   */
  readonly reliable?: boolean;
}

const MAX_QUEUED = 1024;

/**
 * The handler bookkeeping every transport shares: a queue for messages that arrive before a
 * handler is set, one close notification, and nothing delivered after close.
 */
export abstract class BaseTransport implements Transport {
  private messageHandler: ((bytes: Uint8Array) => void) | undefined;
  private closeHandler: ((reason: string) => void) | undefined;
  private queue: Uint8Array[] = [];
  private closedReason: string | undefined;
  private closeReported = false;

  abstract send(bytes: Uint8Array): void;
  protected abstract doClose(reason: string): void;

  get isOpen(): boolean {
    return this.closedReason === undefined;
  }

  onMessage(handler: (bytes: Uint8Array) => void): void {
    this.messageHandler = handler;
    const queued = this.queue;
    this.queue = [];
    for (const m of queued) {
      if (this.closedReason !== undefined) break;
      handler(m);
    }
  }

  onClose(handler: (reason: string) => void): void {
    this.closeHandler = handler;
    if (this.closedReason !== undefined) this.reportClose();
  }

  close(reason = 'closed'): void {
    if (this.closedReason !== undefined) return;
    this.closedReason = reason;
    this.doClose(reason);
    this.reportClose();
  }

  /** For implementations: a message arrived. */
  protected deliver(bytes: Uint8Array): void {
    if (this.closedReason !== undefined) return;
    if (this.messageHandler) this.messageHandler(bytes);
    else if (this.queue.length < MAX_QUEUED) this.queue.push(bytes);
  }

  /** For implementations: the other end (or the network) closed the pipe. */
  protected closedRemotely(reason: string): void {
    if (this.closedReason !== undefined) return;
    this.closedReason = reason;
    this.reportClose();
  }

  private reportClose(): void {
    if (this.closeReported || !this.closeHandler) return;
    this.closeReported = true;
    this.closeHandler(this.closedReason ?? 'closed');
  }
}

class MemoryEnd extends BaseTransport {
  readonly reliable = true;
  peer: MemoryEnd | undefined;
  send(bytes: Uint8Array): void {
    if (!this.isOpen) return;
    const copy = bytes.slice();
    const peer = this.peer;
    queueMicrotask(() => peer?.receive(copy));
  }
  receive(bytes: Uint8Array): void {
    this.deliver(bytes);
  }
  remoteClose(reason: string): void {
    this.closedRemotely(reason);
  }
  protected doClose(reason: string): void {
    const peer = this.peer;
    queueMicrotask(() => peer?.remoteClose(reason));
  }
}

/**
 * Two connected in-process ends: what one sends the other receives, in order, on a later
 * microtask (never re-entrantly inside `send`). Closing one end closes the other.
 */
export function memoryPair(): [Transport, Transport] {
  const a = new MemoryEnd();
  const b = new MemoryEnd();
  a.peer = b;
  b.peer = a;
  return [a, b];
}

// ------------------------------------------------------------------------------ simulated link

/** Network conditions of one direction of a {@link SimulatedLink}. */
export interface LinkConditions {
  /** Mean one-way delay, in ms. Default 0. */
  latencyMs: number;
  /** Each message's delay is `latency ± jitter`, uniform (never below 0). Default 0. */
  jitterMs: number;
  /** Probability that a message is lost, from 0 to 1. Default 0. */
  loss: number;
}

export interface SimulatedLinkOptions extends Partial<LinkConditions> {
  /** The event queue deliveries go on (its clock is the link's time). */
  scheduler: EventScheduler;
  /** Seed of the delays and losses. Default 1. */
  seed?: number;
  /**
   * Deliver in send order (a stream, like TCP: a message waits for every earlier one). Default
   * false: messages may overtake each other, like UDP datagrams.
   */
  ordered?: boolean;
  /**
   * With `ordered`: a lost message is not lost but sent again a round trip later (`2 × latency`:
   * TCP's fast retransmit, once the messages behind it come back as duplicate acknowledgements),
   * doubled for each further loss of it — and everything behind it waits (head-of-line blocking):
   * loss as TCP makes a steadily sending game feel it, on simulated time. A sender with nothing
   * behind the loss would wait for the retransmission timeout instead (≥ 200 ms; the loss
   * harness's TCP proxy models that case). Default false.
   */
  retransmit?: boolean;
}

/** Counters of one direction of a {@link SimulatedLink}. */
export interface LinkStats {
  sent: number;
  lost: number;
  delivered: number;
  bytesSent: number;
}

class LinkEnd extends BaseTransport {
  constructor(
    private readonly link: SimulatedLink,
    private readonly side: 0 | 1,
  ) {
    super();
  }
  /** Ordered and lossless in this direction now: a stream. */
  get reliable(): boolean {
    return this.link.isReliable(this.side);
  }
  send(bytes: Uint8Array): void {
    if (this.isOpen) this.link.carry(this.side, bytes.slice());
  }
  receive(bytes: Uint8Array): void {
    this.deliver(bytes);
  }
  remoteClose(reason: string): void {
    this.closedRemotely(reason);
  }
  protected doClose(reason: string): void {
    this.link.closeFrom(this.side, reason);
  }
}

/**
 * A link with seeded latency, jitter and loss, on an {@link EventScheduler}: `a` and `b` are its
 * two ends (say, a client and the server). Each direction draws from its own seeded generator,
 * so a run is repeatable. A close is never lost; it arrives after the latency.
 */
export class SimulatedLink {
  readonly a: Transport;
  readonly b: Transport;
  /** `stats[0]`: a → b; `stats[1]`: b → a. */
  readonly stats: [LinkStats, LinkStats] = [
    { sent: 0, lost: 0, delivered: 0, bytesSent: 0 },
    { sent: 0, lost: 0, delivered: 0, bytesSent: 0 },
  ];
  private readonly ends: [LinkEnd, LinkEnd];
  private readonly rng: [Random, Random];
  private readonly conditions: [LinkConditions, LinkConditions];
  private readonly lastDelivery: [number, number] = [-Infinity, -Infinity];
  private readonly scheduler: EventScheduler;
  private readonly ordered: boolean;
  private readonly retransmit: boolean;

  constructor(options: SimulatedLinkOptions) {
    this.scheduler = options.scheduler;
    this.ordered = options.ordered ?? false;
    this.retransmit = options.retransmit ?? false;
    if (this.retransmit && !this.ordered) {
      throw new RangeError('SimulatedLink: retransmit needs ordered (a stream)');
    }
    const seed = options.seed ?? 1;
    this.rng = [new Random(seed), new Random((seed ^ 0x5bd1e995) >>> 0)];
    const c: LinkConditions = {
      latencyMs: options.latencyMs ?? 0,
      jitterMs: options.jitterMs ?? 0,
      loss: options.loss ?? 0,
    };
    checkConditions(c);
    this.conditions = [{ ...c }, { ...c }];
    this.ends = [new LinkEnd(this, 0), new LinkEnd(this, 1)];
    this.a = this.ends[0];
    this.b = this.ends[1];
  }

  /** Change the conditions, of both directions or of one (0: a → b, 1: b → a). */
  setConditions(c: Partial<LinkConditions>, direction?: 0 | 1): void {
    for (const d of direction === undefined ? ([0, 1] as const) : [direction]) {
      const next = { ...this.conditions[d], ...c };
      checkConditions(next);
      this.conditions[d] = next;
    }
  }

  /** @internal Whether the direction out of `side` is a stream: ordered, and lossless or retransmitting. */
  isReliable(side: 0 | 1): boolean {
    return this.ordered && (this.retransmit || this.conditions[side].loss === 0);
  }

  /** @internal */
  carry(from: 0 | 1, bytes: Uint8Array): void {
    const stats = this.stats[from];
    stats.sent++;
    stats.bytesSent += bytes.length;
    const c = this.conditions[from];
    const rng = this.rng[from];
    const lost = c.loss > 0 && rng.next() < c.loss;
    const jitter = c.jitterMs > 0 ? (rng.next() * 2 - 1) * c.jitterMs : 0;
    let resend = 0;
    if (lost) {
      stats.lost++;
      if (!this.retransmit) return;
      // Sent again a round trip later, doubled for each further loss of it.
      let rto = 2 * c.latencyMs;
      resend = rto;
      while (rng.next() < c.loss) {
        rto *= 2;
        resend += rto;
      }
    }
    let at = this.scheduler.now + resend + Math.max(0, c.latencyMs + jitter);
    if (this.ordered) at = Math.max(at, this.lastDelivery[from]);
    this.lastDelivery[from] = at;
    const to = this.ends[from === 0 ? 1 : 0];
    this.scheduler.at(at, () => {
      if (!to.isOpen) return;
      stats.delivered++;
      to.receive(bytes);
    });
  }

  /** @internal */
  closeFrom(from: 0 | 1, reason: string): void {
    const to = this.ends[from === 0 ? 1 : 0];
    const at = Math.max(
      this.scheduler.now + this.conditions[from].latencyMs,
      this.ordered ? this.lastDelivery[from] : -Infinity,
    );
    this.scheduler.at(at, () => {
      to.remoteClose(reason);
    });
  }
}

function checkConditions(c: LinkConditions): void {
  if (!(Number.isFinite(c.latencyMs) && c.latencyMs >= 0)) {
    throw new RangeError(`SimulatedLink: latencyMs must be >= 0, got ${String(c.latencyMs)}`);
  }
  if (!(Number.isFinite(c.jitterMs) && c.jitterMs >= 0)) {
    throw new RangeError(`SimulatedLink: jitterMs must be >= 0, got ${String(c.jitterMs)}`);
  }
  if (!(c.loss >= 0 && c.loss <= 1)) {
    throw new RangeError(`SimulatedLink: loss must be from 0 to 1, got ${String(c.loss)}`);
  }
}
