import type { Simulation } from '../sim/simulation.js';
import { FixedLoop } from '../time/fixed-loop.js';
import type { FixedLoopOptions } from '../time/fixed-loop.js';
import { low32 } from './codec.js';
import { ReplayError } from './errors.js';
import { toFactory, type ReplaySource } from './games.js';
import { replayTimestep } from './format.js';
import type { Replay, ReplayHeader, ReplayInputCursor, ReplayKeyframe } from './format.js';

/**
 * Builds a fresh simulation at tick 0 from a replay's header (seeds, config, players). It must
 * build exactly the start the recorder saw: the checkpoint at tick 0 checks that it does.
 */
export type ReplayFactory = (header: ReplayHeader) => Simulation<unknown>;

/**
 * A stored hash that the re-simulation did not reproduce:
 * - `'checkpoint'` — the state hash after `tick` (a multiple of `checkpointEvery`, tick 0 included);
 * - `'tick-hash'` — the low 32 bits of the hash after `tick` (only with per-tick hashes);
 * - `'final'` — the hash after the last tick (when it is not a checkpoint tick);
 * - `'keyframe'` — the keyframe of `tick` did not restore the state the checkpoint describes
 *   (its `load()` threw, or left another tick or hash); the player falls back to an earlier one.
 */
export interface ReplayMismatch {
  /** The tick after which the hashes differ. */
  readonly tick: number;
  /** Which stored value disagreed. */
  readonly kind: 'checkpoint' | 'tick-hash' | 'final' | 'keyframe';
  /** The value in the file (for `'tick-hash'`, the 32 stored bits). */
  readonly expected: bigint;
  /** The value the simulation produced (for `'tick-hash'`, its low 32 bits; -1n if `load()` threw). */
  readonly actual: bigint;
}

/** Options of a {@link ReplayPlayer}. */
export interface ReplayPlayerOptions {
  /** Called once per stored hash the simulation fails to reproduce (each tick and kind reported once). */
  onMismatch?: (mismatch: ReplayMismatch) => void;
  /**
   * Called after every step the player takes, with the new tick. `resimulating` is true for the
   * steps a seek takes to reach its target (a renderer can skip those).
   */
  onTick?: (tick: number, sim: Simulation<unknown>, resimulating: boolean) => void;
  /** Called when playback reaches the last tick (playback then pauses). */
  onEnd?: () => void;
  /** Compare the per-tick hashes too, when the file has them. Costs a `hash()` every tick. Default false. */
  checkTickHashes?: boolean;
  /** Playback speed, from above 0 to 64 (1 = real time). Default 1. */
  speed?: number;
  /**
   * Options of the {@link FixedLoop} that {@link ReplayPlayer.frame} drives. The step is the
   * replay's. Defaults: `maxAccumulatorMs` 16 000 and `maxStepsPerFrame` 4096, so 64× speed is not
   * clamped away.
   */
  loop?: Omit<FixedLoopOptions, 'step' | 'timeScale'>;
  /**
   * Keep a snapshot every this many ticks of the states the player passes, so a seek restores the
   * nearest one and re-simulates at most this many ticks. Default: 300, or more for long replays
   * (at most ~200 snapshots are kept: `max(300, ceil(ticks / 200))`). 0 keeps none (seeks then
   * re-simulate from tick 0, or from keyframes stored in the file). See {@link ReplayPlayer.buildKeyframes}.
   */
  keyframeEvery?: number;
}

/**
 * Plays a replay back by re-simulation: play, pause, speed, seek (through the nearest keyframe,
 * then re-simulation), step forward and back. Checks every stored hash it passes and reports any
 * mismatch through `onMismatch`.
 *
 * Drive it either by a display — {@link frame} / {@link advanceFrame} run as many ticks as the
 * replay's own {@link FixedLoop} says, times the speed — or directly with {@link advance},
 * {@link advanceTo} and {@link seek}. Which display drives it never changes the states it
 * visits: tick t always has the same state.
 *
 * The simulation object ({@link sim}) may be replaced by a seek; read it after each call.
 * Errors thrown by the factory, `load()` or `step()` come out as `'GAME_REJECTED'` {@link ReplayError}s.
 */
