/**
 * WebRTC: a {@link Transport} over data channels (unreliable for the game, reliable for large
 * messages), peer-to-peer rooms whose creator runs the relay, and the signalling protocol that
 * introduces peers through the server. The `RTCPeerConnection` constructor is injected (the
 * browser's, or `werift`'s in Node). See docs/webrtc.md.
 * @module
 */
export { dataChannelTransport } from './data-channel.js';
export { SignallingHub, SIGNAL_WAITING_TTL_MS } from './hub.js';
export type { SignallingHubOptions, SignallingStats } from './hub.js';
export type { DataChannelTransportOptions } from './data-channel.js';
export {
  SignalClient,
  PeerHost,
  joinPeer,
  UNRELIABLE_LABEL,
  RELIABLE_LABEL,
  UNRELIABLE_STREAM,
  RELIABLE_STREAM,
} from './peer.js';
export type {
  PeerToPeerOptions,
  PeerLink,
  PeerHostOptions,
  PeerHostEvent,
  PeerHosting,
} from './peer.js';
export {
  SIGNAL_VERSION,
  SIGNAL_PROTOCOL,
  MAX_SIGNAL_PEERS,
  DEFAULT_SIGNAL_LIMITS,
  encodeSignal,
  decodeSignal,
} from './signal-messages.js';
export type {
  SignalLimits,
  IceServerConfig,
  SignalKind,
  SignalMessage,
} from './signal-messages.js';
export type {
  SessionDescriptionLike,
  IceCandidateLike,
  DataChannelMessageLike,
  DataChannelLike,
  DataChannelEventLike,
  DataChannelInitLike,
  IceCandidateEventLike,
  PeerConnectionLike,
  PeerConnectionConfigLike,
  PeerConnectionConstructor,
} from './types.js';
