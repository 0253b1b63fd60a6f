/**
 * What the tests of the two arena shooters (capture the flag, survival) share: bot matches, the
 * displays of the breakage tests, and the checks every arena game passes — registry entry,
 * golden hash, determinism, snapshots, refused bytes, replays. Each game's test file adds its
 * own rules.
 */
import { expect, it } from 'vitest';
import {
  Random,
  ReplayRecorder,
  guardSimulation,
  hex64,
  runForHash,
  snapshotRoundTrip,
  readReplay,
  verifyReplay,
  withDeterminismGuard,
  type ButtonInput,
  type DisplayEvent,
  type ReplayHeader,
  type ReplayRecorderOptions,
  type Simulation,
} from 'fixedstep';
import {
  findGame,
  gameFromReplayHeader,
  playOnDisplay,
  replayOptionsFor,
  type Game,
  type GameConfig,
  type RegisteredGame,
} from '@fixedstep/games';

/** What the tests need of an arena game. */
export type Arena = Game & { readonly players: number; readonly state: { readonly clock: number } };

/** An arena game under test. */
export interface Shooter<G extends Arena> {
  /** For log lines: `ctf`, `survival`. */
  readonly name: string;
  readonly definition: RegisteredGame;
  readonly make: (config: GameConfig) => G;
  /** The registry's bot. */
  readonly bot: (game: G, player: number) => ButtonInput;
}

/** Hitches of a struggling machine: 120 to 360 ms without a frame, every few seconds. */
export const HITCHES: DisplayEvent[] = [1500, 4000, 7000, 9500, 12000, 15500, 18000].map(
  (atMs, i) => ({ kind: 'hitch', atMs, durationMs: 120 + 40 * i }),
);

/** Slow, jittery displays, where a variable Δt breaks things. */
export const SLOW_DISPLAYS: { name: string; hz: number; jitter: number; events: DisplayEvent[] }[] =
  [
    { name: '25 Hz ±20% (20–31 Hz)', hz: 25, jitter: 0.2, events: [] },
    { name: '30 Hz ±30% with hitches', hz: 30, jitter: 0.3, events: HITCHES },
    { name: '20 Hz ±30%', hz: 20, jitter: 0.3, events: [] },
  ];

/** Displays from slow to fast, two of them with hitches: the fixed step plays the same on each. */
export const RATE_DISPLAYS: readonly [hz: number, jitter: number, events: DisplayEvent[]][] = [
  [25, 0.2, []],
  [30, 0.3, HITCHES],
  [60, 0, []],
  [144, 0.1, HITCHES],
];

/** Inputs for the human players of `game`, all played by the bot. */
export function botInputs<G extends Arena>(
  shooter: Shooter<G>,
  game: G,
): (tick: number) => ButtonInput[] {
  const inputs = new Array<ButtonInput>(game.players).fill(0);
  return () => {
    for (let p = 0; p < game.players; p++) inputs[p] = shooter.bot(game, p);
    return inputs;
  };
}

/** A bot match of `ticks` ticks (or until it is over). */
export function botMatch<G extends Arena>(
  shooter: Shooter<G>,
  seed: number,
  players: number,
  ticks: number,
): G {
  const game = shooter.make({ seed, players });
  const inputs = botInputs(shooter, game);
  while (game.tick < ticks && !game.over) game.step(inputs(game.tick));
  return game;
}

/**
 * The shooter's registry entry: found by id, 60 Hz, the shooters' key map, config bytes that
 * round-trip and refuse too many players; configs the game refuses; a bot for it only.
 */
