/**
 * The parts of the WebRTC API the library uses, typed structurally: the browser's
 * `RTCPeerConnection` fits, and so does a Node implementation such as `werift` (pure TypeScript,
 * from the npm registry). The library never imports one: the constructor is injected, so it keeps
 * no runtime dependency and its declarations need no DOM library.
 */
import type { IceServerConfig } from './signal-messages.js';

/** A session description (offer or answer). */
export interface SessionDescriptionLike {
  type: 'offer' | 'answer' | 'pranswer' | 'rollback';
  sdp?: string;
}

/** An ICE candidate as `toJSON()` gives it and `addIceCandidate` takes it. */
export interface IceCandidateLike {
  candidate?: string;
  sdpMid?: string | null;
  sdpMLineIndex?: number | null;
}

/** The message event of a data channel: `data` is an ArrayBuffer (browser), a Buffer or a string. */
export interface DataChannelMessageLike {
  data: unknown;
}

/** The part of an `RTCDataChannel` the transport uses. */
export interface DataChannelLike {
  readonly label: string;
  readonly readyState: string;
  readonly bufferedAmount: number;
  binaryType?: string;
  /**
   * Sends bytes. Typed `never` so that every implementation's own parameter type fits (the
   * browser's `ArrayBufferView<ArrayBuffer>`, werift's `Buffer`); the library passes a Uint8Array,
   * which all of them take.
   */
  send(data: never): void;
  close(): void;
  // Handlers take `never` for the same reason as `send`: each implementation types its events its
  // own way; the library's handlers read only what the `…Like` event types below say.
  onopen?: ((event: never) => unknown) | null;
  onclose?: ((event: never) => unknown) | null;
  onmessage?: ((event: never) => unknown) | null;
}

/** Options of `createDataChannel`. */
export interface DataChannelInitLike {
  ordered?: boolean;
  maxRetransmits?: number;
  /**
   * Both peers create the channel themselves, with the same `id`, instead of one announcing it to
   * the other (DCEP). Each side's own `ordered` and `maxRetransmits` then govern what it sends.
   */
  negotiated?: boolean;
  /** The SCTP stream of a negotiated channel (0–65534), the same on both sides. */
  id?: number;
}

/** The part of an `RTCPeerConnection` the library uses. */
export interface PeerConnectionLike {
  readonly connectionState: string;
  createDataChannel(label: string, init?: DataChannelInitLike): DataChannelLike;
  createOffer(): Promise<SessionDescriptionLike>;
  createAnswer(): Promise<SessionDescriptionLike>;
  setLocalDescription(description: SessionDescriptionLike): Promise<unknown>;
  setRemoteDescription(description: SessionDescriptionLike): Promise<unknown>;
  readonly localDescription: SessionDescriptionLike | null | undefined;
  addIceCandidate(candidate: IceCandidateLike): Promise<unknown>;
  close(): unknown;
  onicecandidate?: ((event: never) => unknown) | null;
  ondatachannel?: ((event: never) => unknown) | null;
  onconnectionstatechange?: ((event: never) => unknown) | null;
}

/** What an `icecandidate` event carries, as far as the library reads it. */
export interface IceCandidateEventLike {
  candidate?: { toJSON?(): IceCandidateLike } | IceCandidateLike | null;
}

/** What a `datachannel` event carries. */
export interface DataChannelEventLike {
  channel: DataChannelLike;
}

/** What `new RTCPeerConnection(config)` takes, as far as the library sets it. */
export interface PeerConnectionConfigLike {
  iceServers: IceServerConfig[];
  iceTransportPolicy?: 'all' | 'relay';
}

/**
 * An `RTCPeerConnection` constructor: `globalThis.RTCPeerConnection` in a browser, `werift`'s in
 * Node (`import { RTCPeerConnection } from 'werift'`).
 */
export type PeerConnectionConstructor = new (
  config: PeerConnectionConfigLike,
) => PeerConnectionLike;
