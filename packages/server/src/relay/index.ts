/**
 * The relay of `fixedstep` over the game registry, attached to the HTTP server at `/ws/<room>`, and
 * a Node WebSocket client.
 * @module
 */
export {
  attachRelay,
  createRelay,
  registryCatalog,
  RelayEndpoint,
  RELAY_UPDATE_MS,
} from './endpoint.js';
export type { RelayEndpointOptions } from './endpoint.js';
export { connectNodeWebSocket } from './client.js';
export type { NodeWebSocketOptions } from './client.js';
