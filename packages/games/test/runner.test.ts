import { describe, expect, it } from 'vitest';
import fc from 'fast-check';
import {
  fnv1a64Hex,
  guardSimulation,
  hashTrace,
  hex64,
  packButtons,
  runForHash,
  snapshotRoundTrip,
  type ButtonInput,
} from 'fixedstep';
import {
  GAMES,
  OBSTACLE_KINDS,
  RUNNER_TUNING,
  RunnerButtons,
  RunnerGame,
  decodeGameConfig,
  encodeGameConfig,
  findGame,
  runnerBot,
  runnerGame,
} from '@fixedstep/games';

const JUMP = 1 << RunnerButtons.jump;
const TAP: ButtonInput = packButtons(JUMP, JUMP);

function runner(seed = 1): RunnerGame {
  return new RunnerGame({ seed, players: 1 });
}

/** Inputs from the bot, into one reused array. */
function botInputs(game: RunnerGame): (tick: number) => readonly ButtonInput[] {
  const inputs = [0];
  return () => {
    inputs[0] = runnerBot(game, 0);
    return inputs;
  };
}

/** Jump, then step with `input` until the player lands. Returns the ticks in the air. */
function jump(game: RunnerGame, input: ButtonInput, each?: () => void): number {
  game.step([TAP]);
  let ticks = 1;
  for (; !game.onGround && ticks < 1000; ticks++) {
    game.step([input]);
    each?.();
  }
  return ticks;
}

function thrown(fn: () => void): unknown {
  try {
    fn();
  } catch (e) {
    return e;
  }
  return undefined;
}

function sameBytes(a: Uint8Array, b: Uint8Array): boolean {
  return a.length === b.length && a.every((v, i) => v === b[i]);
}

/** Step with no buttons until the run ends (or `limit` ticks). */
function crash(game: RunnerGame, limit = 3600): void {
  for (let t = 0; t < limit && !game.over; t++) game.step([0]);
}

describe('runner: registry and config', () => {
  it('is registered under its id, one player at 60 Hz', () => {
    expect(findGame('runner')).toBe(runnerGame);
    expect(GAMES).toContain(runnerGame);
    expect(runnerGame.info).toMatchObject({
      id: 'runner',
      stepSeconds: 1 / 60,
      tickRate: 60,
      minPlayers: 1,
      maxPlayers: 1,
    });
    expect(runnerGame.info.buttons.map((b) => b.name)).toEqual(['jump', 'duck']);
    const game = runnerGame.create({ seed: 9, players: 1 });
    expect(game).toBeInstanceOf(RunnerGame);
    expect(game.tick).toBe(0);
    expect(game.info).toBe(runnerGame.info);
  });

  it('encodes its config with the shared helpers and reads it back', () => {
    const config = { seed: 0xdeadbeef, players: 1 };
    const bytes = runnerGame.encodeConfig(config);
    expect(bytes).toEqual(encodeGameConfig(config));
    expect(runnerGame.decodeConfig(bytes)).toEqual(config);
    expect(decodeGameConfig(bytes, 1, 1)).toEqual(config);
    fc.assert(
      fc.property(fc.nat({ max: 0xffffffff }), (seed) => {
        const c = { seed, players: 1 };
        expect(runnerGame.decodeConfig(runnerGame.encodeConfig(c))).toEqual(c);
      }),
    );
  });

  it('refuses configs it cannot play', () => {
    const two = encodeGameConfig({ seed: 1, players: 2 });
    expect(() => runnerGame.decodeConfig(two)).toThrow(RangeError);
    expect(() => runnerGame.decodeConfig(two.subarray(0, 3))).toThrow(RangeError);
    expect(() => runnerGame.decodeConfig(Uint8Array.of(1, 0, 0, 0, 1, 0))).toThrow(RangeError);
    expect(() => runnerGame.create({ seed: 1, players: 2 })).toThrow(RangeError);
    expect(() => runnerGame.create({ seed: -1, players: 1 })).toThrow(RangeError);
    expect(() => runnerGame.create({ seed: 1.5, players: 1 })).toThrow(RangeError);
  });
});

