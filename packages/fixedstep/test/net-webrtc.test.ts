import { describe, expect, it } from 'vitest';
import {
  Random,
  SignalError,
  dataChannelTransport,
  decodeSignal,
  encodeSignal,
  type DataChannelLike,
  type DataChannelMessageLike,
  type SignalMessage,
} from 'fixedstep';

const MESSAGES: SignalMessage[] = [
  { type: 'host', room: 'room-1' },
  { type: 'join', room: 'a.b_C' },
  {
    type: 'joined',
    room: 'room-1',
    peer: 0,
    iceServers: [
      { urls: ['stun:127.0.0.1:3478'] },
      { urls: ['turn:127.0.0.1:3478?transport=udp'], username: 'u', credential: 'p' },
    ],
  },
  { type: 'joined', room: 'r', peer: 15, iceServers: [] },
  { type: 'peer', peer: 3 },
  { type: 'signal', peer: 1, kind: 'offer', text: 'v=0\r\no=- 1 2 IN IP4 127.0.0.1\r\n' },
  { type: 'signal', peer: 0, kind: 'candidate', text: '{"candidate":"candidate:1 1 udp …"}' },
  { type: 'signal', peer: 2, kind: 'end-of-candidates', text: '' },
  { type: 'signal', peer: 2, kind: 'fallback', text: '' },
  { type: 'data', peer: 7, bytes: Uint8Array.from([0, 1, 2, 250, 255]) },
  { type: 'leave', peer: 0 },
  { type: 'error', code: 'ROOM_FULL', message: 'all 15 peers are in' },
];

describe('signalling codec', () => {
  it('round-trips every message type, canonically', () => {
    for (const m of MESSAGES) {
      const bytes = encodeSignal(m);
      const back = decodeSignal(bytes);
      expect(back).toEqual(m);
      expect(encodeSignal(back)).toEqual(bytes);
    }
    // A version byte and a type byte, then the fields: `peer 3` is three bytes.
    expect([...encodeSignal({ type: 'peer', peer: 3 })]).toEqual([1, 4, 3]);
  });

  it('throws only SignalError on truncated, extended and mutated messages', () => {
    const rng = new Random(21);
    let refused = 0;
    const outcomes = new Set<string>();
    for (const m of MESSAGES) {
      const bytes = encodeSignal(m);
      for (let n = 0; n < bytes.length; n++) {
        expect(() => decodeSignal(bytes.subarray(0, n))).toThrow(SignalError);
        refused++;
      }
      const longer = new Uint8Array(bytes.length + 1);
      longer.set(bytes);
      expect(() => decodeSignal(longer)).toThrow(/trailing|bytes/);
      for (let k = 0; k < 200; k++) {
        const b = bytes.slice();
        b[rng.int(b.length)] = rng.int(256);
        // Whatever decodes is a valid message: it encodes again, to the same bytes. Anything else
        // is refused with a SignalError, never another exception.
        let outcome: string;
        try {
          const again = encodeSignal(decodeSignal(b));
          outcome =
            again.length === b.length && again.every((x, i) => x === b[i]) ? 'same' : 'other';
        } catch (error) {
          outcome = error instanceof SignalError ? 'refused' : String(error);
        }
        outcomes.add(outcome);
        if (outcome === 'refused') refused++;
      }
    }
    expect([...outcomes].sort()).toEqual(['refused', 'same']);
    expect(refused).toBeGreaterThan(300);
  });

  it('refuses bad values on both sides, naming them', () => {
    expect(() => encodeSignal({ type: 'host', room: 'no spaces' })).toThrow(
      /room name "no spaces" is not/,
    );
    expect(() => encodeSignal({ type: 'peer', peer: 16 })).toThrow(/peer 16 is not from 0 to 15/);
    expect(() =>
      encodeSignal({ type: 'signal', peer: 1, kind: 'offer', text: 'x'.repeat(16 * 1024 + 1) }),
    ).toThrow(/offer text over 16384 bytes/);
    expect(() =>
      encodeSignal({ type: 'data', peer: 1, bytes: new Uint8Array(10) }, { maxDataBytes: 8 }),
    ).toThrow(/tunnelled message of 10 bytes, at most 8/);
    expect(() => decodeSignal(Uint8Array.from([2, 4, 3]))).toThrow(/version 2, expected 1/);
    expect(() => decodeSignal(Uint8Array.from([1, 99]))).toThrow(/unknown message type 99/);
    // A room name the encoder would refuse, written by hand: refused with its offset.
    expect(() => decodeSignal(Uint8Array.from([1, 1, 2, 0x20, 0x21]))).toThrow(
      /room name is not .* \(at byte 2\)/,
    );
    // Long error messages are cut to fit, never refused.
    const long = encodeSignal({ type: 'error', code: 'UNEXPECTED', message: 'é'.repeat(300) });
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
