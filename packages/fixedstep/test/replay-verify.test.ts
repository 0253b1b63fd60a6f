import { describe, expect, it } from 'vitest';
import { ReplayError, ReplayPlayer, packButtons, readReplay, verifyReplay } from 'fixedstep';
import type { ReplayMismatch } from 'fixedstep';
import { FIRE, JUMP, arenaFactory, forge, recordArena, reseal } from './replay-fixture.js';

const TICKS = 6000;
const reference = recordArena({ ticks: TICKS, seed: 3, checkpointEvery: 60, keyframeEvery: 600 });
const withTickHashes = recordArena({
  ticks: TICKS,
  seed: 3,
  checkpointEvery: 60,
  keyframeEvery: 600,
  tickHashes: true,
});

/** The reference inputs with player 0's input at tick `t` turned into a jump + fire press. */
function cheat(t: number): Uint32Array {
  const inputs = reference.inputs.slice();
  inputs[t * 2] = packButtons(1 << JUMP, (1 << JUMP) | (1 << FIRE));
  expect(inputs[t * 2]).not.toBe(reference.inputs[t * 2]);
  return inputs;
}

describe('replay verification', () => {
  it('detects a forged input at the first checkpoint after it (checkpoints only)', () => {
    const forged = forge(reference, { ticks: TICKS, seed: 3, inputs: cheat(5000) });
    // The input of tick 5000 drives the step to tick 5001: states from 5001 on differ. The last
    // checkpoint before is 4980, the first after is 5040.
    const result = verifyReplay(forged, arenaFactory);
    expect(result).toMatchObject({
      ok: false,
      kind: 'checkpoint',
      firstMismatchTick: 5040,
      lastGoodTick: 4980,
      exact: false,
      simulated: 5040,
    });
    expect(result.expected).toBe(reference.hashes[5040]);
    expect(result.actual).not.toBe(reference.hashes[5040]);
  });

  it('names the exact tick with per-tick hashes', () => {
    const forged = forge(withTickHashes, {
      ticks: TICKS,
      seed: 3,
      inputs: cheat(5000),
      tickHashes: true,
    });
    expect(verifyReplay(forged, arenaFactory)).toMatchObject({
      ok: false,
      kind: 'tick-hash',
      firstMismatchTick: 5001,
      lastGoodTick: 5000,
      exact: true,
    });
    expect(verifyReplay(withTickHashes.bytes, arenaFactory).ok).toBe(true);
  });

  it('the player reports the forged checkpoint as it passes it', () => {
    const forged = forge(reference, { ticks: TICKS, seed: 3, inputs: cheat(5000) });
    const seen: ReplayMismatch[] = [];
    const player = new ReplayPlayer(readReplay(forged), arenaFactory, {
      onMismatch: (m) => seen.push(m),
    });
    player.seek(5039);
    expect(seen).toEqual([]);
    player.stepForward();
    expect(seen.map((m) => [m.kind, m.tick])).toEqual([['checkpoint', 5040]]);
    player.advance(TICKS);
    expect(player.firstMismatch?.tick).toBe(5040);
    expect(seen.at(-1)?.kind).toBe('checkpoint');
    expect(seen.at(-1)?.tick).toBe(6000);
    // Passing the same checkpoint again does not report it twice.
    const n = seen.length;
    player.seek(5030);
    player.seek(5050);
    expect(seen).toHaveLength(n);
  });

  it('a replay claiming another seed fails at tick 0', () => {
    const forged = forge(reference, { ticks: TICKS, seed: 4 });
    expect(readReplay(forged).header.seeds).toEqual([4]);
    expect(verifyReplay(forged, arenaFactory)).toMatchObject({
      ok: false,
      kind: 'checkpoint',
      firstMismatchTick: 0,
      lastGoodTick: -1,
      exact: true,
      simulated: 0,
    });
  });

  it('the same inputs with another seed give another replay', () => {
    const other = recordArena({ ticks: TICKS, seed: 4, checkpointEvery: 60 });
    expect(verifyReplay(other.bytes, arenaFactory).ok).toBe(true);
    expect(other.hashes[TICKS]).not.toBe(reference.hashes[TICKS]);
  });

  it('a tampered keyframe fails verification; the player falls back to an earlier one', () => {
    const bytes = reference.bytes.slice();
    const kf = readReplay(bytes).keyframes[4]!; // tick 3000
    bytes[kf.offset + 40] = bytes[kf.offset + 40]! ^ 0x10; // inside a float
    reseal(bytes);
    expect(verifyReplay(bytes, arenaFactory)).toMatchObject({
      ok: false,
      kind: 'keyframe',
      firstMismatchTick: 3000,
      lastGoodTick: 3000,
    });
    const seen: ReplayMismatch[] = [];
    const player = new ReplayPlayer(readReplay(bytes), arenaFactory, {
      onMismatch: (m) => seen.push(m),
    });
    player.seek(3300);
    expect(player.sim.hash()).toBe(reference.hashes[3300]);
    expect(seen.map((m) => [m.kind, m.tick])).toEqual([['keyframe', 3000]]);
    player.seek(3100);
    expect(player.sim.hash()).toBe(reference.hashes[3100]);
    expect(seen).toHaveLength(1);
  });

  it('a keyframe whose load() throws is reported and skipped', () => {
    const bytes = reference.bytes.slice();
    const kf = readReplay(bytes).keyframes[0]!; // tick 600
    bytes[kf.offset + 20] = 0xff; // the body count
    reseal(bytes);
    const seen: ReplayMismatch[] = [];
    const player = new ReplayPlayer(readReplay(bytes), arenaFactory, {
      onMismatch: (m) => seen.push(m),
    });
    player.seek(700);
    player.seek(650);
    expect(player.sim.hash()).toBe(reference.hashes[650]);
    expect(seen).toEqual([
      { tick: 600, kind: 'keyframe', expected: reference.hashes[600], actual: -1n },
    ]);
  });

  it('refuses a replay of another game or version, when asked to', () => {
    const codeOf = (f: () => unknown): string => {
      try {
        f();
        return 'no error';
      } catch (e) {
        return e instanceof ReplayError ? e.code : `not a ReplayError: ${String(e)}`;
      }
    };
    const expectCode = (f: () => unknown, code: string) => {
      expect(codeOf(f)).toBe(code);
    };
    expectCode(() => readReplay(reference.bytes, { gameId: 'ctf' }), 'WRONG_GAME');
    expectCode(() => readReplay(reference.bytes, { gameVersion: '2.0.0' }), 'WRONG_GAME');
    expectCode(
      () => verifyReplay(reference.bytes, arenaFactory, { gameVersion: (v) => v.startsWith('2.') }),
      'WRONG_GAME',
    );
    expect(readReplay(reference.bytes, { gameVersion: (v) => v.startsWith('1.') }).tickCount).toBe(
      TICKS,
    );
    const thrower = () => {
      throw new RangeError('bad config');
    };
    expectCode(() => verifyReplay(reference.bytes, thrower), 'GAME_REJECTED');
    expectCode(() => new ReplayPlayer(readReplay(reference.bytes), thrower), 'GAME_REJECTED');
  });
});
