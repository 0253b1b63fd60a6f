import { describe, expect, it } from 'vitest';
import {
  BUTTON_WORD,
  CorrectionSmoother,
  EventScheduler,
  Random,
  Relay,
  RollbackSession,
  SimulatedLink,
  gameCatalog,
} from 'fixedstep';
import { Toy } from './toy-game.js';

const catalog = gameCatalog([
  { id: 'toy', version: 1, tickRate: 60, minPlayers: 1, maxPlayers: 4, input: BUTTON_WORD },
]);

/**
 * A match of the toy on one simulated clock: a relay (updated at 120 Hz, its randomness seeded
 * with `relaySeed`) and a rollback session on each of `links`, framed at 60 Hz, all players of
 * the toy seeded `seed`, to `ticks`. `input` is what player `i` (in slot `slot`) presses at `tick`.
 */
function toyMatch(o: {
  relaySeed: number;
  links: { seed: number; latencyMs: number; jitterMs: number; loss?: number }[];
  seed: number;
  ticks: number;
  input: (i: number, slot: number, tick: number, sim: { readonly tick: number }) => number;
}): { scheduler: EventScheduler; relay: Relay; sessions: RollbackSession[] } {
  const scheduler = new EventScheduler();
  const rng = new Random(o.relaySeed);
  const relay = new Relay({ clock: scheduler.clock, catalog, randomU32: () => rng.nextU32() });
  scheduler.every(1000 / 120, () => {
    relay.update();
  });
  const players = o.links.length;
  const sessions = o.links.map((conditions, i) => {
    const link = new SimulatedLink({ scheduler, ...conditions });
    relay.accept(link.b);
    let slot = -1;
    const s: RollbackSession = new RollbackSession({
      transport: link.a,
      clock: scheduler.clock,
      room: 'r',
      game: 'toy',
      gameVersion: 1,
      players,
      seed: o.seed,
      stopAt: o.ticks,
      createSimulation: (w) => {
        slot = w.slot;
        return new Toy(players, o.seed);
      },
      localInput: (tick, sim) => o.input(i, slot, tick, sim),
    });
    scheduler.every(1000 / 60, () => {
      s.frame();
    });
    return s;
  });
  return { scheduler, relay, sessions };
}

describe('input delay changed during a match', () => {
  it('takes effect at the agreed tick on both players, and both end on the same hash', () => {
    const ticks = 900;
    // For each player: the tick on which each issued input was asked for, against the sim's tick.
    const issuedAt: Map<number, number>[] = [new Map<number, number>(), new Map<number, number>()];
    const { scheduler, relay, sessions } = toyMatch({
      relaySeed: 3,
      links: [0, 1].map((i) => ({ seed: 10 + i, latencyMs: 40, jitterMs: 10, loss: 0.05 })),
      seed: 5,
      ticks,
      input: (i, slot, tick, sim) => {
        issuedAt[i]!.set(tick, sim.tick);
        return ((tick >> 4) + slot) & 3;
      },
    });
    // Both players agree: from tick 300 on, 4 ticks of input delay (from the default 1).
    for (const s of sessions) s.setInputDelay(4, 300);
    expect(sessions[0]!.inputDelayTicks).toBe(1);
    expect(scheduler.runUntilDone(() => sessions.every((s) => s.isFinished), 60_000)).toBe(true);
    for (const [i, s] of sessions.entries()) {
      expect(s.inputDelayTicks).toBe(4);
      // Inputs asked for while the simulation was well before 300 are for about lead + 1 ticks
      // ahead; well after, 3 ticks further ahead. The distance is what the delay changed.
      const ahead = (from: number, to: number) => {
        const d: number[] = [];
        for (const [tick, at] of issuedAt[i]!) if (at >= from && at < to) d.push(tick - at);
        return d.reduce((a, b) => a + b, 0) / d.length;
      };
      const before = ahead(100, 290);
      const after = ahead(400, 800);
      expect(after - before, `player ${i}: ${before} → ${after}`).toBeGreaterThan(2.5);
      expect(after - before).toBeLessThan(3.5);
    }
    const hashes = sessions.map((s) => s.hashAt(ticks));
    expect(hashes[0]).toBeDefined();
    expect(hashes[0]).toBe(hashes[1]);
    expect(relay.room('r')!.desyncs).toHaveLength(0);
  });

  it('refuses a delay out of range, naming it', () => {
    const s = idleSession();
    expect(() => {
      s.setInputDelay(61);
    }).toThrow(/from 0 to 60, got 61/);
    expect(() => {
      s.setInputDelay(2, -1);
    }).toThrow(/atTick must be a tick/);
  });
});

