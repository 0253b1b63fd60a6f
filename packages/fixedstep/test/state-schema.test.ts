import { describe, expect, it } from 'vitest';
import {
  BitWriter,
  ByteWriter,
  PriorityAccumulator,
  ProtocolError,
  Random,
  StateSchema,
  decodeSchemaDelta,
  defineStateSchema,
  encodeSchemaDelta,
  type StateColumn,
} from 'fixedstep';

/**
 * A small state laid out as games write theirs: a head, a count, bodies in columns (quantised
 * positions moved by velocities, a flag), a local solver column, and an exact f64.
 */
const COLUMNS: StateColumn[] = [
  { name: 'magic', type: 'u32', group: 'head' },
  { name: 'tick', type: 'u32', group: 'head' },
  { name: 'bodies', type: 'u16', group: 'head' },
  { name: 'secret', type: 'u32', count: 2, local: true },
  { name: 'flag', type: 'u8', count: { of: 'bodies', max: 64 }, group: 'b' },
  {
    name: 'x',
    type: 'f64',
    count: { of: 'bodies', max: 64 },
    group: 'b',
    precision: 1 / 8,
    min: -100,
    max: 100,
    rate: 'vx',
  },
  {
    name: 'vx',
    type: 'f64',
    count: { of: 'bodies', max: 64 },
    group: 'b',
    precision: 1 / 4,
    min: -50,
    max: 50,
  },
  {
    name: 'life',
    type: 'f32',
    count: { of: 'bodies', max: 64 },
    group: 'b',
    precision: 1 / 16,
    min: 0,
    max: 10,
    rounding: 'away',
  },
  { name: 'mass', type: 'f64', count: { of: 'bodies', max: 64 }, group: 'b' },
  { name: 'warm', type: 'i16', count: { of: 'bodies', max: 64 }, local: true },
];
const SCHEMA = defineStateSchema({ columns: COLUMNS });

interface Body {
  flag: number;
  x: number;
  vx: number;
  life: number;
  mass: number;
  warm: number;
}

const F32 = new DataView(new ArrayBuffer(4));
function f32Bits(v: number): number {
  F32.setFloat32(0, v, true);
  return F32.getUint32(0, true);
}

function state(tick: number, bodies: Body[], secret = [7, 9]): Uint8Array {
  const w = new ByteWriter(64);
  w.u32(0xabcd).u32(tick).u16(bodies.length).u32(secret[0]!).u32(secret[1]!);
  for (const b of bodies) w.u8(b.flag);
  for (const b of bodies) w.f64(b.x);
  for (const b of bodies) w.f64(b.vx);
  for (const b of bodies) w.u32(f32Bits(b.life));
  for (const b of bodies) w.f64(b.mass);
  for (const b of bodies) w.u16(b.warm & 0xffff);
  return w.finish();
}

function randomBodies(rng: Random, n: number): Body[] {
  return Array.from({ length: n }, () => ({
    flag: rng.int(3),
    x: rng.range(-90, 90),
    vx: rng.range(-40, 40),
    life: rng.int(4) === 0 ? 0 : rng.range(0, 9),
    mass: rng.range(0.5, 2),
    warm: rng.int(1000) - 500,
  }));
}

function roundTrip(
  base: Int32Array | undefined,
  next: Int32Array,
  seconds = 0,
): { words: Int32Array; bytes: number } {
  const out = new BitWriter();
  encodeSchemaDelta(SCHEMA, base, next, out, seconds);
  const bytes = out.finish();
  return {
    words: decodeSchemaDelta(SCHEMA, base, bytes, SCHEMA.maxWords, seconds),
    bytes: bytes.length,
  };
}

