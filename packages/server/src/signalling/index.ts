/**
 * WebRTC signalling on the server: the `fixedstep` hub on `/signal/<room>`.
 * @module
 */
export {
  attachSignalling,
  iceServersFromEnv,
  SignallingEndpoint,
  SIGNALLING_UPDATE_MS,
} from './endpoint.js';
export type { SignallingEndpointOptions } from './endpoint.js';
