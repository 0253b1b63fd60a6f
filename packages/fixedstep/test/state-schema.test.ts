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
  predictedWords,
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

/** `ticks` at 60 a second. */
function at60(ticks: number): { ticks: number; tickRate: number } {
  return { ticks, tickRate: 60 };
}

function roundTrip(
  base: Int32Array | undefined,
  next: Int32Array,
  ticks = 0,
): { words: Int32Array; bytes: number } {
  const out = new BitWriter();
  encodeSchemaDelta(SCHEMA, base, next, out, at60(ticks));
  const bytes = out.finish();
  return {
    words: decodeSchemaDelta(SCHEMA, base, bytes, SCHEMA.maxWords, at60(ticks)),
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
      [
        [
          { name: 'a', type: 'f64', precision: 1, min: 0, max: 9, group: 'g' },
          { name: 'v', type: 'f64', precision: 1, min: 0, max: 9, group: 'g', rate: 'a' },
          { name: 'x', type: 'f64', precision: 1, min: 0, max: 9, group: 'g', rate: 'v' },
        ],
        /column x: its rate v has a rate of its own/,
      ],
      [[{ name: 'x', type: 'u16', extrapolate: true }], /extrapolate is for quantised columns/],
      [
        [
          { name: 'v', type: 'f64', precision: 1, min: 0, max: 9, group: 'g' },
          {
            name: 'x',
            type: 'f64',
            precision: 1,
            min: 0,
            max: 9,
            group: 'g',
            rate: 'v',
            extrapolate: true,
          },
        ],
        /extrapolate is for quantised columns without a rate/,
      ],
      [
        [{ name: 'x', type: 'f64', precision: 1, min: 0, max: 9, extrapolate: 1 as never }],
        /extrapolate must be true or false/,
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
      const { words, bytes } = roundTrip(base, next, 3);
      expect(Array.from(words)).toEqual(Array.from(next));
      total += bytes;
    }
    expect(total).toBeGreaterThan(0);
  });

  it('predict a body under constant acceleration from both rates: a step off at most, where the base rate alone misses by several', () => {
    // Bodies stepped as games step them (v += a·Δt, then x += v·Δt) from a base n ticks back; the
    // snapshot brings the new velocity, so the position is predicted from both.
    const rng = new Random(12);
    const xAt = SCHEMA.sent.findIndex((c) => c.name === 'x');
    let worst = 0;
    let worstOld = 0;
    for (let round = 0; round < 200; round++) {
      const n = 1 + rng.int(8);
      const bodies = randomBodies(rng, 20).map((b) => ({
        ...b,
        x: rng.range(-20, 20),
        vx: rng.range(-10, 10),
      }));
      const accel = bodies.map(() => rng.range(-30, 30));
      const base = SCHEMA.quantise(state(round, bodies));
      // Start from what was sent (the server snaps its world to it).
      const moving = bodies.map((b, i) => ({
        ...b,
        x: base[3 + 20 + i]! / 8,
        vx: base[3 + 40 + i]! / 4,
      }));
      for (let t = 0; t < n; t++) {
        for (const [i, b] of moving.entries()) {
          b.vx += accel[i]! / 60;
          b.x += b.vx / 60;
        }
      }
      const next = SCHEMA.quantise(state(round + n, moving));
      const expected = predictedWords(SCHEMA, base, next, at60(n));
      for (let i = 0; i < 20; i++) {
        const w = 3 + 20 + i;
        worst = Math.max(worst, Math.abs(next[w]! - expected[w]!));
        // The base's rate alone (what a snapshot without the new velocity could do).
        const old = base[w]! + Math.round((base[w + 20]! * SCHEMA.sent[xAt]!.rateScale * n) / 60);
        worstOld = Math.max(worstOld, Math.abs(next[w]! - old));
      }
      expect(Array.from(roundTrip(base, next, n).words)).toEqual(Array.from(next));
    }
    // The velocity's own rounding (1/4 u/s) moves x by up to 1/8 u/s × n/60 ≤ 1/60 u: a step of
    // 1/8 u is the most it can be off, from the rounding of x itself.
    expect(worst).toBeLessThanOrEqual(1);
    expect(worstOld).toBeGreaterThanOrEqual(3);
  });

  it('extrapolate a column from the base and an older snapshot: a body in a straight line costs nothing', () => {
    const schema = defineStateSchema({
      columns: [
        { name: 'n', type: 'u16', group: 'head' },
        {
          name: 'x',
          type: 'f64',
          count: { of: 'n', max: 64 },
          group: 'b',
          precision: 1 / 8,
          min: -1000,
          max: 1000,
          extrapolate: true,
        },
      ],
    });
    const rng = new Random(21);
    // Whole steps (1/8) a tick, each body its own.
    const speeds = Array.from({ length: 40 }, () => rng.int(41) - 20);
    const at = (tick: number): Int32Array => {
      const w = new ByteWriter(8);
      w.u16(40);
      for (const v of speeds) w.f64((v * (tick - 100)) / 8);
      return schema.quantise(w.finish());
    };
    const code = (older: boolean): { bytes: number; words: Int32Array } => {
      const e = { ticks: 3, tickRate: 60, older: older ? at(94) : undefined, olderTicks: 6 };
      const out = new BitWriter();
      encodeSchemaDelta(schema, at(100), at(103), out, e);
      const bytes = out.finish();
      return { bytes: bytes.length, words: decodeSchemaDelta(schema, at(100), bytes, 999, e) };
    };
    // Positions a whole step a tick apart: with the older snapshot each row is where the line goes.
    const withOlder = code(true);
    const without = code(false);
    expect(Array.from(withOlder.words)).toEqual(Array.from(at(103)));
    expect(Array.from(without.words)).toEqual(Array.from(at(103)));
    expect(withOlder.bytes).toBeLessThanOrEqual(2);
    expect(without.bytes).toBeGreaterThan(20);
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
    expect(roundTrip(words, moved, 30).bytes).toBe(1);
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
        at60(held ? tick - heldTick : 0),
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
        at60(held ? tick - heldTick : 0),
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
