/**
 * State sync on simulated links (delay, jitter, loss): clients see the server's world, their own
 * player answers without input lag, a correction glides, and a game that is not deterministic
 * still converges — while lockstep on the same game is caught by desync detection.
 */
import { describe, expect, it } from 'vitest';
import {
  SimulatedMatch,
  fnv1a64,
  hex64,
  isDown,
  type ButtonInput,
  type StateSyncSession,
} from 'fixedstep';
import {
  Arena,
  SHOVE,
  SPEED,
  World,
  arenaGame,
  scripted,
  type Drift,
} from './state-sync-fixture.js';

const LOSSY = { latencyMs: 100, jitterMs: 30, loss: 0.05 };

describe('state sync: clients see the server’s world', () => {
  it('every snapshot a client holds is the server’s state at that tick, through 100 ± 30 ms and 5 % loss', () => {
    const w = new World(arenaGame(), LOSSY);
    const clients = [w.client(), w.client()];
    let checks = 0;
    const server = w.room.simulation;
    w.onFrame = (s) => {
      s.frame(w.scheduler.now);
      s.render(w.scheduler.now);
      const state = s.snapshotState;
      if (state === undefined) return;
      const want = server.history!.get(s.snapshotTick);
      expect(hex64(fnv1a64(state)), `tick ${s.snapshotTick}`).toBe(hex64(want!));
      checks++;
    };
    w.run(20_000);
    expect(checks).toBeGreaterThan(2000);
    for (const s of clients) {
      expect(s.phase).toBe('running');
      expect(s.stats.badSnapshots).toBe(0);
      expect(s.stats.deltaSnapshots).toBeGreaterThan(300);
      // Full snapshots only on join (until the first acknowledgement is back) — never after.
      expect(s.stats.fullSnapshots).toBeLessThanOrEqual(8);
      // The prediction keeps up with the server: the client is ahead of the newest snapshot.
      expect(s.tick).toBeGreaterThan(s.snapshotTick);
    }
    // Loss happened, and snapshots were delta-coded against older acknowledged ones.
    expect(w.links[0]!.stats[1].lost).toBeGreaterThan(10);
    expect(w.room.stats.deltaSnapshots).toBeGreaterThan(10 * w.room.stats.fullSnapshots);
  });

  it('draws the other player between the server’s snapshots, a render delay behind', () => {
    const w = new World(arenaGame(), { latencyMs: 50, jitterMs: 10, loss: 0 });
    const a = w.client();
    w.client();
    const trail = w.room.simulation.trail!;
    const every = w.room.snapshotEvery;
    let compared = 0;
    let worst = 0;
    w.onFrame = (s, i) => {
      s.frame(w.scheduler.now);
      const out = s.render(w.scheduler.now);
      if (i !== 0 || s.renderTick < 120) return;
      // The other disc (slot 1) is drawn between the snapshot ticks around the render tick.
      const r = s.renderTick;
      const t0 = Math.floor(r / every) * every;
      const t1 = t0 + every;
      const p0 = trail.get(t0)!;
      const p1 = trail.get(t1) ?? p0;
      const u = t1 === t0 ? 0 : (r - t0) / (t1 - t0);
      const other = 1 - s.welcome!.slot;
      for (const k of [2 * other, 2 * other + 1]) {
        const want = p0[k]! + (p1[k]! - p0[k]!) * Math.min(1, u);
        worst = Math.max(worst, Math.abs(out[k]! - want));
      }
      compared++;
    };
    w.run(10_000);
    expect(compared).toBeGreaterThan(400);
    // Exactly the server's numbers, blended (float rounding only) — or held at the newest
    // snapshot for the few frames it was late.
    expect(a.stats.starvedFrames).toBeLessThan(compared / 20);
    expect(worst).toBeLessThan(SPEED / 60 + 1e-9);
    // The render delay covers a snapshot interval and the one-way delay with its jitter.
    expect(a.renderDelayMs).toBeGreaterThan(50 + 40);
    expect(a.renderDelayMs).toBeLessThan(50 + 50 + 30);
    expect(a.stats.jitterMs).toBeGreaterThan(5);
    expect(a.stats.jitterMs).toBeLessThan(30);
  });
});

