/**
 * The signalling protocol: how a room's host and the peers joining it find each other through the
 * server (`/signal` on `fixedstep serve`) — offer, answer and ICE candidates — and, when a direct
 * connection cannot be made, the tunnel that carries their game messages through the server
 * instead. Its own small binary codec, separate from the relay protocol (docs/webrtc.md).
 *
 * Every message is `[version u8 = 1][type u8][fields]`: varints are canonical unsigned LEB128 of a
 * u32, strings a varint byte length then UTF-8, byte fields a varint length then the bytes.
 * Decoding checks every length against the bytes left and the limits before allocating, and throws
 * only {@link SignalError}.
 */
import { ByteReader, ByteWriter, type ByteReadProblem } from '../../det/bytes.js';

/** Version byte of every signalling message. */
export const SIGNAL_VERSION = 1;

/** Room names: 1–32 of `A–Z a–z 0–9 _ - .` (the relay's rule). */
export const SIGNAL_ROOM_PATTERN = /^[A-Za-z0-9_.-]{1,32}$/;

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
const KINDS: readonly SignalKind[] = [
  'offer',
  'answer',
  'candidate',
  'end-of-candidates',
  'fallback',
];

/** Error codes the server sends. */
export type SignalErrorCode =
  | 'BAD_MESSAGE'
  | 'ROOM_TAKEN'
  | 'NO_ROOM'
  | 'ROOM_FULL'
  | 'NO_PEER'
  | 'RATE_LIMIT'
  | 'TOO_LARGE'
  | 'SERVER_FULL'
  | 'TIMEOUT'
  | 'UNEXPECTED';
const ERROR_CODES: readonly SignalErrorCode[] = [
  'BAD_MESSAGE',
  'ROOM_TAKEN',
  'NO_ROOM',
  'ROOM_FULL',
  'NO_PEER',
  'RATE_LIMIT',
  'TOO_LARGE',
  'SERVER_FULL',
  'TIMEOUT',
  'UNEXPECTED',
];

/**
 * The messages. C→S: `host` (I host this room), `join` (I join it). S→C: `joined` (you are in: your
 * peer id — 0 for the host — and the ICE servers to use), `peer` (to the host: a peer joined),
 * `leave` (a peer, or the host — peer 0 — went away), `error`. Both ways: `signal` (offer, answer,
 * candidate … for / from `peer`; the server stamps the sender) and `data` (a tunnelled game
 * message for / from `peer`).
 */
export type SignalMessage =
  | { type: 'host'; room: string }
  | { type: 'join'; room: string }
  | { type: 'joined'; room: string; peer: number; iceServers: IceServerConfig[] }
  | { type: 'peer'; peer: number }
  | { type: 'signal'; peer: number; kind: SignalKind; text: string }
  | { type: 'data'; peer: number; bytes: Uint8Array }
  | { type: 'leave'; peer: number }
  | { type: 'error'; code: SignalErrorCode; message: string };

const TYPES = ['host', 'join', 'joined', 'peer', 'signal', 'data', 'leave', 'error'] as const;
const MAX_ERROR_BYTES = 200;
const MAX_URL_BYTES = 512;
const MAX_CREDENTIAL_BYTES = 512;

/** Why a signalling message was refused. */
export class SignalError extends Error {
  constructor(
    readonly problem: ByteReadProblem | 'bad-version' | 'bad-type' | 'bad-value',
    message: string,
    readonly offset = -1,
  ) {
    super(offset >= 0 ? `signalling: ${message} (at byte ${offset})` : `signalling: ${message}`);
    this.name = 'SignalError';
  }
}

function checkRoom(room: string): void {
  if (!SIGNAL_ROOM_PATTERN.test(room)) {
    throw new SignalError(
      'bad-value',
      `room name ${JSON.stringify(room)} is not 1–32 of A–Z a–z 0–9 _ - .`,
    );
  }
}

function checkPeer(peer: number): void {
  if (!(Number.isInteger(peer) && peer >= 0 && peer <= MAX_SIGNAL_PEERS)) {
    throw new SignalError('bad-value', `peer ${peer} is not from 0 to ${MAX_SIGNAL_PEERS}`);
  }
}

const encoder = new TextEncoder();
function utf8Length(s: string): number {
  return encoder.encode(s).length;
}

/**
 * Encodes a signalling message (canonical: decoding and re-encoding gives the same bytes). Throws
 * a {@link SignalError} for a value the decoder would refuse (a bad room name, a text over the
 * limit …), so nothing undecodable is ever sent.
 */
