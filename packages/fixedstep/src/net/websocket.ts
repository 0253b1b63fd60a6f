import type { WebSocketClassLike, WebSocketLike } from './platform.js';
import { BaseTransport, type Transport } from './transport.js';

/** Options of the WebSocket adapters. */
export interface WebSocketTransportOptions {
  /**
   * Close the connection when this many bytes are waiting to be sent (a peer that does not read).
   * Default 4 MiB.
   */
  maxBufferedBytes?: number;
}

const CONNECTING = 0;
const OPEN = 1;

/** Close reasons must fit a WebSocket close frame (123 bytes). */
function closeReason(reason: string): string {
  const bytes = new TextEncoder().encode(reason);
  return bytes.length <= 120 ? reason : reason.slice(0, 40);
}

/** Default {@link WebSocketTransportOptions.maxBufferedBytes}: 4 MiB. */
const DEFAULT_MAX_BUFFERED_BYTES = 4 << 20;

/** The part of a WebSocket, browser or Node, that sending and closing use. */
interface SocketLike {
  readonly readyState: number;
  readonly bufferedAmount: number;
  close(code?: number, reason?: string): void;
}

/**
 * What the browser and the Node adapter share: sends made while connecting are queued and go out
 * on open, a peer that does not read is cut off at the buffer cap, and the close reason fits a
 * close frame. Each adapter wires its socket's events and writes a frame its own way.
 */
abstract class WebSocketTransportCore<W extends SocketLike> extends BaseTransport {
  readonly reliable = true;
  private pending: Uint8Array[] = [];
  constructor(
    protected readonly ws: W,
    private readonly maxBuffered: number,
  ) {
    super();
  }
  /** The socket opened: what was sent while it connected goes now. */
  protected opened(): void {
    const queued = this.pending;
    this.pending = [];
    for (const b of queued) this.send(b);
  }
  /** Writes one binary frame on the open socket. */
  protected abstract write(bytes: Uint8Array): void;
  send(bytes: Uint8Array): void {
    if (!this.isOpen) return;
    if (this.ws.readyState === CONNECTING) {
      this.pending.push(bytes.slice());
      return;
    }
    if (this.ws.readyState !== OPEN) return;
    if (this.ws.bufferedAmount > this.maxBuffered) {
      this.close('send buffer overflow');
      return;
    }
    this.write(bytes);
  }
  protected doClose(reason: string): void {
    try {
      this.ws.close(1000, closeReason(reason));
    } catch {
      // already closing
    }
  }
}

class BrowserWebSocketTransport extends WebSocketTransportCore<WebSocketLike> {
  constructor(ws: WebSocketLike, maxBuffered: number) {
    super(ws, maxBuffered);
    ws.binaryType = 'arraybuffer';
    ws.addEventListener('open', () => {
      this.opened();
    });
    ws.addEventListener('message', (event) => {
      const data = event.data;
      if (data instanceof ArrayBuffer) this.deliver(new Uint8Array(data));
      else this.close('text message on a binary protocol');
    });
    ws.addEventListener('close', (event) => {
      this.closedRemotely(event.reason || `closed (${event.code})`);
    });
    ws.addEventListener('error', () => {
      this.closedRemotely('connection error');
    });
  }
  protected write(bytes: Uint8Array): void {
    this.ws.send(bytes);
  }
}

/**
 * A {@link Transport} over a browser `WebSocket` (binary frames; a text frame closes it). Sends
 * made while it is still connecting are queued and go out on open. Any object shaped as
 * {@link WebSocketLike} will do (the browser's, Node 22's global one, the `ws` package's).
 */
export function webSocketTransport(
  ws: WebSocketLike,
  options: WebSocketTransportOptions = {},
): Transport {
  return new BrowserWebSocketTransport(ws, options.maxBufferedBytes ?? DEFAULT_MAX_BUFFERED_BYTES);
}

/**
 * Opens a browser WebSocket to `url` and resolves with its transport once it is open (rejects on
 * error or after `timeoutMs`, default 10 s). `WebSocketClass` defaults to the global one.
 */
export function connectWebSocket(
  url: string,
  options: WebSocketTransportOptions & {
    timeoutMs?: number;
    WebSocketClass?: WebSocketClassLike;
  } = {},
): Promise<Transport> {
  const Ctor: WebSocketClassLike | undefined = options.WebSocketClass ?? globalThis.WebSocket;
  if (typeof Ctor !== 'function') {
    return Promise.reject(
      new TypeError('connectWebSocket: no WebSocket here (in Node 20 use nodeWebSocketTransport)'),
    );
  }
  return new Promise((resolve, reject) => {
    const ws = new Ctor(url);
    const transport = webSocketTransport(ws, options);
    const timer = setTimeout(() => {
      transport.close('connect timeout');
      reject(new Error(`connectWebSocket: ${url} did not open in time`));
    }, options.timeoutMs ?? 10_000);
    ws.addEventListener('open', () => {
      clearTimeout(timer);
      resolve(transport);
    });
    ws.addEventListener('error', () => {
      clearTimeout(timer);
      reject(new Error(`connectWebSocket: cannot connect to ${url}`));
    });
  });
}

/**
 * The part of a Node `ws` WebSocket (the `ws` package, v8) the adapter uses — typed structurally
 * so the library needs no dependency.
 */
export interface NodeWebSocketLike {
  readonly readyState: number;
  readonly bufferedAmount: number;
  send(data: Uint8Array, options: { binary: boolean }): void;
  close(code?: number, reason?: string): void;
  on(event: 'message', listener: (data: unknown, isBinary: boolean) => void): unknown;
  on(event: 'close', listener: (code: number, reason: Uint8Array) => void): unknown;
  on(event: 'error', listener: (error: Error) => void): unknown;
  on(event: 'open', listener: () => void): unknown;
}

function toBytes(data: unknown): Uint8Array | undefined {
  if (data instanceof Uint8Array) return data;
  if (data instanceof ArrayBuffer) return new Uint8Array(data);
  if (Array.isArray(data)) {
    let n = 0;
    for (const part of data) {
      if (!(part instanceof Uint8Array)) return undefined;
      n += part.length;
    }
    const out = new Uint8Array(n);
    let at = 0;
    for (const part of data as Uint8Array[]) {
      out.set(part, at);
      at += part.length;
    }
    return out;
  }
  return undefined;
}

class NodeWebSocketTransport extends WebSocketTransportCore<NodeWebSocketLike> {
  constructor(ws: NodeWebSocketLike, maxBuffered: number) {
    super(ws, maxBuffered);
    ws.on('open', () => {
      this.opened();
    });
    ws.on('message', (data, isBinary) => {
      const bytes = isBinary ? toBytes(data) : undefined;
      if (bytes) this.deliver(bytes);
      else this.close('text message on a binary protocol');
    });
    ws.on('close', (code, reason) => {
      const text = new TextDecoder().decode(reason);
      this.closedRemotely(text || `closed (${code})`);
    });
    ws.on('error', (error) => {
      this.closedRemotely(`connection error: ${error.message}`);
    });
  }
  protected write(bytes: Uint8Array): void {
    this.ws.send(bytes, { binary: true });
  }
}

/**
 * A {@link Transport} over a Node `ws` WebSocket (server side, or a Node client: Node 20 has no
 * global WebSocket). Binary frames only; a text frame closes the connection.
 */
export function nodeWebSocketTransport(
  ws: NodeWebSocketLike,
  options: WebSocketTransportOptions = {},
): Transport {
  return new NodeWebSocketTransport(ws, options.maxBufferedBytes ?? DEFAULT_MAX_BUFFERED_BYTES);
}
