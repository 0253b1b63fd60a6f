import { fnv1a64 } from '../det/hash.js';
import { low32 } from './codec.js';
import { ReplayError } from './errors.js';
import { Replay, checkGame, readReplay } from './format.js';
import type { ReadReplayOptions } from './format.js';
import { createSimulation } from './player.js';
import type { ReplayMismatch } from './player.js';
import { toFactory, type ReplaySource } from './games.js';

/** Options of {@link verifyReplay}. */
export interface VerifyReplayOptions extends ReadReplayOptions {
  /** Called every `progressEvery` ticks and once at the end, with the tick reached and the total. */
  onProgress?: (tick: number, total: number) => void;
  /** Ticks between progress reports. Default 1 % of the replay (at least 1). */
  progressEvery?: number;
  /** Also compare every keyframe, byte for byte, with `save()` at its tick. Default true. */
  checkKeyframes?: boolean;
}

/**
 * What {@link verifyReplay} found. Where the first divergence lies, given the data in the file:
 * the state after `lastGoodTick` matched a stored hash, the state after `firstMismatchTick` did
 * not, so the first tick whose state differs is in (`lastGoodTick`, `firstMismatchTick`]. With
 * per-tick hashes (or a mismatch right after a good tick) that range is one tick and `exact` is
 * true; with checkpoints only, it is at most one checkpoint interval.
 */
export interface VerifyResult {
  /** True when every stored hash (and keyframe, if checked) was reproduced. */
  readonly ok: boolean;
  /** Ticks in the replay. */
  readonly ticks: number;
  /** Ticks re-simulated (verification stops at the first mismatch), skipped ones included. */
  readonly simulated: number;
  /**
   * The tick after which the game declared its state frozen (`Simulation.frozen`), from
   * which the remaining ticks were jumped over with `skip()` rather than stepped — every stored
   * hash and keyframe still computed and compared; -1 if every tick was stepped.
   */
  readonly frozenFrom: number;
  /** The first tick after which a stored value was not reproduced, or -1. */
  readonly firstMismatchTick: number;
  /** Which stored value it was, or null. */
  readonly kind: ReplayMismatch['kind'] | null;
  /**
   * The stored value (a checkpoint or final hash; the 32 bits of a tick hash; for a keyframe,
   * FNV-1a 64 of its stored bytes), or null.
   */
  readonly expected: bigint | null;
  /** The value the simulation produced (for a keyframe, FNV-1a 64 of `save()`), or null. */
  readonly actual: bigint | null;
  /** The last tick whose state matched a stored hash (-1 if even tick 0 did not); `ticks` when ok. */
  readonly lastGoodTick: number;
  /** Whether `firstMismatchTick` is exactly the first tick whose state differs (see above). */
  readonly exact: boolean;
  /** The parsed replay. */
  readonly replay: Replay;
}

/**
 * Re-simulate a replay from tick 0 with the game's factory and compare every stored hash: the
 * checkpoint at tick 0 (the factory rebuilt the same start: same seeds, same config), every
 * checkpoint, every per-tick hash when present, every keyframe, the final hash.
 *
 * A game whose state is `Simulation.frozen` (a finished match) is not stepped through
 * the rest of the file: it is moved from one stored hash to the next with `skip()`, and each of
 * those hashes is still computed and compared — a file whose hashes after the end are not those
 * of the frozen state is refused as before, at the first such tick.
 *
 * `input` is the file's bytes (parsed with `options`' limits and expectations) or a parsed
 * {@link Replay} (checked against `options.gameId`/`gameVersion` only).
 *
 * Throws a {@link ReplayError} for a file that does not parse (see {@link readReplay}) and
 * `'GAME_REJECTED'` when the game's factory, or its `step()` or `skip()`, throws; a file that parses but does
 * not replay is `{ ok: false }`. Runs at most `tickCount` steps (bounded by `limits.maxTicks`).
 */