export function expectRegistered<G extends Arena>(shooter: Shooter<G>, config: GameConfig): void {
  const def = shooter.definition;
  expect(findGame(shooter.name)).toBe(def);
  const max = def.info.maxPlayers;
  expect(def.info).toMatchObject({ id: shooter.name, tickRate: 60, minPlayers: 1 });
  expect(def.decodeConfig(def.encodeConfig(config))).toEqual(config);
  expect(() => def.decodeConfig(def.encodeConfig({ seed: 1, players: max + 1 }))).toThrow(
    RangeError,
  );
  const keys = def.info.buttons.flatMap((b) => b.keys);
  for (const k of ['KeyW', 'ArrowUp', 'ArrowDown', 'KeyA', 'ArrowLeft', 'KeyD', 'Space', 'KeyJ']) {
    expect(keys).toContain(k);
  }
  expect(() => shooter.make({ seed: -1, players: 1 })).toThrow(RangeError);
  expect(() => shooter.make({ seed: 1, players: 0 })).toThrow(RangeError);
  expect(() => shooter.make({ seed: 1, players: max + 1 })).toThrow(RangeError);
  expect(() => def.bot({} as Game, 0)).toThrow(TypeError);
}

/** The numbers of {@link itIsDeterministic}'s tests. */
export interface DeterminismCase {
  /** The golden hash of a minute of bots (60 Hz, seed 1, one player). */
  golden: string;
  /** Players and ticks of the two bot matches that must hash the same. */
  players: number;
  twiceTicks: number;
  /** Ticks under the determinism guard (seed 2). */
  guardTicks: number;
  /** Ticks before the snapshot of the round trip (seed 3, two players). */
  snapshotTicks: number;
}

/** The determinism tests: golden hash, same twice, no clocks or engine math, snapshot round trip. */
export function itIsDeterministic<G extends Arena>(
  shooter: Shooter<G>,
  c: DeterminismCase,
  /** Something a guarded run must have made more than none of (enemies met, …). */
  progress?: (game: G) => number,
): void {
  it('golden hash after a minute of bots (60 Hz, seed 1)', () => {
    const game = shooter.make({ seed: 1, players: 1 });
    const actual = runForHash(game, 3600, botInputs(shooter, game));
    // A deliberate change to the simulation re-blesses this: paste the printed value.
    if (actual !== c.golden) {
      console.log(`${shooter.name} golden hash: expected ${c.golden}, actual ${actual}`);
    }
    expect(actual).toBe(c.golden);
  });

  it('runs the same twice, and another seed runs otherwise', () => {
    const hash = (seed: number) => botMatch(shooter, seed, c.players, c.twiceTicks).hash();
    expect(hex64(hash(5))).toBe(hex64(hash(5)));
    expect(hash(6)).not.toBe(hash(5));
  });

  it('never calls a clock, Math.random or engine trig, in its steps or its bots', () => {
    const game = shooter.make({ seed: 2, players: 2 });
    const guarded = guardSimulation(game);
    const inputs = botInputs(shooter, game);
    for (let t = 0; t < c.guardTicks; t++) guarded.step(withDeterminismGuard(() => inputs(t)));
    expect(guarded.tick).toBe(c.guardTicks);
    if (progress) expect(progress(game)).toBeGreaterThan(0);
  });

  it('snapshot round trip: save, load, then 300 equal hashes', () => {
    // Both games get the inputs the bots choose in the first one.
    let first: G | null = null;
    const make = () => {
      const g = shooter.make({ seed: 3, players: 2 });
      first ??= g;
      return g;
    };
    const inputs = (): ButtonInput[] =>
      first === null ? [0, 0] : [shooter.bot(first, 0), shooter.bot(first, 1)];
    const result = snapshotRoundTrip(make, inputs, c.snapshotTicks, 300);
    expect(result.message).toBe('equal hashes for 300 ticks after the snapshot');
    expect(result.ok).toBe(true);
  });
}

/**
 * Checks that `game` refuses what no state of it can be — bytes cut short, a byte too many,
 * another game's magic (`notThis`), a state of a game for `otherPlayers` — and returns the check
 * for the game's own cases: `load` throws `why` and leaves the game as it was.
 */