describe('runner: determinism', () => {
  // A deliberate change to the simulation changes these: bump RUNNER_INFO.version and re-bless.
  it('golden hash after 3600 ticks (60 s) of the bot, seed 1', () => {
    const game = runner(1);
    const actual = runForHash(game, 3600, botInputs(game));
    expect(actual, `runner golden hash changed: actual ${actual}`).toBe('7d09b4835a10cb4f');
  });

  it('golden digest of the per-tick hashes of those 3600 ticks (catches mid-air changes too)', () => {
    const game = runner(1);
    const trace = hashTrace(game, 3600, botInputs(game));
    const actual = fnv1a64Hex(new TextEncoder().encode(trace.join('')));
    expect(actual, `runner golden trace digest changed: actual ${actual}`).toBe('0941e0bb4b9114dc');
  });

  it('golden hash after 3600 ticks with no input: crashes into the first obstacle', () => {
    const game = runner(1);
    const actual = runForHash(game, 3600, () => [0]);
    expect(actual, `runner no-input hash changed: actual ${actual}`).toBe('4f78b87c46504397');
    expect(game.over).toBe(true);
  });

  it('snapshot round trip: equal hashes for 120 ticks after load, mid-air and mid-course', () => {
    for (const warmup of [1, 60, 95, 600, 2000]) {
      let probe = runner(4);
      const result = snapshotRoundTrip(
        () => (probe = runner(4)),
        // The bot reads whichever game it is handed; both see equal states.
        () => [runnerBot(probe, 0)],
        warmup,
      );
      expect(result.ok, `warmup ${warmup}: ${result.message}`).toBe(true);
    }
  });

  it('snapshot round trip across a crash and a restart', () => {
    const script = (t: number): ButtonInput[] => [t === 250 || t === 251 ? TAP : 0];
    const result = snapshotRoundTrip(() => runner(2), script, 240, 300);
    expect(result.ok, `crash and restart: ${result.message}`).toBe(true);
  });

  it('the same seed gives the same course; another seed another one', () => {
    const course = (seed: number) => {
      const g = runner(seed);
      const inputs = botInputs(g);
      const kinds: number[] = [];
      let last = -1;
      for (let t = 0; t < 6000; t++) {
        g.step(inputs(t));
        const x = g.obstacleX(g.obstacleCount - 1);
        if (x !== last) kinds.push(g.obstacleKind(g.obstacleCount - 1));
        last = x;
      }
      return kinds.join('');
    };
    expect(course(5)).toBe(course(5));
    expect(course(5)).not.toBe(course(6));
  });

  it('steps under the determinism guard: no clock, no Math.random, no engine trig', () => {
    const game = guardSimulation(runner(3));
    const inputs = [0];
    for (let t = 0; t < 1200; t++) {
      inputs[0] = runnerBot(game, 0);
      game.step(inputs);
    }
    expect(game.hash()).toBe(game.hash());
    expect(game.tick).toBe(1200);
  });

  it('update(1/60) is step()', () => {
    const a = runner(7);
    const b = runner(7);
    const inputs = [0];
    for (let t = 0; t < 2000; t++) {
      inputs[0] = runnerBot(a, 0);
      a.step(inputs);
      b.update(1 / 60, inputs);
    }
    expect(hex64(b.hash())).toBe(hex64(a.hash()));
  });
});