export class ReplayPlayer {
  /** The replay being played. */
  readonly replay: Replay;
  private readonly factory: ReplayFactory;
  private readonly options: ReplayPlayerOptions;
  private current: Simulation<unknown>;
  private readonly cursor: ReplayInputCursor;
  private readonly inputs: unknown[] = [];
  private readonly words: Uint32Array;
  /** Snapshots the player took itself, by tick (multiples of {@link cacheEvery}). */
  private readonly cache = new Map<number, Uint8Array>();
  private readonly cacheEvery: number;
  private t = 0;
  private playing = false;
  private speedValue = 1;
  private loopValue: FixedLoop | null = null;
  private readonly badKeyframes = new Set<number>();
  private readonly reported = new Set<string>();
  private first: ReplayMismatch | null = null;

  /**
   * Builds the simulation at tick 0 (and checks it against the checkpoint at tick 0). `game` is a
   * factory, a game definition, or a list of them (the header says which).
   */
  constructor(replay: Replay, game: ReplaySource, options: ReplayPlayerOptions = {}) {
    this.replay = replay;
    this.factory = toFactory(game);
    this.options = options;
    this.cursor = replay.inputCursor();
    this.inputs.length = replay.playerCount;
    this.words = new Uint32Array(replay.playerCount * replay.words);
    const every = options.keyframeEvery ?? Math.max(300, Math.ceil(replay.tickCount / 200));
    if (!Number.isInteger(every) || every < 0) {
      throw new RangeError(
        `ReplayPlayer: keyframeEvery must be a non-negative integer, got ${String(every)}`,
      );
    }
    this.cacheEvery = every;
    this.setSpeed(options.speed ?? 1);
    this.current = this.fresh();
  }

  /** The simulation at the current tick (for rendering; do not step it yourself). */
  get sim(): Simulation<unknown> {
    return this.current;
  }

  /** The current tick, 0 … {@link Replay.tickCount}. */
  get tick(): number {
    return this.t;
  }

  /** Whether the player is at the last tick. */
  get ended(): boolean {
    return this.t >= this.replay.tickCount;
  }

  /** Whether {@link frame} / {@link advanceFrame} advance time. */
  get isPlaying(): boolean {
    return this.playing;
  }

  /** The playback speed. */
  get speed(): number {
    return this.speedValue;
  }

  /** The first mismatch found so far, or null. */
  get firstMismatch(): ReplayMismatch | null {
    return this.first;
  }

  /** The loop that {@link frame} drives (its `alpha` interpolates rendering). */
  get loop(): FixedLoop {
    if (this.loopValue === null) {
      const loop = new FixedLoop({
        maxAccumulatorMs: 16_000,
        maxStepsPerFrame: 4096,
        ...this.options.loop,
        step: replayTimestep(this.replay.header),
        timeScale: this.speedValue,
      });
      if (!this.playing) loop.pause();
      this.loopValue = loop;
    }
    return this.loopValue;
  }

  /** Start (or resume) playback. Does nothing at the end; seek back first. */
  play(): void {
    if (this.ended) return;
    this.playing = true;
    this.loopValue?.resume();
  }

  /** Pause playback: frames keep coming, ticks do not. */
  pause(): void {
    this.playing = false;
    this.loopValue?.pause();
  }

  /** Set the playback speed (above 0, at most 64). It scales how many ticks run, never the step. */
  setSpeed(speed: number): void {
    if (!(Number.isFinite(speed) && speed > 0 && speed <= 64)) {
      throw new RangeError(
        `ReplayPlayer: speed must be above 0 and at most 64, got ${String(speed)}`,
      );
    }
    this.speedValue = speed;
    this.loopValue?.setTimeScale(speed);
  }

  /**
   * Feed one display frame by a clock reading in ms; runs the ticks due. Returns how many ran.
   * Throws a RangeError if the replay's step is not a {@link Timestep} (1/n s, or whole ns from
   * 1 µs to 10 s); {@link advance} and {@link seek} work with any step.
   */
  frame(nowMs: number): number {
    return this.runDue(this.loop.frame(nowMs));
  }

  /** Feed one display frame by its Δt in ms; runs the ticks due. Returns how many ran. */
  advanceFrame(dtMs: number): number {
    return this.runDue(this.loop.advance(dtMs));
  }

  private runDue(n: number): number {
    if (!this.playing) return 0;
    return this.advance(n);
  }

