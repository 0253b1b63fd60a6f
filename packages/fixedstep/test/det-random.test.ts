import { execFileSync, spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { describe, expect, it } from 'vitest';
import { Random } from 'fixedstep';

function first(seed: number, n: number): number[] {
  const r = new Random(seed);
  return Array.from({ length: n }, () => r.nextU32());
}

// The first 20 outputs of xoshiro128** after the SplitMix32 seed expansion (checked against the C
// reference below when it was pinned). A change here changes every replay and golden hash.
const GOLDEN: Record<number, number[]> = {
  0: [
    3809008728, 1133695204, 53579671, 2891528803, 139681546, 2203266335, 104831812, 1587294886,
    2629861951, 58120585, 4102032208, 181034053, 1844616607, 157872427, 3090281447, 3255003311,
    1874033228, 2253272953, 2750776137, 879057133,
  ],
  1: [
    2442144158, 3238099751, 3819917871, 2104621829, 2021136066, 4223536128, 1515984730, 2298887649,
    1445082595, 3688943618, 2160875214, 3324748392, 2623305997, 1948320246, 1148926009, 3148779566,
    2872583135, 2572790369, 3354354593, 229342951,
  ],
  42: [
    2837322924, 544945897, 479756282, 3500138142, 339756180, 113173290, 65323186, 1112262688,
    3782522214, 1395801302, 787581093, 2038421698, 4161304501, 4042942491, 3318109410, 3426010765,
    2132581468, 3088945547, 2296110748, 445720661,
  ],
};

/** The reference: Blackman & Vigna's xoshiro128** and the same SplitMix32-style seeding, in C. */
const C_REFERENCE = String.raw`
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
static uint32_t s[4];
static uint32_t sm;
static uint32_t splitmix32(void) {
  uint32_t z = (sm += 0x9e3779b9u);
  z = (z ^ (z >> 16)) * 0x85ebca6bu;
  z = (z ^ (z >> 13)) * 0xc2b2ae35u;
  return z ^ (z >> 16);
}
static inline uint32_t rotl(const uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }
static uint32_t next(void) {
  const uint32_t result = rotl(s[1] * 5, 7) * 9;
  const uint32_t t = s[1] << 9;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rotl(s[3], 11);
  return result;
}
int main(int argc, char **argv) {
  unsigned long count = strtoul(argv[1], 0, 10);
  for (int a = 2; a < argc; a++) {
    sm = (uint32_t)strtoul(argv[a], 0, 10);
    for (int i = 0; i < 4; i++) s[i] = splitmix32();
    if ((s[0] | s[1] | s[2] | s[3]) == 0) s[0] = 1;
    printf("%s", argv[a]);
    for (unsigned long i = 0; i < count; i++) printf(" %u", next());
    printf("\n");
  }
  return 0;
}
`;

const hasGcc = spawnSync('gcc', ['--version']).status === 0;

describe('Random: golden sequences', () => {
  it.each([0, 1, 42])('seed %i gives the pinned first 20 outputs', (seed) => {
    const actual = first(seed, 20);
    expect(actual, `seed ${seed} now gives [${actual.join(', ')}]`).toEqual(GOLDEN[seed]);
  });

  it('matches the C reference (gcc -O2) for 1000 outputs of several seeds', (ctx) => {
    if (!hasGcc) {
      // eslint-disable-next-line vitest/no-disabled-tests -- only where gcc is missing, with a visible note
      ctx.skip('gcc not found: the cross-check against the C reference of xoshiro128** is skipped');
    }
    const dir = mkdtempSync(join(tmpdir(), 'fixedstep-xoshiro-'));
    try {
      writeFileSync(join(dir, 'xoshiro.c'), C_REFERENCE);
      const exe = join(dir, 'xoshiro');
      execFileSync('gcc', ['-O2', '-o', exe, join(dir, 'xoshiro.c')]);
      const seeds = [0, 1, 42, 7, 123456789, 2147483648, 4294967295];
      const lines = execFileSync(exe, ['1000', ...seeds.map(String)], { encoding: 'utf8' })
        .trim()
        .split('\n');
      expect(lines).toHaveLength(seeds.length);
      for (const [i, seed] of seeds.entries()) {
        const c = lines[i]!.split(' ').map(Number);
        expect(c[0]).toBe(seed);
        expect(first(seed, 1000), `seed ${seed}`).toEqual(c.slice(1));
      }
      // and the pinned values are the reference's
      for (const seed of [0, 1, 42]) expect(first(seed, 20)).toEqual(GOLDEN[seed]);
    } finally {
      rmSync(dir, { recursive: true, force: true });
    }
  });

  it('takes the seed modulo 2^32, as the C reference does', () => {
    expect(first(-1, 5)).toEqual(first(4294967295, 5));
    expect(first(4294967296 + 42, 5)).toEqual(first(42, 5));
    expect(first(42.9, 5)).toEqual(first(42, 5));
    expect(first(0, 5)).toEqual(first(-0, 5));
  });
});

describe('Random: state', () => {
  it('save/restore mid-stream gives an identical continuation', () => {
    const a = new Random(2026);
    for (let i = 0; i < 1234; i++) a.nextU32();
    const saved = a.getState();
    const expected = Array.from({ length: 500 }, () => a.nextU32());
    const b = new Random(99);
    b.setState(saved);
    expect(Array.from({ length: 500 }, () => b.nextU32())).toEqual(expected);
    // getState is a copy: stepping does not change what was saved
    const copy = Uint32Array.from(saved);
    a.nextU32();
    expect(saved).toEqual(copy);
    a.setState(saved);
    expect(a.nextU32()).toBe(expected[0]);
  });

  it('seed() restarts the stream', () => {
    const r = new Random(5);
    const head = [r.nextU32(), r.nextU32()];
    r.seed(5);
    expect([r.nextU32(), r.nextU32()]).toEqual(head);
  });

  it('next() is in [0, 1) and range(min, max) in [min, max)', () => {
    const r = new Random(3);
    for (let i = 0; i < 10_000; i++) {
      const u = r.next();
      const v = r.range(-2, 5);
      expect(u >= 0 && u < 1 && v >= -2 && v < 5).toBe(true);
    }
  });
});

/** Pearson's chi-square of `draws` values of `int(n)`, counted in `buckets` equal ranges of [0, n). */
function chiSquare(seed: number, n: number, buckets: number, draws: number): number {
  return chiSquareOf(seed, buckets, draws, (r) => r.int(n), n);
}

function chiSquareOf(
  seed: number,
  buckets: number,
  draws: number,
  draw: (r: Random) => number,
  n: number,
): number {
  const r = new Random(seed);
  const counts = new Array<number>(buckets).fill(0);
  for (let i = 0; i < draws; i++) {
    const v = draw(r);
    const b = Math.floor((v * buckets) / n);
    counts[b]! += 1;
  }
  const expected = draws / buckets;
  return counts.reduce((sum, c) => sum + ((c - expected) * (c - expected)) / expected, 0);
}

describe('Random.int: unbiased', () => {
  it('int(10) over 1e5 draws: chi-square pinned, and below the p = 0.001 critical value', () => {
    const stat = chiSquare(2026, 10, 10, 100_000);
    expect(stat).toBeLessThan(27.877); // χ²(9 df) at p = 0.001
    expect(stat, `chi-square is now ${stat}`).toBe(9.037799999999999);
  });

  it('int(3·2^30): modulo bias would put half the draws in the first third; rejection does not', () => {
    // x mod n for x uniform in [0, 2^32) hits [0, 2^30) twice as often as the rest.
    const stat = chiSquare(7, 3 * 2 ** 30, 3, 100_000);
    expect(stat).toBeLessThan(13.816); // χ²(2 df) at p = 0.001
    expect(stat, `chi-square is now ${stat}`).toBe(4.40114);
    // the same test catches the biased x % n
    expect(
      chiSquareOf(7, 3, 100_000, (r) => r.nextU32() % (3 * 2 ** 30), 3 * 2 ** 30),
    ).toBeGreaterThan(10_000);
  });

  it('covers its range: int(1) is 0, int(2^32) is nextU32', () => {
    const r = new Random(1);
    for (let i = 0; i < 100; i++) expect(r.int(1)).toBe(0);
    const a = new Random(8);
    const b = new Random(8);
    for (let i = 0; i < 100; i++) expect(a.int(2 ** 32)).toBe(b.nextU32());
  });
});

describe('Random: bad arguments throw RangeErrors', () => {
  it.each([0, -1, 1.5, NaN, Infinity, 2 ** 32 + 1])('int(%s)', (n) => {
    expect(() => new Random(1).int(n)).toThrow(RangeError);
  });
  it.each([NaN, Infinity, -Infinity])('seed %s', (seed) => {
    expect(() => new Random(seed)).toThrow(RangeError);
    expect(() => {
      new Random(1).seed(seed);
    }).toThrow(/finite/);
  });
  it('setState with the wrong length or all zeros', () => {
    const r = new Random(1);
    expect(() => {
      r.setState([1, 2, 3]);
    }).toThrow(RangeError);
    expect(() => {
      r.setState([0, 0, 0, 0]);
    }).toThrow(/all-zero/);
  });
});
