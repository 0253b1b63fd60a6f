export { SignallingHub } from './hub.js';
export type { SignallingHubOptions, SignallingStats } from './hub.js';
export { attachSignalling } from './server.js';
export type { SignallingEndpointOptions, SignallingEndpoint } from './server.js';