export function expectRefusals<G extends Arena>(
  shooter: Shooter<G>,
  game: G,
  notThis: RegExp,
  otherPlayers: number,
): (bytes: Uint8Array, why: RegExp) => void {
  const good = game.save();
  const before = game.hash();
  const refused = (bytes: Uint8Array, why: RegExp) => {
    expect(() => {
      game.load(bytes);
    }).toThrow(why);
    expect(game.hash()).toBe(before);
  };
  refused(good.subarray(0, good.length - 1), /truncated/);
  refused(Uint8Array.from([...good, 0]), /trailing/);
  refused(
    Uint8Array.from(good, (b, i) => (i === 0 ? b ^ 1 : b)),
    notThis,
  );
  const players = game.players;
  refused(
    shooter.make({ seed: 4, players: otherPlayers }).save(),
    new RegExp(`${otherPlayers} players, this one has ${players}`),
  );
  // The random generator's state sits after magic, players, tick, clock and the over flag.
  const zeroRng = good.slice();
  zeroRng.fill(0, 18, 34);
  refused(zeroRng, /all-zero/);
  return refused;
}

/**
 * The hash of a bot game played on a simulated display for 14 s: at tick 600 under the fixed
 * step, at the first update at or past 10 s of simulated time under a variable Δt.
 */
export function hashOnDisplay<G extends Arena>(
  shooter: Shooter<G>,
  config: GameConfig,
  loop: 'fixed' | 'variable',
  [hz, jitter, events]: readonly [number, number, DisplayEvent[]],
): string {
  const game = shooter.make(config);
  let hash = '';
  playOnDisplay(game, {
    loop,
    display: { hz, jitter, seed: hz, events },
    seconds: 14,
    inputs: (_g, out) => {
      for (let p = 0; p < game.players; p++) out[p] = shooter.bot(game, p);
    },
    afterUpdate: () => {
      if (loop === 'fixed' ? game.tick === 600 : hash === '' && game.state.clock >= 10) {
        hash = hex64(game.hash());
      }
    },
  });
  return hash;
}

/** A recorded bot match and forgeries of it. */
export interface RecordedMatch {
  readonly bytes: Uint8Array;
  readonly ticks: number;
  readonly players: number;
  /** The inputs, tick by tick: `recorded[t * players + p]`. */
  readonly recorded: Uint32Array;
  /**
   * The same file with other inputs and the recorded hashes (but for `hash.tick`, whose stored
   * hash is `hash.value`): well formed, only re-simulation can tell.
   */
  forge(inputs: Uint32Array, hash?: { tick: number; value: bigint }): Uint8Array;
}

/** Records `ticks` of a bot match of `config` with the registry's recorder options. */
export function recordBotMatch<G extends Arena>(
  shooter: Shooter<G>,
  config: GameConfig,
  names: readonly string[],
  ticks: number,
  extra: Pick<ReplayRecorderOptions, 'keyframeEvery'> = {},
): RecordedMatch {
  const def = shooter.definition;
  const n = config.players;
  const game = shooter.make(config);
  const rec = new ReplayRecorder(replayOptionsFor(def, config, names, extra));
  rec.start(game);
  const recorded = new Uint32Array(ticks * n);
  const hashes: bigint[] = [game.hash()];
  const inputs = botInputs(shooter, game);
  for (let t = 0; t < ticks; t++) {
    const frame = inputs(t);
    for (let p = 0; p < n; p++) recorded[t * n + p] = frame[p]!;
    game.step(frame);
    rec.record(frame, game);
    hashes.push(game.hash());
  }
  const forge = (inputsOf: Uint32Array, hash?: { tick: number; value: bigint }): Uint8Array => {
    const puppet = {
      tick: 0,
      hash: () => (puppet.tick === hash?.tick ? hash.value : hashes[puppet.tick]!),
      save: () => new Uint8Array(0),
    };
    const r = new ReplayRecorder(replayOptionsFor(def, config, names));
    r.start(puppet);
    const frame = new Array<ButtonInput>(n).fill(0);
    for (let t = 0; t < ticks; t++) {
      puppet.tick++;
      for (let p = 0; p < n; p++) frame[p] = inputsOf[t * n + p]!;
      r.record(frame, puppet);
    }
    return r.finish();
  };
  return { bytes: rec.finish(), ticks, players: n, recorded, forge };
}

/**
 * Player 0's input at tick `t` of `match` turned the opposite way (up↔down, left↔right): the
 * forgery fails at the first checkpoint after it, the unedited forgery verifies.
 */
