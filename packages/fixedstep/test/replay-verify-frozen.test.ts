/**
 * `verifyReplay` and a game that ends: once the simulation declares its state frozen
 * (`Simulation.frozen`), the verifier jumps from one stored hash to the next with `skip()` instead
 * of stepping. These tests check that this saves the steps and nothing else: every hash after the
 * end is still computed and compared, so a file forged after the end is refused where it was
 * refused before, and an honest file gives the same result as when every tick is stepped.
 */
import { describe, expect, it } from 'vitest';
import { ReplayError, ReplayRecorder, readReplay, verifyReplay } from 'fixedstep';
import {
  Arena,
  DEFAULT_CONFIG,
  GAME_ID,
  GAME_VERSION,
  botInputs,
  configBytes,
  parseConfig,
} from './replay-fixture.js';
import type { ReplayHeader, VerifyResult } from 'fixedstep';

/** Ticks in every file; the match ends after {@link END}. */
const TICKS = 3000;
const END = 1234;
const PLAYERS = 2;

/**
 * The fixture's arena, over after {@link END} ticks: from then on a step only counts the tick. It
 * does not say so (no `frozen`, no `skip`): the verifier steps it to the last tick.
 */
class EndingArena extends Arena {
  /** `step()` calls so far. */
  steps = 0;
  override step(inputs: readonly number[]): void {
    this.steps++;
    if (this.tick >= END) this.tick++;
    else super.step(inputs);
  }
}

/** The same game, saying that it is frozen after the end and skipping ticks then. */
class FreezingArena extends EndingArena {
  /** `skip()` calls so far. */
  skips = 0;
  /** Ticks to add to what `skip` is asked (a broken game), 0 for an honest one. */
  skipError = 0;
  get frozen(): boolean {
    return this.tick >= END;
  }
  skip(ticks: number): void {
    if (!this.frozen) throw new RangeError('not over');
    this.skips++;
    this.tick += ticks + this.skipError;
  }
}

/** A factory of `Game`s for a header (as the fixture's), that keeps the last one it built. */
function factoryOf<S extends EndingArena>(
  Game: new (...args: ConstructorParameters<typeof Arena>) => S,
) {
  const f = (header: ReplayHeader): S =>
    (f.last = new Game(parseConfig(header.config), header.seeds[0] ?? 0, header.players.length));
  f.last = undefined as S | undefined;
  return f;
}

const stepped = factoryOf(EndingArena);
const freezing = factoryOf(FreezingArena);

interface Recording {
  checkpointEvery?: number;
  keyframeEvery?: number;
  tickHashes?: boolean;
  /** Store this value instead of the state's hash after `tick` (a checkpoint, tick hash or the final hash). */
  forgeHash?: { tick: number; hash: bigint };
  /** Store this state instead of the one after `tick` (a keyframe). */
  forgeKeyframe?: { tick: number; bytes: Uint8Array };
}

/** Records the ending arena; the hashes and keyframes it writes are the game's, but for the forgeries. */
function record(o: Recording = {}): Uint8Array {
  const game = new EndingArena(DEFAULT_CONFIG, 5, PLAYERS);
  const inputs = botInputs(11, TICKS, PLAYERS);
  const rec = new ReplayRecorder({
    gameId: GAME_ID,
    gameVersion: GAME_VERSION,
    tickRate: 60,
    seeds: [5],
    config: configBytes(),
    players: ['ada', 'grace'],
    checkpointEvery: o.checkpointEvery ?? 60,
    keyframeEvery: o.keyframeEvery ?? 0,
    tickHashes: o.tickHashes ?? false,
  });
  // What the recorder reads: the game, but for the forged values.
  const seen = {
    get tick() {
      return game.tick;
    },
    hash: () => (o.forgeHash?.tick === game.tick ? o.forgeHash.hash : game.hash()),
    save: () => (o.forgeKeyframe?.tick === game.tick ? o.forgeKeyframe.bytes : game.save()),
  };
  rec.start(seen);
  const frame = new Array<number>(PLAYERS).fill(0);
  for (let t = 0; t < TICKS; t++) {
    for (let p = 0; p < PLAYERS; p++) frame[p] = inputs[t * PLAYERS + p]!;
    game.step(frame);
    rec.record(frame, seen);
  }
  return rec.finish();
}