describe('state sync: the own player answers at once', () => {
  it('an input shows on the own screen in the frame it is sampled; the other screen sees it a round of delays later', () => {
    const w = new World(arenaGame(), { latencyMs: 60, jitterMs: 10, loss: 0 });
    const sampledAt = new Map<number, number>();
    const seenOwn = new Map<number, number>();
    const seenOther = new Map<number, number>();
    // Player 0 changes direction every 120 ticks (scripted): watch those ticks.
    const turns = [360, 480, 600, 720, 840];
    const a = w.client({
      localInput: (tick) => {
        if (turns.includes(tick)) sampledAt.set(tick, w.scheduler.now);
        return scripted(tick, 0);
      },
    });
    const b = w.client();
    w.onFrame = (s, i) => {
      s.frame(w.scheduler.now);
      s.render(w.scheduler.now);
      for (const t of turns) {
        // The input of tick t is in every state after tick t.
        if (i === 0 && !seenOwn.has(t) && s.tick > t) seenOwn.set(t, w.scheduler.now);
        if (i === 1 && !seenOther.has(t) && s.renderTick > t + 1) seenOther.set(t, w.scheduler.now);
      }
    };
    w.run(16_000);
    // The joins raced on the jittery link: either may have slot 0.
    expect(new Set([a.welcome?.slot, b.welcome?.slot])).toEqual(new Set([0, 1]));
    for (const t of turns) {
      const own = seenOwn.get(t)! - sampledAt.get(t)!;
      const other = seenOther.get(t)! - sampledAt.get(t)!;
      // Sampled and predicted in the same frame: zero input lag on the own screen…
      expect(own, `tick ${t}`).toBe(0);
      // …while the other player sees it after the uplink (60 ms), the snapshot, the downlink
      // (60 ms) and its render delay.
      expect(other, `tick ${t}`).toBeGreaterThan(150);
    }
    // The prediction ran ahead of the server: its input was in before the server stepped it.
    expect(a.stats.filledInputs).toBe(0);
    expect(a.stats.lead).toBeGreaterThanOrEqual(Math.ceil(60 / (1000 / 60)));
  });
});

describe('state sync: corrections are smoothed on screen', () => {
  /** The largest per-frame move of the own disc's drawn y, and the largest correction. */
  function run(halfLifeMs: number): { jump: number; correction: number; corrections: number } {
    // The client's copy forgets the conveyor (a server rule shoving disc 0 by SHOVE units).
    const w = new World(arenaGame(), { latencyMs: 50, jitterMs: 5, loss: 0 });
    let lastY: number | undefined;
    let jump = 0;
    const a = w.client({
      createSimulation: (setup) => new Arena(setup.players, setup.seed, { noShove: true }),
      smoothingHalfLifeMs: halfLifeMs,
      // Walk right and left only: the drawn y moves by corrections alone.
      localInput: (tick) => (Math.floor(tick / 120) % 2 === 0 ? 1 << 1 : 1 << 0),
    });
    w.onFrame = (s, i) => {
      s.frame(w.scheduler.now);
      const out = s.render(w.scheduler.now);
      if (i !== 0 || s.tick < 120) return;
      if (lastY !== undefined) jump = Math.max(jump, Math.abs(out[1]! - lastY));
      lastY = out[1]!;
    };
    w.run(25_000);
    return { jump, correction: a.stats.maxCorrection, corrections: a.stats.corrections };
  }

  it('a 3-unit correction glides over frames instead of jumping', () => {
    const smooth = run(80);
    const raw = run(0);
    // Both saw the conveyor's shoves as corrections of SHOVE units…
    expect(smooth.correction).toBeCloseTo(SHOVE, 6);
    expect(raw.correction).toBeCloseTo(SHOVE, 6);
    expect(smooth.corrections).toBeGreaterThanOrEqual(4);
    // …without smoothing the disc jumps by all of it in one frame; with an 80 ms half-life the
    // largest step is what decays in one 16.7 ms frame: 3 × (1 − 2^(−16.7/80)) ≈ 0.40.
    expect(raw.jump).toBeCloseTo(SHOVE, 6);
    expect(smooth.jump).toBeLessThan(0.45);
    expect(smooth.jump).toBeGreaterThan(0.3);
  });
});

