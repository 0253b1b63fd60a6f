/**
 * The multiplayer server: the relay core of `fixedstep` over the game registry, attached to the
 * lab's HTTP server at `/ws`, and a Node WebSocket client.
 * @module
 */
export { gameCatalog, createRelay } from './catalog.js';
export { attachRelay } from './server.js';
export type { RelayEndpoint, RelayEndpointOptions } from './server.js';
export { connectNodeWebSocket } from './client.js';