export function verifyReplay(
  input: Uint8Array | Replay,
  game: ReplaySource,
  options: VerifyReplayOptions = {},
): VerifyResult {
  const factory = toFactory(game);
  let replay: Replay;
  if (input instanceof Replay) {
    replay = input;
    checkGame(replay.header, options, replay.sections[0]?.offset ?? -1);
  } else {
    replay = readReplay(input, options);
  }
  const total = replay.tickCount;
  const every = options.progressEvery ?? Math.max(1, Math.floor(total / 100));
  if (!Number.isInteger(every) || every < 1) {
    throw new RangeError(
      `verifyReplay: progressEvery must be a positive integer, got ${String(every)}`,
    );
  }
  const checkKeyframes = options.checkKeyframes ?? true;
  const n = replay.checkpointEvery;
  const m = replay.keyframeEvery;
  const tickHashes = replay.tickHashes;

  const sim = createSimulation(factory, replay.header);
  let lastGood = -1;
  let frozenFrom = -1;
  const fail = (
    tick: number,
    kind: ReplayMismatch['kind'],
    expected: bigint,
    actual: bigint,
  ): VerifyResult => ({
    ok: false,
    ticks: total,
    simulated: sim.tick,
    frozenFrom,
    firstMismatchTick: tick,
    kind,
    expected,
    actual,
    lastGoodTick: lastGood,
    exact: tick === 0 || tick - lastGood === 1,
    replay,
  });

  const h0 = BigInt.asUintN(64, sim.hash());
  if (h0 !== replay.checkpoints[0]) return fail(0, 'checkpoint', replay.checkpoints[0]!, h0);
  lastGood = 0;

  const cursor = replay.inputCursor();
  const schema = replay.header.input;
  const w = replay.words;
  const words = new Uint32Array(replay.playerCount * w);
  const inputs: unknown[] = new Array<unknown>(replay.playerCount).fill(0);
  const canSkip = typeof sim.skip === 'function';
  let nextProgress = every;
  // From one tick with something to check (a stored hash or keyframe, a progress report) to the
  // next: stepped tick by tick — or, once the game says its state is frozen, jumped over with
  // skip(), since no input can change it any more. Either way every stored value is compared.
  for (let t = 0; t < total;) {
    let next = Math.min(total, nextProgress, nextMultiple(t, n));
    if (tickHashes !== null) next = t + 1;
    if (checkKeyframes && m !== 0) next = Math.min(next, nextMultiple(t, m));
    try {
      if (frozenFrom >= 0) {
        sim.skip!(next - t);
        if (sim.tick !== next) throw new RangeError(`skip() left tick ${sim.tick}, not ${next}`);
        t = next;
      } else {
        for (; t < next; t++) {
          cursor.nextWords(words);
          for (let p = 0; p < inputs.length; p++) inputs[p] = schema.decode(words, p * w);
          sim.step(inputs);
        }
      }
    } catch (e) {
      throw new ReplayError(
        'GAME_REJECTED',
        `the simulation threw on tick ${t}: ${String(e)}`,
        -1,
        e,
      );
    }
    const onCheckpoint = t % n === 0;
    if (onCheckpoint || tickHashes !== null || t === total) {
      const h = BigInt.asUintN(64, sim.hash());
      if (onCheckpoint) {
        const expected = replay.checkpoints[t / n]!;
        if (h !== expected) return fail(t, 'checkpoint', expected, h);
      } else if (tickHashes !== null && tickHashes[t - 1] !== low32(h)) {
        return fail(t, 'tick-hash', BigInt(tickHashes[t - 1]!), BigInt(low32(h)));
      } else if (t === total && h !== replay.finalHash) {
        return fail(t, 'final', replay.finalHash, h);
      }
      lastGood = t;
    }
    if (checkKeyframes && m !== 0 && t % m === 0) {
      const stored = replay.keyframes[t / m - 1]!.bytes;
      const saved = sim.save();
      if (!equalBytes(stored, saved)) {
        return fail(t, 'keyframe', fnv1a64(stored), fnv1a64(saved));
      }
    }
    if (t === nextProgress) {
      options.onProgress?.(t, total);
      nextProgress += every;
    }
    if (frozenFrom < 0 && canSkip && sim.frozen === true) frozenFrom = t;
  }
  if (total % every !== 0 || total === 0) options.onProgress?.(total, total);
  return {
    ok: true,
    ticks: total,
    simulated: total,
    frozenFrom,
    firstMismatchTick: -1,
    kind: null,
    expected: null,
    actual: null,
    lastGoodTick: total,
    exact: true,
    replay,
  };
}

/** The first multiple of `every` after `t`. */
function nextMultiple(t: number, every: number): number {
  return t - (t % every) + every;
}

function equalBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}