describe('state sync works when the game is not deterministic', () => {
  /** Each player walks left and right in a lane of its own (no collisions). */
  const lanes = (tick: number): ButtonInput => (Math.floor(tick / 90) % 2 === 0 ? 1 << 1 : 1 << 0);
  const DRIFT: Drift = { force: 1e-6, reorder: true };

  it('drifting clients stay within a bounded error of the server; the error does not grow', () => {
    const w = new World(arenaGame(), { latencyMs: 100, jitterMs: 30, loss: 0 });
    const predicted = new Map<number, number>(); // tick → own x predicted for it (the freshest)
    const clients = [0, 1].map(() =>
      w.client({
        createSimulation: (setup) => new Arena(setup.players, setup.seed, DRIFT),
        localInput: lanes,
      }),
    );
    w.onFrame = (s, i) => {
      s.frame(w.scheduler.now);
      s.render(w.scheduler.now);
      if (i === 0 && s.simulation) predicted.set(s.tick, s.simulation.x[s.welcome!.slot]!);
    };
    const seconds = 30;
    w.run(seconds * 1000);
    const trail = w.room.simulation.trail!;
    const slot = clients[0]!.welcome!.slot;
    const errorIn = (from: number, to: number) => {
      let worst = 0;
      for (const [tick, x] of predicted) {
        if (tick < from || tick >= to) continue;
        const server = trail.get(tick);
        if (server) worst = Math.max(worst, Math.abs(x - server[2 * slot]!));
      }
      return worst;
    };
    const early = errorIn(120, 600);
    const late = errorIn(seconds * 60 - 600, seconds * 60);
    // An uncorrected copy of the same game drifts 1e-6 a tick: after 30 s it is 1.8e-3 off.
    const alone = new Arena(2, 7, DRIFT);
    const exact = new Arena(2, 7);
    for (let t = 0; t < seconds * 60; t++) {
      alone.step([lanes(t), lanes(t)]);
      exact.step([lanes(t), lanes(t)]);
    }
    const uncorrected = Math.abs(alone.x[slot]! - exact.x[slot]!);
    expect(uncorrected).toBeGreaterThan(1.7e-3);
    // With state sync the client is off by at most the drift of the ticks it predicts past the
    // snapshot (lead + round trip ≈ 20 ticks ⇒ 2e-5), early and late alike.
    const bound = 40e-6;
    expect(early, `early error ${early}`).toBeLessThan(bound);
    expect(late, `late error ${late}`).toBeLessThan(bound);
    expect(late).toBeGreaterThan(0); // it does drift between snapshots
    for (const s of clients) expect(s.stats.badSnapshots).toBe(0);
  });

  it('lockstep on the same game is caught by desync detection', () => {
    const game = arenaGame();
    const match = new SimulatedMatch({
      game,
      seed: 7,
      ticks: 600,
      link: { latencyMs: 50, jitterMs: 10, loss: 0 },
      clients: [
        { kind: 'lockstep' },
        {
          kind: 'lockstep',
          createSimulation: (w) => new Arena(w.players, w.seed, DRIFT),
        },
      ],
      relay: { hashEvery: 30 },
    });
    const result = match.run(60_000);
    expect(result.hashesAgree).toBe(false);
    const desyncs = result.room?.desyncs ?? [];
    expect(desyncs.length).toBe(1);
    // The drift changes the state from the first step on: the relay pins tick 1.
    expect(desyncs[0]!.tick).toBeLessThanOrEqual(30);
  });
});

