/**
 * The fuzz test of every wire protocol, derived from its declaration: for every message type, random
 * valid messages round-trip canonically, and any damage to their bytes is refused with the one
 * error type, naming the protocol and the field. Nothing here lists a protocol's fields by hand.
 */
import fc from 'fast-check';
import { describe, expect, it } from 'vitest';
import {
  MATCH_PROTOCOL,
  ProtocolError,
  RELAY_PROTOCOL,
  Random,
  SIGNAL_PROTOCOL,
  STATE_SYNC_PROTOCOL,
  type WireProtocol,
} from 'fixedstep';
import { ByteWriter } from '../src/det/bytes.js';
import { Layout, WireReader, type Fields, type Limits } from '../src/net/wire/fields.js';

const PROTOCOLS = [
  RELAY_PROTOCOL,
  STATE_SYNC_PROTOCOL,
  SIGNAL_PROTOCOL,
  MATCH_PROTOCOL,
] as unknown as WireProtocol<{ type: string }, object>[];

/** A decode that must return a message or throw a ProtocolError — never anything else. */
function decodeOrError(p: WireProtocol<{ type: string }, object>, b: Uint8Array) {
  try {
    return p.decode(b);
  } catch (error) {
    if (error instanceof ProtocolError) return error;
    throw error;
  }
}

describe.each(PROTOCOLS.map((p) => [p.name, p] as const))('the %s protocol', (_name, p) => {
  it('round-trips random messages of every type, canonically, each within its declared size', () => {
    for (const type of p.types) {
      fc.assert(
        fc.property(fc.integer(), (seed) => {
          const m = p.sample(type, new Random(seed));
          const b = p.encode(m);
          expect(b[0]).toBe(p.header);
          expect(b[1]).toBe(p.code(type));
          expect(p.peek(b)).toBe(type);
          expect(b.length).toBeLessThanOrEqual(p.maxBytes(type));
          const back = p.decode(b);
          expect(back).toEqual(m);
          // Canonical: the decoded message encodes to the same bytes.
          expect(p.encode(back)).toEqual(b);
        }),
        { numRuns: 150 },
      );
    }
  });

  it('the compiled codec of each message (Node) writes and reads exactly what the generic loops do', () => {
    // The protocol's layouts are private: reach them as the decoder does.
    const layouts = (p as unknown as { byType: Map<string, { layout: Layout }> }).byType;
    let compiled = 0;
    for (const type of p.types) {
      const layout = layouts.get(type)!.layout;
      for (let seed = 0; seed < 60; seed++) {
        const m = p.sample(type, new Random(seed)) as unknown as Fields;
        const generic = new ByteWriter();
        const fast = new ByteWriter();
        expect(layout.encodeMessage(fast, m, p.limits as Limits)).toBeUndefined();
        expect(layout.encode(generic, m, p.limits as Limits)).toBeUndefined();
        expect(fast.finish()).toEqual(generic.finish());
        const bytes = p.encode(m as never);
        const read = (how: (r: WireReader) => Fields) => {
          const r = new WireReader(bytes, p.name, p.limits as Limits);
          const out = how(r);
          r.end();
          return out;
        };
        const viaCompiled = read((r) => layout.readMessage(r, type));
        expect(viaCompiled).toStrictEqual(read((r) => layout.read(r, { type })));
        expect(Object.keys(viaCompiled)[0]).toBe('type');
      }
      if ((layout as unknown as { compiledRead: unknown }).compiledRead) compiled++;
    }
    // Every message without optional fields has its compiled codec here (a Node process).
    expect(compiled).toBeGreaterThan(0);
  });

  it('refuses damaged bytes with a ProtocolError naming the protocol — nothing else, ever', () => {
    fc.assert(
      fc.property(
        fc.constantFrom(...p.types),
        fc.integer(),
        fc.nat(),
        fc.integer({ min: 0, max: 255 }),
        (type, seed, at, v) => {
          const b = p.encode(p.sample(type, new Random(seed)));
          const flipped = b.slice();
          flipped[at % b.length] = v;
          const r = decodeOrError(p, flipped);
          // Whatever decodes is a valid message; anything else is refused naming the protocol.
          expect(r instanceof ProtocolError ? r.protocol : p.name).toBe(p.name);
          const cut = decodeOrError(p, b.subarray(0, at % b.length));
          expect(cut).toBeInstanceOf(ProtocolError);
          const longer = new Uint8Array(b.length + 1);
          longer.set(b);
          longer[b.length] = v;
          const extra = decodeOrError(p, longer);
          expect(extra).toBeInstanceOf(ProtocolError);
          expect((extra as ProtocolError).code).toMatch(/TRAILING_BYTES|TOO_LARGE/);
        },
      ),
      { numRuns: 3000 },
    );
  });

  it('refuses random bytes behind a valid header, naming the message type', () => {
    fc.assert(
      fc.property(fc.constantFrom(...p.types), fc.uint8Array({ maxLength: 120 }), (type, body) => {
        const b = new Uint8Array(body.length + 2);
        b.set([p.header, p.code(type)]);
        b.set(body, 2);
        const r = decodeOrError(p, b);
        expect(r instanceof ProtocolError ? r.messageType : type).toBe(type);
      }),
      { numRuns: 3000 },
    );
  });

  it('tells another protocol, and another version of itself, apart in words', () => {
    for (const other of PROTOCOLS) {
      if (other === p) continue;
      const b = other.encode(other.sample(other.types[0]!, new Random(1)));
      const e = decodeOrError(p, b) as ProtocolError;
      expect(e.code).toBe('BAD_VERSION');
      expect(e.message).toContain(`a ${other.name} message, not ${p.name}`);
    }
    const older = p.encode(p.sample(p.types[0]!, new Random(2)));
    older[0] = p.header - 1;
    const e = decodeOrError(p, older) as ProtocolError;
    expect(e.code).toBe('BAD_VERSION');
    expect(e.message).toMatch(/the other side is older \(reload the page or update fixedstep\)/);
  });

  it('refuses to encode a message that breaks its declaration, naming the field', () => {
    for (const type of p.types) {
      const m = p.sample(type, new Random(3)) as Record<string, unknown>;
      const field = Object.keys(m).find((k) => k !== 'type');
      if (field === undefined) continue;
      const broken = { ...m, [field]: Symbol('not a value') };
      expect(() => p.encode(broken as never)).toThrow(new RegExp(`cannot encode ${type}\\.`));
    }
  });
});