export function expectEditCaught(match: RecordedMatch, t: number): void {
  const i = t * match.players;
  const edited = match.recorded.slice();
  edited[i] = match.recorded[i]! ^ 0b1111;
  const forged = match.forge(edited);
  const result = verifyReplay(forged, gameFromReplayHeader);
  const every = readReplay(forged).checkpointEvery;
  const next = Math.ceil((t + 1) / every) * every;
  expect(result).toMatchObject({ ok: false, kind: 'checkpoint', firstMismatchTick: next });
  expect(verifyReplay(match.forge(match.recorded), gameFromReplayHeader).ok).toBe(true);
}

/**
 * The end of a match: from `over` on the game says it is frozen, `skip(k)` leaves what k steps
 * with any inputs leave, and `verifyReplay` jumps over the rest of a file — still refusing one
 * whose hashes after the end are forged, and answering for an honest one exactly what stepping
 * every tick answers.
 */
export function itStandsStillAfterTheEnd<G extends Arena & Required<Pick<Game, 'frozen' | 'skip'>>>(
  shooter: Shooter<G>,
  config: GameConfig,
): void {
  /** The bot match of `config`, played to its end. */
  const ended = (): G => {
    const game = botMatch(shooter, config.seed, config.players, 60 * 60 * 60);
    expect(game.over).toBe(true);
    return game;
  };

  it('after the end, skip(k) leaves the state k steps with any inputs leave', () => {
    const fresh = shooter.make(config);
    expect(fresh.frozen).toBe(false);
    expect(() => {
      fresh.skip(1);
    }).toThrow(RangeError);
    const game = ended();
    expect(game.frozen).toBe(true);
    const copy = shooter.make(config);
    copy.load(game.save());
    const rng = new Random(9);
    const inputs = new Array<ButtonInput>(config.players).fill(0);
    for (const k of [1, 59, 600]) {
      for (let t = 0; t < k; t++) {
        for (let p = 0; p < config.players; p++) inputs[p] = rng.nextU32() & 0xffff;
        game.step(inputs);
      }
      copy.skip(k);
      expect(copy.tick).toBe(game.tick);
      expect(copy.save()).toEqual(game.save());
      expect(copy.frozen).toBe(true);
    }
    expect(() => {
      copy.skip(-1);
    }).toThrow(RangeError);
    expect(() => {
      copy.skip(1.5);
    }).toThrow(RangeError);
  });

  it('a replay that runs on after the end: verified without stepping the rest, forged hashes there refused', () => {
    const end = ended().tick;
    const names = Array.from({ length: config.players }, (_, p) => `p${p}`);
    const match = recordBotMatch(shooter, config, names, end + 3000, { keyframeEvery: 1200 });
    const skipping = verifyReplay(match.bytes, gameFromReplayHeader);
    expect(skipping).toMatchObject({ ok: true, simulated: match.ticks });
    expect(skipping.frozenFrom).toBeGreaterThanOrEqual(end);
    expect(skipping.frozenFrom).toBeLessThan(end + 600);
    // The same game without `frozen`: stepped to the last tick, the same answer.
    const stepping = (header: ReplayHeader): Simulation => {
      const g = gameFromReplayHeader(header);
      return {
        get tick() {
          return g.tick;
        },
        step: (i: readonly ButtonInput[]) => {
          g.step(i);
        },
        save: () => g.save(),
        load: (b: Uint8Array) => {
          g.load(b);
        },
        hash: () => g.hash(),
      };
    };
    const stepped = verifyReplay(match.bytes, stepping);
    expect(stepped.frozenFrom).toBe(-1);
    expect({ ...skipping, frozenFrom: -1 }).toEqual(stepped);

    const every = readReplay(match.bytes).checkpointEvery;
    const forgedAt = (Math.floor(match.ticks / every) - 1) * every;
    expect(forgedAt).toBeGreaterThan(skipping.frozenFrom);
    const forged = match.forge(match.recorded, { tick: forgedAt, value: 0x5eedn });
    expect(verifyReplay(forged, gameFromReplayHeader)).toMatchObject({
      ok: false,
      kind: 'checkpoint',
      firstMismatchTick: forgedAt,
      lastGoodTick: forgedAt - every,
      expected: 0x5eedn,
    });
  });
}
