import WebSocket from 'ws';
import { nodeWebSocketTransport, type Transport } from 'fixedstep';

/** Options of {@link connectNodeWebSocket}. */
export interface NodeWebSocketOptions {
  /** Give up (and reject) when not open within this, ms. Default 10 000. */
  timeoutMs?: number;
  /** The local address to connect from (tests and benchmarks: `127.0.0.x` is a client of its own). */
  localAddress?: string;
  /** Extra request headers, e.g. an `Origin`. */
  headers?: Record<string, string>;
}

/**
 * Opens a WebSocket from Node (20 has no global WebSocket) to a server's surface, e.g.
 * `ws://127.0.0.1:8080/ws/<room>`, and resolves with its transport once open.
 */
export function connectNodeWebSocket(
  url: string,
  options: NodeWebSocketOptions = {},
): Promise<Transport> {
  const timeoutMs = options.timeoutMs ?? 10_000;
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url, {
      perMessageDeflate: false,
      ...(options.localAddress !== undefined ? { localAddress: options.localAddress } : {}),
      ...(options.headers !== undefined ? { headers: options.headers } : {}),
    });
    const timer = setTimeout(() => {
      ws.terminate();
      reject(new Error(`${url} did not open in time`));
    }, timeoutMs);
    ws.once('open', () => {
      clearTimeout(timer);
      resolve(nodeWebSocketTransport(ws));
    });
    ws.once('error', (error) => {
      clearTimeout(timer);
      reject(error);
    });
  });
}
