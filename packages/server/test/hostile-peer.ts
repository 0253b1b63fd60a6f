/**
 * A raw client of the hostile suite (`hostile.test.ts`): one WebSocket from a loopback address of
 * its own (Linux takes any source in 127.0.0.0/8, so each address is a client of its own to the
 * server's per-address caps), speaking one surface's protocol by hand so it can misbehave.
 * @module
 */
import WebSocket from 'ws';
import type { ErrorMessage, WireProtocol } from 'fixedstep';

/** What every protocol's messages have. */
export interface AnyMessage {
  type: string;
}

/** How a peer's socket ended: its close code and reason (`HTTP <status>` for a refused upgrade). */
export interface Closed {
  code: number;
  reason: string;
}

let nextHost = 0;
/**
 * A fresh client address, 127.0.<b>.<c> from 127.0.1.1 on (127.0.0.x is left to tests that name
 * their addresses).
 */
export function freshAddress(): string {
  const n = nextHost++;
  return `127.0.${1 + Math.floor(n / 250)}.${1 + (n % 250)}`;
}

/** How long a wait on a peer's state may take before the test fails, ms. */
export const WAIT_MS = 10_000;

/**
 * One raw client. `status` is 101 once its WebSocket opened, or the HTTP status its upgrade was
 * refused with; `got` holds every message it received, decoded; `closed` how it ended.
 */
export class Peer<M extends AnyMessage = AnyMessage> {
  readonly got: M[] = [];
  status = 0;
  closed: Closed | undefined;
  private readonly wakers = new Set<() => void>();
  private readonly handlers: ((m: M) => void)[] = [];
  private readonly timers = new Set<ReturnType<typeof setInterval>>();

  private constructor(
    readonly ws: WebSocket,
    readonly protocol: WireProtocol<M, object>,
    readonly address: string,
  ) {}

  /** Opens a client of `url` from `address`; resolves once it is open or refused. */
  static open<M extends AnyMessage>(
    url: string,
    protocol: WireProtocol<M, object>,
    address: string,
    headers: Record<string, string> = {},
  ): Promise<Peer<M>> {
    const ws = new WebSocket(url, { localAddress: address, headers });
    const p = new Peer<M>(ws, protocol, address);
    ws.on('message', (data: Buffer, isBinary: boolean) => {
      if (isBinary) {
        // A frame may hold several messages (a relay's batch frame).
        for (const b of protocol.split(new Uint8Array(data))) {
          const m = protocol.decode(b, { from: 'server' });
          p.got.push(m);
          for (const h of p.handlers) h(m);
        }
      }
      p.wake();
    });
    return new Promise((resolve) => {
      ws.on('open', () => {
        p.status = 101;
        resolve(p);
      });
      ws.on('error', (error) => {
        if (p.status !== 0) return;
        // `ws` names a refused upgrade's status: "Unexpected server response: 429".
        p.status = Number(/response: (\d+)/.exec(error.message)?.[1] ?? -1);
        p.closed = { code: 0, reason: `HTTP ${p.status}` };
        resolve(p);
      });
      ws.on('close', (code, reason) => {
        p.closed ??= { code, reason: reason.toString() };
        for (const t of p.timers) clearInterval(t);
        p.timers.clear();
        p.wake();
      });
    });
  }

  /** Whether its WebSocket is open. */
  get open(): boolean {
    return this.ws.readyState === WebSocket.OPEN;
  }

  /**
   * Sends `m` in the surface's protocol (nothing once closed). Any message of the protocol will do:
   * write it `satisfies` its protocol's type (`{ … } satisfies NetMessage`) to have it checked.
   */
  send(m: M | (AnyMessage & Record<string, unknown>)): void {
    if (this.open) this.ws.send(this.protocol.encode(m as M));
  }

  /** Sends bytes (a binary frame) or a string (a text frame) as they are. */
  raw(data: Uint8Array | string): void {
    if (this.open) this.ws.send(data);
  }

  /** The first message of `type` it got. */
  first(type: M['type']): M | undefined {
    return this.got.find((m) => m.type === type);
  }

  /** The last message of `type` it got. */
  last(type: M['type']): M | undefined {
    for (let i = this.got.length - 1; i >= 0; i--) {
      if (this.got[i]!.type === type) return this.got[i];
    }
    return undefined;
  }

  /** The fatal error the server closed it with, if any. */
  get error(): ErrorMessage | undefined {
    return this.got.find((m) => m.type === 'error' && (m as unknown as ErrorMessage).fatal) as
      ErrorMessage | undefined;
  }

  /**
   * How it ended up: the first of `wanted` message types it got, else the code of the fatal error
   * it was closed with, `HTTP <status>` for a refused upgrade, or `closed <code>`. Waits until one
   * is known.
   */
  outcome(wanted: readonly M['type'][], timeoutMs = WAIT_MS): Promise<string> {
    return this.until(
      `one of ${wanted.join(', ')}`,
      () => {
        const hit = this.got.find((m) => wanted.includes(m.type));
        if (hit) return hit.type;
        if (this.error) return this.error.code;
        if (this.closed)
          return this.status === 101 ? `closed ${this.closed.code}` : `HTTP ${this.status}`;
        return undefined;
      },
      timeoutMs,
    );
  }

  /** Resolves once the socket is closed (with how), failing the test after `timeoutMs`. */
  ended(timeoutMs = WAIT_MS): Promise<Closed> {
    return this.until('its close', () => this.closed, timeoutMs);
  }

  /**
   * Resolves with `test()`'s value as soon as it is neither undefined nor false — checked now and
   * after every message and the close; rejects after `timeoutMs`, naming `what` and the messages.
   */
  until<T>(what: string, test: () => T | undefined | false, timeoutMs = WAIT_MS): Promise<T> {
    return new Promise<T>((resolve, reject) => {
      const check = (): boolean => {
        const v = test();
        if (v === undefined || v === false) return false;
        this.wakers.delete(waker);
        clearTimeout(timer);
        resolve(v);
        return true;
      };
      const waker = () => {
        check();
      };
      const timer = setTimeout(() => {
        this.wakers.delete(waker);
        const types = this.got.map((m) => m.type).slice(-12);
        reject(
          new Error(
            `${this.address}: no ${what} within ${timeoutMs} ms (last messages: ${types.join(', ')}; ` +
              `${this.closed ? `closed ${this.closed.code} ${this.closed.reason}` : 'open'})`,
          ),
        );
      }, timeoutMs);
      this.wakers.add(waker);
      check();
    });
  }

  /** Runs `fn` every `ms` until the socket closes (a keep-alive, a player's inputs). */
  every(ms: number, fn: () => void): void {
    if (this.closed) return;
    this.timers.add(setInterval(fn, ms));
  }

  /** Answers the server's liveness probes (pings), as every client library does. */
  answerPings(): void {
    this.onMessage((m) => {
      if (m.type !== 'ping') return;
      const ping = m as unknown as { id: number; time: number };
      this.send({ type: 'pong', id: ping.id, time: ping.time, serverTime: 0 });
    });
  }

  /** Calls `handler` with every message from now on. */
  onMessage(handler: (m: M) => void): void {
    this.handlers.push(handler);
  }

  /** Closes the socket (a close frame). */
  close(): void {
    this.ws.close();
  }

  /** Drops the connection without a close frame: a pulled cable, as the server sees it. */
  cut(): void {
    this.ws.terminate();
  }

  private wake(): void {
    for (const w of [...this.wakers]) w();
  }
}
