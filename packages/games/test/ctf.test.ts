import { describe, expect, it } from 'vitest';
import { Random, readReplay, verifyReplay, type DisplayEvent } from 'fixedstep';
import {
  CTF,
  CtfGame,
  FlagState,
  ShooterButtons,
  ctfBot,
  ctfGame,
  gameFromReplayHeader,
  playOnDisplay,
} from '@fixedstep/games';
import {
  HITCHES,
  RATE_DISPLAYS,
  SLOW_DISPLAYS,
  botMatch,
  expectEditCaught,
  expectRefusals,
  expectRegistered,
  hashOnDisplay,
  itIsDeterministic,
  itStandsStillAfterTheEnd,
  recordBotMatch,
  type Shooter,
} from './arena-games.js';

const FIRE = 1 << ShooterButtons.fire;

const CTF_SHOOTER: Shooter<CtfGame> = {
  name: 'ctf',
  definition: ctfGame,
  make: (config) => new CtfGame(config),
  bot: ctfBot,
};

describe('capture the flag: the game', () => {
  it('is in the registry, with its config bytes and key map', () => {
    expectRegistered(CTF_SHOOTER, { seed: 0xdeadbeef, players: 3 });
    expect(ctfGame.info.maxPlayers).toBe(4);
  });

  it('starts with four players a side at their bases and both flags home', () => {
    const game = new CtfGame({ seed: 1, players: 1 });
    const s = game.state;
    expect([...s.active]).toEqual([1, 1, 1, 1, 1, 1, 1, 1]);
    expect([...s.alive]).toEqual([1, 1, 1, 1, 1, 1, 1, 1]);
    for (let p = 0; p < 8; p++) expect(s.x[p]! < CTF.width / 2).toBe(p % 2 === 0);
    expect([...s.flagState]).toEqual([FlagState.home, FlagState.home]);
    expect(game.hud()).toMatchObject({ kills: 0, flags: 0, red: 0, blue: 0 });
  });

  itIsDeterministic(CTF_SHOOTER, {
    golden: GOLDEN,
    players: 2,
    twiceTicks: 1200,
    guardTicks: 900,
    snapshotTicks: 900,
  });

  it('load rejects bytes it cannot read, and is then unchanged', () => {
    const expectRefused = expectRefusals(
      CTF_SHOOTER,
      botMatch(CTF_SHOOTER, 4, 2, 600),
      /not a capture-the-flag/,
      1,
    );
    /** A state made wrong on purpose, saved by another game. */
    const tampered = (change: (g: CtfGame) => void): Uint8Array => {
      const g = botMatch(CTF_SHOOTER, 4, 2, 600);
      change(g);
      return g.save();
    };
    expectRefused(
      tampered((g) => {
        g.state.x[3] = NaN;
      }),
      /player 3: a number is not finite/,
    );
    expectRefused(
      tampered((g) => {
        g.state.alive[2] = 7;
      }),
      /player 2/,
    );
    expectRefused(
      tampered((g) => {
        g.state.facing[1] = 9;
      }),
      /facing 9/,
    );
    expectRefused(
      tampered((g) => {
        g.state.flagState[0] = FlagState.carried;
        g.state.flagCarrier[0] = 2; // red's own player cannot carry red's flag
      }),
      /flag 0: carried by 2/,
    );
  });

  it('update(dt) refuses a Δt that is not a finite number ≥ 0', () => {
    const game = new CtfGame({ seed: 1, players: 1 });
    for (const dt of [NaN, -0.01, Infinity]) {
      expect(() => {
        game.update(dt, [0]);
      }).toThrow(RangeError);
    }
    game.update(0.05, [0]);
    expect(game.tick).toBe(1);
    expect(game.state.clock).toBe(0.05);
  });
});

describe('capture the flag: a bot match', () => {
  it('3 minutes of bots: kills, deaths and flags captured', () => {
    const game = botMatch(CTF_SHOOTER, MATCH_SEED, 1, 3 * 60 * 60);
    const s = game.state;
    const hud = game.hud();
    const total = (a: Uint32Array) => a.reduce((x, y) => x + y, 0);
    expect(hud.kills).toBeGreaterThan(0);
    expect(hud.flags).toBeGreaterThan(0);
    expect(hud.deaths).toBeGreaterThan(0);
    expect(total(s.kills)).toBe(total(s.deaths));
    expect(hud.red! + hud.blue!).toBeGreaterThan(1);
    expect(hud.throughWalls).toBe(0);
  });

  it('plays the same at every display rate under the fixed step (bots, hitches and all)', () => {
    const config = { seed: 8, players: 2 };
    const fixed = RATE_DISPLAYS.map((d) => hashOnDisplay(CTF_SHOOTER, config, 'fixed', d));
    expect(new Set(fixed).size).toBe(1);
    expect(fixed[0]).toHaveLength(16);
  });
});

