/**
 * The signalling protocol: how a room's host and the peers joining it find each other through the
 * server (`/signal/<room>` on `fixedstep serve`) — offer, answer and ICE candidates — and, when a
 * direct connection cannot be made, the tunnel that carries their game messages through the server
 * instead. Declared once (`net/wire`), family 0x40; docs/webrtc.md has the table.
 *
 * Version 2 declares the messages as data, shares the error list with the other protocols, and
 * lets a peer join only with the room's invite token, which the host gets in its `joined`.
 * @module
 */
import {
  ERROR_FIELDS,
  PING_FIELDS,
  PONG_FIELDS,
  TOKEN_BYTES,
  tokenField,
  type ErrorMessage,
  type PingMessage,
  type PongMessage,
} from '../wire/common.js';
import { bytes, list, name, oneOf, optional, struct, text, uint } from '../wire/fields.js';
import { defineProtocol } from '../wire/protocol.js';

/** The signalling protocol's version (byte 0 of every message is 0x40 | this). */
export const SIGNAL_VERSION = 2;

/** Peers a signalling room holds besides its host (peer ids 1 … this). */
export const MAX_SIGNAL_PEERS = 15;

/** Limits of the decoder (and of what the encoder accepts). */
export interface SignalLimits {
  /** Longest SDP or candidate text, in UTF-8 bytes. Default 16 KiB. */
  maxTextBytes: number;
  /** Longest tunnelled message, in bytes. Default 1 MiB + 1 KiB (a relay message with a snapshot). */
  maxDataBytes: number;
  /** ICE servers in a `joined` message. Default 8. */
  maxIceServers: number;
  /** URLs per ICE server. Default 8. */
  maxUrls: number;
}

/** The default {@link SignalLimits}. */
export const DEFAULT_SIGNAL_LIMITS: Readonly<SignalLimits> = Object.freeze({
  maxTextBytes: 16 * 1024,
  maxDataBytes: (1 << 20) + 1024,
  maxIceServers: 8,
  maxUrls: 8,
});

/**
 * A STUN or TURN server, as `RTCPeerConnection`'s `iceServers` takes it: `urls` like
 * `stun:stun.example.org:3478` or `turn:127.0.0.1:3478?transport=udp`, and for TURN the
 * credentials.
 */
export interface IceServerConfig {
  urls: string[];
  username?: string;
  credential?: string;
}

/** What a `signal` message carries. */
export type SignalKind = 'offer' | 'answer' | 'candidate' | 'end-of-candidates' | 'fallback';
const KINDS = ['offer', 'answer', 'candidate', 'end-of-candidates', 'fallback'] as const;

/**
 * The messages. C→S: `host` (I host this room), `join` (I join it, with its invite). S→C: `joined`
 * (you are in: your peer id — 0 for the host —, the room's invite for the host to hand out, and the
 * ICE servers to use), `peer` (to the host: a peer joined), `leave` (a peer, or the host — peer 0 —
 * went away), `error`. Both ways: `signal` (offer, answer, candidate … for / from `peer`; the server
 * stamps the sender) and `data` (a tunnelled game message for / from `peer`); `ping` and `pong`
 * keep a quiet connection alive.
 */
export type SignalMessage =
  | { type: 'host'; room: string }
  | { type: 'join'; room: string; invite: Uint8Array }
  | {
      type: 'joined';
      room: string;
      peer: number;
      invite: Uint8Array;
      iceServers: IceServerConfig[];
    }
  | { type: 'peer'; peer: number }
  | { type: 'signal'; peer: number; kind: SignalKind; text: string }
  | { type: 'data'; peer: number; bytes: Uint8Array }
  | { type: 'leave'; peer: number }
  | ErrorMessage
  | PingMessage
  | PongMessage;

const peer = () => uint({ max: MAX_SIGNAL_PEERS });

/** The signalling protocol: encode, decode, sizes (see `net/wire`). */
export const SIGNAL_PROTOCOL = defineProtocol<SignalMessage, SignalLimits>({
  name: 'signalling',
  family: 0x40,
  version: SIGNAL_VERSION,
  limits: DEFAULT_SIGNAL_LIMITS,
  messages: {
    host: { code: 0x01, from: 'client', fields: { room: name() } },
    join: {
      code: 0x02,
      from: 'client',
      fields: { room: name(), invite: bytes({ max: TOKEN_BYTES, sizes: [TOKEN_BYTES] }) },
    },
    joined: {
      code: 0x03,
      from: 'server',
      fields: {
        room: name(),
        peer: peer(),
        invite: tokenField(),
        iceServers: list(
          struct<IceServerConfig>({
            urls: list(text({ max: 512 }), { min: 1, max: 'maxUrls' }),
            username: optional(text({ max: 512 })),
            credential: optional(text({ max: 512 })),
          }),
          { max: 'maxIceServers' },
        ),
      },
    },
    peer: { code: 0x04, from: 'server', fields: { peer: peer() } },
    signal: {
      code: 0x05,
      from: 'both',
      // An SDP has line breaks.
      fields: {
        peer: peer(),
        kind: oneOf(KINDS),
        text: text({ max: 'maxTextBytes', controls: true }),
      },
    },
    data: {
      code: 0x06,
      from: 'both',
      fields: { peer: peer(), bytes: bytes({ max: 'maxDataBytes' }) },
    },
    leave: { code: 0x07, from: 'server', fields: { peer: peer() } },
    error: { code: 0x08, from: 'server', fields: ERROR_FIELDS },
    // Liveness: the server pings a quiet member (a host waiting for its joiners), which answers.
    ping: { code: 0x09, from: 'both', fields: PING_FIELDS },
    pong: { code: 0x0a, from: 'both', fields: PONG_FIELDS },
  },
});

/**
 * Encodes a signalling message (canonical: decoding and re-encoding gives the same bytes). Throws a
 * RangeError naming the field for a value the decoder would refuse (a bad room name, a text over
 * the limit …), so nothing undecodable is ever sent.
 */
export function encodeSignal(m: SignalMessage): Uint8Array {
  return SIGNAL_PROTOCOL.encode(m);
}

/** Decodes one signalling message; throws only a `ProtocolError` naming the field, whatever the bytes. */
export function decodeSignal(
  bytes: Uint8Array,
  limits: Readonly<SignalLimits> = DEFAULT_SIGNAL_LIMITS,
): SignalMessage {
  return SIGNAL_PROTOCOL.decode(bytes, { limits });
}
