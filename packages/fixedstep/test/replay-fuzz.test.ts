import { describe, expect, it } from 'vitest';
import { Random, ReplayError, ReplayPlayer, readReplay, verifyReplay } from 'fixedstep';
import type { ReplayLimits } from 'fixedstep';
import { arenaFactory, recordArena, reseal } from './replay-fixture.js';

/**
 * Mutation fuzzing of the reader, verifier and player. Every mutated file must either parse (and
 * then verify, ok or not, and play) or throw a ReplayError — never any other exception. Time is
 * bounded by the limits (at most `maxTicks` steps per verification), not by a timer.
 */

const LIMITS: ReplayLimits = {
  maxFileBytes: 1 << 20,
  maxTicks: 4000,
  maxPlayers: 8,
  maxSeeds: 8,
  maxConfigBytes: 4096,
  maxKeyframeBytes: 1 << 16,
  maxKeyframes: 1 << 16,
};

const bases = [
  recordArena({ ticks: 300, players: 2, checkpointEvery: 20, keyframeEvery: 60, tickHashes: true }),
  recordArena({ ticks: 240, players: 1, checkpointEvery: 30, seed: 77 }),
  recordArena({ ticks: 0, players: 3 }),
].map((r) => r.bytes);

type Mutation = (b: Uint8Array, rng: Random) => Uint8Array;

function splice(b: Uint8Array, offset: number, remove: number, insert: Uint8Array): Uint8Array {
  remove = Math.min(remove, b.length - offset);
  const out = new Uint8Array(b.length - remove + insert.length);
  out.set(b.subarray(0, offset));
  out.set(insert, offset);
  out.set(b.subarray(offset + remove), offset + insert.length);
  return out;
}

function randomBytes(rng: Random, n: number): Uint8Array {
  const out = new Uint8Array(n);
  for (let i = 0; i < n; i++) out[i] = rng.int(256);
  return out;
}

function flipBits(b: Uint8Array, rng: Random, n: number): Uint8Array {
  // Distinct bits: flipping one bit twice would give back the original file.
  const out = b.slice();
  const bits = new Set<number>();
  while (bits.size < Math.min(n, out.length * 8)) bits.add(rng.int(out.length * 8));
  for (const bit of bits) out[bit >>> 3] = out[bit >>> 3]! ^ (1 << (bit & 7));
  return out;
}

/** Offsets of every length-like field of a valid file: the file length, section lengths. */
function lengthFields(b: Uint8Array): number[] {
  return [12, ...readReplay(b).sections.map((s) => s.offset + 1)];
}

const HUGE = [0xffffffff, 0x7fffffff, 0x80000000, 0x10000, 0];

const mutations: Record<string, Mutation> = {
  'bit flips': (b, rng) => flipBits(b, rng, 1 + rng.int(4)),
  truncation: (b, rng) => b.slice(0, rng.int(b.length)),
  insertion: (b, rng) => splice(b, rng.int(b.length + 1), 0, randomBytes(rng, 1 + rng.int(16))),
  deletion: (b, rng) => splice(b, rng.int(b.length), 1 + rng.int(16), new Uint8Array(0)),
  'huge length field': (b, rng) => {
    const out = b.slice();
    const fields = lengthFields(b);
    const at = fields[rng.int(fields.length)]!;
    const v = rng.next() < 0.8 ? HUGE[rng.int(HUGE.length)]! : rng.nextU32();
    new DataView(out.buffer).setUint32(at, v, true);
    return rng.next() < 0.5 && at !== 12 ? reseal(out) : out;
  },
  'huge varint': (b, rng) => {
    // Overwrite bytes inside GAME/TICKS/INPUTS with 0xff runs (varints that never end or
    // overflow), checksum recomputed so the parser gets that far.
    const s = readReplay(b).sections;
    const sec = s[rng.int(Math.min(3, s.length))]!;
    const out = b.slice();
    const at = sec.offset + 5 + rng.int(Math.max(1, sec.length));
    for (let i = 0; i < 1 + rng.int(6) && at + i < out.length - 8; i++) out[at + i] = 0xff;
    return reseal(out);
  },
  garbage: (b, rng) => {
    const g = randomBytes(rng, rng.int(600));
    if (rng.next() < 0.5 && g.length >= 24) {
      g.set(b.subarray(0, 12)); // magic + version: reach the length and checksum checks
      return rng.next() < 0.5 ? reseal(g) : g;
    }
    return g;
  },
  'resealed byte changes': (b, rng) => {
    const out = b.slice();
    const n = 1 + rng.int(3);
    for (let i = 0; i < n; i++) {
      const at = 16 + rng.int(out.length - 24);
      out[at] = rng.next() < 0.5 ? rng.int(256) : [0x00, 0x7f, 0x80, 0xff][rng.int(4)]!;
    }
    return reseal(out);
  },
  'resealed bit flips': (b, rng) =>
    reseal(flipBits(b.subarray(0, b.length - 8), rng, 1 + rng.int(2))),
  'resealed insertion/deletion': (b, rng) => {
    const at = 16 + rng.int(b.length - 24);
    const out =
      rng.next() < 0.5
        ? splice(b, at, 0, randomBytes(rng, 1 + rng.int(8)))
        : splice(b, at, 1 + rng.int(8), new Uint8Array(0));
    return reseal(out);
  },
};