describe('state sync: joining', () => {
  it('a late joiner gets one full snapshot and then deltas; a spectator sees everything, predicts nothing', () => {
    const w = new World(arenaGame(), { latencyMs: 40, jitterMs: 5, loss: 0 });
    const a = w.client();
    w.run(3000);
    const late = w.client();
    const watcher = w.client({ role: 'spectator' });
    w.run(3000);
    expect(late.welcome?.slot).toBe(1);
    expect(late.stats.fullSnapshots).toBeGreaterThanOrEqual(1);
    expect(late.stats.fullSnapshots).toBeLessThanOrEqual(3);
    expect(late.stats.deltaSnapshots).toBeGreaterThan(40);
    expect(watcher.welcome?.slot).toBe(-1);
    expect(watcher.stats.deltaSnapshots).toBeGreaterThan(40);
    expect(watcher.stats.reconciliations).toBe(0);
    expect(watcher.tick).toBe(watcher.snapshotTick);
    expect(a.stats.fullSnapshots).toBeLessThanOrEqual(3);
    // The room refuses a third player (two slots), with a reason.
    const third = w.client();
    const errors: string[] = [];
    w.run(500);
    for (const e of third.errors) errors.push(e.code);
    expect(errors).toEqual(['ROOM_FULL']);
    expect(third.phase).toBe('closed');
  });

  it('a player takes its slot back with its token', () => {
    const w = new World(arenaGame(), { latencyMs: 20, jitterMs: 0, loss: 0 });
    const a = w.client();
    w.client();
    w.run(1000);
    const token = a.welcome!.token;
    expect(token.length).toBe(16);
    a.leave();
    w.run(200);
    expect(w.room.occupied()).toEqual([false, true]);
    const back = w.client({ token });
    w.run(1000);
    expect(back.welcome?.slot).toBe(0);
    expect(back.phase).toBe('running');
    expect(w.room.occupied()).toEqual([true, true]);
  });

  it('holds still for a stalled link, then catches up from the next snapshot', () => {
    const w = new World(arenaGame(), { latencyMs: 30, jitterMs: 0, loss: 0 });
    const a = w.client({ maxPrediction: 30 });
    w.run(2000);
    // The downlink goes dark for a second: the prediction runs maxPrediction ticks past the
    // newest snapshot and waits there.
    w.links[0]!.setConditions({ loss: 1 }, 1);
    w.run(1000);
    expect(a.tick).toBe(a.snapshotTick + 30);
    expect(a.stats.stallFrames).toBeGreaterThan(20);
    w.links[0]!.setConditions({ loss: 0 }, 1);
    w.run(500);
    const server = w.room.simulation.tick;
    expect(a.snapshotTick).toBeGreaterThan(server - 10);
    expect(a.tick).toBeGreaterThan(server);
    expect(isDown(scripted(0, 0), 1)).toBe(true);
  });
});

describe('state sync: sessions are checked', () => {
  it('refuses options out of range, naming them', () => {
    const w = new World(arenaGame(), {});
    expect(() => w.client({ maxPrediction: 0 })).toThrow(
      /maxPrediction must be an integer from 1 to 600, got 0/,
    );
    expect(() => w.client({ lead: 120 })).toThrow(
      /lead must be 'auto' or an integer from 0 to maxPrediction - 1, got 120/,
    );
    expect(() => w.client({ renderDelay: -5 })).toThrow(
      /renderDelay must be 'auto' or ms >= 0, got -5/,
    );
  });

  it('the same link seeds give the same run, number for number', () => {
    const once = (): unknown => {
      const w = new World(arenaGame(), LOSSY);
      const s: StateSyncSession<ButtonInput, Arena>[] = [w.client(), w.client()];
      w.run(5000);
      return [s.map((c) => ({ ...c.stats })), { ...w.room.stats }, w.room.simulation.hash()];
    };
    expect(once()).toEqual(once());
  });
});