describe("capture the flag: the talk's breakage, for real", () => {
  /**
   * Player 0 stands 100 units east of the base's 4-unit front wall, facing west, holding fire for
   * 20 s; player 1 stands behind the wall, inside the base. Every bullet seen west of the wall
   * went through it.
   */
  function shootAtThinWall(
    loop: 'fixed' | 'variable',
    hz: number,
    jitter: number,
    events: DisplayEvent[],
  ) {
    const game = new CtfGame({ seed: 1, players: 2, fill: false });
    game.place(0, 300, 320, 4);
    game.place(1, 120, 320, 0);
    const wallWest = 196;
    const through = new Set<number>();
    const run = playOnDisplay(game, {
      loop,
      display: { hz, jitter, seed: 3, events },
      seconds: 20,
      inputs: (_g, out) => {
        out[0] = FIRE;
        out[1] = 0;
      },
      afterUpdate: () => {
        const b = game.state.bullets;
        for (let i = 0; i < b.capacity; i++) {
          if (b.alive[i] === 1 && b.x[i]! < wallWest) through.add(b.serial[i]!);
        }
        if (game.state.alive[1] === 1) game.place(1, 120, 320, 0); // the target stays put
      },
    });
    return {
      shots: game.state.shots,
      through: through.size,
      kills: game.state.kills[0]!,
      counted: game.state.bullets.throughWalls,
      maxDtMs: run.maxDt * 1000,
    };
  }

  for (const d of SLOW_DISPLAYS) {
    it(`bullets vs a 4-unit wall on a ${d.name} display: through under update, none under step`, () => {
      const naive = shootAtThinWall('variable', d.hz, d.jitter, d.events);
      const fixed = shootAtThinWall('fixed', d.hz, d.jitter, d.events);
      expect(naive.shots).toBeGreaterThan(50);
      expect(naive.through).toBeGreaterThan(naive.shots / 2);
      expect(naive.counted).toBeGreaterThanOrEqual(naive.through);
      expect(naive.kills).toBeGreaterThan(0);
      expect(fixed.shots).toBeGreaterThan(50);
      expect(fixed.through).toBe(0);
      expect(fixed.counted).toBe(0);
      expect(fixed.kills).toBe(0);
    });
  }

  it('a bot match on a 25 Hz display: bullets through walls under update, none under step', () => {
    const play = (loop: 'fixed' | 'variable') => {
      const game = new CtfGame({ seed: 3, players: 1 });
      playOnDisplay(game, {
        loop,
        display: { hz: 25, jitter: 0.2, seed: 3, events: HITCHES },
        seconds: 60,
        inputs: (g, out) => {
          out[0] = ctfBot(g, 0);
        },
      });
      return game.hud();
    };
    const naive = play('variable');
    const fixed = play('fixed');
    expect(naive.throughWalls).toBeGreaterThan(0);
    expect(fixed.throughWalls).toBe(0);
  });
});

describe('capture the flag: the players’ tunnelling diagnostic', () => {
  it('counts every move whose path meets a wall (the moves it skips cannot meet one)', () => {
    // One player walked from random spots (near walls, inside them, at the field's edge) in
    // every direction, for Δt from a fixed step to a tenth of a second: each move counts
    // exactly when the walls' own crossing test says its path meets a wall.
    const rng = new Random(5);
    const game = new CtfGame({ seed: 1, players: 1, fill: false });
    const s = game.state;
    const rects = game.walls.rects;
    let counted = 0;
    let skippedCandidates = 0;
    for (let k = 0; k < 4000; k++) {
      const rect = rects[rng.int(rects.length)]!;
      const x = rng.int(3) === 0 ? rng.range(0, CTF.width) : rng.range(rect.x0 - 20, rect.x1 + 20);
      const y = rng.int(3) === 0 ? rng.range(0, CTF.height) : rng.range(rect.y0 - 20, rect.y1 + 20);
      game.place(0, x, y, 0);
      const dt = [1 / 60, 1 / 30, 0.05, 0.1][rng.int(4)]!;
      const before = s.playersThroughWalls;
      const x0 = s.x[0]!;
      const y0 = s.y[0]!;
      if (dt * CTF.playerSpeed < CTF.playerRadius - 1) skippedCandidates++;
      game.update(dt, [1 << [0, 1, 2, 3][rng.int(4)]!]);
      const crossed = game.walls.crosses(x0, y0, s.x[0]!, s.y[0]!);
      expect({ k, x0, y0, dt, counted: s.playersThroughWalls - before }).toEqual({
        k,
        x0,
        y0,
        dt,
        counted: crossed ? 1 : 0,
      });
      if (crossed) counted++;
      if (s.over === 1) break;
    }
    expect(counted).toBeGreaterThan(50);
    expect(skippedCandidates).toBeGreaterThan(1000);
  });
});

describe('capture the flag: replays', () => {
  itStandsStillAfterTheEnd(CTF_SHOOTER, { seed: 11, players: 2 });

  const match = recordBotMatch(CTF_SHOOTER, { seed: 11, players: 2 }, ['ann', 'bob'], 2 * 60 * 60);

  it('records two minutes of a 2-player bot match and verifies it by re-simulation', () => {
    const replay = readReplay(match.bytes, { gameId: 'ctf' });
    expect(replay.tickCount).toBe(match.ticks);
    expect(replay.header.players).toEqual(['ann', 'bob']);
    const result = verifyReplay(match.bytes, gameFromReplayHeader);
    expect(result).toMatchObject({ ok: true, ticks: match.ticks, lastGoodTick: match.ticks });
  });

  it('an edited input is caught at the next checkpoint', () => {
    // Player 0 alive and moving at tick t: make it move the opposite way for one tick.
    const { recorded } = match;
    let t = 4000;
    while (recorded[t * 2] === 0 || recorded[t * 2] === recorded[(t - 1) * 2]) t++;
    expectEditCaught(match, t);
  });
});

const GOLDEN = 'f94f573ae18710e2';
const MATCH_SEED = 10;