describe('runner: save and load', () => {
  const mid = (() => {
    const g = runner(8);
    const inputs = botInputs(g);
    for (let t = 0; t < 1500; t++) g.step(inputs(t));
    return g;
  })();

  it('save() is canonical bytes; hash() is FNV-1a 64 over them', () => {
    const bytes = mid.save();
    const copy = runner(99);
    copy.load(bytes);
    expect(copy.save()).toEqual(bytes);
    expect(copy.hash()).toBe(mid.hash());
    expect(copy.tick).toBe(1500);
    expect(copy.hud()).toEqual(mid.hud());
  });

  it('load rejects every truncation and trailing bytes with a RangeError, changing nothing', () => {
    const bytes = mid.save();
    const target = runner(1);
    const before = target.hash();
    for (let n = 0; n < bytes.length; n++) {
      expect(() => {
        target.load(bytes.subarray(0, n));
      }).toThrow(RangeError);
    }
    const longer = new Uint8Array(bytes.length + 1);
    longer.set(bytes);
    expect(() => {
      target.load(longer);
    }).toThrow(RangeError);
    expect(target.hash()).toBe(before);
  });

  it('load rejects impossible states with a RangeError', () => {
    const bytes = mid.save();
    const view = new DataView(bytes.buffer);
    const edited = (edit: (v: DataView) => void) => {
      const b = bytes.slice();
      edit(new DataView(b.buffer));
      return b;
    };
    const cases: Record<string, Uint8Array> = {
      magic: edited((v) => {
        v.setUint8(0, 0);
      }),
      flag: edited((v) => {
        v.setUint8(16, 2);
      }),
      noRuns: edited((v) => {
        v.setUint32(12, 0, true);
      }),
      nanDistance: edited((v) => {
        v.setFloat64(19, NaN, true);
      }),
      negativeZero: edited((v) => {
        v.setFloat64(19, -0, true);
      }),
      tooFast: edited((v) => {
        v.setFloat64(27, 1000, true);
      }),
      zeroRandom: edited((v) => {
        for (let i = 0; i < 16; i++) v.setUint8(67 + i, 0);
      }),
      tooManyObstacles: edited((v) => {
        v.setUint8(83, 200);
      }),
      badKind: edited((v) => {
        v.setUint8(84, OBSTACLE_KINDS.length);
      }),
    };
    expect(view.getUint8(83)).toBe(mid.obstacleCount);
    const target = runner(1);
    for (const [name, b] of Object.entries(cases)) {
      expect(() => {
        target.load(b);
      }, `state with a bad ${name}`).toThrow(RangeError);
    }
  });

  it('any bytes: load throws a RangeError, or accepts them and saves them back unchanged', () => {
    const valid = mid.save();
    const target = runner(1);
    fc.assert(
      fc.property(
        fc.oneof(
          fc.uint8Array({ maxLength: 200 }),
          fc
            .tuple(fc.nat({ max: valid.length - 1 }), fc.integer({ min: 0, max: 255 }))
            .map(([i, b]) => {
              const v = valid.slice();
              v[i] = b;
              return v;
            }),
        ),
        (bytes) => {
          const error = thrown(() => {
            target.load(bytes);
          });
          const verdict =
            error === undefined
              ? sameBytes(target.save(), bytes)
                ? 'saved back unchanged'
                : 'saved back changed'
              : error instanceof RangeError
                ? 'RangeError'
                : error instanceof Error
                  ? error.name
                  : 'a thrown non-error';
          expect(['RangeError', 'saved back unchanged']).toContain(verdict);
        },
      ),
      { numRuns: 2000 },
    );
  });
});

