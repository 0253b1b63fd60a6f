/** Untrusted save bytes: every corruption is refused with a RangeError or loads; nothing else. */
import { beforeAll, describe, expect, it } from 'vitest';
import { Random } from 'fixedstep';
import { RapierSimulation, loadRapier, towerScene } from '@fixedstep/rapier';
import { murmur3 } from '../src/checksum.js';

beforeAll(async () => {
  await loadRapier();
});

describe('load() of corrupted saves', () => {
  it('300 saves with flipped bytes, cut ends or junk: a RangeError or a world, and the simulation still steps', () => {
    const source = new RapierSimulation(towerScene({ rows: 3 }));
    for (let t = 0; t < 40; t++) source.step([t === 5 ? 0x10001 : 0]);
    const good = source.save();
    const sim = new RapierSimulation(towerScene({ rows: 3 }));
    const rng = new Random(17);
    const refusals: unknown[] = [];
    let loaded = 0;
    for (let k = 0; k < 300; k++) {
      let bytes = good.slice();
      const kind = k % 3;
      if (kind === 0) {
        for (let i = 0; i < 1 + rng.int(8); i++) bytes[rng.int(bytes.length)] = rng.int(256);
      } else if (kind === 1) {
        bytes = bytes.subarray(0, rng.int(bytes.length));
      } else {
        for (let i = 0; i < 64; i++) bytes[60 + rng.int(bytes.length - 60)] = rng.int(256);
      }
      try {
        sim.load(bytes);
        loaded++;
      } catch (e) {
        refusals.push(e);
      }
      // Whatever happened, the simulation is usable: it steps and saves.
      sim.step([0]);
      expect(sim.save().length).toBeGreaterThan(100);
    }
    expect(refusals.filter((e) => !(e instanceof RangeError))).toEqual([]);
    expect(refusals.length).toBeGreaterThan(150);
    expect(refusals.length + loaded).toBe(300);
    sim.load(good);
    expect(sim.hash()).toBe(source.hash());
    source.dispose();
    sim.dispose();
  });
});

describe('the snapshot checksum', () => {
  it('is MurmurHash3 x86_32: the reference vectors', () => {
    const utf8 = (s: string) => new TextEncoder().encode(s);
    expect(murmur3(new Uint8Array(0), 0)).toBe(0);
    expect(murmur3(new Uint8Array(0), 1)).toBe(0x514e28b7);
    expect(murmur3(utf8('hello'), 0)).toBe(0x248bfa47);
    expect(murmur3(utf8('Hello, world!'), 1234)).toBe(0xfaf6cdb3);
    expect(murmur3(utf8('The quick brown fox jumps over the lazy dog'), 0x9747b28c)).toBe(
      0x2fa826cd,
    );
    // The same bytes at an odd offset (a snapshot inside a save) give the same checksum.
    const b = utf8('xThe quick brown fox jumps over the lazy dog');
    expect(murmur3(b.subarray(1), 0x9747b28c)).toBe(0x2fa826cd);
  });
});
