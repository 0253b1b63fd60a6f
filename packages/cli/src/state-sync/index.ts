/**
 * State-sync rooms on the lab's HTTP server: WebSocket connections at `/state/<room>`, rooms in a
 * pool of worker threads.
 * @module
 */
export { attachStateSync } from './attach.js';
export type { StateSyncEndpoint, StateSyncEndpointOptions } from './attach.js';
