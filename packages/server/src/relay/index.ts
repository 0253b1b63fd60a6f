/**
 * The multiplayer server: the relay core of `fixedstep` over the game registry, attached to the
 * lab's HTTP server at `/ws` (and `/ws/<room>`), and a Node WebSocket client.
 * @module
 */
export { gameCatalog, createRelay } from './catalog.js';
export { attachRelay, addressKey, relayEndpointOptionsFromEnv } from './endpoint.js';
export type {
  RelayEndpoint,
  RelayEndpointOptions,
  TrustedProxy,
  OriginPolicy,
} from './endpoint.js';
export { connectNodeWebSocket } from './client.js';