describe('replay fuzz', () => {
  it('every mutated file parses and verifies cleanly, or throws a ReplayError', () => {
    const rng = new Random(20240601);
    const names = Object.keys(mutations);
    const PER_KIND = 600;
    const outcomes = new Map<string, number>();
    const byKind = new Map<string, Set<string>>();
    let total = 0;
    let steps = 0;
    for (const name of names) {
      const mutate = mutations[name]!;
      const seen = new Set<string>();
      for (let i = 0; i < PER_KIND; i++) {
        const base = bases[i % bases.length]!;
        const file = mutate(base, rng);
        let outcome: string;
        try {
          const replay = readReplay(file, { limits: LIMITS });
          const result = verifyReplay(replay, arenaFactory);
          steps += result.simulated;
          outcome = result.ok ? 'parsed, verified ok' : `parsed, verify failed (${result.kind})`;
          const player = new ReplayPlayer(replay, arenaFactory, { checkTickHashes: true });
          player.seek(rng.int(replay.tickCount + 1));
          player.seek(replay.tickCount);
          player.stepBack();
          steps += 2 * replay.tickCount;
        } catch (e) {
          if (!(e instanceof ReplayError)) {
            throw new Error(
              `mutation "${name}" #${i} threw ${String(e)} — file: ${Buffer.from(file).toString('hex')}`,
              { cause: e },
            );
          }
          outcome = e.code;
        }
        outcomes.set(outcome, (outcomes.get(outcome) ?? 0) + 1);
        seen.add(outcome);
        total++;
      }
      byKind.set(name, seen);
    }
    // What the fuzz reached, shown only when an assertion below fails.
    const lines = [...outcomes].sort((a, b) => b[1] - a[1]).map(([k, n]) => `  ${k}: ${n}`);
    const kinds = [...byKind].map(([name, seen]) => `  ${name}: ${[...seen].join(', ')}`);
    const summary = `replay fuzz: ${total} mutated files, ${steps} simulated steps\n${lines.join('\n')}\n${kinds.join('\n')}`;

    // The fuzz reaches every layer: each check fires, and some mutants get past all of them;
    // without a recomputed checksum, no damaged file is ever accepted.
    const codes = [
      'BAD_MAGIC',
      'TRUNCATED',
      'TRAILING_DATA',
      'BAD_CHECKSUM',
      'CORRUPT',
      'TOO_LARGE',
    ];
    const unsealed = ['bit flips', 'truncation', 'insertion', 'deletion'];
    const found = {
      atLeast5000: total >= 5000,
      codesNeverSeen: codes.filter((code) => !outcomes.has(code)),
      somePassEveryCheck: [...outcomes.keys()].some((k) => k.startsWith('parsed')),
      unsealedAccepted: unsealed.filter((name) =>
        [...byKind.get(name)!].some((k) => k.startsWith('parsed')),
      ),
    };
    // The summary rides along so that a failure shows what the fuzz reached.
    expect({ ...found, summary }).toEqual({
      atLeast5000: true,
      codesNeverSeen: [],
      somePassEveryCheck: true,
      unsealedAccepted: [],
      summary,
    });
  });
});