describe('state schemas', () => {
  it('refuse a definition that cannot describe bytes, naming the column', () => {
    const cases: [StateColumn[], RegExp][] = [
      [[], /columns must be an array of 1/],
      [[{ name: '1x', type: 'u8' }], /column 0 \(1x\): name/],
      [
        [
          { name: 'a', type: 'u8' },
          { name: 'a', type: 'u8' },
        ],
        /column 1 \(a\): the name is used twice/,
      ],
      [[{ name: 'a', type: 'u64' as never }], /type must be one of/],
      [[{ name: 'a', type: 'u8', precision: 1 }], /precision is for f32 and f64 only/],
      [[{ name: 'a', type: 'f64', precision: 0.1 }], /needs finite min < max/],
      [[{ name: 'a', type: 'f64', precision: 1e-9, min: -1e6, max: 1e6 }], /within ±2\^31/],
      [[{ name: 'a', type: 'f64', min: 0, max: 1 }], /min, max and rounding go with precision/],
      [[{ name: 'a', type: 'u8', count: { of: 'n', max: 4 } }], /names no earlier column/],
      [
        [
          { name: 'n', type: 'u8', local: true },
          { name: 'a', type: 'u8', count: { of: 'n', max: 4 } },
        ],
        /cannot take its count from a local one/,
      ],
      [
        [
          { name: 'a', type: 'u8', count: 2, group: 'g' },
          { name: 'b', type: 'u8', count: 3, group: 'g' },
        ],
        /group "g": column b has another count/,
      ],
      [
        [
          { name: 'a', type: 'u8', group: 'g' },
          { name: 'b', type: 'u8', group: 'g', local: true },
        ],
        /group "g" mixes local and sent columns/,
      ],
      [
        [{ name: 'x', type: 'f64', precision: 1, min: 0, max: 1, rate: 'v' }],
        /rate must name a quantised column of its group/,
      ],
    ];
    for (const [columns, message] of cases) {
      expect(() => defineStateSchema({ columns })).toThrow(message);
    }
  });

  it('quantise to exact words, and merge them with the local columns of another state', () => {
    const bodies: Body[] = [
      { flag: 1, x: 1.3, vx: -2.2, life: 0.01, mass: 1.5, warm: -3 },
      { flag: 2, x: -99.99, vx: 49.9, life: 0, mass: 2, warm: 4 },
    ];
    const report = { maxError: 0, clamped: 0 };
    const words = SCHEMA.quantise(state(5, bodies), report);
    // head (magic, tick, bodies), then the body group column by column; mass is 2 words (its bits).
    expect(Array.from(words.subarray(0, 3))).toEqual([0xabcd, 5, 2]);
    expect(Array.from(words.subarray(3, 5))).toEqual([1, 2]); // flags
    expect(Array.from(words.subarray(5, 7))).toEqual([Math.round(1.3 * 8), Math.round(-99.99 * 8)]);
    expect(Array.from(words.subarray(7, 9))).toEqual([Math.round(-2.2 * 4), Math.round(49.9 * 4)]);
    // life rounds away from zero: 0.01 is not 0 (one step of 1/16), 0 stays 0.
    expect(Array.from(words.subarray(9, 11))).toEqual([1, 0]);
    expect(words.length).toBe(11 + 4);
    expect(report.clamped).toBe(0);
    expect(report.maxError).toBeGreaterThan(0.4);
    expect(report.maxError).toBeLessThan(1);
    // Merged into another state: sent columns from the words, local ones (secret, warm) kept.
    const other = state(
      1,
      [
        { flag: 0, x: 0, vx: 0, life: 0, mass: 0, warm: 77 },
        { flag: 0, x: 0, vx: 0, life: 0, mass: 0, warm: 88 },
      ],
      [1, 2],
    );
    const merged = SCHEMA.merge(other, words);
    const expected = state(
      5,
      [
        { flag: 1, x: 10 / 8, vx: -9 / 4, life: 1 / 16, mass: 1.5, warm: 77 },
        { flag: 2, x: -800 / 8, vx: 200 / 4, life: 0, mass: 2, warm: 88 },
      ],
      [1, 2],
    );
    expect(Array.from(merged)).toEqual(Array.from(expected));
    // Quantising a merged state again gives the same words (the server snaps once).
    expect(Array.from(SCHEMA.quantise(merged))).toEqual(Array.from(words));
  });

  it("leave a local: 'zero' column at zero in a merged state, whatever the other state held", () => {
    const schema = defineStateSchema({
      columns: [
        { name: 'n', type: 'u8' },
        { name: 'x', type: 'f64', count: 2, group: 'e', precision: 1 / 4, min: -9, max: 9 },
        { name: 'vx', type: 'f64', count: 2, local: 'zero' },
      ],
    });
    const w = new ByteWriter(64);
    w.u8(3).f64(1.3).f64(-2).f64(5).f64(-6);
    const own = w.finish();
    const merged = schema.merge(own, schema.quantise(own));
    const r = new DataView(merged.buffer);
    expect([r.getUint8(0), r.getFloat64(1, true), r.getFloat64(9, true)]).toEqual([3, 1.25, -2]);
    expect([r.getFloat64(17, true), r.getFloat64(25, true)]).toEqual([0, 0]);
    expect(() =>
      defineStateSchema({ columns: [{ name: 'a', type: 'u8', local: 'yes' as never }] }),
    ).toThrow(/local must be true, false or 'zero'/);
  });

  it('clamp values outside the range, and count them', () => {
    const report = { maxError: 0, clamped: 0 };
    const words = SCHEMA.quantise(
      state(0, [{ flag: 0, x: 250, vx: Number.NaN, life: 1, mass: 1, warm: 0 }]),
      report,
    );
    expect(report.clamped).toBe(2);
    expect(words[4]).toBe(800); // x at max
    expect(words[5]).toBe(-200); // NaN vx at min
  });

  it('refuse bytes of another layout, and words that do not describe a state', () => {
    const good = state(1, randomBodies(new Random(1), 3));
    expect(() => SCHEMA.quantise(good.subarray(0, good.length - 1))).toThrow(
      /end inside column warm/,
    );
    expect(() => SCHEMA.quantise(Uint8Array.of(...good, 0))).toThrow(
      /1 bytes after its last column/,
    );
    const many = state(1, randomBodies(new Random(1), 3));
    many[8] = 200; // bodies = 200 > max 64
    expect(() => SCHEMA.quantise(many)).toThrow(/would hold 200 numbers .* at most 64/);
    const words = SCHEMA.quantise(good);
    expect(() => SCHEMA.merge(good, words.subarray(0, words.length - 1))).toThrow(
      /words, the layout they describe has/,
    );
  });

  it('locate a byte of a state: the column, the row and where the number starts', () => {
    const three = state(1, randomBodies(new Random(1), 3));
    // magic 0, tick 4, bodies 8, secret 10–17, flag 18–20, x 21–44, vx 45–68, life 69–80 …
    expect(SCHEMA.locate(three, 5)).toEqual({
      column: 'tick',
      row: 0,
      count: 1,
      type: 'u32',
      offset: 4,
      local: false,
    });
    expect(SCHEMA.locate(three, 14)).toMatchObject({ column: 'secret', row: 1, local: true });
    expect(SCHEMA.locate(three, 20)).toMatchObject({ column: 'flag', row: 2, offset: 20 });
    expect(SCHEMA.locate(three, 36)).toMatchObject({ column: 'x', row: 1, count: 3, offset: 29 });
    expect(SCHEMA.locate(three, 72)).toMatchObject({ column: 'life', row: 0, offset: 69 });
    expect(SCHEMA.locate(three, three.length - 1)).toMatchObject({ column: 'warm', row: 2 });
    expect(SCHEMA.locate(three, three.length)).toBeUndefined();
    expect(SCHEMA.locate(three.subarray(0, 30), 5)).toBeUndefined(); // not the schema's layout
  });

  it('code deltas that decode to the same words: random states, bases of other counts, no base', () => {
    const rng = new Random(24);
    let total = 0;
    for (let round = 0; round < 300; round++) {
      const a = randomBodies(rng, rng.int(20));
      const b = rng.int(3) === 0 ? randomBodies(rng, rng.int(20)) : a.map((body) => ({ ...body }));
      // Move some bodies of b a little, as a step would.
      for (const body of b) {
        if (rng.int(3) === 0) {
          body.x += body.vx * 0.05 + rng.range(-0.2, 0.2);
          body.vx += rng.range(-1, 1);
        }
      }
      const base = rng.int(5) === 0 ? undefined : SCHEMA.quantise(state(round, a));
      const next = SCHEMA.quantise(state(round + 3, b));
      const { words, bytes } = roundTrip(base, next, 0.05);
      expect(Array.from(words)).toEqual(Array.from(next));
      total += bytes;
    }
    expect(total).toBeGreaterThan(0);
  });

  it('cost a bit per group for an unchanged state, and little for one moved body of many', () => {
    const rng = new Random(3);
    const bodies = randomBodies(rng, 64);
    const words = SCHEMA.quantise(state(9, bodies));
    // Nothing changed: a bit per group (head, body group) — one byte.
    expect(roundTrip(words, words).bytes).toBe(1);
    // Bodies that moved exactly as their velocities say cost nothing either (0.5 s later).
    const later = bodies.map((b) => ({ ...b, x: b.x }));
    const moved = SCHEMA.quantise(state(9, later));
    const scale = SCHEMA.sent.find((c) => c.name === 'x')!.rateScale;
    for (let i = 0; i < 64; i++) {
      const x = 3 + 64 + i; // after the head (3 words) and the flags (64)
      moved[x] = moved[x]! + Math.round(moved[x + 64]! * scale * 0.5);
    }
    expect(roundTrip(words, moved, 0.5).bytes).toBe(1);
    // One body of 64 changes its flag: gaps, not a 64-bit bitmap.
    const one = words.slice();
    one[3 + 40] = (one[3 + 40]! + 1) % 3;
    const cost = roundTrip(words, one).bytes;
    expect(cost).toBeLessThanOrEqual(4);
    expect(cost).toBeGreaterThan(1);
  });

  it('refuse damaged payloads with a ProtocolError, never more than the bound', () => {
    const rng = new Random(8);
    const base = SCHEMA.quantise(state(1, randomBodies(rng, 10)));
    const next = SCHEMA.quantise(state(4, randomBodies(rng, 12)));
    const out = new BitWriter();
    encodeSchemaDelta(SCHEMA, base, next, out);
    const good = out.finish();
    let refused = 0;
    let longest = 0;
    const others: unknown[] = [];
    for (let i = 0; i < 2000; i++) {
      const bad = good.slice(0, rng.int(good.length + 1));
      for (let k = 0; k < 3 && bad.length > 0; k++) {
        const at = rng.int(bad.length);
        bad[at] = bad[at]! ^ (1 << rng.int(8));
      }
      try {
        longest = Math.max(longest, decodeSchemaDelta(SCHEMA, base, bad, SCHEMA.maxWords).length);
      } catch (e) {
        if (e instanceof ProtocolError) refused++;
        else others.push(e);
      }
    }
    expect(others).toEqual([]);
    expect(refused).toBeGreaterThan(1000);
    expect(longest).toBeLessThanOrEqual(SCHEMA.maxWords);
    // A bound below the state's words refuses it.
    expect(() => decodeSchemaDelta(SCHEMA, base, good, 10)).toThrow(/more than 10 words/);
  });

  it('are made only by defineStateSchema for a game', async () => {
    const { defineGame, BUTTON_WORD } = await import('fixedstep');
    expect(() =>
      defineGame({
        id: 'x',
        version: 1,
        tickRate: 60,
        input: BUTTON_WORD,
        minPlayers: 1,
        maxPlayers: 1,
        create: () => {
          throw new Error('unused');
        },
        stateSchema: { columns: [] } as unknown as StateSchema,
      }),
    ).toThrow(/stateSchema must be made by defineStateSchema/);
  });
});

