import { describe, expect, it } from 'vitest';
import {
  Random,
  ReplayPlayer,
  ReplayRecorder,
  SimulatedDisplay,
  Timestep,
  fnv1a64Hex,
  hex64,
  readReplay,
  replayTimestep,
  verifyReplay,
} from 'fixedstep';
import type { RecordedRun } from './replay-fixture.js';
import {
  Arena,
  DEFAULT_CONFIG,
  GAME_ID,
  GAME_VERSION,
  arenaFactory,
  configBytes,
  recordArena,
} from './replay-fixture.js';

const TICKS = 10_000;
const run: RecordedRun = recordArena({
  ticks: TICKS,
  players: 2,
  seed: 42,
  checkpointEvery: 60,
  keyframeEvery: 600,
});

describe('replay round trip', () => {
  it('reads back the header, the inputs, the hashes and the keyframes', () => {
    const r = readReplay(run.bytes, { gameId: GAME_ID, gameVersion: GAME_VERSION });
    expect(r.header).toMatchObject({
      formatVersion: 2,
      gameId: GAME_ID,
      gameVersion: GAME_VERSION,
      stepNumerator: 1,
      stepDenominator: 60,
      seeds: [42],
      players: ['player 1', 'player 2'],
    });
    expect([...r.header.config]).toEqual([...configBytes()]);
    expect(r.tickCount).toBe(TICKS);
    expect(r.finalHash).toBe(run.hashes[TICKS]);
    expect(r.checkpoints).toHaveLength(Math.floor(TICKS / 60) + 1);
    r.checkpoints.forEach((h, i) => {
      expect(h).toBe(run.hashes[i * 60]);
    });
    expect(r.keyframes.map((k) => k.tick)).toEqual(
      Array.from({ length: 16 }, (_, i) => (i + 1) * 600),
    );
    expect(r.tickHashes).toBeNull();
    expect(r.sections.map((s) => s.name)).toEqual([
      'GAME',
      'TICKS',
      'INPUTS',
      'CHECKPOINTS',
      'KEYFRAMES',
    ]);
    expect(replayTimestep(r.header).hz).toBe(60);
    // Any Uint8Array will do, e.g. a Node Buffer at an offset in a larger pool.
    const pool = new Uint8Array(run.bytes.length + 13);
    pool.set(run.bytes, 13);
    expect(readReplay(pool.subarray(13)).finalHash).toBe(r.finalHash);
    expect(readReplay(Buffer.from(run.bytes)).tickCount).toBe(TICKS);

    const cursor = r.inputCursor();
    const frame: number[] = [];
    for (let t = 0; t < TICKS; t++) {
      cursor.next(frame);
      expect(frame[0]).toBe(run.inputs[t * 2]);
      expect(frame[1]).toBe(run.inputs[t * 2 + 1]);
    }
    const rng = new Random(3);
    for (let i = 0; i < 500; i++) {
      const t = rng.int(TICKS);
      expect(r.inputsAt(t)).toEqual([run.inputs[t * 2], run.inputs[t * 2 + 1]]);
      expect(r.input(t, 1)).toBe(run.inputs[t * 2 + 1]);
    }
  });

  it('verifies: re-simulation reproduces every checkpoint, keyframe and the final hash', () => {
    const progress: number[] = [];
    const result = verifyReplay(run.bytes, arenaFactory, {
      onProgress: (t, total) => {
        expect(total).toBe(TICKS);
        progress.push(t);
      },
    });
    expect(result).toMatchObject({
      ok: true,
      ticks: TICKS,
      simulated: TICKS,
      firstMismatchTick: -1,
      lastGoodTick: TICKS,
    });
    expect(progress).toHaveLength(100);
    expect(progress.at(-1)).toBe(TICKS);
  });

  it('seek(t) lands on the state a fresh run reaches at t, for random t, in any order', () => {
    const mismatches: unknown[] = [];
    const player = new ReplayPlayer(readReplay(run.bytes), arenaFactory, {
      onMismatch: (m) => mismatches.push(m),
    });
    const rng = new Random(11);
    const targets = [0, 1, 599, 600, 601, TICKS - 1, TICKS, 5000, 4999, 1200];
    for (let i = 0; i < 60; i++) targets.push(rng.int(TICKS + 1));
    for (const t of targets) {
      player.seek(t);
      expect(player.tick).toBe(t);
      expect(player.sim.tick).toBe(t);
      expect(hex64(player.sim.hash())).toBe(hex64(run.hashes[t]!));
    }
    expect(mismatches).toEqual([]);
    expect(player.firstMismatch).toBeNull();
  });

  it('steps back and forward tick by tick', () => {
    const player = new ReplayPlayer(readReplay(run.bytes), arenaFactory);
    player.advanceTo(1805);
    for (let t = 1804; t >= 1795; t--) {
      player.stepBack();
      expect(player.tick).toBe(t);
      expect(player.sim.hash()).toBe(run.hashes[t]);
    }
    for (let t = 1796; t <= 1810; t++) {
      player.stepForward();
      expect(player.sim.hash()).toBe(run.hashes[t]);
    }
    player.seek(0);
    player.stepBack();
    expect(player.tick).toBe(0);
    player.seek(TICKS);
    player.stepForward();
    expect(player.tick).toBe(TICKS);
    expect(player.ended).toBe(true);
  });

  it('plays identically at any display rate and speed (per-tick hashes)', () => {
    const expected = run.hashes.slice(1).map(hex64);
    const replay = readReplay(run.bytes);
    const playAt = (hz: number, jitter: number, speed: number) => {
      const seen: string[] = [];
      let ended = 0;
      const player = new ReplayPlayer(replay, arenaFactory, {
        speed,
        onTick: (_t, sim, resimulating) => {
          expect(resimulating).toBe(false);
          seen.push(hex64(sim.hash()));
        },
        onEnd: () => ended++,
      });
      player.play();
      const display = new SimulatedDisplay({ hz, jitter, seed: hz });
      let frames = 0;
      while (!player.ended && frames < 1_000_000) {
        player.frame(display.next().time);
        frames++;
      }
      expect(ended).toBe(1);
      expect(player.isPlaying).toBe(false);
      return { seen, frames };
    };
    const at30 = playAt(30, 0, 1);
    const at144 = playAt(144, 0.2, 1);
    const fast = playAt(60, 0, 8);
    expect(at30.seen).toEqual(expected);
    expect(at144.seen).toEqual(expected);
    expect(fast.seen).toEqual(expected);
    // Real time: 10 000 ticks at 60 Hz are 166.7 s, whatever the display.
    expect(at30.frames).toBeGreaterThanOrEqual(5000);
    expect(at30.frames).toBeLessThanOrEqual(5002);
    expect(at144.frames).toBeGreaterThan(20_000);
    expect(fast.frames).toBeLessThanOrEqual(1252);
  });

  it('pauses and resumes; the paused time is not played', () => {
    const player = new ReplayPlayer(readReplay(run.bytes), arenaFactory);
    expect(player.advanceFrame(0)).toBe(0);
    player.play();
    expect(player.advanceFrame(1000)).toBe(60);
    player.pause();
    expect(player.advanceFrame(5000)).toBe(0);
    player.play();
    expect(player.advanceFrame(500)).toBe(30);
    expect(player.tick).toBe(90);
    player.setSpeed(2);
    expect(player.advanceFrame(500)).toBe(60);
    expect(player.sim.hash()).toBe(run.hashes[150]);
    expect(() => {
      player.setSpeed(0);
    }).toThrow(RangeError);
  });

  it('writes identical bytes for identical runs, and a golden file hash', () => {
    const a = recordArena({ ticks: 600, seed: 5, keyframeEvery: 120, tickHashes: true });
    const b = recordArena({ ticks: 600, seed: 5, keyframeEvery: 120, tickHashes: true });
    expect(fnv1a64Hex(a.bytes)).toBe(fnv1a64Hex(b.bytes));
    // Re-bless on a deliberate change of the format, the arena or the bot (print the actual value).
    const golden = fnv1a64Hex(a.bytes);
    if (golden !== GOLDEN_FILE_HASH) console.log(`replay golden file hash: ${golden}`);
    expect(golden).toBe(GOLDEN_FILE_HASH);
  });

  it('finish() can be called mid-recording; recording goes on', () => {
    const sim = new Arena(DEFAULT_CONFIG, 9, 1);
    const rec = new ReplayRecorder({
      gameId: GAME_ID,
      gameVersion: GAME_VERSION,
      tickRate: Timestep.fromMs(30),
      seeds: [9],
      config: configBytes(),
      players: ['solo'],
      checkpointEvery: 10,
      keyframeEvery: 50,
      tickHashes: true,
    });
    rec.start(sim);
    const empty = readReplay(rec.finish());
    expect(empty.tickCount).toBe(0);
    expect(empty.finalHash).toBe(empty.checkpoints[0]);
    expect(verifyReplay(empty, arenaFactory).ok).toBe(true);
    let midway: Uint8Array = new Uint8Array(0);
    for (let t = 0; t < 123; t++) {
      const input = t % 17 < 5 ? 1 : 0;
      sim.step([input]);
      rec.record([input], sim);
      if (t === 76) midway = rec.finish();
    }
    const mid = readReplay(midway);
    expect(mid.tickCount).toBe(77);
    expect(verifyReplay(mid, arenaFactory).ok).toBe(true);
    const r = readReplay(rec.finish());
    expect(r.header.stepNumerator).toBe(3);
    expect(r.header.stepDenominator).toBe(100);
    expect(replayTimestep(r.header).ms).toBe(30);
    expect(r.tickCount).toBe(123);
    expect(r.tickHashes).toHaveLength(123);
    expect(verifyReplay(r, arenaFactory)).toMatchObject({ ok: true, exact: true });
  });

  it('refuses misuse of the recorder with RangeErrors', () => {
    const options = {
      gameId: GAME_ID,
      gameVersion: GAME_VERSION,
      tickRate: 60,
      players: ['a'],
    };
    expect(() => new ReplayRecorder({ ...options, gameId: '' })).toThrow(RangeError);
    expect(() => new ReplayRecorder({ ...options, gameId: 'x'.repeat(256) })).toThrow(RangeError);
    expect(() => new ReplayRecorder({ ...options, players: [] })).toThrow(RangeError);
    expect(() => new ReplayRecorder({ ...options, players: ['\ud800'] })).toThrow(RangeError);
    expect(() => new ReplayRecorder({ ...options, seeds: [-1] })).toThrow(RangeError);
    expect(() => new ReplayRecorder({ ...options, checkpointEvery: 0 })).toThrow(RangeError);
    expect(
      () => new ReplayRecorder({ ...options, checkpointEvery: 60, keyframeEvery: 90 }),
    ).toThrow(RangeError);
    const rec = new ReplayRecorder(options);
    const sim = new Arena(DEFAULT_CONFIG, 1, 1);
    expect(() => {
      rec.record([0], sim);
    }).toThrow(/start/);
    rec.start(sim);
    sim.step([0]);
    expect(() => {
      rec.record([0, 0], sim);
    }).toThrow(RangeError);
    expect(() => {
      rec.record([2 ** 32], sim);
    }).toThrow(RangeError);
    rec.record([0], sim);
    expect(() => {
      rec.record([0], sim);
    }).toThrow(/tick 1, expected 2/);
    sim.step([0]);
    expect(() => rec.finish()).toThrow(/tick 2/);
  });
});

/** FNV-1a 64 of the 600-tick golden replay file (format 2: format 1 plus the input schema descriptor). */
const GOLDEN_FILE_HASH = 'c7ab59aad7c2590a';
