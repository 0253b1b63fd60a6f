import fc from 'fast-check';
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_PROTOCOL_LIMITS,
  MessageType,
  PROTOCOL_VERSION,
  ProtocolError,
  decodeMessage,
  encodeMessage,
  peekMessageType,
  type NetErrorCode,
  type NetMessage,
} from 'fixedstep';

const u32 = fc.integer({ min: 0, max: 0xffffffff });
const small = fc.integer({ min: 0, max: 100_000 });
const name = fc.stringMatching(/^[A-Za-z0-9_.-]{1,32}$/);
// Times are written canonically (-0 as +0, like every float of fixedstep), so -0 is not generated.
const time = fc
  .double({ min: -1e12, max: 1e12, noNaN: true, noDefaultInfinity: true })
  .map((t) => (t === 0 ? 0 : t));
const hash = fc.bigInt({ min: 0n, max: (1n << 64n) - 1n });
const bytes = (max: number) => fc.uint8Array({ maxLength: max });
const token = fc.uint8Array({ minLength: 16, maxLength: 16 });
/** Up to 10 characters without control characters (at most 30 UTF-8 bytes). */
const printable = fc.string({
  maxLength: 10,
  unit: fc
    .oneof(fc.integer({ min: 0x20, max: 0x7e }), fc.integer({ min: 0xa0, max: 0x2fff }))
    .map((c) => String.fromCodePoint(c)),
});