  /** Step `ticks` ticks forward (stopping at the end). Returns how many ran. */
  advance(ticks: number): number {
    if (!Number.isInteger(ticks) || ticks < 0) {
      throw new RangeError(
        `ReplayPlayer.advance: ticks must be a non-negative integer, got ${String(ticks)}`,
      );
    }
    const n = Math.min(ticks, this.replay.tickCount - this.t);
    for (let i = 0; i < n; i++) this.stepOnce(false);
    if (n > 0 && this.ended) this.reachEnd();
    return n;
  }

  /** Go to `tick` (forward by stepping, backward by seeking). Same as {@link seek}. */
  advanceTo(tick: number): void {
    this.seek(tick);
  }

  /** One tick forward (nothing at the end). */
  stepForward(): void {
    this.advance(1);
  }

  /** One tick back: a seek to tick − 1 (nothing at tick 0). */
  stepBack(): void {
    if (this.t > 0) this.seek(this.t - 1);
  }

  /**
   * Go to `tick` (0 … tickCount): restore the last keyframe at or before it (or rebuild tick 0
   * with the factory), then re-simulate up to it — or just step forward when that is shorter.
   * The state reached is the one a run from tick 0 reaches: keyframes only save time.
   */
  seek(tick: number): void {
    const total = this.replay.tickCount;
    if (!Number.isInteger(tick) || tick < 0 || tick > total) {
      throw new RangeError(
        `ReplayPlayer.seek: tick must be an integer from 0 to ${total}, got ${String(tick)}`,
      );
    }
    if (tick === this.t) return;
    let kf = this.usableKeyframe(tick);
    const cached = this.cachedAtOrBefore(tick);
    const best = Math.max(kf?.tick ?? 0, cached);
    if (!(tick > this.t && best <= this.t)) {
      // Restore: the nearest snapshot of our own that loads, else the best stored keyframe that
      // loads cleanly, else tick 0.
      if (!(cached >= (kf?.tick ?? 0) && cached > 0 && this.restoreCached(cached))) {
        for (;;) {
          if (kf === undefined) {
            this.current = this.fresh();
            break;
          }
          if (this.restore(kf)) break;
          kf = this.usableKeyframe(tick);
        }
      }
    }
    while (this.t < tick) this.stepOnce(true);
    if (this.ended) this.reachEnd();
  }

  /**
   * Re-simulate from the furthest state reached to the end once, keeping a snapshot every
   * `keyframeEvery` ticks, so every later seek is short (a 10-minute replay at 60 Hz keeps 120
   * snapshots; at a million ticks a second this takes a few tens of ms). Checks every stored hash
   * on the way, like playback. Returns to the tick it started from. `onProgress(tick, total)` is
   * called every 1 % or so.
   */
  buildKeyframes(onProgress?: (tick: number, total: number) => void): void {
    const from = this.t;
    const total = this.replay.tickCount;
    const every = Math.max(1, Math.floor(total / 100));
    const furthest = this.cachedAtOrBefore(total);
    if (furthest > this.t) this.seek(furthest);
    while (this.t < total) {
      this.stepOnce(true);
      if (this.t % every === 0) onProgress?.(this.t, total);
    }
    onProgress?.(total, total);
    this.seek(from);
  }

  /** Snapshots the player keeps for seeking, and their bytes in all. */
  get cachedKeyframes(): { count: number; bytes: number } {
    let bytes = 0;
    for (const b of this.cache.values()) bytes += b.length;
    return { count: this.cache.size, bytes };
  }

  private cachedAtOrBefore(tick: number): number {
    if (this.cacheEvery === 0) return 0;
    for (let t = tick - (tick % this.cacheEvery); t > 0; t -= this.cacheEvery) {
      if (this.cache.has(t)) return t;
    }
    return 0;
  }

  private restoreCached(tick: number): boolean {
    try {
      // A copy: a load() that keeps a view of its bytes must not write into the cache.
      this.current.load(this.cache.get(tick)!.slice());
      if (this.current.tick !== tick) throw new RangeError('load() left another tick');
    } catch {
      this.cache.delete(tick);
      return false;
    }
    this.t = tick;
    this.cursor.seek(tick);
    return true;
  }