describe('the wire layer', () => {
  it('refuses before allocating: a byte field claiming 2^32 − 1 bytes behind a short header', () => {
    const snapshot = RELAY_PROTOCOL.code('snapshot');
    const huge = Uint8Array.of(
      RELAY_PROTOCOL.header,
      snapshot,
      1,
      1,
      1,
      0xff,
      0xff,
      0xff,
      0xff,
      0x0f,
    );
    const e = decodeOrError(RELAY_PROTOCOL, huge) as ProtocolError;
    expect(e.code).toBe('TOO_LARGE');
    expect(e.messageType).toBe('snapshot');
    expect(e.field).toBe('bytes');
  });

  it('derives each side’s largest message from the declarations and the limits', () => {
    // Clients of the relay send inputs, hashes and — when asked — a snapshot: the snapshot rules.
    expect(RELAY_PROTOCOL.largest('client')).toBeGreaterThan(1 << 20);
    expect(
      RELAY_PROTOCOL.largest('client', { ...RELAY_PROTOCOL.limits, maxSnapshotBytes: 1000 }),
    ).toBeLessThan(8000);
    // A quick-match client sends a request, an accept or a cancel: a few dozen bytes.
    expect(MATCH_PROTOCOL.largest('client')).toBeLessThan(100);
    expect(STATE_SYNC_PROTOCOL.largest('client')).toBeLessThan(8000);
  });
});