describe('several local players on one machine', () => {
  /**
   * Three players: sessions 0 and 1 share one machine (their inputs change every 8 ticks),
   * session 2 is remote and holds nothing (predicting it is always right). Slots go by arrival. Returns each session's rollbacks
   * and hash at the end.
   */
  function play(link: boolean) {
    const ticks = 600;
    const { scheduler, relay, sessions } = toyMatch({
      relaySeed: 4,
      links: [0, 1, 2].map((i) => ({ seed: 20 + i, latencyMs: 30, jitterMs: 5 })),
      seed: 9,
      ticks,
      input: (i, slot, tick) => (i === 2 ? 0 : ((tick >> 3) + slot) & 3),
    });
    if (link) RollbackSession.linkLocalPlayers([sessions[0]!, sessions[1]!]);
    expect(scheduler.runUntilDone(() => sessions.every((s) => s.isFinished), 60_000)).toBe(true);
    expect(sessions.map((s) => s.welcome?.slot).sort((a, b) => (a ?? -1) - (b ?? -1))).toEqual([
      0, 1, 2,
    ]);
    expect(relay.room('r')!.desyncs).toHaveLength(0);
    return {
      rollbacks: sessions.map((s) => s.stats.rollbacks),
      hashes: sessions.map((s) => s.hashAt(ticks)),
    };
  }

  it("linked sessions use each other's issued inputs: no rollbacks between them, same hashes", () => {
    const apart = play(false);
    const linked = play(true);
    // Apart, each local player mispredicts the other one every time it changes its input.
    expect(apart.rollbacks[0]).toBeGreaterThan(30);
    expect(apart.rollbacks[1]).toBeGreaterThan(30);
    // Linked, nothing is left to mispredict: the remote player never changes its input.
    expect(linked.rollbacks.slice(0, 2)).toEqual([0, 0]);
    // The remote player still predicts the local ones (rollbacks as before), and every machine
    // simulated the same confirmed inputs either way.
    expect(linked.rollbacks[2]).toBeGreaterThan(30);
    expect(linked.hashes[0]).toBeDefined();
    expect(new Set([...apart.hashes, ...linked.hashes]).size).toBe(1);
  });

  it('refuses a session listed twice', () => {
    const s = idleSession();
    expect(() => {
      RollbackSession.linkLocalPlayers([s, s]);
    }).toThrow(/listed twice/);
  });
});

describe('CorrectionSmoother', () => {
  it('blends the drawn position from the mispredicted to the corrected over the frames', () => {
    const s = new CorrectionSmoother({ frames: 4 });
    // Predicted at (10, 0), the rollback says (6, 2); the entity keeps moving +1 x a frame.
    s.correct(7, [10, 0], [6, 2]);
    const drawn: number[][] = [];
    for (let f = 0; f < 5; f++) {
      drawn.push(s.apply(7, [6 + f, 2]));
      s.frame();
    }
    expect(drawn).toEqual([
      [10, 0],
      [7 + 3, 2 - 1.5],
      [8 + 2, 2 - 1],
      [9 + 1, 2 - 0.5],
      [10, 2],
    ]);
    expect(s.isBlending(7)).toBe(false);
    // Another entity was never corrected: drawn as it is.
    expect(s.apply(8, [1, 2])).toEqual([1, 2]);
  });

  it('a second correction starts from where the blend had got to; a teleport snaps', () => {
    const s = new CorrectionSmoother({ frames: 4, snapDistance: 50 });
    s.correct(1, [8, 0], [0, 0]);
    s.frame();
    s.frame(); // half way: drawn 4 ahead of the truth
    expect(s.apply(1, [0, 0])).toEqual([4, 0]);
    s.correct(1, [0, 0], [2, 0]); // the truth moves 2 on: drawn stays where it was
    expect(s.apply(1, [2, 0])).toEqual([4, 0]);
    s.correct(1, [4, 0], [400, 0]);
    expect(s.apply(1, [400, 0])).toEqual([400, 0]);
    expect(s.isBlending(1)).toBe(false);
  });

  it('refuses bad options and values', () => {
    expect(() => new CorrectionSmoother({ frames: 0 })).toThrow(/frames must be an integer/);
    expect(() => new CorrectionSmoother({ snapDistance: -1 })).toThrow(/snapDistance/);
    const s = new CorrectionSmoother();
    expect(() => {
      s.correct(1, [Number.NaN, 0], [0, 0]);
    }).toThrow(/non-finite/);
    expect(() => {
      s.correct(1, [0], [0, 0]);
    }).toThrow(/needs 2 values/);
  });
});

/** A rollback session of the toy game on a link nothing answers: for checks of its arguments. */
function idleSession(): RollbackSession {
  return new RollbackSession({
    transport: new SimulatedLink({ scheduler: new EventScheduler() }).a,
    clock: { now: () => 0 },
    room: 'r',
    game: 'toy',
    gameVersion: 1,
    createSimulation: () => new Toy(1, 1),
  });
}
