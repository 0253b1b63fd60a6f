/**
 * WebRTC signalling on the server: the `fixedstep` hub on `/signal/<room>`.
 * @module
 */
export { attachSignalling, SignallingEndpoint, SIGNALLING_UPDATE_MS } from './endpoint.js';
export type { SignallingEndpointOptions } from './endpoint.js';