export function encodeSignal(m: SignalMessage, limits: Partial<SignalLimits> = {}): Uint8Array {
  const l = { ...DEFAULT_SIGNAL_LIMITS, ...limits };
  const w = new ByteWriter(64);
  w.u8(SIGNAL_VERSION).u8(TYPES.indexOf(m.type) + 1);
  switch (m.type) {
    case 'host':
    case 'join':
      checkRoom(m.room);
      w.str(m.room);
      break;
    case 'joined': {
      checkRoom(m.room);
      checkPeer(m.peer);
      if (m.iceServers.length > l.maxIceServers) {
        throw new SignalError(
          'bad-value',
          `${m.iceServers.length} ICE servers, at most ${l.maxIceServers}`,
        );
      }
      w.str(m.room).varint(m.peer).varint(m.iceServers.length);
      for (const s of m.iceServers) {
        if (s.urls.length < 1 || s.urls.length > l.maxUrls) {
          throw new SignalError(
            'bad-value',
            `an ICE server needs 1 to ${l.maxUrls} urls, got ${s.urls.length}`,
          );
        }
        w.varint(s.urls.length);
        for (const u of s.urls) {
          if (utf8Length(u) > MAX_URL_BYTES)
            throw new SignalError('bad-value', `ICE server url over ${MAX_URL_BYTES} bytes`);
          w.str(u);
        }
        const user = s.username ?? '';
        const cred = s.credential ?? '';
        if (utf8Length(user) > MAX_CREDENTIAL_BYTES || utf8Length(cred) > MAX_CREDENTIAL_BYTES) {
          throw new SignalError(
            'bad-value',
            `ICE server credentials over ${MAX_CREDENTIAL_BYTES} bytes`,
          );
        }
        w.str(user).str(cred);
      }
      break;
    }
    case 'peer':
    case 'leave':
      checkPeer(m.peer);
      w.varint(m.peer);
      break;
    case 'signal':
      checkPeer(m.peer);
      if (utf8Length(m.text) > l.maxTextBytes) {
        throw new SignalError('too-large', `${m.kind} text over ${l.maxTextBytes} bytes`);
      }
      w.varint(m.peer)
        .u8(KINDS.indexOf(m.kind) + 1)
        .str(m.text);
      break;
    case 'data':
      checkPeer(m.peer);
      if (m.bytes.length > l.maxDataBytes) {
        throw new SignalError(
          'too-large',
          `tunnelled message of ${m.bytes.length} bytes, at most ${l.maxDataBytes}`,
        );
      }
      w.varint(m.peer).varint(m.bytes.length).bytes(m.bytes);
      break;
    case 'error': {
      const code = ERROR_CODES.indexOf(m.code);
      if (code < 0) throw new SignalError('bad-value', `unknown error code ${m.code}`);
      let text = m.message;
      while (utf8Length(text) > MAX_ERROR_BYTES) text = text.slice(0, -1);
      w.u8(code + 1).str(text);
      break;
    }
  }
  return w.finish();
}

/**
 * Decodes one signalling message. Throws only a {@link SignalError} (naming the field and the byte
 * offset), whatever the bytes.
 */
export function decodeSignal(bytes: Uint8Array, limits: Partial<SignalLimits> = {}): SignalMessage {
  const l = { ...DEFAULT_SIGNAL_LIMITS, ...limits };
  if (bytes.length > l.maxDataBytes + 32) {
    throw new SignalError('too-large', `message of ${bytes.length} bytes`);
  }
  const r = new ByteReader(bytes, {
    fail: (problem, message, offset) => {
      throw new SignalError(problem, message, offset);
    },
  });
  const version = r.u8('version');
  if (version !== SIGNAL_VERSION)
    throw new SignalError('bad-version', `version ${version}, expected ${SIGNAL_VERSION}`, 0);
  const typeByte = r.u8('type');
  const type = TYPES[typeByte - 1];
  if (type === undefined) throw new SignalError('bad-type', `unknown message type ${typeByte}`, 1);
  const room = (): string => {
    const at = r.pos;
    const s = r.str('room', 32);
    if (!SIGNAL_ROOM_PATTERN.test(s))
      throw new SignalError('bad-value', 'room name is not 1–32 of A–Z a–z 0–9 _ - .', at);
    return s;
  };
  const peer = (): number => r.count('peer', MAX_SIGNAL_PEERS);
  let m: SignalMessage;
  switch (type) {
    case 'host':
    case 'join':
      m = { type, room: room() };
      break;
    case 'joined': {
      const name = room();
      const p = peer();
      const n = r.count('ICE servers', l.maxIceServers);
      const iceServers: IceServerConfig[] = [];
      for (let i = 0; i < n; i++) {
        const urls: string[] = [];
        const u = r.count('urls', l.maxUrls, 1);
        for (let k = 0; k < u; k++) urls.push(r.str('url', MAX_URL_BYTES));
        const username = r.str('username', MAX_CREDENTIAL_BYTES);
        const credential = r.str('credential', MAX_CREDENTIAL_BYTES);
        const server: IceServerConfig = { urls };
        if (username !== '') server.username = username;
        if (credential !== '') server.credential = credential;
        iceServers.push(server);
      }
      m = { type, room: name, peer: p, iceServers };
      break;
    }
    case 'peer':
    case 'leave':
      m = { type, peer: peer() };
      break;
    case 'signal': {
      const p = peer();
      const at = r.pos;
      const k = KINDS[r.u8('kind') - 1];
      if (k === undefined) throw new SignalError('bad-value', 'unknown signal kind', at);
      m = { type, peer: p, kind: k, text: r.str('text', l.maxTextBytes) };
      break;
    }
    case 'data':
      m = { type, peer: peer(), bytes: r.field('data', l.maxDataBytes) };
      break;
    case 'error': {
      const at = r.pos;
      const code = ERROR_CODES[r.u8('code') - 1];
      if (code === undefined) throw new SignalError('bad-value', 'unknown error code', at);
      m = { type, code, message: r.str('message', MAX_ERROR_BYTES) };
      break;
    }
  }
  r.end();
  return m;
}
