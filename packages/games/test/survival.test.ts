import { describe, expect, it } from 'vitest';
import { readReplay, verifyReplay, type DisplayEvent } from 'fixedstep';
import {
  SURVIVAL,
  SurvivalGame,
  WavePhase,
  gameFromReplayHeader,
  playOnDisplay,
  survivalBot,
  survivalGame,
  waveSize,
} from '@fixedstep/games';
import {
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

const SURVIVAL_SHOOTER: Shooter<SurvivalGame> = {
  name: 'survival',
  definition: survivalGame,
  make: (config) => new SurvivalGame(config),
  bot: survivalBot,
};

/**
 * Whether the segment from (x0, y0) to (x1, y1) meets a wall of `game`: the test's own
 * Liang–Barsky, independent of the game's collision code.
 */
function pathMeetsWall(
  game: SurvivalGame,
  x0: number,
  y0: number,
  x1: number,
  y1: number,
): boolean {
  return game.walls.rects.some((r) => {
    let t0 = 0;
    let t1 = 1;
    const clip = (p: number, q: number) => {
      if (p === 0) return q >= 0;
      const t = q / p;
      if (p < 0) t0 = Math.max(t0, t);
      else t1 = Math.min(t1, t);
      return t0 <= t1;
    };
    const dx = x1 - x0;
    const dy = y1 - y0;
    return (
      clip(-dx, x0 - r.x0) && clip(dx, r.x1 - x0) && clip(-dy, y0 - r.y0) && clip(dy, r.y1 - y0)
    );
  });
}

describe('survival: the game', () => {
  it('is in the registry, with its config bytes and key map', () => {
    expectRegistered(SURVIVAL_SHOOTER, { seed: 77, players: 2 });
    expect(survivalGame.info.maxPlayers).toBe(2);
    expect(() => new SurvivalGame({ seed: 1, players: 1, lives: 0 })).toThrow(RangeError);
  });

  it('starts with 15 lives and sends its first wave after a second', () => {
    const game = new SurvivalGame({ seed: 1, players: 1 });
    expect(game.hud()).toMatchObject({ kills: 0, lives: 15, wave: 0 });
    for (let t = 0; t < 61; t++) game.step([0]);
    expect(game.state.wave).toBe(1);
    expect(game.state.phase).toBe(WavePhase.spawning);
    expect(game.state.enemies + game.state.toSpawn).toBe(waveSize(1));
  });

  itIsDeterministic(
    SURVIVAL_SHOOTER,
    { golden: GOLDEN, players: 2, twiceTicks: 1800, guardTicks: 1200, snapshotTicks: 1500 },
    (game) => game.state.enemies + game.state.cleared,
  );

  it('load rejects bytes it cannot read, and is then unchanged', () => {
    const expectRefused = expectRefusals(
      SURVIVAL_SHOOTER,
      botMatch(SURVIVAL_SHOOTER, 4, 1, 1500),
      /not a survival state/,
      2,
    );
    const tampered = (change: (g: SurvivalGame) => void): Uint8Array => {
      const g = botMatch(SURVIVAL_SHOOTER, 4, 1, 1500);
      change(g);
      return g.save();
    };
    const live = (g: SurvivalGame) => g.state.enemyAlive.indexOf(1);
    expectRefused(
      tampered((g) => {
        g.state.ex[live(g)] = Infinity;
      }),
      /a number is not finite/,
    );
    expectRefused(
      tampered((g) => {
        g.state.espeed[live(g)] = 1e6;
      }),
      /too fast/,
    );
    expectRefused(
      tampered((g) => {
        g.state.ex[g.state.enemyAlive.indexOf(0)] = 5; // an empty slot with something in it
      }),
      /not zeroed/,
    );
    expectRefused(
      tampered((g) => {
        g.state.lives[0] = 0;
      }),
      /alive with no lives/,
    );
    expectRefused(
      tampered((g) => {
        g.state.phase = 7;
      }),
      /wave phase/,
    );
  });
});

describe('survival: a bot match', () => {
  it('3 minutes of the bot: waves cleared, enemies killed, lives lost', () => {
    const game = botMatch(SURVIVAL_SHOOTER, 1, 1, 3 * 60 * 60);
    const hud = game.hud();
    expect(hud.cleared).toBeGreaterThan(3);
    expect(hud.kills).toBeGreaterThan(50);
    expect(hud.lives).toBeLessThan(SURVIVAL.lives);
    expect(hud.throughWalls).toBe(0);
  });

  it('until the end: the game is over when the lives are gone, and then stands still', () => {
    const game = botMatch(SURVIVAL_SHOOTER, 2, 1, 20 * 60 * 60);
    expect(game.over).toBe(true);
    expect(game.hud().lives).toBe(0);
    const hud = game.hud();
    const tick = game.tick;
    game.step([survivalBot(game, 0)]);
    expect(game.tick).toBe(tick + 1);
    expect(game.hud()).toEqual(hud);
  });
});

describe("survival: the talk's breakage, for real", () => {
  /**
   * The player waits west of the 10-unit wall at x = 110–120; every half second an enemy at
   * full speed (330 units/s) appears east of it and runs straight at the player — into the wall.
   * Under the fixed step it slides along the wall and comes round its end; under a variable Δt
   * a long frame carries it past the wall's middle and the push-out puts it on the player's side.
   */
  function rushAtWall(
    loop: 'fixed' | 'variable',
    hz: number,
    jitter: number,
    events: DisplayEvent[],
  ) {
    const game = new SurvivalGame({ seed: 1, players: 1, waves: false, lives: 255 });
    game.place(0, 60, 300, 0);
    let spawned = 0;
    let nextSpawn = 0;
    const last = new Map<number, readonly [number, number]>();
    const through = new Set<number>();
    const run = playOnDisplay(game, {
      loop,
      display: { hz, jitter, seed: 3, events },
      seconds: 20,
      inputs: (_g, out) => {
        out[0] = 0;
      },
      afterUpdate: () => {
        const s = game.state;
        if (s.clock >= nextSpawn) {
          game.spawnEnemy(250, 262 + ((spawned * 13) % 76), SURVIVAL.maxEnemySpeed);
          spawned++;
          nextSpawn += 0.5;
        }
        for (let e = 0; e < SURVIVAL.enemyCapacity; e++) {
          if (s.enemyAlive[e] === 0) continue;
          const id = s.enemySerial[e]!;
          const p = last.get(id);
          if (p && pathMeetsWall(game, p[0], p[1], s.ex[e]!, s.ey[e]!)) through.add(id);
          last.set(id, [s.ex[e]!, s.ey[e]!]);
        }
      },
    });
    return {
      spawned,
      through: through.size,
      counted: game.state.enemiesThroughWalls,
      livesLost: 255 - game.state.lives[0]!,
      maxDtMs: run.maxDt * 1000,
    };
  }

  for (const d of SLOW_DISPLAYS) {
    it(`fast enemies vs a 10-unit wall on a ${d.name} display: through under update, none under step`, () => {
      const naive = rushAtWall('variable', d.hz, d.jitter, d.events);
      const fixed = rushAtWall('fixed', d.hz, d.jitter, d.events);
      expect(naive.spawned).toBeGreaterThanOrEqual(39);
      expect(naive.through).toBeGreaterThan(naive.spawned / 2);
      expect(naive.counted).toBeGreaterThanOrEqual(naive.through);
      expect(fixed.spawned).toBeGreaterThanOrEqual(39);
      expect(fixed.through).toBe(0);
      expect(fixed.counted).toBe(0);
      // Under the fixed step they still get to the player — the long way round.
      expect(fixed.livesLost).toBeGreaterThan(5);
    });
  }

  it('the same waves on every display under the fixed step; different ones under update', () => {
    const config = { seed: 9, players: 1 };
    const fixed = RATE_DISPLAYS.map((d) => hashOnDisplay(SURVIVAL_SHOOTER, config, 'fixed', d));
    expect(new Set(fixed).size).toBe(1);
    const naive = RATE_DISPLAYS.map((d) => hashOnDisplay(SURVIVAL_SHOOTER, config, 'variable', d));
    expect(new Set(naive).size).toBe(RATE_DISPLAYS.length);
  });
});

describe('survival: replays', () => {
  itStandsStillAfterTheEnd(SURVIVAL_SHOOTER, { seed: 2, players: 1 });

  const match = recordBotMatch(SURVIVAL_SHOOTER, { seed: 12, players: 1 }, ['solo'], 2 * 60 * 60, {
    keyframeEvery: 1200,
  });

  it('records two minutes of the bot and verifies it by re-simulation (keyframes too)', () => {
    const replay = readReplay(match.bytes, { gameId: 'survival' });
    expect(replay.tickCount).toBe(match.ticks);
    expect(replay.keyframes).toHaveLength(match.ticks / 1200);
    expect(verifyReplay(match.bytes, gameFromReplayHeader)).toMatchObject({
      ok: true,
      ticks: match.ticks,
      lastGoodTick: match.ticks,
    });
  });

  it('an edited input is caught at the next checkpoint', () => {
    const { recorded } = match;
    let t = 5000;
    while ((recorded[t]! & 0b1111) === 0) t++;
    expectEditCaught(match, t); // the opposite direction for one tick
  });
});

const GOLDEN = '351bbd2d2758daff';
