import { BaseTransport, type Transport } from '../transport.js';
import type { DataChannelLike, DataChannelMessageLike } from './types.js';

/** Options of {@link dataChannelTransport}. */
export interface DataChannelTransportOptions {
  /**
   * Messages up to this many bytes go on the unreliable channel (one datagram: a lost one is lost,
   * the protocol above resends what matters). Larger ones — a welcome with a snapshot — go on the
   * reliable channel, in chunks. Default 1100 (one UDP datagram on any path, with the DTLS, SCTP
   * and TURN headers).
   */
  maxUnreliableBytes?: number;
  /** Largest message accepted, in bytes; a larger one closes the transport. Default 1 MiB + 1 KiB. */
  maxMessageBytes?: number;
  /** Close when this many bytes wait to be sent on a channel (a peer that does not read). Default 4 MiB. */
  maxBufferedBytes?: number;
  /** Called once when the transport closes (e.g. to close the peer connection). */
  onClose?: (reason: string) => void;
}

/** Bytes of one chunk on the reliable channel (below every implementation's message limit). */
const CHUNK_BYTES = 16 * 1024;
const LAST = 0;
const MORE = 1;

/** The message bytes of a data channel event: an ArrayBuffer (browser), a Buffer/Uint8Array (Node). */
function toBytes(data: unknown): Uint8Array | undefined {
  if (data instanceof Uint8Array) return data;
  if (data instanceof ArrayBuffer) return new Uint8Array(data);
  if (ArrayBuffer.isView(data))
    return new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  return undefined;
}

class DataChannelTransport extends BaseTransport {
  private readonly maxUnreliable: number;
  private readonly maxMessage: number;
  private readonly maxBuffered: number;
  private parts: Uint8Array[] = [];
  private partBytes = 0;
  private readonly onClosed: ((reason: string) => void) | undefined;

  constructor(
    private readonly unreliable: DataChannelLike,
    private readonly reliableChannel: DataChannelLike | undefined,
    options: DataChannelTransportOptions,
  ) {
    super();
    this.maxUnreliable = options.maxUnreliableBytes ?? 1100;
    this.maxMessage = options.maxMessageBytes ?? (1 << 20) + 1024;
    this.maxBuffered = options.maxBufferedBytes ?? 4 << 20;
    this.onClosed = options.onClose;
    if (!(Number.isInteger(this.maxUnreliable) && this.maxUnreliable >= 1)) {
      throw new RangeError(
        `maxUnreliableBytes must be a positive integer, got ${this.maxUnreliable}`,
      );
    }
    for (const ch of reliableChannel ? [unreliable, reliableChannel] : [unreliable]) {
      ch.binaryType = 'arraybuffer';
      ch.onclose = () => {
        this.closedRemotely(`data channel ${ch.label} closed`);
        this.onClosed?.('closed by the peer');
      };
    }
    unreliable.onmessage = (event: DataChannelMessageLike) => {
      const bytes = toBytes(event.data);
      if (bytes === undefined) this.close('text message on a binary protocol');
      else if (bytes.length > this.maxMessage) this.close(`message of ${bytes.length} bytes`);
      else this.deliver(bytes);
    };
    if (reliableChannel) {
      reliableChannel.onmessage = (event: DataChannelMessageLike) => {
        const bytes = toBytes(event.data);
        if (bytes === undefined || bytes.length < 1) {
          this.close('bad chunk on the reliable channel');
          return;
        }
        this.onChunk(bytes);
      };
    }
  }

  /** Reliable, ordered chunks: `[0 last | 1 more][payload]`, reassembled up to the limit. */
  private onChunk(bytes: Uint8Array): void {
    const flag = bytes[0]!;
    const payload = bytes.subarray(1);
    if (flag !== LAST && flag !== MORE) {
      this.close(`bad chunk flag ${flag}`);
      return;
    }
    this.partBytes += payload.length;
    if (this.partBytes > this.maxMessage) {
      this.close(`message of more than ${this.maxMessage} bytes`);
      return;
    }
    this.parts.push(payload.slice());
    if (flag === MORE) return;
    const out = new Uint8Array(this.partBytes);
    let at = 0;
    for (const p of this.parts) {
      out.set(p, at);
      at += p.length;
    }
    this.parts = [];
    this.partBytes = 0;
    this.deliver(out);
  }

  send(bytes: Uint8Array): void {
    if (!this.isOpen) return;
    const big = bytes.length > this.maxUnreliable && this.reliableChannel !== undefined;
    const ch = big ? this.reliableChannel : this.unreliable;
    if (ch.readyState !== 'open') return;
    if (ch.bufferedAmount > this.maxBuffered) {
      this.close('send buffer overflow');
      return;
    }
    try {
      if (!big) {
        ch.send(bytes as never);
        return;
      }
      for (let at = 0; at < bytes.length; at += CHUNK_BYTES) {
        const end = Math.min(bytes.length, at + CHUNK_BYTES);
        const chunk = new Uint8Array(end - at + 1);
        chunk[0] = end === bytes.length ? LAST : MORE;
        chunk.set(bytes.subarray(at, end), 1);
        ch.send(chunk as never);
      }
    } catch (error) {
      this.close(`send failed: ${String(error)}`);
    }
  }

  protected doClose(reason: string): void {
    for (const ch of this.reliableChannel
      ? [this.unreliable, this.reliableChannel]
      : [this.unreliable]) {
      ch.onmessage = null;
      ch.onclose = null;
      try {
        ch.close();
      } catch {
        // already closing
      }
    }
    this.onClosed?.(reason);
  }
}

/**
 * A {@link Transport} over WebRTC data channels: `unreliable` (create it with
 * `{ ordered: false, maxRetransmits: 0 }`: a datagram, lost or late, never holding up the next)
 * for every message up to `maxUnreliableBytes`, and optionally `reliable` (ordered, retransmitted)
 * for larger ones, sent in chunks of 16 KiB — a late joiner's snapshot. The relay protocol survives
 * loss, duplication and reordering, so mixing the two is safe. Both channels must be open; a
 * closed channel closes the transport. Sends while a channel is not open are dropped (the protocol
 * repeats what matters).
 */
export function dataChannelTransport(
  unreliable: DataChannelLike,
  reliable?: DataChannelLike,
  options: DataChannelTransportOptions = {},
): Transport {
  return new DataChannelTransport(unreliable, reliable, options);
}
