/**
 * The relay protocol's own rules (version 4): what is refused and how compact it is. The generic
 * round trip and fuzz of every message type follow from its declaration (net-wire.test.ts).
 */
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_PROTOCOL_LIMITS,
  PROTOCOL_VERSION,
  ProtocolError,
  RELAY_PROTOCOL,
  decodeMessage,
  encodeMessage,
  type NetMessage,
} from 'fixedstep';

const V = PROTOCOL_VERSION;
const T = (type: NetMessage['type']) => RELAY_PROTOCOL.code(type);

/** decode must return a message or throw a ProtocolError — never anything else. */
function decodeOrProtocolError(b: Uint8Array): NetMessage | ProtocolError {
  try {
    return decodeMessage(b);
  } catch (error) {
    if (error instanceof ProtocolError) return error;
    throw error;
  }
}

describe('the relay protocol', () => {
  it('names what is wrong, with a code and an offset', () => {
    const err = (b: number[]) => decodeOrProtocolError(Uint8Array.from(b)) as ProtocolError;
    expect(err([]).code).toBe('TRUNCATED');
    // Older clients are refused, saying so: protocol 1 (no input schema), 2 (the redundant
    // confirmed stream), 3 (the hand-written codecs).
    for (const old of [1, 2, 3]) {
      expect(err([old, 1]).code).toBe('BAD_VERSION');
      expect(err([old, 1]).message).toContain(
        `relay protocol version ${old}, this side speaks ${V}`,
      );
    }
    expect(err([V + 1, 1]).message).toMatch(/this side is older/);
    expect(err([V, 0x7f]).code).toBe('BAD_TYPE');
    expect(err([V, 0x7f]).offset).toBe(1);
    // A varint with a redundant zero byte is not canonical.
    const nonCanonical = err([V, T('ack'), 0x80, 0x00, 0]);
    expect(nonCanonical.code).toBe('BAD_VALUE');
    expect(nonCanonical.message).toContain('relay ack.room');
    // Room names are 1-32 of A-Z a-z 0-9 _ - .
    const hello = encodeMessage({
      type: 'hello',
      room: 'r',
      role: 'player',
      game: 'ctf',
      gameVersion: 1,
      input: '0123456789abcdef',
      players: 2,
      name: '',
    });
    hello[3] = 0x20; // the room name's one byte becomes a space
    expect(err([...hello]).code).toBe('BAD_VALUE');
    expect(err([...hello]).field).toBe('room');
  });

  it('checks sizes before allocating', () => {
    // A snapshot claiming 2^32 - 1 bytes in a 12-byte message: refused, nothing allocated.
    const huge = Uint8Array.of(V, T('snapshot'), 1, 1, 1, 0xff, 0xff, 0xff, 0xff, 0x0f);
    const e1 = decodeOrProtocolError(huge) as ProtocolError;
    expect(e1.code).toBe('TOO_LARGE');
    // A confirmed message claiming 64 ticks × 16 players × 16 words (shape 255 = 0xff 0x01) with
    // no bytes behind it.
    const e2 = decodeOrProtocolError(
      Uint8Array.of(V, T('confirmed'), 0, 0xff, 0x01, 128, 1),
    ) as ProtocolError;
    expect(e2.code).toBe('TRUNCATED');
    // 17 players (shape 256) is over the limit whatever follows.
    const e2b = decodeOrProtocolError(
      Uint8Array.of(V, T('confirmed'), 0, 0x80, 0x02, 2, 0),
    ) as ProtocolError;
    expect(e2b.code).toBe('TOO_LARGE');
    // 65 ticks is over the limit whatever follows; so are 17 words a tick.
    const e3 = decodeOrProtocolError(
      Uint8Array.of(V, T('input'), 1, 0, 0, 0, 1, 65),
    ) as ProtocolError;
    expect(e3.code).toBe('TOO_LARGE');
    const e4 = decodeOrProtocolError(
      Uint8Array.of(V, T('input'), 1, 0, 0, 0, 17, 1),
    ) as ProtocolError;
    expect(e4.code).toBe('TOO_LARGE');
    // The whole message is checked against the largest its type can be, first.
    const big = new Uint8Array(RELAY_PROTOCOL.maxBytes('snapshot') + 1);
    big.set([V, T('snapshot')]);
    expect((decodeOrProtocolError(big) as ProtocolError).code).toBe('TOO_LARGE');
    const bigAck = new Uint8Array(RELAY_PROTOCOL.maxBytes('ack') + 1);
    bigAck.set([V, T('ack')]);
    expect((decodeOrProtocolError(bigAck) as ProtocolError).code).toBe('TOO_LARGE');
    // Custom, tighter limits.
    const snap = encodeMessage({
      type: 'snapshot',
      room: 1,
      id: 1,
      tick: 1,
      bytes: new Uint8Array(100),
    });
    expect(() => decodeMessage(snap, { ...DEFAULT_PROTOCOL_LIMITS, maxSnapshotBytes: 99 })).toThrow(
      ProtocolError,
    );
  });

  it('is compact: an input a tick is a few bytes, confirmed ticks of held buttons one byte a player', () => {
    const one = encodeMessage({
      type: 'input',
      room: 1,
      player: 0,
      ack: 1000,
      tick: 1012,
      words: 1,
      inputs: Uint32Array.of(0x00010001),
    });
    expect(one.length).toBe(11);
    // 16 ticks × 4 players, everyone holding a button: a byte per player-tick after the first.
    const held = new Uint32Array(16 * 4).fill(0x0001);
    const confirmed = encodeMessage({
      type: 'confirmed',
      inputAck: 5016,
      tick: 5000,
      players: 4,
      words: 1,
      inputs: held,
      delta: false,
    });
    // header, type, tick (2), players and words, count, the inputs, input ack offset.
    expect(confirmed.length).toBe(2 + 2 + 1 + 1 + 64 + 1);
    // One tick of 4 players holding their buttons, XOR-coded against the tick before (held: 0),
    // at tick 100 000 (28 min at 60 Hz): 11 bytes, 13 with a WebSocket frame header.
    const oneTick = encodeMessage({
      type: 'confirmed',
      inputAck: 100_006,
      tick: 100_000,
      players: 4,
      words: 1,
      inputs: new Uint32Array(4),
      delta: true,
    });
    expect(oneTick.length).toBe(2 + 3 + 1 + 1 + 1 + 4);
    expect(decodeMessage(oneTick)).toMatchObject({ inputAck: 100_006, delta: true, players: 4 });
    // A schema with an axis: the axis word is XOR-delta coded too, a byte a tick while it holds.
    const aimed = new Uint32Array(16 * 2);
    for (let t = 0; t < 16; t++) aimed.set([0x0001, 700], t * 2);
    const withAxis = encodeMessage({
      type: 'input',
      room: 1,
      player: 0,
      ack: 0,
      tick: 0,
      words: 2,
      inputs: aimed,
    });
    expect(withAxis.length).toBe(2 + 1 + 1 + 1 + 1 + 1 + 1 + (1 + 2) + 15 * 2);
    const h = encodeMessage({ type: 'hash', room: 1, tick: 600, hash: 0xffffffffffffffffn });
    expect(h.length).toBe(2 + 1 + 2 + 8);
  });

  it('refuses to encode what breaks the rules', () => {
    expect(() =>
      encodeMessage({
        type: 'input',
        room: 1,
        player: 0,
        ack: 0,
        tick: 0,
        words: 1,
        inputs: new Uint32Array(65),
      }),
    ).toThrow(RangeError);
    expect(() =>
      encodeMessage({
        type: 'hello',
        room: 'no spaces',
        role: 'player',
        game: 'ctf',
        gameVersion: 1,
        input: '0123456789abcdef',
        players: 1,
        name: '',
      }),
    ).toThrow(RangeError);
    expect(() =>
      encodeMessage({
        type: 'confirmed',
        inputAck: 9,
        tick: 9,
        players: 1,
        words: 1,
        inputs: new Uint32Array(1),
        delta: false,
      }),
    ).toThrow(/confirmed\.inputAck: 9 is before 10/);
    expect(() => encodeMessage({ type: 'ping', id: -1, time: 0 })).toThrow(RangeError);
    expect(() => encodeMessage({ type: 'ping', id: 1, time: Number.NaN })).toThrow(RangeError);
  });

  it('gives every message its own bytes, also after a refused encode', () => {
    // encodeMessage writes through one reused buffer: what it returns must be a copy, and an
    // encode that throws half-way must not leak into the next message.
    const ping = encodeMessage({ type: 'ping', id: 7, time: 1.5 });
    const pingCopy = ping.slice();
    expect(() => encodeMessage({ type: 'ping', id: 8, time: Number.NaN })).toThrow(RangeError);
    const ack = encodeMessage({ type: 'ack', room: 3, ack: 300 });
    expect(ping).toEqual(pingCopy);
    expect(decodeMessage(ping)).toEqual({ type: 'ping', id: 7, time: 1.5 });
    expect(decodeMessage(ack)).toEqual({ type: 'ack', room: 3, ack: 300 });
    expect(ack.length).toBe(2 + 1 + 2);
  });
});
