export { SignallingHub } from './hub.js';
export type { SignallingHubOptions, SignallingStats } from './hub.js';
export { attachSignalling } from './endpoint.js';
export type { SignallingEndpointOptions, SignallingEndpoint } from './endpoint.js';
