import { describe, expect, it } from 'vitest';
import {
  DEFAULT_SIGNAL_LIMITS,
  SIGNAL_PROTOCOL,
  dataChannelTransport,
  decodeSignal,
  encodeSignal,
  type DataChannelLike,
  type DataChannelMessageLike,
  type PeerConnectionConstructor,
} from 'fixedstep';

describe('signalling messages', () => {
  // Their round trip and fuzz follow from the declaration (net-wire.test.ts); here, its own rules.
  it('are compact: a version byte and a type byte, then the fields', () => {
    expect([...encodeSignal({ type: 'peer', peer: 3 })]).toEqual([SIGNAL_PROTOCOL.header, 4, 3]);
  });

  it('refuses bad values on both sides, naming them', () => {
    expect(() => encodeSignal({ type: 'host', room: 'no spaces' })).toThrow(
      /cannot encode host\.room: "no spaces" is not 1–32 of/,
    );
    expect(() => encodeSignal({ type: 'peer', peer: 16 })).toThrow(/peer: 16 is not from 0 to 15/);
    expect(() =>
      encodeSignal({ type: 'signal', peer: 1, kind: 'offer', text: 'x'.repeat(16 * 1024 + 1) }),
    ).toThrow(/signal\.text: 16385 bytes, at most 16384/);
    const data = encodeSignal({ type: 'data', peer: 1, bytes: new Uint8Array(10) });
    expect(() => decodeSignal(data, { ...DEFAULT_SIGNAL_LIMITS, maxDataBytes: 8 })).toThrow(
      /TOO_LARGE: signalling data: 14 bytes; a data message is at most 12/,
    );
    // A joiner comes with the room's invite: without one it is not a join.
    expect(() => encodeSignal({ type: 'join', room: 'r', invite: new Uint8Array(0) })).toThrow(
      /join\.invite: 0 bytes, not 16/,
    );
    expect(() => decodeSignal(Uint8Array.from([0x41, 4, 3]))).toThrow(
      /signalling protocol version 1, this side speaks 2/,
    );
    expect(() => decodeSignal(Uint8Array.from([SIGNAL_PROTOCOL.header, 99]))).toThrow(
      /unknown message type 0x63/,
    );
    // A room name the encoder would refuse, written by hand: refused with its offset.
    expect(() => decodeSignal(Uint8Array.from([SIGNAL_PROTOCOL.header, 1, 2, 0x20, 0x21]))).toThrow(
      /signalling host\.room: must be 1–32 of .* \(at byte 2\)/,
    );
    // Long error messages are cut to fit, never refused.
    const long = encodeSignal({
      type: 'error',
      code: 'UNEXPECTED',
      fatal: false,
      message: 'é'.repeat(300),
    });
    const back = decodeSignal(long);
    expect(back.type === 'error' && new TextEncoder().encode(back.message).length).toBe(200);
  });
});

/** One end of a fake data channel pair: what one end sends, the other receives. */
class FakeChannel implements DataChannelLike {
  readyState = 'open';
  bufferedAmount = 0;
  binaryType: string | undefined;
  onopen: (() => void) | null = null;
  onclose: (() => void) | null = null;
  onmessage: ((event: DataChannelMessageLike) => unknown) | null | undefined = null;
  other: FakeChannel | undefined;
  readonly sent: Uint8Array[] = [];
  constructor(readonly label: string) {}
  send(data: Uint8Array): void {
    this.sent.push(data.slice());
    const copy = data.slice();
    // Delivered as a browser does: an ArrayBuffer.
    this.other?.onmessage?.({ data: copy.buffer });
  }
  /** Closes both ends; each gets its `close` event, as in a browser. */
  close(): void {
    if (this.readyState === 'closed') return;
    this.readyState = 'closed';
    this.onclose?.();
    const o = this.other;
    if (o && o.readyState !== 'closed') {
      o.readyState = 'closed';
      o.onclose?.();
    }
  }
}

function channelPair(label: string): [FakeChannel, FakeChannel] {
  const a = new FakeChannel(label);
  const b = new FakeChannel(label);
  a.other = b;
  b.other = a;
  return [a, b];
}

function transports(options = {}) {
  const [ua, ub] = channelPair('u');
  const [ra, rb] = channelPair('r');
  const a = dataChannelTransport(ua, ra, options);
  const b = dataChannelTransport(ub, rb, options);
  const got: Uint8Array[] = [];
  b.onMessage((m) => got.push(m));
  const closed: string[] = [];
  a.onClose((r) => closed.push(r));
  return { a, b, ua, ra, ub, got, closed };
}

describe('data channel transport', () => {
  it('takes the browser’s RTCPeerConnection as the DOM types it, without a cast', () => {
    // Held by the type checker (npm run typecheck has the DOM library): this assignment compiles.
    // Node 20 has no WebRTC of its own; werift's constructor is passed as it is in p2p.test.ts.
    const browser: PeerConnectionConstructor | undefined = (
      globalThis as { RTCPeerConnection?: typeof RTCPeerConnection }
    ).RTCPeerConnection;
    expect(browser).toBeUndefined();
  });

  it('small messages go on the unreliable channel, large ones in chunks on the reliable one', () => {
    const { a, ua, ra, got } = transports();
    const small = Uint8Array.from({ length: 1100 }, (_v, i) => i & 255);
    const large = Uint8Array.from({ length: 40_000 }, (_v, i) => (i * 7) & 255);
    a.send(small);
    a.send(large);
    expect(ua.sent.map((s) => s.length)).toEqual([1100]);
    // 16 KiB chunks, each with a flag byte: 1 = more, 0 = last.
    expect(ra.sent.map((s) => [s[0], s.length])).toEqual([
      [1, 16385],
      [1, 16385],
      [0, 40_000 - 2 * 16384 + 1],
    ]);
    expect(got).toEqual([small, large]);
  });

  it('closes on a text message, a bad chunk, an oversized message, a full send buffer', () => {
    {
      const { b, ub } = transports();
      ub.onmessage?.({ data: 'hello' });
      expect(b.isOpen).toBe(false);
    }
    {
      const t = transports();
      const reasons: string[] = [];
      t.b.onClose((r) => reasons.push(r));
      t.ra.send(Uint8Array.from([7, 1, 2]));
      expect(reasons).toEqual(['bad chunk flag 7']);
    }
    {
      const t = transports({ maxMessageBytes: 20_000 });
      const reasons: string[] = [];
      t.b.onClose((r) => reasons.push(r));
      t.a.send(new Uint8Array(30_000));
      expect(reasons).toEqual(['message of more than 20000 bytes']);
      expect(t.got).toHaveLength(0);
    }
    {
      const t = transports({ maxBufferedBytes: 1000 });
      t.ua.bufferedAmount = 1001;
      t.a.send(new Uint8Array(10));
      expect(t.closed).toEqual(['send buffer overflow']);
      expect(t.ua.sent).toHaveLength(0);
    }
  });

  it('a channel closed by the peer closes the transport', () => {
    const { a, b, ub } = transports();
    ub.close();
    expect(a.isOpen).toBe(false);
    expect(b.isOpen).toBe(false);
  });

  it('refuses a bad option, naming it', () => {
    const [u] = channelPair('u');
    expect(() => dataChannelTransport(u, undefined, { maxUnreliableBytes: 0 })).toThrow(
      /maxUnreliableBytes must be a positive integer, got 0/,
    );
  });
});
