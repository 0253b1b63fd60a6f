/**
 * State-sync rooms on the server's HTTP port: WebSocket connections at `/state/<room>`, rooms in a
 * pool of worker threads.
 * @module
 */
export {
  attachStateSync,
  StateSyncEndpoint,
  STATE_SYNC_HEARTBEAT_MS,
  STATE_SYNC_UPDATE_MS,
} from './endpoint.js';
export type { StateSyncEndpointOptions } from './endpoint.js';