/** The result without what only the skipping verifier reports (and the parsed file). */
function comparable(r: VerifyResult): Record<string, unknown> {
  return { ...r, frozenFrom: -1, replay: undefined };
}

describe('verifying a replay of a game that ends', () => {
  const honest = record({ keyframeEvery: 600 });
  /** The first checkpoint at or after the end: where the verifier sees the frozen state. */
  const frozenFrom = Math.ceil(END / 60) * 60;

  it('skips the ticks after the end, and answers as when every tick is stepped', () => {
    const progress: number[] = [];
    const skipping = verifyReplay(honest, freezing, {
      onProgress: (t) => progress.push(t),
      progressEvery: 500,
    });
    expect(skipping).toMatchObject({ ok: true, ticks: TICKS, simulated: TICKS, frozenFrom });
    expect(freezing.last!.steps).toBe(frozenFrom);
    expect(freezing.last!.skips).toBeGreaterThan(0);
    expect(freezing.last!.tick).toBe(TICKS);

    const steppedProgress: number[] = [];
    const all = verifyReplay(honest, stepped, {
      onProgress: (t) => steppedProgress.push(t),
      progressEvery: 500,
    });
    expect(all.frozenFrom).toBe(-1);
    expect(stepped.last!.steps).toBe(TICKS);
    expect(comparable(skipping)).toEqual(comparable(all));
    // The final states are the same, so whatever is read from them (a score) is too.
    expect(freezing.last!.save()).toEqual(stepped.last!.save());
    expect(progress).toEqual(steppedProgress);
    expect(progress).toEqual([500, 1000, 1500, 2000, 2500, 3000]);
  });

  it.each([
    ['the first checkpoint after the end', frozenFrom + 60],
    ['a later checkpoint', 2400],
    ['the last checkpoint', TICKS],
  ])('refuses a file whose hash at %s is forged', (_, tick) => {
    const forged = record({ forgeHash: { tick, hash: 0x0123456789abcdefn } });
    const result = verifyReplay(forged, freezing);
    expect(result).toMatchObject({
      ok: false,
      kind: 'checkpoint',
      firstMismatchTick: tick,
      lastGoodTick: tick - 60,
      expected: 0x0123456789abcdefn,
      frozenFrom,
    });
    expect(comparable(result)).toEqual(comparable(verifyReplay(forged, stepped)));
  });

  it('checks the final hash when the last tick is no checkpoint', () => {
    const honestOdd = record({ checkpointEvery: 7 });
    expect(TICKS % 7).not.toBe(0);
    expect(verifyReplay(honestOdd, freezing)).toMatchObject({ ok: true });
    const forged = record({ checkpointEvery: 7, forgeHash: { tick: TICKS, hash: 42n } });
    expect(readReplay(forged).finalHash).toBe(42n);
    expect(verifyReplay(forged, freezing)).toMatchObject({
      ok: false,
      kind: 'final',
      firstMismatchTick: TICKS,
      expected: 42n,
    });
  });

  it('compares the keyframes after the end', () => {
    const before = new Arena(DEFAULT_CONFIG, 5, PLAYERS);
    const forged = record({
      keyframeEvery: 600,
      forgeKeyframe: { tick: 2400, bytes: before.save() },
    });
    expect(verifyReplay(forged, freezing)).toMatchObject({
      ok: false,
      kind: 'keyframe',
      firstMismatchTick: 2400,
      frozenFrom,
    });
  });

  it('with per-tick hashes: skips one tick at a time and names a forged one exactly', () => {
    expect(verifyReplay(record({ tickHashes: true }), freezing)).toMatchObject({
      ok: true,
      frozenFrom: END,
    });
    expect(freezing.last!.steps).toBe(END);
    const forged = record({ tickHashes: true, forgeHash: { tick: 2001, hash: 7n } });
    expect(verifyReplay(forged, freezing)).toMatchObject({
      ok: false,
      kind: 'tick-hash',
      firstMismatchTick: 2001,
      lastGoodTick: 2000,
      exact: true,
    });
  });

  it('a game whose skip() does not reach the tick asked is rejected, not trusted', () => {
    class Broken extends FreezingArena {
      override skipError = 1;
    }
    const broken = factoryOf(Broken);
    expect(() => verifyReplay(honest, broken)).toThrow(
      expect.objectContaining({ code: 'GAME_REJECTED' }) as ReplayError,
    );
  });
});