/** Every message type, with fields across their ranges. */
const message: fc.Arbitrary<NetMessage> = fc.oneof(
  fc
    .record({
      room: name,
      role: fc.constantFrom('player' as const, 'spectator' as const),
      game: name,
      gameVersion: u32,
      input: fc
        .bigInt({ min: 0n, max: 2n ** 64n - 1n })
        .map((b) => b.toString(16).padStart(16, '0')),
      players: fc.integer({ min: 0, max: 16 }),
      seed: fc.option(u32, { nil: undefined }),
      token: fc.option(token, { nil: undefined }),
      name: printable,
    })
    .map((m): NetMessage => {
      const out: NetMessage = { type: 'hello', ...m };
      if (m.seed === undefined) delete out.seed;
      if (m.token === undefined) delete out.token;
      return out;
    }),
  fc
    .record({
      room: u32,
      peer: small,
      players: fc.integer({ min: 1, max: 16 }),
      seed: u32,
      tickRate: fc.integer({ min: 1, max: 240 }),
      hashEvery: fc.integer({ min: 1, max: 600 }),
      deadlineMs: small,
      inputFrom: u32,
      startTick: u32,
      config: bytes(256),
      token: fc.oneof(token, fc.constant(new Uint8Array(0))),
      invite: fc.oneof(token, fc.constant(new Uint8Array(0))),
      startAt: fc.option(time, { nil: undefined }),
      snapshot: fc.option(bytes(2000), { nil: undefined }),
      slotSeed: fc.nat(),
    })
    .map(({ slotSeed, ...m }): NetMessage => {
      const out: NetMessage = { type: 'welcome', ...m, slot: (slotSeed % (m.players + 1)) - 1 };
      if (m.startAt === undefined) delete out.startAt;
      if (m.snapshot === undefined) delete out.snapshot;
      return out;
    }),
  fc.record({ room: u32, startAt: time }).map((m): NetMessage => ({ type: 'start', ...m })),
  fc
    .record({
      room: u32,
      player: fc.integer({ min: 0, max: 15 }),
      ack: u32,
      tick: fc.integer({ min: 0, max: 1e9 }),
      words: fc.integer({ min: 1, max: 4 }),
      inputs: fc.array(u32, { minLength: 4, maxLength: 256 }),
    })
    .map((m): NetMessage => {
      const ticks = Math.max(1, Math.min(64, Math.floor(m.inputs.length / m.words)));
      return { type: 'input', ...m, inputs: Uint32Array.from(m.inputs.slice(0, ticks * m.words)) };
    }),
  fc
    .record({
      ahead: fc.integer({ min: 0, max: 1e6 }),
      tick: fc.integer({ min: 0, max: 1e9 }),
      players: fc.integer({ min: 1, max: 16 }),
      words: fc.integer({ min: 1, max: 16 }),
      ticks: fc.integer({ min: 0, max: 64 }),
      delta: fc.boolean(),
      seed: fc.array(u32, { minLength: 4 * 16 * 8, maxLength: 4 * 16 * 8 }),
    })
    .map(({ ticks, seed, ahead, ...m }): NetMessage => {
      const n = Math.min(ticks, Math.floor(seed.length / (m.players * m.words)));
      return {
        type: 'confirmed',
        ...m,
        inputAck: m.tick + n + ahead,
        inputs: Uint32Array.from(seed.slice(0, n * m.players * m.words)),
      };
    }),
  fc.record({ room: u32, ack: u32 }).map((m): NetMessage => ({ type: 'ack', ...m })),
  fc.record({ room: u32, tick: u32, hash }).map((m): NetMessage => ({ type: 'hash', ...m })),
  fc
    .record({
      room: u32,
      tick: u32,
      exact: fc.boolean(),
      reportTick: u32,
      groups: fc.array(fc.record({ hash, peers: fc.array(small, { maxLength: 8 }) }), {
        minLength: 1,
        maxLength: 8,
      }),
      maj: fc.nat(),
    })
    .map(({ maj, ...m }): NetMessage => ({
      type: 'desync',
      ...m,
      majority: (maj % (m.groups.length + 1)) - 1,
    })),
  fc.record({ id: u32, time }).map((m): NetMessage => ({ type: 'ping', ...m })),
  fc.record({ id: u32, time, serverTime: time }).map((m): NetMessage => ({ type: 'pong', ...m })),
  fc
    .record({
      room: u32,
      peer: small,
      reason: fc.constantFrom<('left' | 'closed' | 'dropped' | 'timeout' | 'replaced')[]>(
        'left',
        'closed',
        'dropped',
        'timeout',
        'replaced',
      ),
    })
    .map((m): NetMessage => ({ type: 'leave', ...m })),
  fc
    .record({
      code: fc.constantFrom<NetErrorCode[]>(
        'BAD_MESSAGE',
        'RATE_LIMIT',
        'SPOOFED_PLAYER',
        'TICK_WINDOW',
      ),
      message: printable,
      fatal: fc.boolean(),
    })
    .map((m): NetMessage => ({ type: 'error', ...m })),
  fc
    .record({ room: u32, id: u32, tick: fc.integer({ min: -1, max: 1e9 }) })
    .map((m): NetMessage => ({ type: 'snapshot-request', ...m })),
  fc
    .record({ room: u32, id: u32, tick: u32, bytes: bytes(3000) })
    .map((m): NetMessage => ({ type: 'snapshot', ...m })),
  fc
    .record({ room: u32, id: u32, from: u32, count: fc.integer({ min: 1, max: 512 }) })
    .map((m): NetMessage => ({ type: 'hashes-request', ...m })),
  fc
    .record({ room: u32, id: u32, from: u32, hashes: fc.array(hash, { maxLength: 64 }) })
    .map((m): NetMessage => ({ type: 'hashes', ...m, hashes: BigUint64Array.from(m.hashes) })),
);

/** decode must return a message or throw a ProtocolError — never anything else. */
function decodeOrProtocolError(b: Uint8Array): NetMessage | ProtocolError {
  try {
    return decodeMessage(b);
  } catch (error) {
    if (error instanceof ProtocolError) return error;
    throw error;
  }
}

