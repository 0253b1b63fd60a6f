import WebSocket from 'ws';
import { nodeWebSocketTransport, type Transport } from 'fixedstep';

/**
 * Opens a WebSocket from Node (20 has no global WebSocket) to a relay, e.g.
 * `ws://127.0.0.1:8080/ws`, and resolves with its transport once open.
 */
export function connectNodeWebSocket(url: string, timeoutMs = 10_000): Promise<Transport> {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url, { perMessageDeflate: false });
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