describe('a byte budget with a priority accumulator', () => {
  it('keeps each snapshot within the budget, sends the longest-waiting rows, and converges once motion stops', () => {
    const rng = new Random(12);
    let bodies = randomBodies(rng, 60);
    const acc = new PriorityAccumulator();
    let held: Int32Array | undefined;
    let heldTick = -1;
    const sizes: number[] = [];
    let deferred = 0;
    let lastDeferred = -1;
    const BUDGET = 60;
    let last: Int32Array | undefined;
    for (let tick = 0; tick < 120; tick++) {
      // Everything moves for 60 ticks, then stands still.
      if (tick < 60) {
        bodies = bodies.map((b) => ({
          ...b,
          x: b.x + rng.range(-3, 3),
          vx: b.vx + rng.range(-2, 2),
        }));
      }
      const next = SCHEMA.quantise(state(tick, bodies));
      const l = acc.limit(
        SCHEMA,
        held,
        next,
        held ? (tick - heldTick) / 60 : 0,
        BUDGET,
        tick,
        heldTick,
      );
      // The client decodes what it was sent, and acknowledges it at once.
      const decoded = decodeSchemaDelta(
        SCHEMA,
        held,
        l.payload,
        SCHEMA.maxWords,
        held ? (tick - heldTick) / 60 : 0,
      );
      expect(Array.from(decoded)).toEqual(Array.from(l.words));
      if (held) sizes.push(l.payload.length);
      deferred += l.deferred;
      if (l.deferred > 0) lastDeferred = tick;
      held = decoded;
      heldTick = tick;
      last = next;
    }
    // At the end the client holds the server's state exactly.
    expect(Array.from(held!)).toEqual(Array.from(last!));
    expect(deferred).toBeGreaterThan(500);
    expect(Math.max(...sizes)).toBeLessThanOrEqual(60);
    // Once nothing moves, every row is sent within a few snapshots.
    expect(lastDeferred).toBeGreaterThanOrEqual(59);
    expect(lastDeferred).toBeLessThan(75);
  });
});