describe('runner: play', () => {
  it('HUD: score grows with distance; a crash ends the run and sets the highscore', () => {
    const game = runner(1);
    expect(game.hud()).toEqual({ score: 0, highscore: 0 });
    expect(game.over).toBe(false);
    for (let t = 0; t < 60; t++) game.step([0]);
    // One second from 10 m/s at 0.1 m/s²: 10.05 m (semi-implicit Euler: 10.0508), 10 points a metre.
    expect(game.distance).toBeCloseTo(10.0508, 3);
    expect(game.hud()).toEqual({ score: 100, highscore: 0 });
    crash(game);
    expect(game.over).toBe(true);
    const first = game.score;
    // No input: it runs into the first obstacle, which stands at 40 m.
    expect(game.distance + RUNNER_TUNING.playerWidth).toBeGreaterThan(RUNNER_TUNING.firstObstacle);
    expect(game.distance).toBeLessThan(RUNNER_TUNING.firstObstacle + 1);
    expect(game.hud()).toEqual({ score: first, highscore: first });
    // After a crash the world stands still.
    const at = game.distance;
    for (let t = 0; t < 10; t++) game.step([0]);
    expect(game.distance).toBe(at);
  });

  it('restarts on a jump press after half a second, keeping the highscore', () => {
    const game = runner(1);
    crash(game);
    const first = game.score;
    expect(game.runs).toBe(1);
    // Too early: ignored.
    game.step([TAP]);
    expect(game.over).toBe(true);
    for (let t = 0; t < 30; t++) game.step([0]);
    expect(game.canRestart).toBe(true);
    // Held but not pressed: ignored.
    game.step([packButtons(JUMP, 0)]);
    expect(game.over).toBe(true);
    game.step([TAP]);
    expect(game.over).toBe(false);
    expect(game.runs).toBe(2);
    expect(game.hud()).toEqual({ score: 0, highscore: first });
    // A shorter second run leaves the highscore; a longer one raises it.
    crash(game, 30);
    expect(game.hud().highscore).toBe(first);
    const inputs = botInputs(game);
    for (let t = 0; t < 1200; t++) game.step(inputs(t));
    expect(game.over).toBe(false);
    expect(game.score).toBeGreaterThan(first);
    crash(game);
    expect(game.hud()).toEqual({ score: game.score, highscore: game.score });
    expect(game.runs).toBe(2);
  });

  it('jump, duck and fast fall', () => {
    const game = runner(1);
    let apex = 0;
    const airTicks = jump(game, 0, () => (apex = Math.max(apex, game.y)));
    // Exact: v²/2g = 2.03 m in 2v/g = 40.3 ticks; semi-implicit Euler at 1/60 s: 1.933 m, 40 ticks.
    expect(apex).toBeCloseTo(1.9333, 4);
    expect(airTicks).toBe(40);
    const duck = packButtons(1 << RunnerButtons.duck, 1 << RunnerButtons.duck);
    game.step([duck]);
    expect(game.ducking).toBe(true);
    expect(game.playerHeight).toBe(RUNNER_TUNING.duckHeight);
    game.step([0]);
    expect(game.ducking).toBe(false);
    // Duck held in the air: a fast fall lands sooner.
    expect(jump(game, packButtons(1 << RunnerButtons.duck, 0))).toBeLessThan(airTicks);
  });

  it('the bot survives 60 s on many seeds and scores 7800 (780 m)', () => {
    for (let seed = 1; seed <= 20; seed++) {
      const game = runner(seed);
      const inputs = botInputs(game);
      for (let t = 0; t < 3600; t++) game.step(inputs(t));
      expect(game.over, `seed ${seed}`).toBe(false);
      expect(game.score).toBeGreaterThan(7700);
    }
  });

  it('the bot survives 10 minutes at full speed, past birds, and restarts after a crash', () => {
    const game = runner(11);
    const inputs = botInputs(game);
    const seen = new Set<number>();
    for (let t = 0; t < 36_000; t++) {
      game.step(inputs(t));
      seen.add(game.obstacleKind(0));
    }
    expect(game.over).toBe(false);
    expect(game.speed).toBe(RUNNER_TUNING.maxSpeed);
    expect(game.score).toBeGreaterThan(110_000);
    expect([...seen].sort((a, b) => a - b)).toEqual([0, 1, 2, 3]);

    const dead = runner(11);
    crash(dead);
    const botRestart = botInputs(dead);
    for (let t = 0; t < 60 && dead.over; t++) dead.step(botRestart(t));
    expect(dead.over).toBe(false);
    expect(dead.runs).toBe(2);
  });

  it('a huge Δt tunnels through obstacles (the variable-Δt failure), and NaN or negative Δt do nothing', () => {
    const game = runner(1);
    game.update(3.5, [0]);
    expect(game.distance + RUNNER_TUNING.playerWidth).toBeLessThan(RUNNER_TUNING.firstObstacle);
    expect(game.over).toBe(false);
    // One 1 s update carries the player from before the first obstacle (40 m) to past it.
    game.update(1, [0]);
    expect(game.distance).toBeGreaterThan(RUNNER_TUNING.firstObstacle + 1);
    expect(game.over).toBe(false);
    const at = game.distance;
    const tick = game.tick;
    game.update(NaN, [0]);
    game.update(-1, [0]);
    game.update(0, [0]);
    expect(game.tick).toBe(tick + 3);
    expect(game.distance).toBe(at);
    // A long hitch never leaves the course empty.
    game.update(100, [0]);
    expect(game.obstacleCount).toBeGreaterThan(0);
    expect(game.obstacleX(0)).toBeGreaterThan(game.distance - 20);
  });
});