  private usableKeyframe(tick: number): ReplayKeyframe | undefined {
    const kfs = this.replay.keyframes;
    for (let k = this.replay.keyframeAtOrBefore(tick); k !== undefined;) {
      if (!this.badKeyframes.has(k.tick)) return k;
      const i = k.tick / this.replay.keyframeEvery - 2;
      k = i >= 0 ? kfs[i] : undefined;
    }
    return undefined;
  }

  /** Load a keyframe and check it against the checkpoint at its tick; false (and reported) if it fails. */
  private restore(kf: ReplayKeyframe): boolean {
    const expected = this.replay.checkpointAt(kf.tick)!;
    let actual = -1n;
    try {
      // A copy: a load() that keeps a view of its bytes must not write into the file.
      this.current.load(kf.bytes.slice());
      if (this.current.tick === kf.tick) actual = BigInt.asUintN(64, this.current.hash());
    } catch {
      actual = -1n;
    }
    if (actual !== expected) {
      this.badKeyframes.add(kf.tick);
      this.report({ tick: kf.tick, kind: 'keyframe', expected, actual });
      return false;
    }
    this.t = kf.tick;
    this.cursor.seek(kf.tick);
    return true;
  }

  private fresh(): Simulation<unknown> {
    const sim = createSimulation(this.factory, this.replay.header);
    this.t = 0;
    this.cursor.seek(0);
    const expected = this.replay.checkpoints[0]!;
    const actual = BigInt.asUintN(64, sim.hash());
    if (actual !== expected) this.report({ tick: 0, kind: 'checkpoint', expected, actual });
    return sim;
  }

  private stepOnce(resimulating: boolean): void {
    const sim = this.current;
    const r = this.replay;
    this.cursor.nextWords(this.words);
    const schema = r.header.input;
    for (let p = 0; p < this.inputs.length; p++)
      this.inputs[p] = schema.decode(this.words, p * r.words);
    const tick = this.t + 1;
    try {
      sim.step(this.inputs);
    } catch (e) {
      throw new ReplayError(
        'GAME_REJECTED',
        `the simulation threw on tick ${this.t}: ${String(e)}`,
        -1,
        e,
      );
    }
    this.t = tick;
    if (this.cacheEvery !== 0 && tick % this.cacheEvery === 0 && !this.cache.has(tick)) {
      this.cache.set(tick, sim.save());
    }
    const onCheckpoint = tick % r.checkpointEvery === 0;
    const last = tick === r.tickCount;
    const tickHashes = this.options.checkTickHashes === true ? r.tickHashes : null;
    if (onCheckpoint || last || tickHashes !== null) {
      const h = BigInt.asUintN(64, sim.hash());
      if (onCheckpoint) {
        const expected = r.checkpoints[tick / r.checkpointEvery]!;
        if (h !== expected) this.report({ tick, kind: 'checkpoint', expected, actual: h });
      } else if (tickHashes !== null && tickHashes[tick - 1] !== low32(h)) {
        this.report({
          tick,
          kind: 'tick-hash',
          expected: BigInt(tickHashes[tick - 1]!),
          actual: BigInt(low32(h)),
        });
      } else if (last && h !== r.finalHash) {
        this.report({ tick, kind: 'final', expected: r.finalHash, actual: h });
      }
    }
    this.options.onTick?.(tick, sim, resimulating);
  }

  private reachEnd(): void {
    if (this.playing) {
      this.playing = false;
      this.loopValue?.pause();
    }
    this.options.onEnd?.();
  }

  private report(m: ReplayMismatch): void {
    const key = `${m.kind}:${m.tick}`;
    if (this.reported.has(key)) return;
    this.reported.add(key);
    if (this.first === null || m.tick < this.first.tick) this.first = m;
    this.options.onMismatch?.(m);
  }
}

/** Calls a factory, turning its errors into `'GAME_REJECTED'` and checking it starts at tick 0. @internal */
export function createSimulation(
  factory: ReplayFactory,
  header: ReplayHeader,
): Simulation<unknown> {
  let sim: Simulation<unknown>;
  try {
    sim = factory(header);
  } catch (e) {
    throw new ReplayError(
      'GAME_REJECTED',
      `the game's factory refused the header: ${String(e)}`,
      -1,
      e,
    );
  }
  if (sim.tick !== 0) {
    throw new RangeError(`replay factory: the simulation starts at tick ${sim.tick}, not 0`);
  }
  return sim;
}