describe('protocol codec', () => {
  it('round-trips every message type exactly', () => {
    fc.assert(
      fc.property(message, (m) => {
        const b = encodeMessage(m);
        expect(b[0]).toBe(PROTOCOL_VERSION);
        expect(b[1]).toBe(MessageType[m.type]);
        expect(peekMessageType(b)).toBe(m.type);
        const back = decodeMessage(b);
        expect(back).toEqual(m);
        // Canonical: the decoded message encodes to the same bytes.
        expect(encodeMessage(back)).toEqual(b);
      }),
      { numRuns: 2000 },
    );
  });

  it('throws only ProtocolError on random bytes', () => {
    fc.assert(
      fc.property(fc.uint8Array({ maxLength: 200 }), fc.integer({ min: 1, max: 16 }), (b, type) => {
        decodeOrProtocolError(b);
        // With a valid header the body parser is exercised too.
        const framed = new Uint8Array(b.length + 2);
        framed.set([PROTOCOL_VERSION, type]);
        framed.set(b, 2);
        decodeOrProtocolError(framed);
      }),
      { numRuns: 5000 },
    );
  });

  it('throws only ProtocolError on mutated, truncated and extended valid messages', () => {
    fc.assert(
      fc.property(message, fc.nat(), fc.integer({ min: 0, max: 255 }), (m, at, v) => {
        const b = encodeMessage(m);
        const flipped = b.slice();
        flipped[at % b.length] = v;
        decodeOrProtocolError(flipped);
        const cut = b.subarray(0, at % b.length);
        expect(decodeOrProtocolError(cut)).toBeInstanceOf(ProtocolError);
        const longer = new Uint8Array(b.length + 1);
        longer.set(b);
        longer[b.length] = v;
        const r = decodeOrProtocolError(longer);
        expect(r).toBeInstanceOf(ProtocolError);
        expect((r as ProtocolError).code).toBe('TRAILING_BYTES');
      }),
      { numRuns: 2000 },
    );
  });

  it('names what is wrong, with a code and an offset', () => {
    const err = (b: number[]) => decodeOrProtocolError(Uint8Array.from(b)) as ProtocolError;
    expect(err([]).code).toBe('TRUNCATED');
    expect(err([1, 1]).code).toBe('BAD_VERSION'); // protocol 1 (no input schema) is refused
    expect(err([2, 1]).code).toBe('BAD_VERSION'); // protocol 2 (the redundant confirmed stream) too
    expect(err([4, 1]).code).toBe('BAD_VERSION');
    expect(err([3, 0x7f]).code).toBe('BAD_TYPE');
    expect(err([3, 0x7f]).offset).toBe(1);
    // A varint with a redundant zero byte is not canonical.
    expect(err([3, MessageType.ack, 0x80, 0x00, 0]).code).toBe('BAD_VALUE');
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
  });

  it('checks sizes before allocating', () => {
    // A snapshot claiming 2^32 - 1 bytes in a 12-byte message: refused, nothing allocated.
    const huge = Uint8Array.of(3, MessageType.snapshot, 1, 1, 1, 0xff, 0xff, 0xff, 0xff, 0x0f);
    const e1 = decodeOrProtocolError(huge) as ProtocolError;
    expect(e1.code).toBe('TOO_LARGE');
    // A confirmed message claiming 64 ticks × 16 players × 16 words (shape 255 = 0xff 0x01) with
    // no bytes behind it.
    const e2 = decodeOrProtocolError(
      Uint8Array.of(3, MessageType.confirmed, 0, 0, 0xff, 0x01, 128, 1),
    ) as ProtocolError;
    expect(e2.code).toBe('TRUNCATED');
    // 17 players (shape 256) is over the limit whatever follows.
    const e2b = decodeOrProtocolError(
      Uint8Array.of(3, MessageType.confirmed, 0, 0, 0x80, 0x02, 2, 0),
    ) as ProtocolError;
    expect(e2b.code).toBe('TOO_LARGE');
    // 65 ticks is over the limit whatever follows; so are 17 words a tick.
    const e3 = decodeOrProtocolError(
      Uint8Array.of(3, MessageType.input, 1, 0, 0, 0, 1, 65),
    ) as ProtocolError;
    expect(e3.code).toBe('TOO_LARGE');
    const e4 = decodeOrProtocolError(
      Uint8Array.of(3, MessageType.input, 1, 0, 0, 0, 17, 1),
    ) as ProtocolError;
    expect(e4.code).toBe('TOO_LARGE');
    // The whole message is checked first.
    const big = new Uint8Array(DEFAULT_PROTOCOL_LIMITS.maxMessageBytes + 1);
    big.set([3, MessageType.snapshot]);
    expect((decodeOrProtocolError(big) as ProtocolError).code).toBe('TOO_LARGE');
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
    // version, type, tick (2), input ack offset, players and words, count; the inputs.
    expect(confirmed.length).toBe(2 + 2 + 1 + 1 + 1 + 64);
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
    ).toThrow(/input ack/);
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
