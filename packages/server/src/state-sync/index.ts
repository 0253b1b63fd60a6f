/**
 * State-sync rooms on the lab's HTTP server: WebSocket connections at `/state/<room>`, rooms in a
 * pool of worker threads.
 * @module
 */
export { attachStateSync } from './endpoint.js';
export type { StateSyncEndpoint, StateSyncEndpointOptions } from './endpoint.js';
